//! The wgpu renderer of tress.
//!
//! The library renders into **caller-provided** color and depth views: an application creates
//! (or borrows) a [`GpuContext`], builds a [`Renderer`], uploads hair with
//! [`Renderer::upload_hair`] and a head with [`HeadGeometry::new`], then calls
//! [`Renderer::render`] every frame with its [`Targets`] and [`FrameInputs`]. `hybrid/renderer.rs`
//! shows a whole frame top to bottom; the strand technique lives in [`strands`], the
//! polygon-patch technique in [`patches`] ([`PatchRenderer`]), the volume technique in
//! [`volume`] and the strands/volume level-of-detail blend with the [`Renderer`] that draws all
//! three in [`hybrid`] ([`Renderer::set_technique`], several heads of hair in one frame:
//! [`HairObject`]).
//!
//! What a frame needs is prepared on the CPU from a scene ([`PreparedScene`]), with no GPU:
//!
//! ```
//! use tress_render::PreparedScene;
//! # fn main() -> Result<(), tress_render::RenderError> {
//! let text = r#"
//!     strands = { k = 4, alpha = 0.5 }
//!     [[hair]]
//!     generator = { style = "wavy", strands = 500, vertices = 16 }
//! "#;
//! let scene = tress_scene::Scene::from_str(text, ".")?;
//! let prepared = PreparedScene::load(&scene)?; // hair, head mesh, lights, material, settings
//! assert_eq!(prepared.hair_counts(), (500, 500 * 15)); // strands, segments
//! assert_eq!((prepared.strands.k, prepared.strands.alpha), (4, 0.5));
//! let camera = PreparedScene::camera(&scene, [640, 360]);
//! assert_eq!(camera.viewport, [640, 360]);
//! # Ok(()) }
//! ```
//!
//! Then a frame on the GPU (compiled but not run by `cargo test`, which may have no adapter):
//!
//! ```no_run
//! use tress_render::*;
//! # fn main() -> Result<(), RenderError> {
//! let ctx = GpuContext::headless()?;
//! let mut renderer = Renderer::new(&ctx, TargetFormats::default(), StrandSettings::default())?;
//! let targets = OffscreenTargets::new(&ctx, [256, 256], COLOR_FORMAT)?;
//! let camera = Camera::look_at(
//!     glam::Vec3::new(0.0, 0.0, 30.0), glam::Vec3::ZERO, glam::Vec3::Y,
//!     0.8, 0.1, 100.0, [256, 256]);
//! let inputs = FrameInputs {
//!     shared: SharedInputs {
//!         camera,
//!         lights: &[DirectionalLight::default()],
//!         ambient: glam::Vec3::splat(0.1),
//!         head: None,
//!         clear: Some(wgpu::Color::BLACK),
//!     },
//!     material: Material::default(),
//!     hair: None,
//!     objects: &[],
//! };
//! let stats = renderer.render(&ctx, &targets.targets(), &inputs)?;
//! read_texture(&ctx, &targets.color)?.save_png("frame.png")?;
//! # let _ = stats; Ok(()) }
//! ```
//!
//! Conventions: right-handed world, wgpu clip space (depth 0 near, 1 far, `Less`), linear color,
//! premultiplied alpha in the targets. Errors are typed ([`RenderError`]); nothing panics on user
//! data or in a frame.

mod bind;
mod error;
pub mod gpu;
pub mod head;
pub mod hybrid;
mod inputs;
pub mod maps;
pub mod patches;
pub mod satf;
pub mod scene_setup;
mod services;
pub mod session;
pub mod settings_doc;
pub mod shaders;
pub mod sim;
mod stats;
pub mod strands;
pub mod volume;

pub use error::RenderError;
pub use gpu::{
    COLOR_FORMAT, ContextOptions, DEPTH_FORMAT, GpuContext, LinearImage, OffscreenTargets,
    TargetFormats, Targets, Timings, read_texture,
};
pub use head::{HeadGeometry, TriMesh};
pub use hybrid::{FrameInputs, HairObject, MAX_ATTEMPTS, MAX_OBJECTS, PASS_NAMES, Renderer};
pub use hybrid::{HybridSettings, ScreenExtent, TechniqueKind, Transition};
pub use inputs::{Camera, DirectionalLight, Material, SharedInputs};
pub use patches::{
    PatchFrameInputs, PatchFrameStats, PatchGeometry, PatchRenderer, PatchSettings, RenderScheme,
};
pub use satf::{
    SatfDatabase, SatfFrameInputs, SatfFrameStats, SatfGeometry, SatfRenderer, SatfSettings,
};
pub use scene_setup::PreparedScene;
pub use settings_doc::{
    SETTING_TABLES, SettingDoc, settings_markdown, settings_reference, settings_toml,
};
pub use stats::{FrameStats, GpuReport, ObjectFrame, StatsReadback, VolumeFrame};
pub use strands::{PpllStats, Shading, StrandGeometry, StrandSettings, ThicknessFade};
pub use volume::{ShadowMode, VolumeSettings, VolumeStats, VoxelizeMode, Voxelizer};

/// The wgpu version this crate is built on, for callers that need its types.
pub use wgpu;

/// Most directional lights a frame can have (one shadow map each).
pub const MAX_LIGHTS: usize = 4;
