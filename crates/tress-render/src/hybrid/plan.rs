//! What draws one head of hair in a frame: its blend factor (by distance, or by its size on
//! screen under `auto`) and the [`FramePlan`] the renderer encodes.

use glam::Vec3;

use super::{HybridSettings, TechniqueKind, Transition};
use crate::Camera;
use crate::strands::{StrandGeometry, StrandSettings};
use crate::volume::{ShadowMode, VolumeSettings};

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

    /// This plan at another blend factor (`hybrid.budget_ms` chose it), drawn among several
    /// heads of hair (dithered when both renderers draw).
    pub(crate) fn at_factor(
        &self,
        lod: f32,
        (hybrid, strands, volume): (&HybridSettings, &StrandSettings, &VolumeSettings),
    ) -> Self {
        let mut plan = Self::with_factor(lod, self.strands || self.volume, hybrid, strands, volume);
        plan.dither = plan.blend();
        plan.extent = self.extent;
        plan.fallback = self.fallback;
        plan
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
