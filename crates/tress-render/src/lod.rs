//! Level of detail (Jansson et al. 2019 §3 "Overview", §4): which technique draws the hair, and
//! the hybrid's blend between the strand rasterizer and the volume raymarcher.
//!
//! # Implementation
//!
//! - [`TechniqueKind::Strands`] draws only the rasterizer, [`TechniqueKind::Volume`] only the raymarcher;
//!   [`TechniqueKind::Hybrid`] computes a blend factor `f` per frame: the fixed `lod` setting when
//!   given, else `smoothstep(near, far, d)` of the distance `d` from the eye to the centre of the
//!   hair's bounds (`tress_shading::lod_factor`), so close-ups are rasterized and far hair is
//!   raymarched, as the paper proposes.
//! - At `f = 0` the frame is exactly the strand renderer's, at `f = 1` exactly the raymarcher's
//!   (the passes draw straight into the target; tests check both). In between both draw into
//!   premultiplied scratch layers and [`LodBlend`] (`lod_blend.wgsl`) composites
//!   `mix(strands, volume, f)` over the target (`transition = "alpha"`, the paper's alpha-blended
//!   transition), or picks one layer per pixel with a 4 × 4 Bayer threshold
//!   (`transition = "dither"`, the paper's dithered one: `f = k/16` shows the volume in `k` of
//!   every 16 pixels).
//! - The head's shadows follow the rasterizer when it draws (ADSM or volume, its
//!   `shadow_mode`), else the volume's.

use std::str::FromStr;

use glam::Vec3;

use crate::bind::{bind_group, bind_group_layout, texture_2d, uniform};
use crate::gpu::pipeline::{RasterPipeline, over_color_pass, pipeline_layout, premultiplied_over};
use crate::gpu::screen_layer;
use crate::gpu::types::LodParams;
use crate::strands::{StrandGeometry, StrandSettings};
use crate::volume::{ShadowMode, VolumeSettings};
use crate::{Camera, GpuContext, RenderError, shaders};

/// The CPU twins of the blend factor and the dither thresholds (`tress_shading::volume`).
pub use tress_shading::{dither_threshold, lod_factor};

/// What draws a head of hair: the one list of technique names, `tress_scene::TechniqueKind`.
/// This renderer draws [`TechniqueKind::Strands`], [`TechniqueKind::Volume`],
/// [`TechniqueKind::Hybrid`] and [`TechniqueKind::Auto`] (chosen per head of hair and frame from
/// its size on screen: strands from [`HybridSettings::auto_near_px`] up, volume from
/// [`HybridSettings::auto_far_px`] down, the hybrid's blend between).
pub use tress_scene::TechniqueKind;

/// A technique the strand renderer draws ([`TechniqueKind::per_object`]), or the error naming
/// it.
pub fn check_technique(technique: TechniqueKind) -> Result<TechniqueKind, RenderError> {
    if technique.per_object() {
        Ok(technique)
    } else {
        Err(RenderError::Invalid(format!(
            "the strand renderer draws strands, volume, hybrid or auto, not `{technique}`"
        )))
    }
}

/// How the hybrid mixes the two renderers between `near` and `far`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Transition {
    /// Alpha blend of the two layers, `"alpha"`.
    #[default]
    Alpha,
    /// Per-pixel choice with an ordered (Bayer) dither, `"dither"`.
    Dither,
}

impl Transition {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            Transition::Alpha => "alpha",
            Transition::Dither => "dither",
        }
    }
}

impl FromStr for Transition {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "alpha" => Ok(Transition::Alpha),
            "dither" => Ok(Transition::Dither),
            _ => Err(RenderError::Invalid(format!(
                "unknown transition `{s}` (expected alpha or dither)"
            ))),
        }
    }
}

/// Settings of the hybrid (`[hybrid]`).
#[derive(Clone, Debug, PartialEq)]
pub struct HybridSettings {
    /// A fixed blend factor in `[0, 1]` (0 strands, 1 volume); `None` picks it from the distance.
    pub lod: Option<f32>,
    /// Eye distance (world units) up to which only strands are drawn.
    pub near: f32,
    /// Eye distance from which only the volume is drawn.
    pub far: f32,
    /// Alpha-blended or dithered transition.
    pub transition: Transition,
    /// Under `technique = "auto"`: the screen size (the diameter of the hair's bounding
    /// sphere in pixels) from which a head of hair is drawn as strands only (default 720).
    pub auto_near_px: f32,
    /// Under `technique = "auto"`: the screen size up to which it is drawn as the volume only
    /// (default 240); between the two, the hybrid's blend with `f = 1 - smoothstep(far, near,
    /// size)`.
    pub auto_far_px: f32,
}

impl Default for HybridSettings {
    fn default() -> Self {
        HybridSettings {
            lod: None,
            near: 100.0,
            far: 250.0,
            transition: Transition::Alpha,
            auto_near_px: 720.0,
            auto_far_px: 240.0,
        }
    }
}

impl HybridSettings {
    /// Check the ranges; the error names the setting.
    pub fn validate(&self) -> Result<(), RenderError> {
        let bad = |name: &str, why: &str| Err(RenderError::Invalid(format!("hybrid.{name} {why}")));
        if let Some(lod) = self.lod
            && !(0.0..=1.0).contains(&lod)
        {
            return bad("lod", "must be in [0, 1]");
        }
        if !(self.near >= 0.0 && self.near.is_finite()) {
            return bad("near", "must be finite and non-negative");
        }
        if !(self.far >= self.near && self.far.is_finite()) {
            return bad("far", "must be finite and at least `near`");
        }
        if !(self.auto_far_px >= 0.0 && self.auto_far_px.is_finite()) {
            return bad("auto_far_px", "must be finite and non-negative");
        }
        if !(self.auto_near_px >= self.auto_far_px && self.auto_near_px.is_finite()) {
            return bad("auto_near_px", "must be finite and at least `auto_far_px`");
        }
        Ok(())
    }

    /// The blend factor `technique = "auto"` gives a head of hair `size_px` pixels across on
    /// screen: 0 (strands) from `auto_near_px` up, 1 (volume) from `auto_far_px` down, the
    /// smooth step between.
    pub fn auto_factor(&self, size_px: f32) -> f32 {
        if size_px >= self.auto_near_px {
            0.0
        } else if size_px <= self.auto_far_px || size_px.is_nan() {
            1.0
        } else {
            let t = (size_px - self.auto_far_px) / (self.auto_near_px - self.auto_far_px);
            1.0 - t * t * (3.0 - 2.0 * t)
        }
    }

    /// The blend factor at eye distance `distance`.
    pub fn factor(&self, distance: f32) -> f32 {
        self.lod
            .unwrap_or_else(|| tress_shading::lod_factor(distance, self.near, self.far))
    }
}

/// The blend factor of a frame: 0 for strands, 1 for the volume, the hybrid's by distance from
/// the eye to `hair_center`; `auto` by the size on screen of a hair of radius 0 (see
/// [`object_factor`] for the general case).
pub fn frame_factor(
    technique: TechniqueKind,
    hybrid: &HybridSettings,
    camera: &Camera,
    hair_center: Vec3,
) -> f32 {
    object_factor(technique, hybrid, camera, (hair_center, 0.0))
}

/// The blend factor of a head of hair whose bounding sphere is `bounds` (centre, radius): 0 for
/// strands, 1 for the volume, the hybrid's by the distance from the eye to the centre, `auto`'s
/// by the sphere's size on screen ([`HybridSettings::auto_factor`]).
pub fn object_factor(
    technique: TechniqueKind,
    hybrid: &HybridSettings,
    camera: &Camera,
    bounds: (Vec3, f32),
) -> f32 {
    match technique {
        // Patches and SATF are not drawn here ([`check_technique`]).
        TechniqueKind::Strands | TechniqueKind::Patches | TechniqueKind::Satf => 0.0,
        TechniqueKind::Volume => 1.0,
        TechniqueKind::Hybrid => hybrid.factor(camera.eye().distance(bounds.0)),
        TechniqueKind::Auto => hybrid.auto_factor(ScreenExtent::of(camera, bounds).size_px),
    }
}

/// How large a bounding sphere appears on screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenExtent {
    /// The sphere's projected diameter in pixels (very large with the eye inside it).
    pub size_px: f32,
    /// The share of the frame the square around the projected sphere covers, `[0, 1]`.
    pub coverage: f32,
    /// Its centre's distance in front of the eye, along the view direction.
    pub depth: f32,
}

impl ScreenExtent {
    /// The extent of the sphere `(centre, radius)` seen by `camera` (perspective or
    /// orthographic).
    pub fn of(camera: &Camera, (center, radius): (Vec3, f32)) -> ScreenExtent {
        let [w, h] = camera.viewport.map(|v| v.max(1) as f32);
        let view = camera.view_from_world.transform_point3(center);
        let depth = -view.z;
        let scale = camera.clip_from_view.y_axis.y.abs() * h * 0.5;
        let per_unit = if camera.is_orthographic() {
            scale
        } else if depth > radius.max(1e-6) {
            scale / depth
        } else {
            // The eye is inside the sphere (or it is behind): it fills the frame.
            return ScreenExtent {
                size_px: 16.0 * w.max(h),
                coverage: if depth > -radius { 1.0 } else { 0.0 },
                depth,
            };
        };
        let r_px = radius * per_unit;
        let ndc = camera.clip_from_world().project_point3(center);
        let (cx, cy) = ((ndc.x + 1.0) * 0.5 * w, (1.0 - ndc.y) * 0.5 * h);
        let overlap = |c: f32, size: f32| ((c + r_px).min(size) - (c - r_px).max(0.0)).max(0.0);
        ScreenExtent {
            size_px: 2.0 * r_px,
            coverage: (overlap(cx, w) * overlap(cy, h) / (w * h)).clamp(0.0, 1.0),
            depth,
        }
    }
}

/// What draws one head of hair in a frame, decided before anything is encoded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FramePlan {
    /// The blend factor (0 strands, 1 volume).
    pub(crate) lod: f32,
    /// The strand rasterizer draws.
    pub(crate) strands: bool,
    /// The raymarcher draws.
    pub(crate) volume: bool,
    /// The hair is voxelized (the raymarcher or the rasterizer's volume shadows or AO need it).
    pub(crate) voxelize: bool,
    /// Shadows of the head (and the rasterizer) on.
    pub(crate) shadows: bool,
    /// Where those shadows come from.
    pub(crate) shadow_mode: ShadowMode,
    /// The rasterizer multiplies by the volume's ambient occlusion.
    pub(crate) raster_ao: bool,
    /// How the layers mix when both draw.
    pub(crate) transition: Transition,
    /// Both draw into the frame's pixels split by the 4 × 4 dither, without layers (a hybrid
    /// head of hair in a frame of several, which shares the frame's OIT).
    pub(crate) dither: bool,
    /// The hair's size on screen.
    pub(crate) extent: ScreenExtent,
    /// Why it is drawn otherwise than asked.
    pub(crate) fallback: Option<&'static str>,
}

impl FramePlan {
    /// The plan of `hair` (none: only the head) drawn with `technique`, alone in its frame or
    /// (`several`) beside other heads of hair.
    pub(crate) fn new(
        technique: TechniqueKind,
        settings: (&HybridSettings, &StrandSettings, &VolumeSettings),
        camera: &Camera,
        hair: Option<&StrandGeometry>,
        several: bool,
    ) -> Self {
        let (hybrid, strands, volume) = settings;
        let has_hair = hair.is_some_and(|h| h.segment_count() > 0);
        let bounds = hair.map_or((Vec3::ZERO, 0.0), |h| h.bounds);
        let mut lod = object_factor(technique, hybrid, camera, bounds);
        if several {
            // Dithered in the frame: below the smallest threshold of the 4 × 4 dither no pixel
            // shows the volume, above the largest none shows the strands, so the other renderer
            // need not draw at all.
            let (lo, hi) = (0.5 / 16.0, 15.5 / 16.0);
            if lod < lo {
                lod = 0.0;
            } else if lod > hi {
                lod = 1.0;
            }
        }
        let mut plan = Self::with_factor(lod, has_hair, hybrid, strands, volume);
        plan.dither = several && plan.blend();
        plan.extent = ScreenExtent::of(camera, bounds);
        plan
    }

    fn with_factor(
        lod: f32,
        has_hair: bool,
        hybrid: &HybridSettings,
        strands: &StrandSettings,
        volume: &VolumeSettings,
    ) -> Self {
        let draw_strands = has_hair && lod < 1.0;
        let draw_volume = has_hair && lod > 0.0;
        let raster_ao = draw_strands && strands.ao;
        let voxelize = draw_volume
            || raster_ao
            || (draw_strands && strands.shadows && strands.shadow_mode == ShadowMode::Volume);
        // The head follows the rasterizer's shadows when it draws, else the volume's.
        let (shadows, shadow_mode) = if draw_volume && !draw_strands {
            (volume.shadows, ShadowMode::Volume)
        } else if voxelize {
            (strands.shadows, strands.shadow_mode)
        } else {
            (strands.shadows, ShadowMode::Adsm)
        };
        FramePlan {
            lod,
            strands: draw_strands,
            volume: draw_volume,
            voxelize,
            shadows,
            shadow_mode,
            raster_ao,
            transition: hybrid.transition,
            dither: false,
            extent: ScreenExtent {
                size_px: 0.0,
                coverage: 0.0,
                depth: 0.0,
            },
            fallback: None,
        }
    }

    /// This plan as strands alone, without anything from the volume (its volume did not fit
    /// the budget): `why` is reported.
    pub(crate) fn strands_only(
        &self,
        why: &'static str,
        hybrid: &HybridSettings,
        strands: &StrandSettings,
        volume: &VolumeSettings,
    ) -> Self {
        let plain = StrandSettings {
            ao: false,
            shadow_mode: ShadowMode::Adsm,
            ..strands.clone()
        };
        FramePlan {
            extent: self.extent,
            fallback: Some(why),
            ..Self::with_factor(0.0, self.strands || self.volume, hybrid, &plain, volume)
        }
    }

    /// Both renderers draw: into scratch layers, then blended (or dithered in the frame).
    pub(crate) fn blend(&self) -> bool {
        self.strands && self.volume
    }

    /// What drew the hair: strands, volume or hybrid (strands with no hair).
    pub(crate) fn drawn(&self) -> TechniqueKind {
        match (self.strands, self.volume) {
            (true, true) => TechniqueKind::Hybrid,
            (false, true) => TechniqueKind::Volume,
            _ => TechniqueKind::Strands,
        }
    }
}

/// The blend pass (`lod_blend.wgsl`).
#[derive(Debug)]
pub struct LodBlend {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
}

/// Two premultiplied scratch layers of one target size.
#[derive(Debug)]
pub(crate) struct LodLayers {
    pub(crate) size: [u32; 2],
    pub(crate) strands: wgpu::TextureView,
    pub(crate) volume: wgpu::TextureView,
}

impl LodLayers {
    pub(crate) fn new(
        ctx: &GpuContext,
        size: [u32; 2],
        format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        ctx.scoped("allocating the LOD layers", || {
            let layer = |name: &str| {
                screen_layer(ctx, &format!("lod/lod_blend/{name}-layer"), size, format)
            };
            LodLayers {
                size,
                strands: layer("strands"),
                volume: layer("volume"),
            }
        })
    }

    /// Record clears of both layers to transparent.
    pub(crate) fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        for view in [&self.strands, &self.volume] {
            encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("lod/lod_blend/clear-pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
        }
    }
}

impl LodBlend {
    pub(crate) fn new(
        ctx: &GpuContext,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "lod_blend.wgsl", "lod/lod_blend/shader")?;
        ctx.scoped("creating the LOD blend pipeline", || {
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let layout = bind_group_layout(
                ctx,
                "lod/lod_blend/layout",
                &[
                    texture_2d(0, fragment),
                    texture_2d(1, fragment),
                    uniform(2, fragment),
                ],
            );
            let pipeline_layout =
                pipeline_layout(ctx, "lod/lod_blend/pipeline-layout", &[Some(&layout)]);
            let pipeline = RasterPipeline {
                targets: &[Some(premultiplied_over(color_format))],
                ..RasterPipeline::new("lod/lod_blend/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
            let params = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lod/lod_blend/params"),
                size: std::mem::size_of::<LodParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            LodBlend {
                pipeline,
                layout,
                params,
            }
        })
    }

    /// Record the blend of `layers` by the plan's factor and transition over `color`.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        layers: &LodLayers,
        plan: &FramePlan,
        color: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let params = LodParams {
            factor: plan.lod,
            transition: match plan.transition {
                Transition::Alpha => 0,
                Transition::Dither => 1,
            },
            ..Default::default()
        };
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let group = bind_group(
            ctx,
            "lod/lod_blend/bind-group",
            &self.layout,
            &[
                (0, wgpu::BindingResource::TextureView(&layers.strands)),
                (1, wgpu::BindingResource::TextureView(&layers.volume)),
                (2, self.params.as_entire_binding()),
            ],
        );
        let mut pass = over_color_pass(encoder, "lod/lod_blend/pass", color, timestamps);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factor_follows_distance_or_the_fixed_lod() {
        let h = HybridSettings {
            near: 10.0,
            far: 20.0,
            ..Default::default()
        };
        h.validate().unwrap();
        assert_eq!(h.factor(5.0), 0.0);
        assert_eq!(h.factor(15.0), 0.5);
        assert_eq!(h.factor(25.0), 1.0);
        let fixed = HybridSettings {
            lod: Some(0.3),
            ..h.clone()
        };
        assert_eq!(fixed.factor(1000.0), 0.3);
        let cam = Camera::look_at(
            Vec3::new(0.0, 0.0, 15.0),
            Vec3::ZERO,
            Vec3::Y,
            0.8,
            0.1,
            100.0,
            [8, 8],
        );
        assert!((frame_factor(TechniqueKind::Hybrid, &h, &cam, Vec3::ZERO) - 0.5).abs() < 1e-5);
        assert_eq!(
            frame_factor(TechniqueKind::Strands, &h, &cam, Vec3::ZERO),
            0.0
        );
        assert_eq!(
            frame_factor(TechniqueKind::Volume, &h, &cam, Vec3::ZERO),
            1.0
        );
    }

    #[test]
    fn bad_settings_name_themselves() {
        for (h, name) in [
            (
                HybridSettings {
                    lod: Some(1.5),
                    ..Default::default()
                },
                "hybrid.lod",
            ),
            (
                HybridSettings {
                    near: -1.0,
                    ..Default::default()
                },
                "hybrid.near",
            ),
            (
                HybridSettings {
                    near: 5.0,
                    far: 4.0,
                    ..Default::default()
                },
                "hybrid.far",
            ),
        ] {
            let e = h.validate().unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
        for t in TechniqueKind::ALL {
            assert_eq!(check_technique(t).is_ok(), t.per_object(), "{t}");
        }
        assert!(check_technique(TechniqueKind::Auto).is_ok());
        let e = check_technique(TechniqueKind::Satf)
            .unwrap_err()
            .to_string();
        assert!(e.contains("satf"), "{e}");
        for t in [Transition::Alpha, Transition::Dither] {
            assert_eq!(t.name().parse::<Transition>().unwrap(), t);
        }
    }
}
