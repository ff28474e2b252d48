//! The scene reference: every key of the technique tables (`[strands]`, `[volume]`, `[hybrid]`,
//! `[patches]`, `[satf]`) with its default and meaning, from the code itself.
//!
//! Each table's list lives beside its parser (`scene_setup/reference.rs`,
//! `patches/scene_doc.rs`, `satf/scene_doc.rs`), its defaults formatted from the settings'
//! `Default` values, never typed by hand. Unit tests check that the documented keys are exactly
//! the keys the table accepts and that writing each documented default into a scene gives the
//! default settings; the book's tables are this module's [`settings_markdown`] (a test in
//! `tests/book_settings.rs` compares them), and `tress settings` prints them.

use glam::Vec3;

/// One key of a scene table.
#[derive(Clone, Debug, PartialEq)]
pub struct SettingDoc {
    /// The key inside its table; a nested table's keys are dotted (`generator.layers`).
    pub key: &'static str,
    /// The default as a TOML value (`1.5`, `"tip"`, `[1.0, 1.0, 1.0]`), or `None` when the key
    /// is absent by default (the meaning says what absence does).
    pub default: Option<String>,
    /// What the key does, one Markdown paragraph (links are relative to the book's chapters).
    pub meaning: &'static str,
}

/// The tables [`settings_reference`] documents, in the book's order.
pub const SETTING_TABLES: [&str; 5] = ["strands", "volume", "hybrid", "patches", "satf"];

/// Every key of the scene table `table` (one of [`SETTING_TABLES`]) with its default and
/// meaning, in the order the book lists them; `None` for another name.
pub fn settings_reference(table: &str) -> Option<Vec<SettingDoc>> {
    Some(match table {
        "strands" => crate::scene_setup::reference::strands(),
        "volume" => crate::scene_setup::reference::volume(),
        "hybrid" => crate::scene_setup::reference::hybrid(),
        "patches" => crate::patches::scene_doc::patches(),
        "satf" => crate::satf::scene_doc::satf(),
        _ => return None,
    })
}

/// The Markdown table of `table`'s keys (as in the book: key, default, meaning), ending in a
/// newline; `None` for a table [`settings_reference`] does not know.
pub fn settings_markdown(table: &str) -> Option<String> {
    let docs = settings_reference(table)?;
    let mut md = format!("| `[{table}]` key | default | meaning |\n| --- | --- | --- |\n");
    for d in docs {
        let default = match &d.default {
            None => "(none)".to_string(),
            Some(v) if v.starts_with(['"', '[']) => format!("`{v}`"),
            Some(v) => v.clone(),
        };
        let meaning = d.meaning.replace('|', "\\|").replace('\n', " ");
        md.push_str(&format!("| `{}` | {default} | {meaning} |\n", d.key));
    }
    Some(md)
}

/// `table`'s keys as a TOML block a scene can start from: each key at its default with its
/// meaning as a comment above it (keys absent by default commented out); `None` for a table
/// [`settings_reference`] does not know.
pub fn settings_toml(table: &str) -> Option<String> {
    let docs = settings_reference(table)?;
    let mut text = format!("[{table}]\n");
    for d in docs {
        for line in wrap(d.meaning, 96) {
            text.push_str(&format!("# {line}\n"));
        }
        match &d.default {
            Some(v) => text.push_str(&format!("{} = {v}\n", d.key)),
            None => text.push_str(&format!("# {} = (absent)\n", d.key)),
        }
    }
    Some(text)
}

/// `text` broken at spaces into lines of at most `width` characters (longer words stay whole).
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split_whitespace() {
        let line = lines.last_mut().expect("one line");
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(word.to_string());
        } else {
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(word);
        }
    }
    lines
}

/// A setting's value written as TOML: how a documented default is formatted from the code's
/// default.
pub(crate) trait TomlText {
    /// The value as TOML text, `None` for an absent optional value.
    fn toml(&self) -> Option<String>;
}

impl TomlText for f32 {
    fn toml(&self) -> Option<String> {
        // `Debug` is the shortest text that reads back as the same f32, with a `.0` on integers.
        Some(format!("{self:?}"))
    }
}

impl TomlText for f64 {
    fn toml(&self) -> Option<String> {
        Some(format!("{self:?}"))
    }
}

impl TomlText for u32 {
    fn toml(&self) -> Option<String> {
        Some(self.to_string())
    }
}

impl TomlText for u64 {
    fn toml(&self) -> Option<String> {
        Some(self.to_string())
    }
}

impl TomlText for bool {
    fn toml(&self) -> Option<String> {
        Some(self.to_string())
    }
}

impl TomlText for &str {
    fn toml(&self) -> Option<String> {
        Some(format!("\"{self}\""))
    }
}

impl TomlText for [f32; 3] {
    fn toml(&self) -> Option<String> {
        Some(format!("[{:?}, {:?}, {:?}]", self[0], self[1], self[2]))
    }
}

impl TomlText for Vec3 {
    fn toml(&self) -> Option<String> {
        self.to_array().toml()
    }
}

impl<T: TomlText> TomlText for Option<T> {
    fn toml(&self) -> Option<String> {
        self.as_ref().and_then(T::toml)
    }
}

/// A key with no default value (absent unless the scene sets it).
pub(crate) struct Absent;

impl TomlText for Absent {
    fn toml(&self) -> Option<String> {
        None
    }
}

/// One documented key: `default` is the code's default value.
pub(crate) fn doc(key: &'static str, default: impl TomlText, meaning: &'static str) -> SettingDoc {
    SettingDoc {
        key,
        default: default.toml(),
        meaning,
    }
}

#[cfg(test)]
pub(crate) mod introspect {
    //! The keys a serde table struct accepts, read from the struct itself: a deserializer that
    //! records the `fields` serde's derive passes to `deserialize_struct`.

    use serde::de::{self, Deserialize, Deserializer, Visitor};

    struct Fields(Option<&'static [&'static str]>);

    impl<'de> Deserializer<'de> for &mut Fields {
        type Error = de::value::Error;

        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
            Err(de::Error::custom("not a struct"))
        }

        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _name: &'static str,
            fields: &'static [&'static str],
            _visitor: V,
        ) -> Result<V::Value, Self::Error> {
            self.0 = Some(fields);
            Err(de::Error::custom("fields recorded"))
        }

        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
            option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
            ignored_any
        }
    }

    /// The field names of the struct `T` deserializes as (panics for a type that is no struct).
    pub(crate) fn fields<'de, T: Deserialize<'de>>() -> &'static [&'static str] {
        let mut f = Fields(None);
        let _ = T::deserialize(&mut f);
        f.0.expect("a struct")
    }

    /// The documented keys of a table: the top-level `keys`, each nested table's name in it
    /// replaced by its own keys, dotted (`generator.layers`).
    pub(crate) fn flatten(
        keys: &[&str],
        nested: &[(&str, &'static [&'static str])],
    ) -> Vec<String> {
        let mut out = Vec::new();
        for k in keys {
            match nested.iter().find(|(n, _)| n == k) {
                Some((n, inner)) => out.extend(inner.iter().map(|i| format!("{n}.{i}"))),
                None => out.push(k.to_string()),
            }
        }
        out
    }

    /// `docs`' keys equal `accepted`, as sets, and none is listed twice.
    pub(crate) fn assert_same_keys(table: &str, docs: &[super::SettingDoc], accepted: &[String]) {
        let mut documented: Vec<&str> = docs.iter().map(|d| d.key).collect();
        documented.sort_unstable();
        let before = documented.len();
        documented.dedup();
        assert_eq!(before, documented.len(), "[{table}] documents a key twice");
        let mut accepted: Vec<&str> = accepted.iter().map(String::as_str).collect();
        accepted.sort_unstable();
        assert_eq!(
            documented, accepted,
            "[{table}]: the documented keys (left) differ from those the table accepts (right)"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_introspecting_deserializer_reads_a_structs_fields() {
        #[derive(serde::Deserialize)]
        #[allow(dead_code)]
        struct T {
            a: u32,
            b_c: Option<String>,
        }
        assert_eq!(introspect::fields::<T>(), ["a", "b_c"]);
    }

    #[test]
    fn every_table_renders_as_markdown_and_toml() {
        for table in SETTING_TABLES {
            let md = settings_markdown(table).unwrap();
            let rows = settings_reference(table).unwrap().len();
            assert_eq!(md.lines().count(), rows + 2, "{table}");
            let text = settings_toml(table).unwrap();
            // The TOML block parses, and its keys are the defaults.
            let scene = tress_scene::Scene::from_str(&text, ".").unwrap();
            assert!(scene.technique_table(table).is_some(), "{table}");
        }
        assert!(settings_reference("camera").is_none());
        assert_eq!(wrap("a bb ccc", 4), ["a bb", "ccc"]);
        assert_eq!(0.6f32.toml().unwrap(), "0.6");
        assert_eq!(4.0f32.toml().unwrap(), "4.0");
    }
}
