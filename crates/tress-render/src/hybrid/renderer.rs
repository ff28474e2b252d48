//! A whole frame, top to bottom: [`Renderer::render`].
//!
//! ```text
//! plan         per head of hair: technique (auto: by its size on screen) + LOD factor f:
//!              strands (f < 1), volume (f > 0), voxelize?; volumes over the budget -> strands
//! uniforms     camera, lights (+ their shadow cameras) once; per head of hair its strand params,
//!              material and volume params
//! voxelize     per voxelized head of hair: AABB, grid, shared counters, resolve into its own
//!              3D volume (Voxelizer, §3.3)
//! shadow       per light: heads + every rasterized hair's depth from the light (ADSM, §3.4)
//! head         clear (optional), opaque heads with depth writes   (HeadPass)
//! one head of hair:
//!   oit          strands -> shaded, coverage-weighted fragments, either
//!     ppll_build       into per-pixel lists                        (PpllBuild, §3.1-3.2)
//!     ppll_resolve     k nearest sorted + order-independent tail   (PpllResolve, §3.2)
//!   or (ShortCut, strands::oit)
//!     shortcut_depth   k nearest depths per pixel                  (ShortcutDepth)
//!     shortcut_shade   those k shaded, the rest's transmittance    (ShortcutShade)
//!     shortcut_resolve k sorted + the tail, over head              (ShortcutResolve)
//!   raymarch     hair box -> isosurface, shaded                     (Raymarch, §3.3-3.4)
//!   lod_blend    0 < f < 1: strands and volume layers mixed over head (LodBlend, §3, §4)
//! several heads of hair (characters):
//!   raymarch     each volume (and dithered hybrid) far to near, over the target
//!   oit          every rasterized head of hair in one OIT, resolved over the target
//! readback     OIT + each volume's counters + timestamps -> FrameStats; grow the pool or
//!              switch OIT
//! ```
//!
//! With one head of hair, at `f = 0` the strand passes draw straight into the target, at `f = 1`
//! the raymarch does; only in between do both draw into scratch layers that `lod_blend` mixes
//! (see [`crate::hybrid`]). With several, a hybrid head of hair uses the paper's dithered transition
//! in the frame itself (its strands in the shared OIT, its volume in the other pixels), so no
//! head of hair needs an OIT of its own; characters are composited in depth order of groups: the
//! volumes far to near, then every rasterized character in one OIT (so a volume character in
//! front of a rasterized one is covered by its hair where they overlap: `auto` never draws that,
//! as it rasterizes the larger, nearer ones).

mod costs;
mod objects;
mod setup;

pub use objects::{HairObject, MAX_OBJECTS};

use crate::bind::Layouts;
use crate::gpu::types::{self, VolumeParams};
use crate::gpu::{GpuTimer, TargetFormats, Targets};
use crate::head::HeadPass;
use crate::hybrid::{
    FramePlan, HybridSettings, LodBlend, LodLayers, TechniqueKind, check_technique,
};
use crate::inputs::{frame_sphere, lights_uniform};
use crate::services::{FrameServices, FrameTicket};
use crate::stats::{FrameStats, ObjectFrame, SlotInfo, StatsReadback, VolumeFrame};
use crate::strands::oit::{OitInputs, OitPart, StrandOit};
use crate::strands::{
    PpllPool, ShadowCasters, ShadowMap, StrandGeometry, StrandSettings, ThicknessFade,
};
use crate::volume::raymarch::RaymarchInputs;
use crate::volume::{Raymarch, ShadowMode, VolumeSettings, Voxelizer};
use crate::{Camera, GpuContext, Material, RenderError, SharedInputs};
use objects::{Drawn, ObjectSlot, check_objects, frame_objects};

/// Most renders of one frame when PPLL fragments were dropped (see [`Renderer::render`]).
pub const MAX_ATTEMPTS: u32 = 4;

/// Names of the timed passes, in frame order. `volume/voxelize`, `volume/raymarch` and
/// `lod/blend` are timed per head of hair (`GpuReport::object_timings`) and summed for the
/// frame.
pub const PASS_NAMES: &[&str] = &[
    "volume/voxelize",
    "strands/shadow",
    "head",
    "strands/ppll_build",
    "strands/ppll_resolve",
    "strands/shortcut_depth",
    "strands/shortcut_shade",
    "strands/shortcut_resolve",
    "volume/raymarch",
    "lod/blend",
];

/// Everything a frame draws. Plain data: the application owns the geometry and the targets.
#[derive(Clone, Debug)]
pub struct FrameInputs<'a> {
    /// The camera, lights, ambient light, opaque head and clear colour.
    pub shared: SharedInputs<'a>,
    /// The material of `hair` and of the head (whose colour it gives).
    pub material: Material,
    /// The hair, if any, drawn with `material` and the renderer's technique
    /// ([`Renderer::set_technique`]).
    pub hair: Option<&'a StrandGeometry>,
    /// More heads of hair in the same frame (characters), after `hair`, each with its own
    /// material and technique; they share the lights, the shadow maps and one OIT, each volume
    /// character has its own volume (at most [`MAX_OBJECTS`] in all).
    pub objects: &'a [HairObject<'a>],
}

/// The hair renderer with its head pass: the strand rasterizer, the volume raymarcher and their
/// level-of-detail blend ([`TechniqueKind`]) for one or several heads of hair; renders into
/// caller-provided targets.
#[derive(Debug)]
pub struct Renderer {
    formats: TargetFormats,
    settings: StrandSettings,
    technique: TechniqueKind,
    volume_settings: VolumeSettings,
    hybrid: HybridSettings,
    volume_sampler: wgpu::Sampler,
    fallback_volume: (wgpu::TextureView, wgpu::Buffer),
    voxelizer: Option<Voxelizer>,
    raymarch: Raymarch,
    lod_blend: LodBlend,
    layers: Option<LodLayers>,
    layouts: Layouts,
    /// Object `i`'s uniforms and bind groups (slot 0 always exists: the head's).
    slots: Vec<ObjectSlot>,
    shadow: ShadowMap,
    head_pass: HeadPass,
    oit: StrandOit,
    services: FrameServices,
    /// Objects already warned about their volume not fitting the budget.
    warned: Vec<bool>,
    /// What the renderers cost on this device, learned from the frames (`hybrid.budget_ms`).
    costs: crate::hybrid::budget::CostModel,
}

/// What one submitted frame was: its index, readback slot, plans and OIT.
struct Submitted {
    ticket: FrameTicket,
    plans: Vec<FramePlan>,
    oit: Option<OitFrame>,
}

impl Renderer {
    /// Every fragment the PPLL stored in the last frame it drew, per pixel (None before the
    /// first PPLL frame). Read after [`Renderer::render`] of a frame drawn with the PPLL and
    /// nothing lost (`FrameStats`' `oit`), this is the whole frame's hair, for CPU composites
    /// such as the exact sorted reference of `tress render --exact-oit`.
    pub fn ppll_fragments(
        &self,
        ctx: &GpuContext,
    ) -> Result<Option<crate::strands::PpllFragments>, RenderError> {
        self.oit.ppll_fragments(ctx)
    }

    /// Render one frame into `targets` and submit it on `ctx.queue`.
    ///
    /// With [`StatsReadback::Wait`] and a clearing frame (`inputs.shared.clear` set), a frame that
    /// dropped PPLL fragments is rendered again with the grown pool, or with ShortCut when the
    /// pool's cap cannot hold it and `strands.oit` is `auto` (at most [`MAX_ATTEMPTS`] times in
    /// all), so offline renders are complete; under `auto` a PPLL frame whose k-buffer merged
    /// most fragments unsorted is drawn again with ShortCut
    /// ([`crate::strands::oit::AUTO_TAIL_SHARE`]). `FrameStats::attempts` says how many it took. A
    /// frame drawn over the caller's content (`clear: None`) is never repeated: the next frame
    /// uses the grown pool or ShortCut.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        inputs: &FrameInputs<'_>,
    ) -> Result<FrameStats, RenderError> {
        // ---- validate inputs (never panic on user data)
        let size = targets.validate_view(
            self.formats,
            &inputs.shared.camera,
            inputs.shared.lights.len(),
        )?;
        inputs.material.validate()?;
        for o in inputs.objects {
            o.material.validate()?;
            check_technique(o.technique)?;
        }
        check_objects(usize::from(inputs.hair.is_some()) + inputs.objects.len())?;
        if !inputs.shared.ambient.is_finite() {
            return Err(RenderError::Invalid("ambient light is not finite".into()));
        }

        // ---- results of earlier frames: statistics, pool growth, OIT choice
        let mut report = self.services.harvest(ctx)?;
        if let Some(r) = &report {
            self.oit.learn(ctx, &self.settings, r);
        }

        let mut attempts = 0;
        loop {
            attempts += 1;
            let sub = self.submit(ctx, targets, inputs, size)?;
            let (ppll_capacity, ppll_bytes) = match sub.oit {
                Some((crate::strands::OitKind::Ppll, _)) => {
                    (self.oit.ppll_capacity(), self.oit.ppll_bytes())
                }
                _ => (0, 0),
            };
            let mut retry = false;
            if let (StatsReadback::Wait, Some(_)) = (self.services.readback, sub.ticket.slot) {
                report = self.services.results(ctx, sub.ticket, None)?.or(report);
                if let Some(r) = report.as_ref().filter(|r| r.frame == sub.ticket.frame) {
                    retry = self.oit.learn(ctx, &self.settings, r);
                }
            }
            if retry && inputs.shared.clear.is_some() && attempts < MAX_ATTEMPTS {
                tracing::debug!(
                    frame = sub.ticket.frame,
                    "fragments were lost or mostly unsorted: rendering the frame again"
                );
                continue;
            }
            let ppll = (ppll_capacity, ppll_bytes);
            let stats = self.frame_stats(inputs, size, &sub, (attempts, ppll), report);
            self.learn_costs(&stats);
            return Ok(stats);
        }
    }

    /// The statistics of a submitted frame (its attempts and the PPLL's capacity and bytes
    /// while it drew).
    fn frame_stats(
        &self,
        inputs: &FrameInputs<'_>,
        size: [u32; 2],
        sub: &Submitted,
        (attempts, (ppll_capacity, ppll_bytes)): (u32, (u32, u64)),
        gpu: Option<crate::GpuReport>,
    ) -> FrameStats {
        let hair = frame_objects(inputs.hair, inputs.material, self.technique, inputs.objects);
        let voxelized = sub.plans.iter().filter(|p| p.voxelize).count() as u64;
        let volume = self.voxelizer.as_ref().filter(|_| voxelized > 0).map(|v| {
            let voxelized = || sub.plans.iter().enumerate().filter(|(_, p)| p.voxelize);
            VolumeFrame {
                resolution: voxelized()
                    .filter_map(|(i, _)| v.grid_resolution(i))
                    .max()
                    .unwrap_or_else(|| v.resolution()),
                bytes: v.counter_bytes()
                    + voxelized()
                        .map(|(i, _)| v.object_grid_bytes(i))
                        .sum::<u64>(),
            }
        });
        let objects = sub
            .plans
            .iter()
            .enumerate()
            .zip(&hair)
            .filter(|(_, (h, ..))| h.is_some())
            .map(|((i, p), (h, ..))| ObjectFrame {
                technique: p.drawn(),
                lod: p.lod,
                size_px: p.extent.size_px,
                coverage: p.extent.coverage,
                segments: h.map_or(0, StrandGeometry::segment_count),
                volume_bytes: match (&self.voxelizer, p.voxelize) {
                    (Some(v), true) => v.object_grid_bytes(i),
                    _ => 0,
                },
                volume_resolution: match (&self.voxelizer, p.voxelize) {
                    (Some(v), true) => v.grid_resolution(i).unwrap_or(0),
                    _ => 0,
                },
                geometry_bytes: h.map_or(0, StrandGeometry::bytes),
                fallback: p.fallback,
            })
            .collect();
        FrameStats {
            frame: sub.ticket.frame,
            size,
            segments: hair
                .iter()
                .map(|(h, ..)| h.map_or(0, StrandGeometry::segment_count))
                .sum(),
            ppll_capacity,
            ppll_bytes,
            oit: sub.oit,
            attempts,
            gpu,
            lod: sub.plans.first().map_or(0.0, |p| p.lod),
            volume,
            objects,
        }
    }

    /// Encode and submit one frame.
    fn submit(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        inputs: &FrameInputs<'_>,
        size: [u32; 2],
    ) -> Result<Submitted, RenderError> {
        // ---- plan: what draws each head of hair this frame (crate::hybrid), volumes in budget
        let hair = frame_objects(inputs.hair, inputs.material, self.technique, inputs.objects);
        let several = hair.len() > 1;
        let settings = (&self.hybrid, &self.settings, &self.volume_settings);
        let mut drawn: Vec<Drawn<'_>> = hair
            .iter()
            .map(|&(h, material, technique)| Drawn {
                hair: h.filter(|h| h.segment_count() > 0),
                material,
                plan: FramePlan::new(technique, settings, &inputs.shared.camera, h, several),
            })
            .collect();
        if several {
            self.fit_budget(&mut drawn, &hair, size);
        }
        self.ensure_slots(ctx, drawn.len())?;
        self.grant_volumes(ctx, &mut drawn)?;
        let single = (!several).then(|| drawn[0]);
        if single.is_some_and(|d| d.plan.blend())
            && self.layers.as_ref().is_none_or(|l| l.size != size)
        {
            self.layers = None;
            self.layers = Some(LodLayers::new(ctx, size, self.formats.color)?);
        }

        // ---- OIT buffers for this target size (only when strands draw; strands::oit)
        let rasterized = drawn.iter().any(|d| d.hair.is_some() && d.plan.strands);
        let oit_kind = rasterized.then(|| self.oit.kind(&self.settings));
        if let Some(kind) = oit_kind {
            self.oit.prepare(ctx, &self.settings, size, kind)?;
        }
        let oit = oit_kind.map(|kind| (kind, self.oit.bytes(kind)));

        // ---- uniforms: the frame's camera and lights, then each head of hair's own
        // The shadow maps frame the hair and head of a single head of hair; among several, the
        // rasterized ones (the others' shadows come from their volumes).
        let union = |filter: &dyn Fn(&Drawn<'_>) -> bool| {
            hair.iter()
                .zip(&drawn)
                .filter(|(_, d)| filter(d))
                .filter_map(|((h, ..), _)| h.map(|h| h.bounds))
                .fold(None, |acc, b| frame_sphere(acc, Some(b)))
        };
        let bounds = if several {
            union(&|d| d.plan.strands).or_else(|| union(&|_| true))
        } else {
            frame_sphere(union(&|_| true), inputs.shared.head.map(|h| h.bounds))
        };
        let (lights, light_cameras) = lights_uniform(
            inputs.shared.ambient,
            inputs.shared.lights,
            Some((bounds, self.shadow.size())),
        )?;
        let mut base = self.settings.params();
        if let Some(kind) = oit_kind {
            self.oit.fill_params(kind, &mut base);
        } else {
            (base.node_capacity, base.nodes_per_chunk) = (1, 1);
        }
        base.target_width = size[0];
        base.target_height = size[1];
        base.light_count = lights.count;
        self.services
            .write_view(ctx, &inputs.shared.camera, &lights);
        for (i, (d, &(unfiltered, ..))) in drawn.iter().zip(&hair).enumerate() {
            // The width of a shadow-map line in the volume's ADSM model: of the frame's maps
            // where they shade this head of hair, else of maps framing it alone.
            let own = (several && !d.plan.strands)
                .then(|| d.hair.map(|h| h.bounds))
                .flatten();
            let radius = own.or(bounds).map_or(1.0, |b| b.1);
            let view = (&inputs.shared.camera, &lights);
            self.write_object_uniforms(ctx, i, d, unfiltered, base, view, radius);
        }

        let ticket = self.services.begin(ctx)?;
        let adsm = drawn
            .iter()
            .any(|d| d.plan.shadows && d.plan.shadow_mode == ShadowMode::Adsm)
            && !light_cameras.is_empty()
            && bounds.is_some();
        let casters: Vec<&StrandGeometry> = drawn
            .iter()
            .filter(|d| d.plan.strands)
            .filter_map(|d| d.hair)
            .collect();
        let timer = &self.services.timer;
        let (shadow, head_pass, strand_oit) = (&self.shadow, &self.head_pass, &self.oit);
        let shadow_width_px = self.settings.shadow_width_px;
        let (raymarch, lod_blend, layers) = (&self.raymarch, &self.lod_blend, &self.layers);
        let voxelizer = self.voxelizer.as_ref();
        let slots = &self.slots;
        let ring = &mut self.services.ring;
        ctx.scoped("rendering a frame", || {
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("frame/encoder"),
                });
            // ---- voxelization of each head of hair that needs its volume (§3.3)
            if let Some(v) = voxelizer {
                for (i, d) in drawn.iter().enumerate().filter(|(_, d)| d.plan.voxelize) {
                    if let Some(h) = d.hair {
                        let writes = timer.object_compute_writes("volume/voxelize", i, true, true);
                        v.encode(&mut encoder, i, h, writes);
                    }
                }
            }
            // ---- shadow maps (§3.4, ADSM) of the heads and every rasterized head of hair
            if adsm {
                shadow.encode(
                    ctx,
                    &mut encoder,
                    timer,
                    &light_cameras,
                    ShadowCasters {
                        hair: &casters,
                        head: inputs.shared.head,
                        width_px: shadow_width_px,
                    },
                );
            }
            // ---- opaque head, depth written
            head_pass.encode(
                &mut encoder,
                targets,
                inputs.shared.clear,
                timer.render_writes("head", true, true),
                [&slots[0].view_group, &slots[0].lighting_group],
                inputs.shared.head,
            );
            let part = |i: usize, geometry| OitPart {
                view: &slots[i].view_group,
                lighting: &slots[i].lighting_group,
                geometry,
            };
            let march = |encoder: &mut wgpu::CommandEncoder, i: usize, color, timer: &GpuTimer| {
                let volume = voxelizer.and_then(|v| Some((v.occupancy(i)?, v.highlights(i)?)));
                if let Some((occupancy, highlights)) = volume {
                    let inputs = RaymarchInputs {
                        view: &slots[i].view_group,
                        lighting: &slots[i].lighting_group,
                        depth: targets.depth,
                        occupancy,
                        highlights,
                        color,
                    };
                    let writes = timer.object_render_writes("volume/raymarch", i, true, true);
                    raymarch.encode(ctx, encoder, &inputs, writes);
                }
            };
            if let Some(d) = single {
                // ---- one head of hair: the LOD layers when both renderers draw
                let plan = &d.plan;
                let layers = layers.as_ref().filter(|_| plan.blend());
                if let Some(l) = layers {
                    l.clear(&mut encoder);
                }
                // ---- strands: PPLL build and resolve (§3.1-3.2), or ShortCut (strands::oit)
                if let (Some(geometry), Some(kind)) = (d.hair, oit_kind) {
                    let parts = [part(0, geometry)];
                    let inputs = OitInputs {
                        view: &slots[0].view_group,
                        parts: &parts,
                        depth: targets.depth,
                        color: layers.map_or(targets.color, |l| &l.strands),
                    };
                    strand_oit.encode(ctx, &mut encoder, kind, &inputs, timer);
                }
                // ---- volume: raymarch to the isosurface (§3.3-3.4)
                if plan.volume && plan.voxelize {
                    march(
                        &mut encoder,
                        0,
                        layers.map_or(targets.color, |l| &l.volume),
                        timer,
                    );
                }
                // ---- level-of-detail blend of the two layers (§3, §4)
                if let Some(l) = layers {
                    lod_blend.encode(
                        ctx,
                        &mut encoder,
                        l,
                        plan,
                        targets.color,
                        timer.object_render_writes("lod/blend", 0, true, true),
                    );
                }
            } else {
                // ---- several heads of hair: every volume far to near, then one OIT for all
                let mut marched: Vec<usize> = (0..drawn.len())
                    .filter(|&i| drawn[i].plan.volume && drawn[i].plan.voxelize)
                    .collect();
                marched.sort_by(|&a, &b| {
                    let depth = |i: usize| drawn[i].plan.extent.depth;
                    depth(b).total_cmp(&depth(a))
                });
                for i in marched {
                    march(&mut encoder, i, targets.color, timer);
                }
                if let Some(kind) = oit_kind {
                    let parts: Vec<OitPart<'_>> = drawn
                        .iter()
                        .enumerate()
                        .filter(|(_, d)| d.plan.strands)
                        .filter_map(|(i, d)| Some(part(i, d.hair?)))
                        .collect();
                    let inputs = OitInputs {
                        view: &slots[0].view_group,
                        parts: &parts,
                        depth: targets.depth,
                        color: targets.color,
                    };
                    strand_oit.encode(ctx, &mut encoder, kind, &inputs, timer);
                }
            }
            // ---- statistics readback: the OIT's counters, each volume's, the timestamps
            let ppll = oit_kind == Some(crate::strands::OitKind::Ppll);
            let info = SlotInfo {
                frame: ticket.frame,
                capacity: if ppll { strand_oit.ppll_capacity() } else { 0 },
                head_bytes: if ppll { PpllPool::head_bytes(size) } else { 0 },
                oit,
                satf: false,
                objects: drawn.len(),
            };
            let counters = oit_kind.and_then(|k| strand_oit.counters(k));
            let volumes: Vec<(usize, &wgpu::Buffer)> = voxelizer.map_or_else(Vec::new, |v| {
                (0..drawn.len())
                    .filter(|&o| drawn[o].plan.voxelize)
                    .filter_map(|o| Some((o, v.stats_buffer(o)?)))
                    .collect()
            });
            ticket.submit(ctx, (ring, timer), encoder, counters, &volumes, info);
        })?;

        Ok(Submitted {
            ticket,
            plans: drawn.iter().map(|d| d.plan).collect(),
            oit,
        })
    }

    /// Write object `i`'s strand settings, material and volume uniforms for this frame: `base`
    /// holds the settings every head of hair shares; `unfiltered` is its hair as given (its
    /// centre even when it has no segments); `shadow_radius` the radius of the sphere its
    /// shadow maps frame.
    #[allow(clippy::too_many_arguments)]
    fn write_object_uniforms(
        &mut self,
        ctx: &GpuContext,
        i: usize,
        d: &Drawn<'_>,
        unfiltered: Option<&StrandGeometry>,
        base: types::StrandParams,
        (camera, lights): (&Camera, &types::LightsUniform),
        shadow_radius: f32,
    ) {
        let (plan, hair) = (&d.plan, d.hair);
        let mut params = base;
        params.shadows = u32::from(plan.shadows);
        params.thickness_fade = match (self.settings.thickness_fade, hair) {
            (ThicknessFade::Tip, Some(h)) if h.max_thickness() > 0.0 => 1,
            (ThicknessFade::Projected, Some(h)) if h.has_thickness() => 2,
            _ => 0,
        };
        params.thickness_ref = hair.map_or(1.0, |h| h.max_thickness().max(1e-20));
        params.vertex_color = u32::from(hair.is_some_and(|h| h.has_color()));
        params.hair_center = unfiltered.map_or([0.0; 3], |h| h.bounds.0.to_array());
        params.lod_factor = plan.lod;
        params.lod_dither = u32::from(plan.dither);
        let mut volume = match hair {
            Some(h) if plan.voxelize => {
                // Its own grid's resolution (by its size on screen), not `volume.resolution`.
                let resolution = self
                    .voxelizer
                    .as_ref()
                    .and_then(|v| v.grid_resolution(i))
                    .unwrap_or(self.volume_settings.resolution);
                let settings = crate::volume::VolumeSettings {
                    resolution,
                    ..self.volume_settings.clone()
                };
                Voxelizer::params(&settings, h)
            }
            _ => VolumeParams::default(),
        };
        volume.world_from_clip = types::mat4(camera.clip_from_world().inverse());
        volume.shading = params.shading;
        // The strands' own Kajiya-Kay highlights, integrated per voxel for this view and these
        // lights (`volume.highlights = "strands"`; other shading models use the mean tangent).
        if self.settings.shading == crate::Shading::KajiyaKay && volume.highlights != 0 {
            let count = (lights.count as usize).min(lights.lights.len());
            let view = tress_shading::highlights::HighlightView {
                eye: camera.eye(),
                forward: camera.forward(),
                orthographic: camera.is_orthographic(),
                lights: lights.lights[..count]
                    .iter()
                    .map(|l| glam::Vec3::from_array(l.to_light))
                    .collect(),
                exponent: d.material.primary_exponent,
            };
            Voxelizer::set_highlight_view(&mut volume, &view);
        } else {
            volume.highlights = 0;
        }
        // The strands' tip fade weighs the voxelized tangents (`VolumeParams::fade_ref`).
        volume.fade_ref = if params.thickness_fade == 1 {
            params.thickness_ref
        } else {
            0.0
        };
        // The volume is as opaque as the strands' lines (`volume.opacity = "strands"`).
        if self.volume_settings.opacity == crate::volume::Opacity::Strands {
            volume.optical_width = tress_shading::line_optical_width(
                self.settings.alpha,
                self.settings.width_px,
                self.settings.coverage,
            );
        }
        volume.raster_shadow_mode = u32::from(plan.shadow_mode == ShadowMode::Volume);
        volume.raster_ao = u32::from(plan.raster_ao);
        if self.volume_settings.occlusion == crate::volume::Occlusion::Adsm {
            // ADSM's model in the volume: the strands' r and alpha, so both techniques darken
            // alike.
            volume.occlusion_r = self.settings.shadow_r;
            volume.shadow_alpha = self.settings.shadow_alpha;
            // A shadow-map line's width: `shadow_width_px` texels of the light's map over the
            // bounding sphere.
            volume.occlusion_width =
                self.settings.shadow_width_px * 2.0 * shadow_radius / self.shadow.size() as f32;
            volume.occlusion_bias = self.settings.shadow_bias;
        }
        let slot = &mut self.slots[i];
        let mut material = d.material.uniform();
        if self.settings.shading == crate::Shading::Marschner {
            let uniform = slot.fiber.get(&d.material.fiber);
            material.fiber = uniform.marschner;
            material.dual = uniform.dual;
            if !self.settings.multiple_scattering {
                // Dual scattering's d_f and d_b: no forward or backward scattered light.
                material.dual.params[1] = 0.0;
                material.dual.params[2] = 0.0;
            }
        }
        let q = &ctx.queue;
        q.write_buffer(&slot.params, 0, bytemuck::bytes_of(&params));
        q.write_buffer(&slot.material, 0, bytemuck::bytes_of(&material));
        q.write_buffer(&slot.volume_params, 0, bytemuck::bytes_of(&volume));
    }
}

/// The OIT that drew a frame's strands and the bytes of its buffers.
type OitFrame = (crate::strands::OitKind, u64);
