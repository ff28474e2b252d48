//! One scene, drawn with any of the five techniques: what the benchmarks and the viewer render
//! through, so that they have no rendering logic of their own.
//!
//! A [`Session`] loads a [`Scene`] once (hair, head, lights), uploads what the current technique
//! needs on first use and keeps it while other techniques are tried: the strand renderer
//! ([`crate::Renderer`]) draws `strands`, `volume`, `hybrid` and `auto`, every `[[hair]]` entry
//! as a head of hair of its own ([`crate::HairObject`], with its material and technique: a
//! scene of several characters), [`crate::PatchRenderer`] draws `patches` and
//! [`crate::SatfRenderer`] draws `satf` (every entry merged). Settings change by the scene's
//! dotted names ([`Session::set`]), and every frame reports its per-pass GPU times and a
//! [`Memory`] breakdown.
//!
//! A frame: the session decides what every technique shares (the camera, the lights, the
//! ambient light, the head, the clear colour, the prepared scene: `technique::SharedFrame`) and
//! hands it to the current technique through one trait (`technique::Technique::draw`), which
//! each technique implements in its own folder with only its own state (`hybrid/technique.rs`,
//! `patches/technique.rs`, `satf/technique.rs`).
//!
//! ```no_run
//! use tress_render::session::{Session, SessionOptions, scene_from_inputs};
//! use tress_render::*;
//! # fn main() -> Result<(), RenderError> {
//! let ctx = GpuContext::headless()?;
//! let (scene, auto_frame) = scene_from_inputs(&[])?; // the built-in demo
//! let options = SessionOptions { auto_frame, ..Default::default() };
//! let mut session = Session::new(&ctx, TargetFormats::default(), scene, options)?;
//! session.set_technique(&ctx, "volume")?;
//! let targets = OffscreenTargets::new(&ctx, [640, 360], COLOR_FORMAT)?;
//! let camera = session.camera([640, 360]);
//! let frame = session.render(&ctx, &targets.targets(), &camera, None)?;
//! println!("{} MiB", frame.memory.total() >> 20);
//! # Ok(()) }
//! ```

mod inputs;
mod memory;
mod simulation;
pub(crate) mod technique;

use std::time::Instant;

use glam::Vec3;
use tress_scene::Scene;

pub use inputs::{DEMO_SCENE, scene_from_inputs};

use crate::hybrid::StrandTechnique;
use crate::patches::PatchTechnique;
use crate::satf::SatfTechnique;
pub use memory::Memory;
pub use simulation::{SessionSimulation, SimulationFrame};
use technique::{SharedFrame, Technique, TechniqueFrame};

use crate::patches::scene::{PatchScene, patch_settings};
use crate::satf::scene::SatfScene;
use crate::scene_setup::{PreparedHair, PreparedScene, frame_bounds};
use crate::{
    Camera, DirectionalLight, FrameStats, GpuContext, HeadGeometry, LinearImage, PatchFrameStats,
    RenderError, SatfDatabase, SatfFrameStats, SatfGeometry, SharedInputs, StatsReadback,
    TargetFormats, Targets, Timings, TriMesh,
};

/// The techniques a session draws, in the order the viewer cycles them (the names of
/// [`tress_scene::TechniqueKind::ALL`]).
pub use tress_scene::{TECHNIQUES, TechniqueKind};

/// Constant ambient light of every technique's shading (linear RGB per channel) of a scene that
/// does not set `ambient`.
pub const AMBIENT: f32 = tress_scene::DEFAULT_AMBIENT;

/// Finds the SATF database for a scene's `[satf]` settings (the CLI's loads the file or its
/// cache, baking it on first use). The error is one line.
pub type DatabaseLoader = Box<
    dyn FnMut(&SatfScene) -> Result<tress_satf::Database, Box<dyn std::error::Error + Send + Sync>>,
>;

/// How a [`Session`] is built.
#[derive(Default)]
pub struct SessionOptions {
    /// Frame the camera on the loaded hair or cards (inputs without a camera of their own).
    pub auto_frame: bool,
    /// Dotted `key=value` overrides applied to the scene before loading, and again after
    /// framing (so they win over it).
    pub overrides: Vec<String>,
    /// The SATF database source; without one the `satf` technique reports that it needs one.
    pub satf_database: Option<DatabaseLoader>,
    /// How GPU statistics are read back (default wait: each frame reports its own).
    pub readback: StatsReadback,
}

impl std::fmt::Debug for SessionOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SessionOptions")
            .field("auto_frame", &self.auto_frame)
            .field("overrides", &self.overrides)
            .field("satf_database", &self.satf_database.is_some())
            .field("readback", &self.readback)
            .finish()
    }
}

/// What one technique reported about a frame.
#[derive(Clone, Debug, PartialEq)]
pub enum FrameDetail {
    /// `strands`, `volume`, `hybrid` or `auto` (each head of hair's in `objects`).
    Strands(FrameStats),
    /// `patches`.
    Patches(PatchFrameStats),
    /// `satf`.
    Satf(SatfFrameStats),
}

/// What [`Session::render`] returns.
#[derive(Clone, Debug, PartialEq)]
pub struct SessionFrame {
    /// The technique that drew the frame.
    pub technique: &'static str,
    /// Target size in pixels.
    pub size: [u32; 2],
    /// Per-pass GPU times (`None` until the first results arrive with deferred readback).
    pub timings: Option<Timings>,
    /// CPU wall time of the `render` call (encoding, submission and, with waiting readback, the
    /// GPU's work), milliseconds.
    pub wall_ms: f64,
    /// GPU memory this frame's technique uses (pools of other techniques drawn before by the
    /// same renderer are not counted).
    pub memory: Memory,
    /// The technique's own statistics.
    pub detail: FrameDetail,
}

/// What the `satf` technique was prepared with (see [`Session::satf`]).
#[derive(Clone, Copy, Debug)]
pub struct SatfInfo<'a> {
    /// The scene's `[satf]` settings.
    pub settings: &'a SatfScene,
    /// The clusters uploaded (their counts: [`SatfGeometry::stats`]).
    pub geometry: &'a SatfGeometry,
    /// The HRIR database uploaded.
    pub database: &'a SatfDatabase,
    /// CPU milliseconds spent fitting or generating the clusters.
    pub clusters_ms: f64,
}

/// A scene loaded for rendering with any technique (see the module docs).
pub struct Session {
    formats: TargetFormats,
    scene: Scene,
    prepared: PreparedScene,
    head: Option<HeadGeometry>,
    technique: TechniqueKind,
    strands: Option<StrandTechnique>,
    patches: Option<PatchTechnique>,
    satf: Option<SatfTechnique>,
    loader: Option<DatabaseLoader>,
    readback: StatsReadback,
    hair_visible: bool,
    /// The hair and head were given by the application ([`Session::with_hair`]), not loaded
    /// from the scene.
    given: bool,
    /// The hair's simulation, when one runs ([`Session::start_simulation`]).
    simulation: Option<SessionSimulation>,
    /// Clear the color target's alpha to 0 rather than 1 ([`Session::set_transparent_background`]).
    transparent: bool,
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session")
            .field("technique", &self.technique)
            .field("strands", &self.strands.is_some())
            .field("patches", &self.patches.is_some())
            .field("satf", &self.satf.is_some())
            .finish_non_exhaustive()
    }
}

/// An invalid-input error with its message (errors from other crates convert with `?`).
fn invalid(message: impl Into<String>) -> RenderError {
    RenderError::Invalid(message.into())
}

/// The name in [`TECHNIQUES`] of a technique, or an error listing them.
pub fn technique_name(name: &str) -> Result<&'static str, RenderError> {
    technique_kind(name).map(TechniqueKind::name)
}

/// The technique of a name, or an error listing them.
pub fn technique_kind(name: &str) -> Result<TechniqueKind, RenderError> {
    name.parse().map_err(|_| {
        invalid(format!(
            "unknown technique `{name}` (available: {})",
            TECHNIQUES.join(", ")
        ))
    })
}

/// Load a scene's hair, head and settings, framing the camera on the hair when asked.
fn load_scene(
    mut scene: Scene,
    auto_frame: bool,
    overrides: &[String],
) -> Result<(Scene, PreparedScene), RenderError> {
    scene.apply_overrides(overrides)?;
    technique_name(&scene.technique)?;
    let mut prepared = PreparedScene::load(&scene)?;
    if let (true, Some(b)) = (auto_frame, prepared.hair_bounds()) {
        frame_bounds(&mut scene, b.min, b.max);
        scene.apply_overrides(overrides)?;
        prepared = prepared.reload_settings(&scene)?;
    }
    Ok((scene, prepared))
}

impl Session {
    /// Load `scene` (see [`SessionOptions`]) and upload what its technique needs.
    pub fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        scene: Scene,
        options: SessionOptions,
    ) -> Result<Session, RenderError> {
        let (scene, prepared) = load_scene(scene, options.auto_frame, &options.overrides)?;
        Self::assemble(ctx, formats, scene, prepared, options, false)
    }

    /// A session over hair and a head the application holds in memory (its own assets, as in
    /// `examples/embed.rs`): each of `hair` is a character, `head` the opaque mesh; `scene`
    /// gives the technique, settings, lights, camera and background (its `[[hair]]` and
    /// `[head]` are not read). [`Session::set`] on a key that would reload hair or head from the
    /// scene is refused.
    pub fn with_hair(
        ctx: &GpuContext,
        formats: TargetFormats,
        mut scene: Scene,
        hair: Vec<PreparedHair>,
        head: Option<TriMesh>,
        options: SessionOptions,
    ) -> Result<Session, RenderError> {
        scene.apply_overrides(&options.overrides)?;
        technique_name(&scene.technique)?;
        // The head is the given mesh (the cards' sort centre is its bounding sphere's).
        scene.head = tress_scene::HeadSpec {
            generated: Some(false),
            ..Default::default()
        };
        let settings = PreparedScene::load_settings(&scene)?;
        // The first character's material gives the head its colour (as a loaded scene's does).
        let material = hair.first().map_or(settings.material, |h| h.material);
        let mut prepared = PreparedScene {
            material,
            objects: hair,
            head,
            ..settings
        };
        if let (true, Some(b)) = (options.auto_frame, prepared.hair_bounds()) {
            frame_bounds(&mut scene, b.min, b.max);
            scene.apply_overrides(&options.overrides)?;
            prepared = PreparedScene {
                material,
                ..prepared.reload_settings(&scene)?
            };
        }
        Self::assemble(ctx, formats, scene, prepared, options, true)
    }

    /// The session over a loaded scene: the head uploaded and the technique prepared.
    fn assemble(
        ctx: &GpuContext,
        formats: TargetFormats,
        scene: Scene,
        prepared: PreparedScene,
        options: SessionOptions,
        given: bool,
    ) -> Result<Session, RenderError> {
        let head = prepared
            .head
            .as_ref()
            .map(|m| HeadGeometry::new(ctx, m))
            .transpose()?;
        let technique = technique_kind(&scene.technique)?;
        let mut session = Session {
            formats,
            scene,
            prepared,
            head,
            technique,
            strands: None,
            patches: None,
            satf: None,
            loader: options.satf_database,
            readback: options.readback,
            hair_visible: true,
            given,
            simulation: None,
            transparent: false,
        };
        session.prepare(ctx)?;
        // Cards without hair (an OBJ) are framed on the cards.
        if let (true, true, Some(p)) = (
            options.auto_frame,
            session.prepared.objects.is_empty(),
            &session.patches,
        ) && let Some(b) = p.scene.mesh.bounds()
        {
            frame_bounds(&mut session.scene, b.min, b.max);
            session.scene.apply_overrides(&options.overrides)?;
        }
        Ok(session)
    }

    /// The scene as loaded and changed by [`Session::set`].
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The loaded hair, head, lights and settings.
    pub fn prepared(&self) -> &PreparedScene {
        &self.prepared
    }

    /// The current technique (one of [`TECHNIQUES`]).
    pub fn technique(&self) -> &'static str {
        self.technique.name()
    }

    /// The current technique.
    pub fn technique_kind(&self) -> TechniqueKind {
        self.technique
    }

    /// The scene's camera for a target of `size` pixels.
    pub fn camera(&self, size: [u32; 2]) -> Camera {
        PreparedScene::camera(&self.scene, size)
    }

    /// The scene's lights.
    pub fn lights(&self) -> &[DirectionalLight] {
        &self.prepared.lights
    }

    /// Switch technique for every head of hair (each `[[hair]]` entry's own `technique` is
    /// dropped: [`Scene::force_technique`]), uploading what it needs on first use. On error the
    /// technique is unchanged.
    pub fn set_technique(&mut self, ctx: &GpuContext, name: &str) -> Result<(), RenderError> {
        let kind = technique_kind(name)?;
        let old = (
            self.technique,
            self.prepared
                .objects
                .iter()
                .map(|o| o.technique)
                .collect::<Vec<_>>(),
        );
        self.technique = kind;
        for o in &mut self.prepared.objects {
            o.technique = kind;
        }
        if let Err(e) = self.prepare(ctx) {
            self.technique = old.0;
            for (o, t) in self.prepared.objects.iter_mut().zip(old.1) {
                o.technique = t;
            }
            return Err(e);
        }
        self.scene.force_technique(kind.name())?;
        Ok(())
    }

    /// Change a setting by its dotted scene name (`strands.k=8`, `volume.steps=128`,
    /// `light.0.intensity=2`, `technique="volume"`, ...). Technique settings apply to the live
    /// renderers; patch, SATF, hair and head settings rebuild what depends on them. On error
    /// nothing changes.
    pub fn set(&mut self, ctx: &GpuContext, key_value: &str) -> Result<(), RenderError> {
        let mut scene = self.scene.clone();
        scene.apply_override(key_value)?;
        let key = key_value.split('=').next().unwrap_or("").trim();
        let root = key.split('.').next().unwrap_or("");
        match root {
            "camera" | "output" => {
                self.scene = scene;
                Ok(())
            }
            "technique" => {
                let t = scene.technique.clone();
                self.set_technique(ctx, &t)
            }
            _ if is_light_key(key) => {
                let prepared = PreparedScene::load_settings(&scene)?;
                if key.contains(".material.") {
                    // SATF reads the hair colour into its lighting settings.
                    self.satf = None;
                    // The patches take their highlight constants and fibre from the material.
                    if let Some(p) = &mut self.patches {
                        let first = scene.hair.first().map(|_| &prepared.material);
                        p.renderer
                            .set_settings(ctx, patch_settings(&scene, first)?)?;
                    }
                }
                if let Some(s) = &mut self.strands {
                    s.renderer.apply_settings(ctx, &prepared)?;
                }
                for (o, spec) in self.prepared.objects.iter_mut().zip(&scene.hair) {
                    o.material = crate::scene_setup::hair_material(&spec.material)?;
                }
                self.prepared.lights = prepared.lights;
                self.prepared.material = prepared.material;
                self.prepared.background = prepared.background;
                self.prepared.ambient = prepared.ambient;
                self.prepared.strands = prepared.strands;
                self.prepared.volume = prepared.volume;
                self.prepared.hybrid = prepared.hybrid;
                self.scene = scene;
                Ok(())
            }
            "patches" | "satf" => {
                // Drop what the table builds; `prepare` rebuilds it now if it is drawn.
                let patches = if root == "patches" {
                    self.patches.take()
                } else {
                    None
                };
                let satf = if root == "satf" {
                    self.satf.take()
                } else {
                    None
                };
                let old = std::mem::replace(&mut self.scene, scene);
                if let Err(e) = self.prepare(ctx) {
                    self.scene = old;
                    self.patches = self.patches.take().or(patches);
                    self.satf = self.satf.take().or(satf);
                    return Err(e);
                }
                Ok(())
            }
            _ if self.given => Err(invalid(format!(
                "{key}: this session's hair and head were given by the application \
                 (Session::with_hair); they are not loaded from the scene"
            ))),
            _ => {
                // Hair, head, materials: load everything again.
                let (scene, prepared) = load_scene(scene, false, &[])?;
                let head = prepared
                    .head
                    .as_ref()
                    .map(|m| HeadGeometry::new(ctx, m))
                    .transpose()?;
                let old = (
                    std::mem::replace(&mut self.scene, scene),
                    std::mem::replace(&mut self.prepared, prepared),
                    std::mem::replace(&mut self.head, head),
                    self.strands.take(),
                    self.patches.take(),
                    self.satf.take(),
                );
                if let Err(e) = self.prepare(ctx) {
                    (
                        self.scene,
                        self.prepared,
                        self.head,
                        self.strands,
                        self.patches,
                        self.satf,
                    ) = old;
                    return Err(e);
                }
                Ok(())
            }
        }
    }

    /// Upload what the current technique needs, if not yet there.
    fn prepare(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        match self.technique {
            TechniqueKind::Patches if self.patches.is_none() => {
                self.patches = Some(PatchTechnique::new(
                    ctx,
                    self.formats,
                    &self.scene,
                    &self.prepared,
                    self.readback,
                )?);
            }
            TechniqueKind::Satf if self.satf.is_none() => {
                self.satf = Some(SatfTechnique::new(
                    ctx,
                    self.formats,
                    (&self.scene, &self.prepared),
                    self.loader.as_mut(),
                    self.readback,
                )?);
            }
            TechniqueKind::Strands
            | TechniqueKind::Volume
            | TechniqueKind::Hybrid
            | TechniqueKind::Auto => {
                if self.strands.is_none() {
                    self.strands = Some(StrandTechnique::new(
                        ctx,
                        self.formats,
                        &self.prepared,
                        self.readback,
                    )?);
                }
                if let Some(s) = &mut self.strands {
                    s.renderer.set_technique(self.technique)?;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The SATF settings in use, once the `satf` technique has been prepared.
    pub fn satf_settings(&self) -> Option<&SatfScene> {
        self.satf.as_ref().map(|s| &s.settings)
    }

    /// What the `satf` technique was prepared with, once it has been.
    pub fn satf(&self) -> Option<SatfInfo<'_>> {
        self.satf.as_ref().map(|s| SatfInfo {
            settings: &s.settings,
            geometry: &s.geometry,
            database: &s.database,
            clusters_ms: s.clusters_ms,
        })
    }

    /// The hair cards, once the `patches` technique has been prepared.
    pub fn patch_scene(&self) -> Option<&PatchScene> {
        self.patches.as_ref().map(|p| &p.scene)
    }

    /// Move the hair's vertices to those of `asset` (animated hair: same strands and vertex
    /// counts as the loaded hair). The strands, volume and hybrid techniques draw the moved hair
    /// from the next frame on, the volume voxelized again; the other techniques keep what they
    /// built from the loaded hair, so this is an error while one of them is current.
    pub fn update_hair_positions(
        &mut self,
        ctx: &GpuContext,
        asset: &tress_hair::HairAsset,
    ) -> Result<(), RenderError> {
        if !self.technique.draws_strands() {
            return Err(invalid(format!(
                "moving hair is drawn by the strands, volume and hybrid techniques, not `{}`",
                self.technique
            )));
        }
        self.prepare(ctx)?;
        let Some(s) = self.strands.as_mut().filter(|s| !s.hair.is_empty()) else {
            return Err(invalid("the scene has no hair to move"));
        };
        if let [only] = s.hair.as_mut_slice() {
            return only.update_positions(ctx, asset);
        }
        // Several heads of hair: each takes its entry's strands of the merged asset.
        let counts: Vec<usize> = s.hair.iter().map(|g| g.strand_count() as usize).collect();
        if counts.iter().sum::<usize>() != asset.strand_count() {
            return Err(invalid(format!(
                "update_hair_positions: the asset has {} strands, the scene's hair {}",
                asset.strand_count(),
                counts.iter().sum::<usize>()
            )));
        }
        let mut first = 0;
        for (geometry, n) in s.hair.iter_mut().zip(counts) {
            geometry.update_positions(ctx, &asset.strand_span(first..first + n)?)?;
            first += n;
        }
        Ok(())
    }

    /// Turn `image`, the last strand frame read back, into that frame as exact sorted
    /// compositing draws it ([`crate::strands::PpllFragments::sort_exactly`] with the PPLL's
    /// lists). False (and `image` unchanged) when no strand frame was drawn with the PPLL; the
    /// caller checks that the frame lost nothing.
    pub fn sort_exactly(
        &self,
        ctx: &GpuContext,
        image: &mut LinearImage,
    ) -> Result<bool, RenderError> {
        let Some(path) = &self.strands else {
            return Ok(false);
        };
        let Some(lists) = path.renderer.ppll_fragments(ctx)? else {
            return Ok(false);
        };
        lists.sort_exactly(image, self.prepared.strands.k as usize);
        Ok(true)
    }

    /// Draw the hair (default) or only the head and background: the bare frame against which
    /// the hair's screen coverage is measured.
    pub fn set_hair_visible(&mut self, visible: bool) {
        self.hair_visible = visible;
    }

    /// How GPU statistics are read back from now on.
    pub fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.readback = mode;
        let prepared: [Option<&mut dyn Technique>; 3] = [
            self.strands.as_mut().map(|t| t as &mut dyn Technique),
            self.patches.as_mut().map(|t| t as &mut dyn Technique),
            self.satf.as_mut().map(|t| t as &mut dyn Technique),
        ];
        for t in prepared.into_iter().flatten() {
            t.set_stats_readback(mode);
        }
    }

    /// Clear the color target's alpha to 0 (`true`) instead of 1, so that after a frame the
    /// alpha channel holds the coverage of the hair and the head (every pass blends
    /// premultiplied), while the color channels still show them over the scene's background.
    pub fn set_transparent_background(&mut self, transparent: bool) {
        self.transparent = transparent;
    }

    /// Render one frame with the current technique into `targets` (cleared to the scene's
    /// background) from `camera`, with `lights` or the scene's.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        camera: &Camera,
        lights: Option<&[DirectionalLight]>,
    ) -> Result<SessionFrame, RenderError> {
        self.prepare(ctx)?;
        let kind = self.technique;
        let frame = SharedFrame {
            shared: SharedInputs {
                camera: *camera,
                lights: lights.unwrap_or(&self.prepared.lights),
                ambient: Vec3::splat(self.prepared.ambient),
                head: self.head.as_ref(),
                clear: self.prepared.clear_color().map(|c| wgpu::Color {
                    a: if self.transparent { 0.0 } else { c.a },
                    ..c
                }),
            },
            prepared: &self.prepared,
            hair_visible: self.hair_visible,
            kind,
        };
        let technique: Option<&mut dyn Technique> = match kind {
            TechniqueKind::Patches => self.patches.as_mut().map(|t| t as &mut dyn Technique),
            TechniqueKind::Satf => self.satf.as_mut().map(|t| t as &mut dyn Technique),
            _ => self.strands.as_mut().map(|t| t as &mut dyn Technique),
        };
        let technique =
            technique.ok_or_else(|| invalid(format!("the {kind} technique is not prepared")))?;
        let start = Instant::now();
        let result = technique.draw(ctx, targets, &frame);
        let TechniqueFrame {
            timings,
            memory,
            detail,
        } = result?;
        Ok(SessionFrame {
            technique: self.technique.name(),
            size: [camera.viewport[0], camera.viewport[1]],
            timings,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
            memory,
            detail,
        })
    }
}

/// Whether a dotted key only changes settings, lights or materials (no reload).
fn is_light_key(key: &str) -> bool {
    let root = key.split('.').next().unwrap_or("");
    matches!(
        root,
        "strands" | "volume" | "hybrid" | "light" | "lights" | "background" | "ambient"
    ) || (root == "hair" && key.contains(".material."))
}
