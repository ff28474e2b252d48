//! The R key: WGSL read again from a checkout, and the session rebuilt on it.
//!
//! [`tress_render::shaders::set_source_dir`] makes every pipeline created from then on read its
//! WGSL from a folder laid out like the renderer's `src/` instead of the copies built into the
//! binary. R points it at a checkout's `crates/tress-render/src` and rebuilds the session, so
//! every pipeline is compiled again from the files on disk: shader edits show without
//! recompiling. A shader that does not compile leaves the running session as it was and shows
//! the error; fixing the file and pressing R again retries. The checkout is the one under
//! [`SOURCE_DIR_ENV`], else the first folder from the working directory upwards that holds one,
//! else the folder the binary was built from, if it is still there
//! ([`tress_render::shaders::checkout_source_dir`]). Without any, R rebuilds the session from
//! the built-in WGSL.

use std::path::{Path, PathBuf};

/// Environment variable: the repository root whose `crates/tress-render/src` R reads WGSL from.
pub const SOURCE_DIR_ENV: &str = "TRESS_SOURCE_DIR";

/// The renderer's source folder inside a checkout.
const RENDER_SRC: &str = "crates/tress-render/src";

/// The renderer's source folder R reads from (see the module docs).
pub(crate) fn find_checkout() -> Option<PathBuf> {
    let is_src = |root: &Path| {
        let src = root.join(RENDER_SRC);
        src.join("shaders").join("mod.rs").is_file().then_some(src)
    };
    if let Some(root) = std::env::var_os(SOURCE_DIR_ENV).filter(|v| !v.is_empty()) {
        return is_src(Path::new(&root));
    }
    std::env::current_dir()
        .ok()
        .and_then(|cwd| cwd.ancestors().find_map(is_src))
        .or_else(tress_render::shaders::checkout_source_dir)
}

/// Where the file `path` of `SOURCES` lies below a renderer `src/` folder (`common/` is in
/// `shaders/`).
fn file_below_src(src: &Path, path: &str) -> PathBuf {
    if path.starts_with("common/") {
        src.join("shaders").join(path)
    } else {
        src.join(path)
    }
}

/// The built-in WGSL files whose copy under `src` differs or is missing.
pub(crate) fn changed_shaders(src: &Path) -> Vec<&'static str> {
    tress_render::shaders::SOURCES
        .iter()
        .filter(|(path, built_in)| {
            std::fs::read_to_string(file_below_src(src, path))
                .ok()
                .as_deref()
                != Some(*built_in)
        })
        .map(|(path, _)| *path)
        .collect()
}

/// The status line after R rebuilt the session from `checkout` (or the built-in WGSL).
pub(crate) fn report(checkout: Option<&Path>) -> String {
    let Some(src) = checkout else {
        return format!(
            "R: session rebuilt from the built-in WGSL (no checkout found: run from one or set \
             {SOURCE_DIR_ENV})"
        );
    };
    let changed = changed_shaders(src);
    let edits = if changed.is_empty() {
        "same as the built-in WGSL".to_string()
    } else {
        let shown: Vec<&str> = changed.iter().take(4).copied().collect();
        format!(
            "{} file(s) differ from the built-in WGSL: {}{}",
            changed.len(),
            shown.join(", "),
            if changed.len() > shown.len() {
                ", ..."
            } else {
                ""
            }
        )
    };
    format!(
        "R: WGSL read from {} ({edits}), session rebuilt",
        src.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changed_shaders_compares_a_folder_with_the_built_in_wgsl() {
        let src = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(RENDER_SRC);
        // A copy of the built-in files is unchanged; an edit and a missing file are named.
        let dir = std::env::temp_dir().join(format!("tress-viewer-reload-{}", std::process::id()));
        for (path, text) in tress_render::shaders::SOURCES {
            let file = file_below_src(&dir, path);
            std::fs::create_dir_all(file.parent().unwrap()).unwrap();
            std::fs::write(&file, text).unwrap();
        }
        assert!(changed_shaders(&dir).is_empty());
        assert!(report(Some(&dir)).contains("same as the built-in"));
        std::fs::write(file_below_src(&dir, "common/camera.wgsl"), "// edited\n").unwrap();
        std::fs::remove_file(file_below_src(&dir, "hybrid/lod_blend.wgsl")).unwrap();
        assert_eq!(
            changed_shaders(&dir),
            vec!["common/camera.wgsl", "hybrid/lod_blend.wgsl"]
        );
        assert!(report(Some(&dir)).contains("2 file(s) differ"));
        assert!(report(None).contains(SOURCE_DIR_ENV));
        std::fs::remove_dir_all(&dir).unwrap();
        // The checkout this test runs in has every file where the renderer looks for it.
        for (path, _) in tress_render::shaders::SOURCES {
            assert!(file_below_src(&src, path).is_file(), "{path}");
        }
    }
}
