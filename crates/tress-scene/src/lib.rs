//! Scene files for tress: camera, lights, hair assets, head mesh and technique settings.
//!
//! A scene is a TOML file read with [`Scene::from_path`] (or [`Scene::from_str`] with the folder
//! that relative paths resolve against). Every key has a default, so an empty file is a valid
//! scene: a grey background, a camera framing the default head, a warm key light and a cool fill
//! light, the generated head, no hair, 1280 × 720, the `strands` technique.
//!
//! ```
//! use tress_scene::Scene;
//!
//! let text = r#"
//!     technique = "volume"
//!     [[hair]]
//!     generator = { style = "curly", strands = 200 }
//! "#;
//! let mut scene = Scene::from_str(text, ".")?; // "." : where relative paths resolve
//! scene.apply_override("hair.0.generator.vertices=16")?;
//! let hair = scene.load_hair()?;
//! assert_eq!((hair[0].strand_count(), hair[0].vertex_count()), (200, 3200));
//!
//! let error = Scene::from_str("[camera]\nfov = 35\n", ".").unwrap_err();
//! assert!(error.to_string().contains("unknown field `fov`"));
//! # Ok::<(), tress_scene::SceneError>(())
//! ```
//!
//! - **Unknown keys are errors** that name the key and its line:
//!   `scene.toml: line 4, column 1: unknown field `fov`, expected one of `eye`, ...`. Values are
//!   then range-checked ([`Scene::validate`]); those errors name the dotted key
//!   (`hair.0.strand_ratio: must lie in (0, 1], got 2`). Every message is a single line.
//! - **Overrides** `--set key=value` ([`Scene::apply_override`]) address any value by its dotted
//!   key, with array indices for `[[light]]` and `[[hair]]`: `camera.fov_y_deg=35`, `strands.k=8`,
//!   `light.0.intensity=2`, `hair.0.material.base_color=[0.3,0.2,0.1]`,
//!   `hair.0.generator.strands=5000`. The value is parsed as TOML, or taken as a string when it is
//!   not TOML (`technique=volume`). Missing tables are created, and the index one past the end of
//!   an array appends an entry. The result is checked exactly like a file: unknown keys and bad
//!   values are errors that name the override.
//! - **Technique tables** (`[strands]`, `[volume]`, `[hybrid]`, `[patches]`, `[satf]`, see
//!   [`TECHNIQUES`]) are kept as free TOML tables; each technique reads its own with
//!   [`Scene::technique_settings`] into a `#[serde(deny_unknown_fields, default)]` struct and gets
//!   the same key-and-line errors.
//! - **Hair** entries read files (`files = [...]`, merged) or run a generator
//!   (`generator = { style = "curly", ... }`, absent fields at the style's defaults), then add
//!   follow hairs, keep a `strand_ratio` subset and apply a transform: [`Scene::load_hair`].
//! - [`Scene::to_toml_string`] writes a scene that reads back equal.
//!
//! # Reference: the defaults
//!
//! Every top-level key and table at its default value:
//!
#![doc = concat!("```toml\n", include_str!("../doc/defaults.toml"), "```")]
//!
//! One `[[hair]]` entry with every field (the material values are the defaults):
//!
#![doc = concat!("```toml\n", include_str!("../doc/hair.toml"), "```")]

mod error;
mod follow;
mod material;
mod overrides;
mod parts;
mod scene;
mod technique;

pub use error::SceneError;
pub use material::{DEFAULT_EUMELANIN, DEFAULT_PHEOMELANIN, Material};
pub use parts::{Camera, FollowSpec, GeneratorSpec, HairSpec, HeadSpec, Light, Output, Transform};
pub use scene::{DEFAULT_AMBIENT, GeneratedHead, HeadSource, Scene};
pub use technique::{TECHNIQUES, TechniqueKind, UnknownTechnique};

#[cfg(test)]
mod tests;
