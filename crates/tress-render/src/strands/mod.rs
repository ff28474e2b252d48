//! The strand rasterizer of Jansson et al. 2019 (`strands`): strands drawn as screen-width
//! ribbons, Kajiya-Kay or Scheuermann shading, analytic coverage anti-aliasing, a per-pixel
//! linked list (PPLL) k-buffer for order-independent transparency, and approximated deep shadow
//! maps (ADSM).
//!
//! # Implementation
//!
//! Passes, in frame order (see `hybrid/renderer.rs`): [`ShadowMap`] (`shadow.wgsl`), the head pass, then
//! either [`PpllBuild`] (`ppll_build.wgsl`) and [`PpllResolve`] (`ppll_resolve.wgsl`), or
//! [`ShortcutDepth`], [`ShortcutShade`] and [`ShortcutResolve`] (`shortcut_*.wgsl`).
//!
//! - **Geometry (§3, Figure 2).** Strands are lists of straight segments. The paper rasterizes
//!   GPU lines of constant width; wgpu only draws 1-pixel lines, so the vertex shader expands each
//!   segment into a camera-facing quad `width_px` pixels wide, pulling vertices from storage
//!   buffers (six vertices per segment, no index buffer). Segments with an end behind the eye are
//!   culled.
//! - **Lighting (§3.1).** Kajiya-Kay with the tangent `(Q - P) / |Q - P|` of the segment
//!   (`shading = "kajiya-kay"`), or Scheuermann's dual shifted highlights
//!   (`shading = "scheuermann"`). Strands have no surface normal; for Scheuermann the normal is the
//!   direction from the centre of the hair's bounds to the fragment, made perpendicular to the
//!   tangent, and the shift/noise textures are replaced by one random value per strand (a hash of
//!   its index), which varies the highlight from strand to strand as the textures do.
//! - **Coverage (§3.2, listing `strand_coverage`).** The fragment's distance to the projected
//!   centre line, divided by half the width, gives a coverage in `[0, 1]` multiplied into alpha
//!   (`coverage = false` shows the aliased look of Figure 3, left). Alpha is the strand alpha
//!   setting times the asset's `1 - transparency`, times the tip fade when the asset has thickness
//!   (`thickness_fade`): by default (`"tip"`) alpha is scaled by the vertex's thickness relative
//!   to the asset's thickest vertex, so tapered tips fade out while roots keep the strand alpha;
//!   `"projected"` scales it by the fraction of the drawn width the projected thickness covers,
//!   a physical sub-pixel coverage that makes real (70 µm) hair very faint at usual distances.
//! - **Sorting and blending (§3.2).** The build pass shades each fragment and inserts
//!   `{color, alpha, depth, next}` into its pixel's list with an atomic exchange on a per-pixel head
//!   buffer and an atomic node counter; depth writes are off. Fragments behind the head are
//!   rejected against the head's depth in the shader (the fixed-function depth test cannot stop
//!   side effects). The pool is checked with `>= capacity` and dropped fragments are counted
//!   (design rule 8). The resolve pass keeps the `k` nearest fragments sorted (default 16, the
//!   paper's k-buffer size), blends them front to back and merges the rest with the
//!   order-independent weighted average of `tress_shading::blend`, under the front `k`; the result
//!   is blended over the head.
//! - **Node pool.** The pool starts at `ppll_nodes_per_pixel` nodes per target pixel (default 8:
//!   112.5 MiB of nodes + 3.5 MiB of heads at 1280x720) and never exceeds `ppll_max_bytes`
//!   (default 512 MiB) nor [`NODE_CHUNKS`] storage bindings of the device's largest size (one
//!   binding is 128 MiB on lavapipe, so the pool is spread over up to four buffers,
//!   `common/ppll_pool.wgsl`). When a frame dropped fragments, the next frame grows the pool to
//!   1.25x the nodes requested, up to the cap; an offline frame (statistics waited for, targets
//!   cleared by the frame) is rendered again at once with the grown pool, so a single render
//!   comes out complete when the cap allows.
//! - **Bounded-memory OIT (beyond the paper).** `oit = "shortcut"` replaces the lists with
//!   TressFX 4.1's ShortCut, whose memory is fixed by the screen and `shortcut_k`, and which
//!   never drops a fragment; `oit = "auto"` (the default) draws with the PPLL while its grown
//!   pool holds the frame and with ShortCut otherwise, so the paper's scenes at 1280x720 lose
//!   nothing. See [`oit`].
//! - **Self-shadowing (§3.4, ADSM after Lacroix).** One depth map per light (`shadow_map_size`,
//!   default 1024) holds the nearest hair or head depth from the light (orthographic, fitted to
//!   the bounds of hair and head). A fragment `d` world units behind the stored depth gets the
//!   visibility `(1 - alpha)^(d · r)` with `r = shadow_r` strands per world unit and
//!   `alpha = shadow_alpha`, averaged over a `(2 · pcf_radius + 1)²` texel kernel (PCF). The head
//!   receives the same shadows, so hair shadows the scalp.
//! - **Volume shadows and ambient occlusion (§3.4).** With `shadow_mode = "volume"` the hair is
//!   voxelized every frame ([`crate::volume`]) and `d · r` is replaced by the strands counted
//!   through the density volume towards the light (no shadow maps are drawn); with `ao = true`
//!   the shaded color is multiplied by the volume's local ambient occlusion. Both default off, so
//!   the rasterizer alone is the paper's TressFX-like baseline.

mod geometry;
pub mod oit;
pub(crate) mod ppll;
pub(crate) mod ppll_build;
pub(crate) mod ppll_readback;
mod ppll_resolve;
mod shadow;
mod shortcut;
mod shortcut_depth;
mod shortcut_resolve;
mod shortcut_shade;

use std::fmt;
use std::str::FromStr;

pub use geometry::StrandGeometry;
pub use oit::{Oit, OitKind, OitStats};
pub(crate) use ppll::PpllPool;
pub use ppll::{NODE_BYTES, NODE_CHUNKS, PpllStats};
pub use ppll_build::PpllBuild;
pub use ppll_readback::{PpllFragments, unpack_rgb9e5};
pub use ppll_resolve::{MAX_K, PpllResolve};
pub(crate) use shadow::ShadowCasters;
pub use shadow::ShadowMap;
pub use shortcut::{MAX_SHORTCUT_K, shortcut_bytes};
pub use shortcut_depth::ShortcutDepth;
pub use shortcut_resolve::ShortcutResolve;
pub use shortcut_shade::ShortcutShade;
/// The CPU twins a [`PpllFragments`] readback is composited with.
pub use tress_shading::{StrandFragment, resolve_k_buffer};

use crate::RenderError;
use crate::gpu::types::StrandParams;
use crate::volume::ShadowMode;

/// Strand shading model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// Kajiya-Kay diffuse + specular (§3.1), `"kajiya-kay"`.
    #[default]
    KajiyaKay,
    /// Scheuermann's dual shifted highlights, `"scheuermann"`.
    Scheuermann,
    /// Physically based: Marschner's R, TT and TRT lobes (Karis 2016) with dual scattering
    /// driven by the strands ADSM counts towards each light, from the material's fibre
    /// (`[hair.material]` melanin, roughness, tilt, η), `"marschner"`.
    Marschner,
}

impl Shading {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            Shading::KajiyaKay => "kajiya-kay",
            Shading::Scheuermann => "scheuermann",
            Shading::Marschner => "marschner",
        }
    }
}

impl fmt::Display for Shading {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Shading {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "kajiya-kay" => Ok(Shading::KajiyaKay),
            "scheuermann" => Ok(Shading::Scheuermann),
            "marschner" => Ok(Shading::Marschner),
            _ => Err(RenderError::Invalid(format!(
                "unknown shading `{s}` (expected kajiya-kay, scheuermann or marschner)"
            ))),
        }
    }
}

/// How strand alpha follows the asset's per-vertex thickness.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ThicknessFade {
    /// Thickness does not change alpha, `"off"`.
    Off,
    /// Alpha times thickness over the asset's thickest vertex: tapered tips fade out, roots keep
    /// the strand alpha, `"tip"`.
    #[default]
    Tip,
    /// Alpha times the fraction of the drawn width the projected thickness covers (physical
    /// sub-pixel coverage; real hair is far thinner than a pixel, so it is faint), `"projected"`.
    Projected,
}

impl ThicknessFade {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            ThicknessFade::Off => "off",
            ThicknessFade::Tip => "tip",
            ThicknessFade::Projected => "projected",
        }
    }
}

impl FromStr for ThicknessFade {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "off" => Ok(ThicknessFade::Off),
            "tip" => Ok(ThicknessFade::Tip),
            "projected" => Ok(ThicknessFade::Projected),
            _ => Err(RenderError::Invalid(format!(
                "unknown thickness_fade `{s}` (expected off, tip or projected)"
            ))),
        }
    }
}

/// Largest PCF radius (a 17x17 kernel), as in `tress_shading::MAX_PCF_RADIUS`.
pub const MAX_PCF_RADIUS: u32 = tress_shading::MAX_PCF_RADIUS as u32;

/// Settings of the strand technique. Every parameter the paper names is here.
#[derive(Clone, Debug, PartialEq)]
pub struct StrandSettings {
    /// Ribbon width in pixels (the paper's constant line width).
    pub width_px: f32,
    /// Strand opacity, multiplied with the asset's `1 - transparency`.
    pub alpha: f32,
    /// Shading model.
    pub shading: Shading,
    /// Under `shading = "marschner"`: light scattered through other strands (dual scattering's
    /// forward and backward terms) on top of each strand's own R, TT and TRT lobes; `false`
    /// keeps single scattering only, the reference tracer's `trace.bounces = 0` (to measure what
    /// multiple scattering adds). Strands and raymarcher alike.
    pub multiple_scattering: bool,
    /// Multiply alpha by the §3.2 line coverage.
    pub coverage: bool,
    /// How alpha follows the asset's thickness (when it has thickness).
    pub thickness_fade: ThicknessFade,
    /// The order-independent transparency (module [`oit`]): the paper's PPLL, ShortCut, or the
    /// choice per frame (default) that never loses a fragment offline.
    pub oit: Oit,
    /// Fragments per pixel blended in sorted order by the PPLL (the k-buffer size),
    /// `1..=MAX_K`.
    pub k: u32,
    /// Initial PPLL node pool, in nodes per target pixel.
    pub ppll_nodes_per_pixel: f32,
    /// Cap of the node pool in bytes (also bounded by [`NODE_CHUNKS`] of the device's largest
    /// storage binding: 512 MiB on lavapipe).
    pub ppll_max_bytes: u64,
    /// Nearest depths per pixel ShortCut keeps, `1..=MAX_SHORTCUT_K` (default 8: 61.5 MiB at
    /// 1280x720): the `k - 1` nearer fragments are blended in sorted order, the k-th opens the
    /// tail.
    pub shortcut_k: u32,
    /// ADSM self-shadowing on/off.
    pub shadows: bool,
    /// Shadow map edge in texels.
    pub shadow_map_size: u32,
    /// ADSM `r`: expected strands per world unit of depth inside the hair (the default, 4, is
    /// meant for the centimetre-like units of `tress_hair`'s generators).
    pub shadow_r: f32,
    /// ADSM `alpha`: opacity of one occluding strand.
    pub shadow_alpha: f32,
    /// PCF kernel radius in texels (`0..=MAX_PCF_RADIUS`; 1 is a 3x3 kernel).
    pub pcf_radius: u32,
    /// Shadow depth bias in world units.
    pub shadow_bias: f32,
    /// Ribbon width in shadow-map texels.
    pub shadow_width_px: f32,
    /// Self-shadowing from ADSM maps or from the hair volume (§3.4; the volume's march settings
    /// are in [`crate::volume::VolumeSettings`]).
    pub shadow_mode: ShadowMode,
    /// Multiply the shaded color by the hair volume's local ambient occlusion (§3.4).
    pub ao: bool,
}

impl Default for StrandSettings {
    fn default() -> Self {
        StrandSettings {
            width_px: 1.5,
            alpha: 0.6,
            shading: Shading::KajiyaKay,
            multiple_scattering: true,
            coverage: true,
            thickness_fade: ThicknessFade::Tip,
            oit: Oit::Auto,
            k: 16,
            ppll_nodes_per_pixel: 8.0,
            ppll_max_bytes: 512 << 20,
            shortcut_k: 8,
            shadows: true,
            shadow_map_size: 1024,
            shadow_r: 4.0,
            shadow_alpha: 0.25,
            pcf_radius: 1,
            shadow_bias: 0.05,
            shadow_width_px: 1.0,
            shadow_mode: ShadowMode::Adsm,
            ao: false,
        }
    }
}

impl StrandSettings {
    /// Check every setting's range; the error names the setting.
    pub fn validate(&self) -> Result<(), RenderError> {
        let bad =
            |name: &str, why: &str| Err(RenderError::Invalid(format!("strands.{name} {why}")));
        if !(self.width_px > 0.0 && self.width_px <= 64.0) {
            return bad("width_px", "must be in (0, 64]");
        }
        if !(0.0..=1.0).contains(&self.alpha) {
            return bad("alpha", "must be in [0, 1]");
        }
        if !(1..=MAX_K).contains(&self.k) {
            return bad("k", &format!("must be in 1..={MAX_K}"));
        }
        if !(self.ppll_nodes_per_pixel > 0.0 && self.ppll_nodes_per_pixel <= 1024.0) {
            return bad("ppll_nodes_per_pixel", "must be in (0, 1024]");
        }
        if self.ppll_max_bytes < NODE_BYTES {
            return bad("ppll_max_bytes", "must hold at least one node");
        }
        if !(1..=MAX_SHORTCUT_K).contains(&self.shortcut_k) {
            return bad("shortcut_k", &format!("must be in 1..={MAX_SHORTCUT_K}"));
        }
        if !(16..=8192).contains(&self.shadow_map_size) {
            return bad("shadow_map_size", "must be in 16..=8192");
        }
        if !(self.shadow_r >= 0.0 && self.shadow_r.is_finite()) {
            return bad("shadow_r", "must be finite and non-negative");
        }
        if !(0.0..=1.0).contains(&self.shadow_alpha) {
            return bad("shadow_alpha", "must be in [0, 1]");
        }
        if self.pcf_radius > MAX_PCF_RADIUS {
            return bad("pcf_radius", &format!("must be at most {MAX_PCF_RADIUS}"));
        }
        if !self.shadow_bias.is_finite() {
            return bad("shadow_bias", "must be finite");
        }
        if !(self.shadow_width_px > 0.0 && self.shadow_width_px <= 64.0) {
            return bad("shadow_width_px", "must be in (0, 64]");
        }
        Ok(())
    }

    /// The GPU uniform for a frame (fields that depend on the frame filled by the caller).
    pub(crate) fn params(&self) -> StrandParams {
        StrandParams {
            width_px: self.width_px,
            alpha: self.alpha,
            k: self.k,
            shortcut_k: self.shortcut_k,
            shading: match self.shading {
                Shading::KajiyaKay => 0,
                Shading::Scheuermann => 1,
                Shading::Marschner => 2,
            },
            coverage: u32::from(self.coverage),
            shadow_r: self.shadow_r,
            shadow_alpha: self.shadow_alpha,
            pcf_radius: self.pcf_radius as i32,
            shadow_bias: self.shadow_bias,
            shadow_map_size: self.shadow_map_size as f32,
            shadow_width_px: self.shadow_width_px,
            shadows: u32::from(self.shadows),
            ..Default::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_fit_720p_in_128_mib() {
        let s = StrandSettings::default();
        s.validate().expect("defaults are valid");
        let pixels = 1280.0 * 720.0;
        let nodes = (pixels * s.ppll_nodes_per_pixel) as u64;
        let total = nodes * NODE_BYTES + pixels as u64 * 4;
        assert!(total <= 128 << 20, "{total}");
        assert!(nodes * NODE_BYTES <= s.ppll_max_bytes);
        assert_eq!(s.k, 16);
        assert_eq!(s.shadow_map_size, 1024);
        assert_eq!(s.oit, Oit::Auto);
        assert!(shortcut_bytes([1280, 720], s.shortcut_k) <= 64 << 20);
    }

    #[test]
    fn oit_names_round_trip() {
        for o in [Oit::Auto, Oit::Ppll, Oit::Shortcut] {
            assert_eq!(o.name().parse::<Oit>().unwrap(), o);
        }
        assert!("weighted".parse::<Oit>().is_err());
    }

    #[test]
    fn out_of_range_settings_name_themselves() {
        let cases: [(StrandSettings, &str); 6] = [
            (
                StrandSettings {
                    shortcut_k: 17,
                    ..Default::default()
                },
                "strands.shortcut_k",
            ),
            (
                StrandSettings {
                    k: 0,
                    ..Default::default()
                },
                "strands.k",
            ),
            (
                StrandSettings {
                    width_px: 0.0,
                    ..Default::default()
                },
                "strands.width_px",
            ),
            (
                StrandSettings {
                    alpha: 1.5,
                    ..Default::default()
                },
                "strands.alpha",
            ),
            (
                StrandSettings {
                    pcf_radius: 99,
                    ..Default::default()
                },
                "strands.pcf_radius",
            ),
            (
                StrandSettings {
                    shadow_r: f32::NAN,
                    ..Default::default()
                },
                "strands.shadow_r",
            ),
        ];
        for (s, name) in cases {
            let e = s.validate().expect_err(name).to_string();
            assert!(e.contains(name), "{e}");
        }
    }

    #[test]
    fn shading_names_round_trip() {
        for s in [Shading::KajiyaKay, Shading::Scheuermann, Shading::Marschner] {
            assert_eq!(s.name().parse::<Shading>().unwrap(), s);
        }
        assert!("phong".parse::<Shading>().is_err());
    }
}
