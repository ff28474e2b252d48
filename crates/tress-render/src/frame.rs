//! A whole frame, top to bottom: [`Renderer::render`].
//!
//! ```text
//! plan         technique + LOD factor f: strands (f < 1), volume (f > 0), voxelize?
//! uniforms     camera, strand params, lights (+ their shadow cameras), material, volume params
//! voxelize     hair AABB, grid, counters, resolve into the 3D volume (Voxelizer, §3.3)
//! shadow       per light: head + hair depth from the light (ADSM only) (ShadowMap, §3.4)
//! head         clear (optional), opaque head with depth writes      (HeadPass)
//! oit          strands -> shaded, coverage-weighted fragments, either
//!   ppll_build       into per-pixel lists                        (PpllBuild, §3.1-3.2)
//!   ppll_resolve     k nearest sorted + order-independent tail   (PpllResolve, §3.2)
//! or (ShortCut, strands::oit)
//!   shortcut_depth   k nearest depths per pixel                  (ShortcutDepth)
//!   shortcut_shade   those k shaded, the rest's transmittance    (ShortcutShade)
//!   shortcut_resolve k sorted + the tail, over head              (ShortcutResolve)
//! raymarch     hair box -> isosurface, shaded                       (Raymarch, §3.3-3.4)
//! lod_blend    0 < f < 1: strands and volume layers mixed over head (LodBlend, §3, §4)
//! readback     OIT + voxel counters + timestamps -> FrameStats; grow the pool or switch OIT
//! ```
//!
//! At `f = 0` the strand passes draw straight into the target, at `f = 1` the raymarch does; only
//! in between do both draw into scratch layers that `lod_blend` mixes (see [`crate::lod`]).

use glam::Vec3;

mod setup;

use crate::bind::Layouts;
use crate::gpu::types::{self, VolumeParams};
use crate::gpu::{GpuTimer, TargetFormats, Targets, clear_loads};
use crate::head::{HeadGeometry, HeadPass};
use crate::inputs::{frame_sphere, lights_uniform};
use crate::lod::{FramePlan, HybridSettings, LodBlend, LodLayers, Technique};
use crate::stats::{FrameStats, ReadbackRing, SlotInfo, StatsReadback, VolumeFrame};
use crate::strands::oit::{OitInputs, StrandOit};
use crate::strands::{
    PpllPool, ShadowCasters, ShadowMap, StrandGeometry, StrandSettings, ThicknessFade,
};
use crate::volume::raymarch::RaymarchInputs;
use crate::volume::{Raymarch, ShadowMode, VolumeSettings, Voxelizer};
use crate::{Camera, DirectionalLight, GpuContext, Material, RenderError};

/// Most renders of one frame when PPLL fragments were dropped (see [`Renderer::render`]).
pub const MAX_ATTEMPTS: u32 = 4;

/// Names of the timed passes, in frame order.
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
    /// The camera; its viewport must equal the targets' size.
    pub camera: Camera,
    /// Directional lights (at most [`crate::MAX_LIGHTS`]).
    pub lights: &'a [DirectionalLight],
    /// Ambient light, linear RGB.
    pub ambient: Vec3,
    /// Hair and head material.
    pub material: Material,
    /// The hair, if any.
    pub hair: Option<&'a StrandGeometry>,
    /// The opaque head mesh, if any.
    pub head: Option<&'a HeadGeometry>,
    /// Clear color and depth first (linear RGBA), or `None` to draw over what the targets hold.
    pub clear: Option<wgpu::Color>,
}

/// The hair renderer with its head pass: the strand rasterizer, the volume raymarcher and their
/// level-of-detail blend ([`Technique`]); renders into caller-provided targets.
#[derive(Debug)]
pub struct Renderer {
    formats: TargetFormats,
    settings: StrandSettings,
    technique: Technique,
    volume_settings: VolumeSettings,
    hybrid: HybridSettings,
    volume_params: wgpu::Buffer,
    volume_sampler: wgpu::Sampler,
    fallback_volume: (wgpu::TextureView, wgpu::Buffer),
    voxelizer: Option<Voxelizer>,
    raymarch: Raymarch,
    lod_blend: LodBlend,
    layers: Option<LodLayers>,
    layouts: Layouts,
    camera: wgpu::Buffer,
    params: wgpu::Buffer,
    lights: wgpu::Buffer,
    material: wgpu::Buffer,
    view_group: wgpu::BindGroup,
    lighting_group: wgpu::BindGroup,
    shadow: ShadowMap,
    head_pass: HeadPass,
    oit: StrandOit,
    timer: GpuTimer,
    ring: ReadbackRing,
    stats_readback: StatsReadback,
    /// The material fibre's uniform (filled only while the strands shade with it).
    fiber: types::FiberCache,
    frame: u64,
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
    /// With [`StatsReadback::Wait`] and a clearing frame (`inputs.clear` set), a frame that
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
        let size = targets.validate_view(self.formats, &inputs.camera, inputs.lights.len())?;
        inputs.material.validate()?;
        if !inputs.ambient.is_finite() {
            return Err(RenderError::Invalid("ambient light is not finite".into()));
        }

        // ---- results of earlier frames: statistics, pool growth, OIT choice
        let mut report = self.ring.harvest(ctx, &self.timer)?;
        if let Some(r) = &report {
            self.oit.learn(ctx, &self.settings, r);
        }

        let mut attempts = 0;
        loop {
            attempts += 1;
            let (frame, slot, plan, oit) = self.submit(ctx, targets, inputs, size)?;
            let (ppll_capacity, ppll_bytes) = match oit {
                Some((crate::strands::OitKind::Ppll, _)) => {
                    (self.oit.ppll_capacity(), self.oit.ppll_bytes())
                }
                _ => (0, 0),
            };
            let mut retry = false;
            if let (StatsReadback::Wait, Some(i)) = (self.stats_readback, slot) {
                report = self.ring.wait(ctx, &self.timer, i)?.or(report);
                if let Some(r) = report.as_ref().filter(|r| r.frame == frame) {
                    retry = self.oit.learn(ctx, &self.settings, r);
                }
            }
            if retry && inputs.clear.is_some() && attempts < MAX_ATTEMPTS {
                tracing::debug!(
                    frame,
                    "fragments were lost or mostly unsorted: rendering the frame again"
                );
                continue;
            }
            return Ok(FrameStats {
                frame,
                size,
                segments: inputs.hair.map_or(0, |h| h.segment_count()),
                ppll_capacity,
                ppll_bytes,
                oit,
                attempts,
                gpu: report,
                lod: plan.lod,
                volume: self
                    .voxelizer
                    .as_ref()
                    .filter(|_| plan.voxelize)
                    .map(|v| VolumeFrame {
                        resolution: v.resolution(),
                        bytes: v.bytes(),
                    }),
            });
        }
    }

    /// Encode and submit one frame; returns its index, its readback slot, its plan and the OIT
    /// that drew its strands (with the bytes of its buffers).
    fn submit(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        inputs: &FrameInputs<'_>,
        size: [u32; 2],
    ) -> Result<(u64, Option<usize>, FramePlan, Option<OitFrame>), RenderError> {
        // ---- plan: what draws the hair this frame (crate::lod)
        let hair = inputs.hair.filter(|h| h.segment_count() > 0);
        let plan = FramePlan::new(
            self.technique,
            &self.hybrid,
            &self.settings,
            &self.volume_settings,
            inputs,
            hair.is_some(),
        );
        if plan.voxelize && self.voxelizer.is_none() {
            self.voxelizer = Some(Voxelizer::with_params(
                ctx,
                &self.layouts,
                self.volume_settings.resolution,
                &self.volume_params,
            )?);
            self.rebuild_lighting_group(ctx)?;
        }
        if plan.blend() && self.layers.as_ref().is_none_or(|l| l.size != size) {
            self.layers = None;
            self.layers = Some(LodLayers::new(ctx, size, self.formats.color)?);
        }

        // ---- OIT buffers for this target size (only when strands draw; strands::oit)
        let oit_kind = hair
            .filter(|_| plan.strands)
            .map(|_| self.oit.kind(&self.settings));
        if let Some(kind) = oit_kind {
            self.oit.prepare(ctx, &self.settings, size, kind)?;
        }
        let oit = oit_kind.map(|kind| (kind, self.oit.bytes(kind)));

        // ---- uniforms
        let bounds = frame_sphere(inputs.hair.map(|h| h.bounds), inputs.head.map(|h| h.bounds));
        let (lights, light_cameras) = lights_uniform(
            inputs.ambient,
            inputs.lights,
            Some((bounds, self.shadow.size())),
        )?;
        let mut params = self.settings.params();
        if let Some(kind) = oit_kind {
            self.oit.fill_params(kind, &mut params);
        } else {
            (params.node_capacity, params.nodes_per_chunk) = (1, 1);
        }
        params.target_width = size[0];
        params.target_height = size[1];
        params.light_count = lights.count;
        params.shadows = u32::from(plan.shadows);
        params.thickness_fade = match (self.settings.thickness_fade, hair) {
            (ThicknessFade::Tip, Some(h)) if h.max_thickness() > 0.0 => 1,
            (ThicknessFade::Projected, Some(h)) if h.has_thickness() => 2,
            _ => 0,
        };
        params.thickness_ref = hair.map_or(1.0, |h| h.max_thickness().max(1e-20));
        params.vertex_color = u32::from(hair.is_some_and(|h| h.has_color()));
        params.hair_center = inputs.hair.map_or([0.0; 3], |h| h.bounds.0.to_array());
        let mut volume = match hair {
            Some(h) if plan.voxelize => Voxelizer::params(&self.volume_settings, h),
            _ => VolumeParams::default(),
        };
        volume.world_from_clip = types::mat4(inputs.camera.clip_from_world().inverse());
        volume.shading = params.shading;
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
            let radius = bounds.map_or(1.0, |b| b.1);
            volume.occlusion_width =
                self.settings.shadow_width_px * 2.0 * radius / self.shadow.size() as f32;
            volume.occlusion_bias = self.settings.shadow_bias;
        }
        let q = &ctx.queue;
        q.write_buffer(
            &self.camera,
            0,
            bytemuck::bytes_of(&inputs.camera.uniform()),
        );
        q.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        q.write_buffer(&self.lights, 0, bytemuck::bytes_of(&lights));
        let mut material = inputs.material.uniform();
        if self.settings.shading == crate::Shading::Marschner {
            let uniform = self.fiber.get(&inputs.material.fiber);
            material.fiber = uniform.marschner;
            material.dual = uniform.dual;
        }
        q.write_buffer(&self.material, 0, bytemuck::bytes_of(&material));
        q.write_buffer(&self.volume_params, 0, bytemuck::bytes_of(&volume));

        let frame = self.frame;
        self.frame += 1;
        let slot = self.ring.idle();
        let adsm = plan.shadows
            && plan.shadow_mode == ShadowMode::Adsm
            && !light_cameras.is_empty()
            && bounds.is_some();
        let timer = &mut self.timer;
        let (shadow, head_pass, strand_oit) = (&self.shadow, &self.head_pass, &self.oit);
        let shadow_width_px = self.settings.shadow_width_px;
        let (raymarch, lod_blend, layers) = (&self.raymarch, &self.lod_blend, &self.layers);
        let voxelizer = self.voxelizer.as_ref().filter(|_| plan.voxelize);
        let (view, lighting) = (&self.view_group, &self.lighting_group);
        let ring = &mut self.ring;
        ctx.scoped("rendering a frame", || {
            timer.begin_frame();
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("frame/encoder"),
                });
            // ---- voxelization: AABB, grid, counters, volume texture (§3.3)
            if let (Some(v), Some(h)) = (voxelizer, hair) {
                v.encode(
                    &mut encoder,
                    h,
                    timer.compute_writes("volume/voxelize", true, true),
                );
            }
            // ---- shadow maps (§3.4, ADSM)
            if adsm {
                shadow.encode(
                    ctx,
                    &mut encoder,
                    timer,
                    &light_cameras,
                    ShadowCasters {
                        hair,
                        head: inputs.head,
                        width_px: shadow_width_px,
                    },
                );
            }
            // ---- opaque head, depth written
            {
                let mut pass = targets.begin_pass(
                    &mut encoder,
                    "head/head_pass/pass",
                    clear_loads(inputs.clear),
                    timer.render_writes("head", true, true),
                );
                if let Some(head) = inputs.head {
                    pass.set_bind_group(0, view, &[]);
                    pass.set_bind_group(1, lighting, &[]);
                    head_pass.draw(&mut pass, head);
                }
            }
            // ---- the LOD layers, when both renderers draw
            let layers = layers.as_ref().filter(|_| plan.blend());
            if let Some(l) = layers {
                l.clear(&mut encoder);
            }
            // ---- strands: PPLL build and resolve (§3.1-3.2), or ShortCut (strands::oit)
            if let (Some(geometry), Some(kind)) = (hair, oit_kind) {
                let inputs = OitInputs {
                    view,
                    lighting,
                    geometry,
                    depth: targets.depth,
                    color: layers.map_or(targets.color, |l| &l.strands),
                };
                strand_oit.encode(ctx, &mut encoder, kind, &inputs, timer);
            }
            // ---- volume: raymarch to the isosurface (§3.3-3.4)
            if let (Some(v), true) = (voxelizer, plan.volume) {
                let inputs = RaymarchInputs {
                    view,
                    lighting,
                    depth: targets.depth,
                    occupancy: v.occupancy(),
                    color: layers.map_or(targets.color, |l| &l.volume),
                };
                raymarch.encode(
                    ctx,
                    &mut encoder,
                    &inputs,
                    timer.render_writes("volume/raymarch", true, true),
                );
            }
            // ---- level-of-detail blend of the two layers (§3, §4)
            if let Some(l) = layers {
                lod_blend.encode(
                    ctx,
                    &mut encoder,
                    l,
                    &plan,
                    targets.color,
                    timer.render_writes("lod/blend", true, true),
                );
            }
            // ---- statistics readback
            if let Some(i) = slot {
                let ppll = oit_kind == Some(crate::strands::OitKind::Ppll);
                let info = SlotInfo {
                    frame,
                    capacity: if ppll { strand_oit.ppll_capacity() } else { 0 },
                    head_bytes: if ppll { PpllPool::head_bytes(size) } else { 0 },
                    oit,
                    satf: false,
                };
                let counters = oit_kind.and_then(|k| strand_oit.counters(k));
                ring.record(i, &mut encoder, counters, timer, info);
                if let Some(v) = voxelizer {
                    ring.record_volume(i, &mut encoder, v.stats_buffer());
                }
            }
            ctx.queue.submit([encoder.finish()]);
            if let Some(i) = slot {
                ring.map(i);
            }
        })?;

        Ok((frame, slot, plan, oit))
    }
}

/// The OIT that drew a frame's strands and the bytes of its buffers.
type OitFrame = (crate::strands::OitKind, u64);
