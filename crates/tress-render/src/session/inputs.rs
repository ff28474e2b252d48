//! From command-line inputs (nothing, a scene file, hair files or a hair-card OBJ) to a
//! [`Scene`]: shared by `tress render`, `tress bench` and the viewer's file dialog and drops.

use std::path::{Path, PathBuf};

use tress_scene::{HairSpec, Scene};

use crate::RenderError;
use crate::patches::scene::is_obj;

/// The built-in demo (`scenes/demo.toml`): the generated ponytail on the generated head, at 10%
/// of the paper's strand count so that a CPU Vulkan renders it in seconds.
pub const DEMO_SCENE: &str = include_str!("../../../../scenes/demo.toml");

/// An invalid-input error with its message (errors from other crates convert with `?`).
fn invalid(message: impl Into<String>) -> RenderError {
    RenderError::Invalid(message.into())
}

fn is_scene(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// The scene the inputs describe, and whether its camera should be framed on what it loads
/// (hair or card files carry no camera): nothing is the demo, one `.toml` is a scene, one `.obj`
/// is a hair-card mesh for the `patches` technique, anything else is hair files merged with
/// default lights and no head.
pub fn scene_from_inputs(inputs: &[PathBuf]) -> Result<(Scene, bool), RenderError> {
    match inputs {
        [] => Ok((Scene::from_str(DEMO_SCENE, ".")?, false)),
        [one] if is_scene(one) => Ok((Scene::from_path(one)?, false)),
        many if many.iter().any(|p| is_scene(p)) => Err(invalid(
            "give either one scene file or hair files, not both",
        )),
        [one] if is_obj(one) => {
            let mut scene =
                Scene::from_str("technique = \"patches\"\n[head]\ngenerated = false\n", ".")?;
            // A TOML basic string: backslashes and quotes escaped.
            let path = one
                .to_str()
                .filter(|p| !p.chars().any(char::is_control))
                .ok_or_else(|| invalid(format!("{}: unusable file name", one.display())))?
                .replace('\\', "\\\\")
                .replace('"', "\\\"");
            scene.apply_override(&format!("patches.obj=\"{path}\""))?;
            Ok((scene, true))
        }
        many if many.iter().any(|p| is_obj(p)) => Err(invalid("give one hair-card OBJ file alone")),
        files => {
            let mut scene = Scene::from_str("[head]\ngenerated = false\n", ".")?;
            scene.hair = vec![HairSpec {
                files: files.to_vec(),
                ..HairSpec::default()
            }];
            Ok((scene, true))
        }
    }
}
