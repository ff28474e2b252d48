//! `--set key=value` overrides on a TOML document.
//!
//! The key is a dotted path: table keys, and array indices for arrays of tables
//! (`light.0.intensity`, `hair.1.material.base_color`). Missing tables on the way are created; an
//! index equal to an array's length appends an empty table (so `light.2.intensity=0.5` adds a third
//! light with default fields). The value is parsed as a TOML value (`35`, `[0.3, 0.2, 0.1]`,
//! `"text"`, `{ style = "curly" }`); if it does not parse, it is taken as a string, so
//! `technique=volume` needs no quotes. Keys containing dots cannot be addressed.

use toml::{Table, Value};

/// Split `key=value`, trimming both sides.
pub(crate) fn split(set: &str) -> Result<(&str, &str), String> {
    let (key, value) = set.split_once('=').ok_or("expected `key=value`")?;
    let key = key.trim();
    if key.is_empty() {
        return Err("the key is empty".into());
    }
    Ok((key, value.trim()))
}

/// A value as TOML, or as a string when it is not valid TOML.
pub(crate) fn parse_value(text: &str) -> Value {
    let doc = format!("v = {text}");
    match doc.parse::<Table>() {
        Ok(mut t) if t.len() == 1 => t
            .remove("v")
            .unwrap_or_else(|| Value::String(text.to_owned())),
        _ => Value::String(text.to_owned()),
    }
}

/// Set the dotted `key` of `root` to `value`.
pub(crate) fn set(root: &mut Table, key: &str, value: Value) -> Result<(), String> {
    let parts: Vec<&str> = key.split('.').collect();
    if let Some(empty) = parts.iter().position(|p| p.is_empty()) {
        return Err(format!(
            "`{key}` has an empty part at position {}",
            empty + 1
        ));
    }
    let (last, path) = parts.split_last().ok_or("the key is empty")?;
    let mut current = Slot::Table(root);
    let mut walked = String::new();
    for part in path {
        current = current.child(part, &walked)?;
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(part);
    }
    current.assign(last, &walked, value)
}

/// A place in the document that holds children: a table or an array.
enum Slot<'a> {
    Table(&'a mut Table),
    Array(&'a mut Vec<Value>),
}

impl<'a> Slot<'a> {
    /// The child `part` (created as an empty table if missing), as a slot.
    fn child(self, part: &str, walked: &str) -> Result<Slot<'a>, String> {
        let value = match self {
            Slot::Table(t) => t
                .entry(part.to_owned())
                .or_insert_with(|| Value::Table(Table::new())),
            Slot::Array(a) => {
                let i = index(part, a.len(), walked)?;
                if i == a.len() {
                    a.push(Value::Table(Table::new()));
                }
                &mut a[i]
            }
        };
        let here = if walked.is_empty() {
            part.to_owned()
        } else {
            format!("{walked}.{part}")
        };
        match value {
            Value::Table(t) => Ok(Slot::Table(t)),
            Value::Array(a) => Ok(Slot::Array(a)),
            other => Err(format!(
                "`{here}` is a value ({}), not a table or an array",
                other.type_str()
            )),
        }
    }

    /// Set child `part` to `value`.
    fn assign(self, part: &str, walked: &str, value: Value) -> Result<(), String> {
        match self {
            Slot::Table(t) => {
                t.insert(part.to_owned(), value);
            }
            Slot::Array(a) => {
                let i = index(part, a.len(), walked)?;
                if i == a.len() {
                    a.push(value);
                } else {
                    a[i] = value;
                }
            }
        }
        Ok(())
    }
}

/// An array index in `0..=len` (`len` appends).
fn index(part: &str, len: usize, walked: &str) -> Result<usize, String> {
    let i: usize = part
        .parse()
        .map_err(|_| format!("`{walked}` is an array: expected an index, got `{part}`"))?;
    if i > len {
        return Err(format!(
            "`{walked}` has {len} entries: index {i} is out of range (use {len} to append)"
        ));
    }
    Ok(i)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(text: &str) -> Table {
        text.parse().unwrap()
    }

    #[test]
    fn values_parse_as_toml_or_fall_back_to_strings() {
        assert_eq!(parse_value("35"), Value::Integer(35));
        assert_eq!(parse_value("2.5"), Value::Float(2.5));
        assert_eq!(parse_value("true"), Value::Boolean(true));
        assert_eq!(
            parse_value("[0.3, 0.2, 0.1]"),
            Value::Array(vec![
                Value::Float(0.3),
                Value::Float(0.2),
                Value::Float(0.1)
            ])
        );
        assert_eq!(parse_value("\"quoted\""), Value::String("quoted".into()));
        assert_eq!(parse_value("volume"), Value::String("volume".into()));
        // Text that would smuggle in a second key is a plain string.
        assert_eq!(parse_value("1\nx = 2"), Value::String("1\nx = 2".into()));
    }

    #[test]
    fn sets_nested_keys_and_array_entries() {
        let mut t = doc("[camera]\nfov_y_deg = 30\n[[light]]\nintensity = 1.0\n");
        set(&mut t, "camera.fov_y_deg", Value::Integer(35)).unwrap();
        set(&mut t, "light.0.intensity", Value::Float(2.0)).unwrap();
        set(&mut t, "strands.k", Value::Integer(8)).unwrap();
        assert_eq!(t["camera"]["fov_y_deg"], Value::Integer(35));
        assert_eq!(t["light"][0]["intensity"], Value::Float(2.0));
        assert_eq!(t["strands"]["k"], Value::Integer(8));
    }

    #[test]
    fn index_equal_to_length_appends() {
        let mut t = doc("[[light]]\nintensity = 1.0\n");
        set(&mut t, "light.1.intensity", Value::Float(0.5)).unwrap();
        assert_eq!(t["light"].as_array().unwrap().len(), 2);
        assert_eq!(t["light"][1]["intensity"], Value::Float(0.5));
        let e = set(&mut t, "light.5.intensity", Value::Float(0.5)).unwrap_err();
        assert!(e.contains("index 5 is out of range"), "{e}");
        let e = set(&mut t, "light.x.intensity", Value::Float(0.5)).unwrap_err();
        assert!(e.contains("expected an index"), "{e}");
    }

    #[test]
    fn cannot_descend_into_a_value() {
        let mut t = doc("[camera]\nfov_y_deg = 30\n");
        let e = set(&mut t, "camera.fov_y_deg.x", Value::Integer(1)).unwrap_err();
        assert!(e.contains("`camera.fov_y_deg` is a value (integer)"), "{e}");
        assert!(set(&mut t, "camera..x", Value::Integer(1)).is_err());
    }

    #[test]
    fn split_key_value() {
        assert_eq!(split(" camera.near = 2 ").unwrap(), ("camera.near", "2"));
        assert_eq!(split("a=b=c").unwrap(), ("a", "b=c"));
        assert!(split("novalue").is_err());
        assert!(split("=3").is_err());
    }
}
