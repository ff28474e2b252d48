//! The hybrid technique's folder (Jansson et al. 2019 §3 "Overview", §4): the [`Renderer`] that
//! draws the strand rasterizer ([`crate::strands`]), the volume raymarcher ([`crate::volume`])
//! and their level-of-detail blend for one or several heads of hair (`renderer.rs`, one frame
//! top to bottom), what draws each head of hair (`plan.rs`: the blend factor by distance, or by
//! its size on screen under `auto`) and the blend pass ([`LodBlend`]).
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

use crate::RenderError;

pub mod budget;
mod lod_blend;
mod plan;
pub(crate) mod renderer;
mod technique;

pub use lod_blend::LodBlend;
pub(crate) use lod_blend::LodLayers;
pub(crate) use plan::FramePlan;
pub use plan::{ScreenExtent, frame_factor, object_factor};
pub use renderer::{FrameInputs, HairObject, MAX_ATTEMPTS, MAX_OBJECTS, PASS_NAMES, Renderer};
pub(crate) use technique::StrandTechnique;

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
    /// Under `technique = "auto"` with several characters: the GPU milliseconds a frame may
    /// take. Each character's choice by size is kept, nearest first, while it fits beside the
    /// cheapest the farther ones can be drawn; otherwise it is drawn as the cheaper renderer
    /// that fits (strands before the volume), by costs measured on this device
    /// ([`budget`]). `None` (default): no budget, the choice by size alone.
    pub budget_ms: Option<f32>,
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
            budget_ms: None,
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
        if let Some(ms) = self.budget_ms
            && !(ms > 0.0 && ms.is_finite())
        {
            return bad("budget_ms", "must be positive and finite");
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Camera;
    use glam::Vec3;

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
