//! Approximated deep shadow maps, ADSM (Jansson et al. 2019 §3.4, after Lacroix \[Lac13\] as used in
//! Tomb Raider and TressFX).
//!
//! One ordinary depth map per light stores the depth `s` of the first strand the light meets. For
//! a strand fragment at light-space depth `f`, the depth travelled inside the hair is
//! `d = max(0, f - s)`, the number of strands in the way is estimated as `d · r`, and the light
//! that gets through strands of translucency (opacity) `alpha` each is
//!
//! ```text
//! visibility = (1 - alpha)^(d · r)                          (Jansson §3.4)
//! ```
//!
//! The paper calls this the occlusion; it is the fraction of light that arrives (1: lit), so the
//! twin calls it a visibility. `r` is "the expected spacing in-between hair strands" in the paper's
//! words but enters as strands *per unit depth*, i.e. the inverse of the spacing; the name `r` is
//! kept. `d` and `r` must use the same depth unit: with an orthographic light projection and a
//! `[0, 1]` depth map, `r = strands per world unit · (far - near)`.
//!
//! The volume technique replaces the estimate `d · r` with a strand count `n` raymarched through
//! the density volume (Jansson §3.4, second paragraph): [`strand_visibility`] takes that count.
//!
//! **PCF.** [`adsm_pcf`] filters like TressFX: it evaluates the visibility for every depth-map
//! texel of a square kernel and averages the visibilities (not the depths, which would give a
//! hard step at silhouettes). Kernel semantics: the `(2k + 1) × (2k + 1)` texels centred on
//! `texel`, `k = kernel_radius` clamped to `[0, MAX_PCF_RADIUS]`, all weighted equally, with texel
//! coordinates outside the map clamped to its edge (like a clamp-to-edge `textureLoad`).

use glam::IVec2;

use crate::saturate;

/// Largest PCF kernel radius [`adsm_pcf`] honours (a 17 × 17 kernel); larger radii are clamped so
/// a setting cannot make a fragment loop unboundedly.
pub const MAX_PCF_RADIUS: i32 = 8;

/// Errors of the CPU-side helpers.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ShadingError {
    /// A depth map's array does not hold `width · height` depths.
    #[error("a {width}x{height} depth map needs {expected} depths, got {got}")]
    DepthMapSize {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// `width · height`.
        expected: u64,
        /// Length of the array given.
        got: usize,
    },
    /// A depth map with no texels.
    #[error("a depth map needs at least one texel")]
    EmptyDepthMap,
}

/// A read-only view of a shadow depth map: the CPU stand-in for the WGSL `texture_depth_2d`.
///
/// Row-major, row 0 first (the texture's `y = 0` row), `depths[y · width + x]`.
#[derive(Clone, Copy, Debug)]
pub struct DepthMap<'a> {
    width: u32,
    height: u32,
    depths: &'a [f32],
}

impl<'a> DepthMap<'a> {
    /// A view of `depths`, checked to hold exactly `width · height` values, at least one.
    pub fn new(width: u32, height: u32, depths: &'a [f32]) -> Result<Self, ShadingError> {
        let expected = u64::from(width) * u64::from(height);
        if expected == 0 {
            return Err(ShadingError::EmptyDepthMap);
        }
        if depths.len() as u64 != expected {
            return Err(ShadingError::DepthMapSize {
                width,
                height,
                expected,
                got: depths.len(),
            });
        }
        Ok(DepthMap {
            width,
            height,
            depths,
        })
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The depth at `texel`, with coordinates clamped to the map (clamp-to-edge).
    pub fn load(&self, texel: IVec2) -> f32 {
        let x = texel.x.clamp(0, self.width as i32 - 1) as usize;
        let y = texel.y.clamp(0, self.height as i32 - 1) as usize;
        self.depths[y * self.width as usize + x]
    }
}

/// Light through `n` strands of opacity `alpha` each: `(1 - alpha)^n` (Jansson §3.4).
///
/// `n` below 0 counts as 0 and `alpha` is clamped to `[0, 1]`. In `[0, 1]`: 1 for `n = 0` or
/// `alpha = 0`, 0 for `alpha = 1` and `n > 0` (the cases where WGSL `pow` is undefined are handled
/// explicitly, identically in both twins).
pub fn strand_visibility(n: f32, alpha: f32) -> f32 {
    let n = n.max(0.0);
    let transmittance = 1.0 - saturate(alpha);
    if n <= 0.0 {
        return 1.0;
    }
    if transmittance <= 0.0 {
        return 0.0;
    }
    transmittance.powf(n)
}

/// The most strands [`strands_from_visibility`] reports (fully shadowed).
pub const MAX_SHADOW_STRANDS: f32 = 64.0;

/// The strands of opacity `alpha` that let through `visibility` of the light: the inverse of
/// [`strand_visibility`], clamped to `[0, MAX_SHADOW_STRANDS]` (what dual scattering needs from
/// a shadow map that stores only a visibility).
pub fn strands_from_visibility(visibility: f32, alpha: f32) -> f32 {
    let transmittance = 1.0 - saturate(alpha);
    if visibility >= 1.0 || transmittance >= 1.0 {
        return 0.0;
    }
    if visibility <= 0.0 || transmittance <= 0.0 {
        return MAX_SHADOW_STRANDS;
    }
    (visibility.ln() / transmittance.ln()).min(MAX_SHADOW_STRANDS)
}

/// ADSM visibility `(1 - alpha)^(d · r)` for a fragment `d` depth units past the first occluder,
/// with `r` strands per depth unit (Jansson §3.4; see the module docs for units).
pub fn adsm_visibility(d: f32, r: f32, alpha: f32) -> f32 {
    strand_visibility(d * r, alpha)
}

/// The depth `d = max(0, f - s)` a fragment at light-space depth `fragment_depth` (`f`) lies past
/// the first occluder at `occluder_depth` (`s`) (Jansson §3.4). A fragment in front of the stored
/// occluder (the occluder itself, or depth-bias slack) is at `d = 0`.
pub fn adsm_depth(fragment_depth: f32, occluder_depth: f32) -> f32 {
    (fragment_depth - occluder_depth).max(0.0)
}

/// Percentage-closer-filtered ADSM visibility: the mean of
/// [`adsm_visibility`]`(`[`adsm_depth`]`(fragment_depth, map[texel + o]), r, alpha)` over the
/// offsets `o` of the `(2k + 1)²` kernel (module docs: kernel semantics). In `[0, 1]`.
pub fn adsm_pcf(
    map: &DepthMap<'_>,
    texel: IVec2,
    kernel_radius: i32,
    fragment_depth: f32,
    r: f32,
    alpha: f32,
) -> f32 {
    let k = kernel_radius.clamp(0, MAX_PCF_RADIUS);
    let mut sum = 0.0;
    for dy in -k..=k {
        for dx in -k..=k {
            let occluder_depth = map.load(texel + IVec2::new(dx, dy));
            sum += adsm_visibility(adsm_depth(fragment_depth, occluder_depth), r, alpha);
        }
    }
    let side = (2 * k + 1) as f32;
    sum / (side * side)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strands_from_visibility_inverts_strand_visibility() {
        for alpha in [0.05f32, 0.25, 0.6] {
            for n in [0.0f32, 0.5, 1.0, 3.0, 17.0] {
                let back = strands_from_visibility(strand_visibility(n, alpha), alpha);
                assert!((back - n).abs() < 1e-3 * (1.0 + n), "{alpha} {n}: {back}");
            }
        }
        assert_eq!(strands_from_visibility(1.0, 0.3), 0.0);
        assert_eq!(strands_from_visibility(0.0, 0.3), MAX_SHADOW_STRANDS);
        assert_eq!(strands_from_visibility(0.5, 0.0), 0.0);
        assert_eq!(strands_from_visibility(0.5, 1.0), MAX_SHADOW_STRANDS);
        assert_eq!(strands_from_visibility(1e-30, 0.3), MAX_SHADOW_STRANDS);
    }

    #[test]
    fn visibility_limits() {
        assert_eq!(
            adsm_visibility(3.0, 10.0, 0.0),
            1.0,
            "alpha 0: fully visible"
        );
        assert_eq!(
            adsm_visibility(0.0, 10.0, 0.7),
            1.0,
            "at the first occluder: visible"
        );
        assert_eq!(adsm_visibility(3.0, 0.0, 0.7), 1.0, "no strands in the way");
        assert_eq!(adsm_visibility(0.1, 10.0, 1.0), 0.0, "opaque strands block");
        assert_eq!(adsm_visibility(0.0, 10.0, 1.0), 1.0);
        assert_eq!(adsm_visibility(-1.0, 10.0, 0.5), 1.0);
        // Two strands of 50% each pass a quarter.
        assert!((adsm_visibility(0.2, 10.0, 0.5) - 0.25).abs() < 1e-6);
        assert!((strand_visibility(3.0, 0.5) - 0.125).abs() < 1e-7);
    }

    #[test]
    fn visibility_is_bounded_monotonic_and_multiplicative() {
        for a in 0..=10 {
            let alpha = a as f32 / 10.0;
            let mut last = 1.0;
            for i in 0..50 {
                let d = i as f32 * 0.1;
                let v = adsm_visibility(d, 3.0, alpha);
                assert!((0.0..=1.0).contains(&v));
                assert!(v <= last + 1e-7, "non-increasing in depth");
                last = v;
                // Crossing d1 then d2 of hair = crossing d1 + d2.
                let split =
                    adsm_visibility(d * 0.3, 3.0, alpha) * adsm_visibility(d * 0.7, 3.0, alpha);
                assert!((split - v).abs() < 1e-5);
            }
        }
        assert!(adsm_visibility(1.0, 2.0, 0.3) > adsm_visibility(1.0, 2.0, 0.6));
        assert!(adsm_visibility(1.0, 2.0, 0.3) > adsm_visibility(1.0, 4.0, 0.3));
    }

    #[test]
    fn depth_past_occluder() {
        assert_eq!(adsm_depth(0.7, 0.5), 0.7 - 0.5);
        assert_eq!(adsm_depth(0.4, 0.5), 0.0);
    }

    #[test]
    fn depth_map_checks_its_size() {
        let d = [0.0; 6];
        assert!(DepthMap::new(3, 2, &d).is_ok());
        assert_eq!(
            DepthMap::new(4, 2, &d).unwrap_err(),
            ShadingError::DepthMapSize {
                width: 4,
                height: 2,
                expected: 8,
                got: 6
            }
        );
        assert_eq!(
            DepthMap::new(0, 2, &[]).unwrap_err(),
            ShadingError::EmptyDepthMap
        );
    }

    #[test]
    fn depth_map_clamps_to_edge() {
        let d = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let m = DepthMap::new(3, 2, &d).unwrap();
        assert_eq!(m.load(IVec2::new(2, 1)), 6.0);
        assert_eq!(m.load(IVec2::new(-5, -5)), 1.0);
        assert_eq!(m.load(IVec2::new(9, 0)), 3.0);
        assert_eq!(m.load(IVec2::new(1, 7)), 5.0);
    }

    #[test]
    fn pcf_averages_visibilities() {
        // 3×3 map: left column occluder at 0.0, the rest at 0.5; fragment at depth 0.5.
        #[rustfmt::skip]
        let d = [0.0, 0.5, 0.5,
                 0.0, 0.5, 0.5,
                 0.0, 0.5, 0.5];
        let m = DepthMap::new(3, 3, &d).unwrap();
        let centre = IVec2::new(1, 1);
        // Radius 0 is the single texel: d = 0 → visible.
        assert_eq!(adsm_pcf(&m, centre, 0, 0.5, 4.0, 0.5), 1.0);
        // Radius 1: 3 texels at d = 0.5 (0.5·4 = 2 strands → 0.25), 6 at d = 0 (1.0).
        let expected = (3.0 * 0.25 + 6.0 * 1.0) / 9.0;
        assert!((adsm_pcf(&m, centre, 1, 0.5, 4.0, 0.5) - expected).abs() < 1e-6);
        // Negative radius acts as 0.
        assert_eq!(adsm_pcf(&m, centre, -3, 0.5, 4.0, 0.5), 1.0);
        // At the corner the kernel clamps to the edge: x ∈ {-1, 0, 1} reads columns {0, 0, 1},
        // so 6 of 9 samples see the occluder at 0.0 (d = 0.5) and 3 see none (d = 0).
        let corner = adsm_pcf(&m, IVec2::ZERO, 1, 0.5, 4.0, 0.5);
        assert!((corner - (6.0 * 0.25 + 3.0) / 9.0).abs() < 1e-6);
    }

    #[test]
    fn pcf_of_a_flat_map_equals_a_single_lookup() {
        let d = vec![0.2; 25];
        let m = DepthMap::new(5, 5, &d).unwrap();
        for k in [0, 1, 2, 100] {
            let v = adsm_pcf(&m, IVec2::new(2, 2), k, 0.6, 5.0, 0.3);
            assert!((v - adsm_visibility(0.4, 5.0, 0.3)).abs() < 1e-5, "k = {k}");
        }
    }
}
