//! WGSL sources and their composition.
//!
//! Every `.wgsl` file of the crate is embedded here under its path relative to `src/`. A file may
//! pull in another with a line of the form
//!
//! ```text
//! #include "common/camera.wgsl"
//! ```
//!
//! [`compose`] replaces such lines by the included file's (recursively composed) text, each file
//! at most once per composed module, so shared modules can include what they need without
//! duplicate definitions. Nothing else is preprocessed: what a pass runs is plain WGSL.
//!
//! **Reloading from disk.** [`set_source_dir`] makes every pipeline created from then on read the
//! WGSL files from a folder laid out like this crate's `src/` (a checkout's, see
//! [`checkout_source_dir`]) instead of the embedded copies: a viewer rebuilds its renderers after
//! setting it to see shader edits without recompiling. Embedded sources stay the default.

use std::borrow::Cow;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::RwLock;

use crate::RenderError;

/// Every WGSL file of the crate: `(path relative to src/, source)`.
pub const SOURCES: &[(&str, &str)] = &[
    ("common/camera.wgsl", include_str!("common/camera.wgsl")),
    ("common/lights.wgsl", include_str!("common/lights.wgsl")),
    ("common/lighting.wgsl", include_str!("common/lighting.wgsl")),
    ("common/params.wgsl", include_str!("common/params.wgsl")),
    ("common/shading.wgsl", include_str!("common/shading.wgsl")),
    (
        "common/marschner.wgsl",
        include_str!("common/marschner.wgsl"),
    ),
    ("common/ppll.wgsl", include_str!("common/ppll.wgsl")),
    (
        "common/ppll_pool.wgsl",
        include_str!("common/ppll_pool.wgsl"),
    ),
    ("common/shortcut.wgsl", include_str!("common/shortcut.wgsl")),
    (
        "common/shortcut_keys.wgsl",
        include_str!("common/shortcut_keys.wgsl"),
    ),
    (
        "common/strand_fragment.wgsl",
        include_str!("common/strand_fragment.wgsl"),
    ),
    (
        "common/strand_shading.wgsl",
        include_str!("common/strand_shading.wgsl"),
    ),
    ("common/strand.wgsl", include_str!("common/strand.wgsl")),
    ("common/volume.wgsl", include_str!("common/volume.wgsl")),
    ("common/sim.wgsl", include_str!("common/sim.wgsl")),
    ("sim/sim_step.wgsl", include_str!("../sim/sim_step.wgsl")),
    (
        "sim/sim_output.wgsl",
        include_str!("../sim/sim_output.wgsl"),
    ),
    ("common/head.wgsl", include_str!("common/head.wgsl")),
    (
        "common/fullscreen.wgsl",
        include_str!("common/fullscreen.wgsl"),
    ),
    ("maps/maps.wgsl", include_str!("../maps/maps.wgsl")),
    (
        "head/head_pass.wgsl",
        include_str!("../head/head_pass.wgsl"),
    ),
    (
        "strands/shadow.wgsl",
        include_str!("../strands/shadow.wgsl"),
    ),
    (
        "strands/ppll_build.wgsl",
        include_str!("../strands/ppll_build.wgsl"),
    ),
    (
        "strands/ppll_resolve.wgsl",
        include_str!("../strands/ppll_resolve.wgsl"),
    ),
    (
        "strands/shortcut_depth.wgsl",
        include_str!("../strands/shortcut_depth.wgsl"),
    ),
    (
        "strands/shortcut_shade.wgsl",
        include_str!("../strands/shortcut_shade.wgsl"),
    ),
    (
        "strands/shortcut_resolve.wgsl",
        include_str!("../strands/shortcut_resolve.wgsl"),
    ),
    ("satf/types.wgsl", include_str!("../satf/types.wgsl")),
    ("satf/online.wgsl", include_str!("../satf/online.wgsl")),
    (
        "satf/texel_geometry.wgsl",
        include_str!("../satf/texel_geometry.wgsl"),
    ),
    (
        "satf/shadow_lookup.wgsl",
        include_str!("../satf/shadow_lookup.wgsl"),
    ),
    (
        "satf/index_calc.wgsl",
        include_str!("../satf/index_calc.wgsl"),
    ),
    (
        "satf/map_build.wgsl",
        include_str!("../satf/map_build.wgsl"),
    ),
    (
        "satf/cluster_shadow.wgsl",
        include_str!("../satf/cluster_shadow.wgsl"),
    ),
    ("satf/s_maps.wgsl", include_str!("../satf/s_maps.wgsl")),
    ("satf/lighting.wgsl", include_str!("../satf/lighting.wgsl")),
    (
        "satf/texture_map.wgsl",
        include_str!("../satf/texture_map.wgsl"),
    ),
    ("satf/head.wgsl", include_str!("../satf/head.wgsl")),
    (
        "volume/volume_bounds.wgsl",
        include_str!("../volume/volume_bounds.wgsl"),
    ),
    (
        "volume/voxelize.wgsl",
        include_str!("../volume/voxelize.wgsl"),
    ),
    (
        "volume/volume_resolve.wgsl",
        include_str!("../volume/volume_resolve.wgsl"),
    ),
    (
        "volume/ao_bake.wgsl",
        include_str!("../volume/ao_bake.wgsl"),
    ),
    (
        "volume/raymarch.wgsl",
        include_str!("../volume/raymarch.wgsl"),
    ),
    (
        "hybrid/lod_blend.wgsl",
        include_str!("../hybrid/lod_blend.wgsl"),
    ),
    (
        "patches/geometry.wgsl",
        include_str!("../patches/geometry.wgsl"),
    ),
    (
        "patches/z_prime.wgsl",
        include_str!("../patches/z_prime.wgsl"),
    ),
    (
        "patches/patch_shade.wgsl",
        include_str!("../patches/patch_shade.wgsl"),
    ),
    (
        "patches/patch_head.wgsl",
        include_str!("../patches/patch_head.wgsl"),
    ),
];

/// The modules pipelines are created from (every other file is only included).
pub const ENTRY_MODULES: &[&str] = &[
    "head/head_pass.wgsl",
    "strands/shadow.wgsl",
    "strands/ppll_build.wgsl",
    "strands/ppll_resolve.wgsl",
    "strands/shortcut_depth.wgsl",
    "strands/shortcut_shade.wgsl",
    "strands/shortcut_resolve.wgsl",
    "satf/index_calc.wgsl",
    "satf/map_build.wgsl",
    "satf/cluster_shadow.wgsl",
    "satf/s_maps.wgsl",
    "satf/lighting.wgsl",
    "satf/texture_map.wgsl",
    "satf/head.wgsl",
    "volume/volume_bounds.wgsl",
    "volume/voxelize.wgsl",
    "volume/volume_resolve.wgsl",
    "volume/ao_bake.wgsl",
    "volume/raymarch.wgsl",
    "hybrid/lod_blend.wgsl",
    "patches/z_prime.wgsl",
    "patches/patch_shade.wgsl",
    "patches/patch_head.wgsl",
    "sim/sim_step.wgsl",
    "sim/sim_output.wgsl",
];

/// The embedded source of the file at `path`, if the crate has it.
pub fn source(path: &str) -> Option<&'static str> {
    SOURCES.iter().find(|(p, _)| *p == path).map(|(_, s)| *s)
}

static SOURCE_DIR: RwLock<Option<PathBuf>> = RwLock::new(None);

/// Read WGSL from `dir` (laid out like this crate's `src/`) for pipelines created from now on,
/// or from the embedded copies again with `None`. Process-wide.
pub fn set_source_dir(dir: Option<PathBuf>) {
    if let Ok(mut d) = SOURCE_DIR.write() {
        *d = dir;
    }
}

/// The folder set with [`set_source_dir`], if any.
pub fn source_dir() -> Option<PathBuf> {
    SOURCE_DIR.read().ok().and_then(|d| d.clone())
}

/// This crate's `src/` folder when the program runs on the machine it was built on from a
/// checkout (the folder still exists and holds the shaders), else `None`.
pub fn checkout_source_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    dir.join("shaders/common/camera.wgsl")
        .is_file()
        .then_some(dir)
}

/// Where a module's file lies below the crate's `src/` (`common/` lives in `shaders/`).
fn file_below_src(path: &str) -> PathBuf {
    if path.starts_with("common/") {
        Path::new("shaders").join(path)
    } else {
        PathBuf::from(path)
    }
}

/// The source of `path`: from the folder of [`set_source_dir`] when set, else embedded.
fn current_source(module: &str, path: &str) -> Result<Cow<'static, str>, RenderError> {
    let embedded = source(path).ok_or_else(|| RenderError::Shader {
        module: module.to_string(),
        message: if module == path {
            "no such WGSL module".into()
        } else {
            format!("includes unknown module `{path}`")
        },
    })?;
    match source_dir() {
        None => Ok(Cow::Borrowed(embedded)),
        Some(dir) => {
            let file = dir.join(file_below_src(path));
            std::fs::read_to_string(&file)
                .map(Cow::Owned)
                .map_err(|e| RenderError::Shader {
                    module: path.to_string(),
                    message: format!("reading {}: {e}", file.display()),
                })
        }
    }
}

/// The composed text of the crate's module at `path` (see the module docs).
pub fn compose(path: &str) -> Result<String, RenderError> {
    let src = current_source(path, path)?;
    let mut seen = HashSet::from([path.to_string()]);
    let mut out = String::new();
    expand(path, &src, &mut seen, &mut out)?;
    Ok(out)
}

/// Compose WGSL text from outside the crate (e.g. a test harness) whose `#include` lines name the
/// crate's files.
pub fn compose_source(name: &str, src: &str) -> Result<String, RenderError> {
    let mut seen = HashSet::new();
    let mut out = String::new();
    expand(name, src, &mut seen, &mut out)?;
    Ok(out)
}

fn expand(
    name: &str,
    src: &str,
    seen: &mut HashSet<String>,
    out: &mut String,
) -> Result<(), RenderError> {
    for line in src.lines() {
        let Some(rest) = line.trim_start().strip_prefix("#include") else {
            out.push_str(line);
            out.push('\n');
            continue;
        };
        let target = rest
            .trim()
            .strip_prefix('"')
            .and_then(|r| r.strip_suffix('"'))
            .ok_or_else(|| RenderError::Shader {
                module: name.to_string(),
                message: format!("malformed include line `{line}`"),
            })?;
        if !seen.insert(target.to_string()) {
            continue;
        }
        let inc = current_source(name, target)?;
        out.push_str(&format!("// ---- begin {target}\n"));
        expand(target, &inc, seen, out)?;
        out.push_str(&format!("// ---- end {target}\n"));
    }
    Ok(())
}

/// Create a shader module from a composed crate module, labelled `label`.
pub(crate) fn create_module(
    ctx: &crate::GpuContext,
    path: &str,
    label: &str,
) -> Result<wgpu::ShaderModule, RenderError> {
    let text = compose(path)?;
    ctx.scoped(&format!("compiling {path}"), || {
        ctx.device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(text.into()),
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn includes_are_expanded_once() {
        let text = compose_source(
            "test",
            "#include \"common/camera.wgsl\"\n#include \"common/camera.wgsl\"\nfn f() {}\n",
        )
        .expect("composes");
        assert_eq!(text.matches("// ---- begin common/camera.wgsl").count(), 1);
        assert!(text.ends_with("fn f() {}\n"));
    }

    #[test]
    fn unknown_and_malformed_includes_are_errors() {
        let e = compose_source("t", "#include \"nope.wgsl\"\n").expect_err("unknown");
        assert!(e.to_string().contains("nope.wgsl"));
        assert!(compose_source("t", "#include nope\n").is_err());
        assert!(compose("missing.wgsl").is_err());
    }

    #[test]
    fn every_embedded_file_is_found_in_the_checkout() {
        let dir = checkout_source_dir().expect("tests run from the checkout");
        for (path, text) in SOURCES {
            let file = dir.join(file_below_src(path));
            let on_disk = std::fs::read_to_string(&file)
                .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            assert_eq!(on_disk, *text, "{path}");
        }
    }

    #[test]
    fn a_source_folder_replaces_the_embedded_text_until_reset() {
        let src = checkout_source_dir().unwrap();
        let dir = std::env::temp_dir().join(format!("tress-shaders-{}", std::process::id()));
        for (path, _) in SOURCES {
            let to = dir.join(file_below_src(path));
            std::fs::create_dir_all(to.parent().unwrap()).unwrap();
            std::fs::copy(src.join(file_below_src(path)), &to).unwrap();
        }
        let camera = dir.join("shaders/common/camera.wgsl");
        let mut text = std::fs::read_to_string(&camera).unwrap();
        text.push_str("// edited on disk\n");
        std::fs::write(&camera, text).unwrap();
        set_source_dir(Some(dir.clone()));
        let edited = compose("head/head_pass.wgsl");
        std::fs::remove_file(dir.join("hybrid/lod_blend.wgsl")).unwrap();
        let missing = compose("hybrid/lod_blend.wgsl");
        set_source_dir(None);
        assert!(edited.unwrap().contains("// edited on disk"));
        let e = missing.unwrap_err().to_string();
        assert!(e.contains("lod_blend.wgsl"), "{e}");
        assert!(
            !compose("head/head_pass.wgsl")
                .unwrap()
                .contains("// edited on disk")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn every_listed_module_exists_and_composes() {
        for path in ENTRY_MODULES {
            let text = compose(path).expect("composes");
            assert!(!text.contains("#include"), "{path}");
        }
    }
}
