//! Semantics-aware texture function hair (Xu et al. 2006, `satf`): hair clusters drawn as layered
//! generalized-cylinder shells whose reflectance and opacity maps come, every frame, from an
//! off-line HRIR database, lit, self-shadowed and blended on the GPU.
//!
//! The CPU side (clusters, density fields, the database and its bake, the CPU twins of the
//! online math) lives in [`tress_satf`]; this module uploads clusters ([`SatfGeometry`]) and the
//! database ([`SatfDatabase`]) and runs the online phase ([`SatfRenderer`]). [`scene`] turns a
//! scene's `[satf]` table into [`SatfSettings`] and its hair into clusters.
//!
//! # Implementation
//!
//! Paper: Z. Xu, X. D. Yang, "A Hybrid Off-line/On-line Approach to Hair Rendering" (2006),
//! `papers/xu-2006-satf.txt`. A frame (`renderer.rs`) runs the on-line phase of §6.1 / Figure 3
//! as the stages the paper times in Table 1, each a timed GPU pass:
//!
//! | Table 1 | pass (`.wgsl` ↔ owner) | what |
//! | --- | --- | --- |
//! | I, index calculation | `index_calc` ↔ [`IndexCalc`] | §6.2.1: per boundary sector `Params(b) = (ρ_feature, θ_v, θ_l)` and its nearest database sample; per HSV equation 6 and the records to use |
//! | C, map construction | `map_build` ↔ [`MapBuild`] | §6.2.2: re-map and α-map texels by sweeping the averaged record (uniform HSV) or equation 7 between the two boundary records |
//! | S, shadowing | `cluster_shadow` ↔ [`ClusterShadow`], `s_maps` ↔ [`SMaps`] | §6.4: s-maps by equation 12; shadows between clusters |
//! | L, lighting | `lighting` ↔ [`Lighting`] | §6.3: equations 8–11 per point |
//! | M, texture mapping | `texture_map` ↔ [`TextureMap`] | §6.5: the layer meshes with their maps, equation 13, blending by equation 14 |
//!
//! plus the head (`head` ↔ [`SatfHead`]), drawn first. Every formula lives in `online.wgsl`, the
//! twin of `tress_satf::online` / `database` (tests/satf_math.rs compares them on the GPU).
//!
//! - **Structure (§3.2, §6.1).** With the sampling of equation 3 ([`ShellSampling`]: `s_t`, `s_v`,
//!   `s_u`, the innermost `core_rings` rings forming the transparent core), layer `k` of a
//!   cluster is ring `core_rings + k`; its mesh is its outer surface `v = v_{j+1}`, tessellated
//!   into `s_t · mesh_t` by `s_u · mesh_u` quads with texture coordinates `(u / 2π, t)`, so
//!   `P(u,v),k` and `P(u,v),k+1` share texture coordinates as §6.1 says.
//! - **Maps.** Each layer of each cluster owns a tile of one atlas: `s_u · pixels` texels around
//!   (HRIR pixel `j` of sector `m` is column `m · pixels + j`, the HRIR's `s` axis running with
//!   `u`) by `s_t · map_rows` texels along. Row `r` of an HSV's rows holds `γ = r / (rows − 1)`
//!   like `tress_satf::Database::hsv_maps`, so the first and last rows carry the boundary
//!   records exactly. Choice: **the database's `θ_l` is the key light's** ([`SatfSettings::key_light`],
//!   default the first light): an HRIR carries one light direction, the paper has one light.
//! - **Index calculation.** The density features `ρ_feature` of every boundary sector depend
//!   only on the strands, so they are computed once when the clusters are uploaded
//!   ([`SatfGeometry::new`], CPU, `tress_satf::shell::cluster_features`, timed as
//!   [`SatfGeometry::features_ms`]); the GPU pass does the per-frame part: the view and light
//!   azimuths at each sector's anchor (the middle of its outer arc), the nearest sample by the
//!   weighted feature distance (brute force over the samples), equation 6 with
//!   [`tress_satf::LookupSettings`] and, for uniform HSVs, the nearest sample of `Params_ave`.
//! - **Reflectance** ([`Reflectance`]). An HRIR's `r̂e` is accumulated by equation 5 and so already
//!   carries the ray's opacity; equation 14 multiplies by `α` again. The default
//!   [`Reflectance::Straight`] divides it out (`r̂e / α̂`), so coverage counts once;
//!   [`Reflectance::Premultiplied`] uses `r̂e` as stored, the literal reading.
//! - **Lighting (equations 8–11)** per texel of every layer (the paper's "for each `P(u,v),k`"),
//!   at the layer surface interpolated from the mesh (`texel_geometry.wgsl`), with `v` toward the
//!   camera. Several lights add, each times its color × intensity and its visibility through
//!   other clusters; the frame's ambient light adds `ambient · f_dif`. With the default white
//!   light `f_speI` is the light's color as §6.3 says.
//!   **SATF keeps its paper's lighting** under `strands.shading = "marschner"` (and has no
//!   `shading` key of its own): equations 8–11 mix the database's `r̂e` (Phong on the
//!   density gradient, §5.1) with Kajiya-Kay's diffuse and shifted specular lobes; a physically
//!   based fibre would need HRIRs traced with its BSDF, which the paper's off-line phase does
//!   not define. `tress bench --quality --shading marschner` scores it as it is.
//! - **Shadows.** Within a cluster, equation 12 ([`tress_satf::online::ShadowApprox`]: the
//!   exponential definition by default, or its linear form), `c(k)` = the layers outside `k` at the
//!   same texel. Between clusters the paper casts shadow volumes; **here a shadow map is the
//!   departure**: per light, the outermost layer mesh of every cluster and the head are drawn
//!   from the light, keeping the nearest surface's depth and its cluster id, and a point is
//!   shadowed (by [`SatfSettings::shadow_opacity`], since a cluster is translucent) where
//!   another cluster or the head lies nearer the light by more than
//!   [`SatfSettings::shadow_bias`], with a PCF kernel of [`SatfSettings::pcf_radius`]. A
//!   cluster never shadows itself through the map: that is equation 12's job, as in the paper.
//!   The head receives the clusters' shadows.
//! - **Blending (equation 14).** Within a cluster the eye ray meets the far half's layers from
//!   the outside in and then the near half's from the inside out, so each cluster is drawn as
//!   back faces of layers `n−1 … 0` then front faces of `0 … n−1`, each fragment the
//!   premultiplied `(Y α, α)` with blend One / OneMinusSrcAlpha: exactly equation 14 with
//!   `Y_bk` what lies behind (background, head, other clusters); the core is transparent.
//!   Clusters are sorted back to front by the distance of their bounding sphere's centre each
//!   frame; intersecting clusters blend in that order (the paper does not say more). The far
//!   half uses the same maps: a sector seen from the core side has `|θ_v| > π/2`, which the
//!   database covers (its rays cross the shell from the inner face).
//!
//! # Performance (Table 1's stages)
//!
//! `tress render --technique satf --json` reports the stages in `satf.stages_ms`. On lavapipe
//! the compute passes' timestamps were observed not to bound their work (it shows up in later
//! passes, and a stage's reading varies tenfold between frames), so these figures use `satf.stage_timing = "wall_clock"` ([`StageTiming`]): each stage submitted
//! alone and waited for. Development machine, llvmpipe (LLVM 15, 2 cores shared with other
//! builds, load about 5), release build, default settings and database (2048 samples, 16 × 16
//! angles, 16 pixels; baked in 2.3 s, 17 MiB), 800 × 450, two lights, medians of 3 runs, ms:
//!
//! | scene | C# | L# | S# | H# | I | C | M | L | S | head |
//! | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |
//! | demo ponytail, fitted clusters | 82 | 246 | 13,632 | 31,488 | 490 | 112 | 1224 | 231 | 853 | 42 |
//! | demo head, generated clusters | 60 | 180 | 9,000 | 23,040 | 259 | 85 | 378 | 161 | 644 | 28 |
//!
//! ```text
//! tress render --technique satf --set 'satf.stage_timing="wall_clock"' -o demo.png --json
//! tress render --technique satf --set 'satf.clusters="generate"' \
//!     --set 'satf.stage_timing="wall_clock"' -o generated.png --json
//! ```
//!
//! lavapipe is a CPU: the ratios, not the milliseconds, carry over. The index calculation is
//! dominated by the brute-force nearest-sample search (2048 samples per sector and per uniform
//! HSV), shadowing by the two 1024² cluster shadow maps and the 9-tap PCF per texel and light,
//! texture mapping by overdraw (six layer surfaces per cluster, 16 texel loads per fragment).
//! CPU work outside the frame: fitting 82 clusters to the ponytail 0.36 s, sector features 0.17 s.
//! No real GPU was lent to this task.

mod cluster_shadow;
mod database;
mod geometry;
mod head;
mod index_calc;
mod lighting;
mod map_build;
mod passes;
mod renderer;
mod s_maps;
pub mod scene;
pub(crate) mod scene_doc;
mod technique;
mod texture_map;

pub use cluster_shadow::ClusterShadow;
pub use database::SatfDatabase;
pub use geometry::{SatfGeometry, SatfReadback};
pub use head::SatfHead;
pub use index_calc::IndexCalc;
pub use lighting::Lighting;
pub use map_build::MapBuild;
pub use renderer::{SatfFrameInputs, SatfFrameStats, SatfRenderer};
pub use s_maps::SMaps;
pub(crate) use technique::SatfTechnique;
pub use texture_map::TextureMap;
pub use tress_satf::ShellSampling;
pub use tress_satf::database::LookupSettings;
pub use tress_satf::online::{SatfLighting, ShadowApprox};

use crate::RenderError;

/// Names of the timed passes, in frame order: Table 1's stages, plus the head.
pub const PASS_NAMES: &[&str] = &[
    "satf/index_calculation",
    "satf/map_construction",
    "satf/shadowing",
    "satf/lighting",
    "satf/head",
    "satf/texture_mapping",
];

/// What the re-maps hold (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Reflectance {
    /// `r̂e / α̂`: the average reflectance of the hair a ray met (default).
    #[default]
    Straight,
    /// `r̂e` as accumulated by equation 5 (premultiplied by the ray's opacity).
    Premultiplied,
}

impl std::str::FromStr for Reflectance {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, RenderError> {
        match s {
            "straight" => Ok(Reflectance::Straight),
            "premultiplied" => Ok(Reflectance::Premultiplied),
            _ => Err(RenderError::Invalid(format!(
                "satf.reflectance must be \"straight\" or \"premultiplied\", got \"{s}\""
            ))),
        }
    }
}

/// How [`SatfRenderer::render`] times the stages of Table 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StageTiming {
    /// GPU timestamps around each stage's passes, one submission per frame (default).
    #[default]
    Timestamps,
    /// Each stage submitted alone and waited for; CPU wall-clock milliseconds. For devices whose
    /// timestamps do not bound the work, and as a cross-check: on lavapipe the compute passes'
    /// timestamps were observed not to (map construction read 0.1 ms in one frame and 76 ms in
    /// the next, its work showing up in later passes). Slower: the GPU idles between stages.
    WallClock,
}

impl StageTiming {
    /// The frame timer's mode that times the stages this way.
    pub(crate) fn timer_mode(self) -> crate::gpu::TimerMode {
        match self {
            StageTiming::Timestamps => crate::gpu::TimerMode::Timestamps,
            StageTiming::WallClock => crate::gpu::TimerMode::WallClock,
        }
    }
}

impl std::str::FromStr for StageTiming {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, RenderError> {
        match s {
            "timestamps" => Ok(StageTiming::Timestamps),
            "wall_clock" => Ok(StageTiming::WallClock),
            _ => Err(RenderError::Invalid(format!(
                "satf.stage_timing must be \"timestamps\" or \"wall_clock\", got \"{s}\""
            ))),
        }
    }
}

/// Every setting of the SATF technique (scene table `[satf]`, see [`scene`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SatfSettings {
    /// Equation 3's sampling and the core (`s_t`, `s_v`, `s_u`, `core_rings`). Default 16, 4, 8, 1.
    pub sampling: ShellSampling,
    /// Map rows per HSV along `t`. Default 4.
    pub map_rows: u32,
    /// Layer mesh quads per HSV along `t`. Default 2.
    pub mesh_t: u32,
    /// Layer mesh quads per sector around `u`. Default 4.
    pub mesh_u: u32,
    /// Nearest-record search and equation 6 (`feature_weights`, `angle_weight`, `k_threshold`).
    pub lookup: LookupSettings,
    /// Equations 8–11.
    pub lighting: SatfLighting,
    /// `k_shadow` of equation 12. Default 0.6.
    pub k_shadow: f32,
    /// How equation 12 is evaluated. Default exponential.
    pub shadow_approx: ShadowApprox,
    /// Equation 12's s-maps on (off: `τ = 1`). Default on.
    pub local_shadows: bool,
    /// What the re-maps hold. Default [`Reflectance::Straight`].
    pub reflectance: Reflectance,
    /// The light whose azimuth indexes the database. Default 0 (the first light).
    pub key_light: u32,
    /// Shadow maps between clusters. Default on.
    pub cluster_shadows: bool,
    /// Shadow map edge in texels. Default 1024.
    pub shadow_map_size: u32,
    /// Light a shadowing cluster blocks, in `[0, 1]`. Default 0.7.
    pub shadow_opacity: f32,
    /// Depth bias of the shadow test, world units. Default 0.5 (the scenes' centimetres).
    pub shadow_bias: f32,
    /// PCF kernel radius in texels (0..=8). Default 1.
    pub pcf_radius: u32,
    /// How the stages are timed. Default [`StageTiming::Timestamps`].
    pub stage_timing: StageTiming,
}

impl Default for SatfSettings {
    fn default() -> Self {
        SatfSettings {
            sampling: ShellSampling::default(),
            map_rows: 4,
            mesh_t: 2,
            mesh_u: 4,
            lookup: LookupSettings::default(),
            lighting: SatfLighting::default(),
            k_shadow: 0.6,
            shadow_approx: ShadowApprox::Exponential,
            local_shadows: true,
            reflectance: Reflectance::Straight,
            key_light: 0,
            cluster_shadows: true,
            shadow_map_size: 1024,
            shadow_opacity: 0.7,
            shadow_bias: 0.5,
            pcf_radius: 1,
            stage_timing: StageTiming::Timestamps,
        }
    }
}

impl SatfSettings {
    /// Check every range; errors name the setting.
    pub fn validate(&self) -> Result<(), RenderError> {
        let bad = |name: &str, why: &str| Err(RenderError::Invalid(format!("satf.{name} {why}")));
        self.sampling
            .validate()
            .map_err(|e| RenderError::setting("satf sampling", e))?;
        for (name, n, max) in [
            ("map_rows", self.map_rows, 64),
            ("mesh_t", self.mesh_t, 64),
            ("mesh_u", self.mesh_u, 64),
        ] {
            if !(1..=max).contains(&n) {
                return bad(name, &format!("must be in 1..={max}, got {n}"));
            }
        }
        let l = &self.lookup;
        if l.feature_weights
            .iter()
            .any(|w| !(w.is_finite() && *w >= 0.0))
        {
            return bad("feature_weights", "must be finite and non-negative");
        }
        if !(l.angle_weight.is_finite() && l.angle_weight >= 0.0) {
            return bad("angle_weight", "must be finite and non-negative");
        }
        if !(l.k_threshold.is_finite() && l.k_threshold >= 0.0) {
            return bad("k_threshold", "must be finite and non-negative");
        }
        let p = &self.lighting;
        for (name, x) in [
            ("k_dif", p.k_dif),
            ("k_spe1", p.k_spe1),
            ("k_spe2", p.k_spe2),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return bad(name, "must be finite and non-negative");
            }
        }
        for (name, c) in [
            ("f_dif", p.f_dif),
            ("f_spe1", p.f_spe1),
            ("f_spe2", p.f_spe2),
        ] {
            if !(c.is_finite() && c.min_element() >= 0.0) {
                return bad(name, "must be a finite non-negative color");
            }
        }
        if !(p.primary_shift.is_finite() && p.secondary_shift.is_finite()) {
            return bad("primary_shift / secondary_shift", "must be finite");
        }
        if !(p.k_h.is_finite() && p.k_h > 0.0) {
            return bad("k_h", "must be positive");
        }
        if !(self.k_shadow.is_finite() && self.k_shadow >= 0.0) {
            return bad("k_shadow", "must be finite and non-negative");
        }
        if self.key_light >= crate::MAX_LIGHTS as u32 {
            return bad("key_light", &format!("must be below {}", crate::MAX_LIGHTS));
        }
        if !(16..=8192).contains(&self.shadow_map_size) {
            return bad("shadow_map_size", "must be in 16..=8192");
        }
        if !(0.0..=1.0).contains(&self.shadow_opacity) {
            return bad("shadow_opacity", "must be in [0, 1]");
        }
        if !(self.shadow_bias.is_finite() && self.shadow_bias >= 0.0) {
            return bad("shadow_bias", "must be finite and non-negative");
        }
        if self.pcf_radius > 8 {
            return bad("pcf_radius", "must be at most 8");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_ranges_are_named() {
        SatfSettings::default().validate().unwrap();
        let err = SatfSettings {
            map_rows: 0,
            ..Default::default()
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(err.contains("satf.map_rows"), "{err}");
        let err = SatfSettings {
            shadow_opacity: 1.5,
            ..Default::default()
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(err.contains("shadow_opacity"), "{err}");
        let mut s = SatfSettings::default();
        s.sampling.core_rings = s.sampling.sv;
        assert!(s.validate().is_err());
        assert_eq!(
            "premultiplied".parse::<Reflectance>().unwrap(),
            Reflectance::Premultiplied
        );
        assert!("other".parse::<Reflectance>().is_err());
    }
}
