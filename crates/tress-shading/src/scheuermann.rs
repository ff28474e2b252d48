//! Scheuermann's hair lighting (ATI, SIGGRAPH 2004 sketch and slides "Hair Rendering and
//! Shading"): a Kajiya-Kay-style model tuned to match Marschner et al. 2003 phenomenologically.
//!
//! - *Shifted tangents* (slide "Shifting Specular Highlights", `ShiftTangent`): nudging the tangent
//!   along the normal moves the highlight along the strand. With `t` pointing from root to tip, a
//!   positive shift moves the highlight towards the root, a negative one towards the tip.
//! - *Strand specular* (slide "Specular Strand Lighting", `StrandSpecular`): `sin(t, h)^exponent`
//!   with the half vector `h`, attenuated by `smoothstep(-1, 0, t·h)`.
//! - *Dual highlights* (slide "Putting it All Together", `HairLighting`): a primary highlight
//!   shifted towards the tip and a colored secondary highlight shifted towards the root and
//!   modulated by a noise mask (Marschner's R and TRT lobes), a softened `N·L` diffuse term, all
//!   multiplied by the base color, the light color and the ambient occlusion.
//!
//! The slides read the shift and the noise from textures by `uv`; here their values arrive in a
//! [`HairSample`] so that any technique (patches with textures, strands with per-strand random
//! values) can feed them. The slides' `HairLighting` also returns the alpha texture's value; the
//! twin returns only the color and leaves alpha to the caller.

use glam::Vec3;

use crate::{saturate, sin_from_cos, smoothstep};

/// `ShiftTangent(T, N, shift) = normalize(T + shift · N)` (Scheuermann 2004, slide "Shifting
/// Specular Highlights").
///
/// `shift = 0` returns `t` (normalized). Precondition: `t + shift·n ≠ 0`, which holds for unit
/// `t ⟂ n`.
pub fn shift_tangent(t: Vec3, n: Vec3, shift: f32) -> Vec3 {
    (t + shift * n).normalize()
}

/// `StrandSpecular(T, V, L, exponent)` (Scheuermann 2004, slide "Specular Strand Lighting"):
///
/// ```text
/// h         = normalize(l + v)
/// sin_th    = sqrt(1 - (t·h)²)
/// dir_atten = smoothstep(-1, 0, t·h)
/// result    = dir_atten · sin_th^exponent
/// ```
///
/// In `[0, 1]`; 1 when `h ⟂ t`. Symmetric in `l` and `v`. Unlike [`crate::kajiya_kay_specular`]
/// it depends on the sign of `t` through `dir_atten`, which fades the lobe when the half vector
/// points against the tangent. Preconditions: `l + v ≠ 0`, `exponent > 0` (WGSL `pow`).
pub fn strand_specular(t: Vec3, v: Vec3, l: Vec3, exponent: f32) -> f32 {
    let h = (l + v).normalize();
    let dot_th = t.dot(h);
    let sin_th = sin_from_cos(dot_th);
    let dir_atten = smoothstep(-1.0, 0.0, dot_th);
    dir_atten * sin_th.powf(exponent)
}

/// Scheuermann's diffuse term `saturate(lerp(0.25, 1, n·l))` (slide "Putting it All Together"):
/// an `N·L` term whose shadow boundary is shifted for a softer look, used instead of Kajiya-Kay's
/// `sin(t, l)`, which "looks too bright without proper self-shadowing" (slide "Shader Breakdown").
///
/// 0.25 when `n ⟂ l`, 1 when `n = l`, 0 from `n·l = -1/3` on.
pub fn scheuermann_diffuse(n: Vec3, l: Vec3) -> f32 {
    let n_dot_l = n.dot(l);
    saturate(0.25 + (1.0 - 0.25) * n_dot_l)
}

/// The material constants of Scheuermann's `HairLighting` (the slide's light-blue "external
/// constants"). Techniques other than `patches` reuse it for their dual-highlight shading.
///
/// The field order matches the WGSL `struct HairLighting`, chosen so each `vec3f` packs with the
/// scalar after it (64 bytes as a uniform).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairLighting {
    /// `diffuseColor`: multiplies the diffuse term.
    pub diffuse_color: Vec3,
    /// `specExp1`: exponent of the primary highlight (> 0).
    pub primary_exponent: f32,
    /// `specularColor1`: color of the primary highlight (Marschner's R lobe, light-colored).
    pub primary_color: Vec3,
    /// `primaryShift`: tangent shift of the primary highlight (negative: towards the tip).
    pub primary_shift: f32,
    /// `specularColor2`: color of the secondary highlight (Marschner's TRT lobe, hair-colored).
    pub secondary_color: Vec3,
    /// `specExp2`: exponent of the secondary highlight (> 0), usually lower than the primary's.
    pub secondary_exponent: f32,
    /// `secondaryShift`: tangent shift of the secondary highlight (positive: towards the root).
    pub secondary_shift: f32,
}

impl Default for HairLighting {
    /// A white diffuse multiplier (the base color carries the hue), a light-colored narrow
    /// primary highlight shifted 0.1 towards the tip, and a warm, broader secondary highlight
    /// shifted 0.1 towards the root (Marschner's lobes are a few degrees apart; `0.1 ≈ tan 5.7°`).
    fn default() -> Self {
        HairLighting {
            diffuse_color: Vec3::ONE,
            primary_exponent: 80.0,
            primary_color: Vec3::splat(0.3),
            primary_shift: -0.1,
            secondary_color: Vec3::new(0.5, 0.4, 0.3),
            secondary_exponent: 16.0,
            secondary_shift: 0.1,
        }
    }
}

/// Per-fragment inputs of [`hair_lighting`]: what the slide's vertex shader passes down and what
/// its pixel shader reads from textures. Field order matches the WGSL `struct HairSample`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairSample {
    /// Unit tangent `T`, root to tip.
    pub tangent: Vec3,
    /// `tex2D(tSpecShift, uv)`: the shift texture's value in `[0, 1]`; `0.5` is subtracted (as
    /// on the slide), so 0.5 means no extra shift.
    pub shift_tex: f32,
    /// Unit normal `N`, perpendicular to `T`.
    pub normal: Vec3,
    /// `tex2D(tSpecMask, uv)`: the noise that modulates the secondary highlight, in `[0, 1]`.
    pub spec_mask: f32,
    /// `tex2D(tBase, uv)`: the base color (linear RGB).
    pub base_color: Vec3,
    /// `ambOcc`: ambient occlusion in `[0, 1]` (1: unoccluded).
    pub amb_occ: f32,
}

/// Scheuermann's `HairLighting` (slide "Putting it All Together") for one light:
///
/// ```text
/// shift    = s.shift_tex - 0.5
/// t1       = shift_tangent(T, N, primary_shift + shift)
/// t2       = shift_tangent(T, N, secondary_shift + shift)
/// diffuse  = scheuermann_diffuse(N, L) · diffuse_color
/// specular = primary_color · strand_specular(t1, V, L, primary_exponent)
///          + secondary_color · spec_mask · strand_specular(t2, V, L, secondary_exponent)
/// rgb      = (diffuse + specular) · base_color · light_color · amb_occ
/// ```
///
/// `l` points towards the light, `v` towards the eye. Returns the color only (see module docs).
pub fn hair_lighting(
    p: &HairLighting,
    s: &HairSample,
    l: Vec3,
    light_color: Vec3,
    v: Vec3,
) -> Vec3 {
    let shift = s.shift_tex - 0.5;
    let t1 = shift_tangent(s.tangent, s.normal, p.primary_shift + shift);
    let t2 = shift_tangent(s.tangent, s.normal, p.secondary_shift + shift);
    let diffuse = scheuermann_diffuse(s.normal, l) * p.diffuse_color;
    let primary = p.primary_color * strand_specular(t1, v, l, p.primary_exponent);
    let secondary =
        p.secondary_color * s.spec_mask * strand_specular(t2, v, l, p.secondary_exponent);
    (diffuse + primary + secondary) * s.base_color * light_color * s.amb_occ
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::sphere;

    #[test]
    fn zero_shift_keeps_the_tangent() {
        for &t in &sphere(20) {
            let (n, _) = t.any_orthonormal_pair();
            assert!((shift_tangent(t, n, 0.0) - t).length() < 1e-6);
        }
    }

    #[test]
    fn shift_tilts_towards_the_normal_by_atan_shift() {
        let t = Vec3::X;
        let n = Vec3::Y;
        for shift in [-2.0f32, -0.3, 0.1, 1.0] {
            let s = shift_tangent(t, n, shift);
            assert!((s.length() - 1.0).abs() < 1e-6);
            // The shifted tangent makes the angle atan(shift) with t, towards +n for shift > 0.
            assert!((s.y.atan2(s.x) - shift.atan()).abs() < 1e-6);
        }
    }

    #[test]
    fn strand_specular_bounds_and_symmetry() {
        let dirs = sphere(48);
        for &t in dirs.iter().step_by(5) {
            for &l in dirs.iter().step_by(3) {
                for &v in dirs.iter().step_by(4) {
                    if (l + v).length() < 1e-3 {
                        continue;
                    }
                    let s = strand_specular(t, v, l, 32.0);
                    assert!((0.0..=1.0).contains(&s), "{s}");
                    assert!((s - strand_specular(t, l, v, 32.0)).abs() < 1e-6);
                    let h = (l + v).normalize();
                    let sin_pow = (1.0 - t.dot(h).powi(2)).max(0.0).sqrt().powf(32.0);
                    if t.dot(h) >= 0.0 {
                        assert!((s - sin_pow).abs() < 1e-6, "no attenuation when t·h >= 0");
                    } else {
                        assert!(s <= sin_pow + 1e-7, "attenuated when t·h < 0");
                    }
                }
            }
        }
    }

    #[test]
    fn strand_specular_peaks_when_half_vector_is_perpendicular() {
        let t = Vec3::X;
        let l = Vec3::new(0.3, 0.9, 0.1).normalize();
        let v = Vec3::new(-0.3, 0.9, -0.1).normalize(); // h = (0, 0.9, 0)/|.| ⟂ t
        assert!((strand_specular(t, v, l, 100.0) - 1.0).abs() < 1e-5);
        // Half vector along -t: sin = 0 and smoothstep(-1, 0, -1) = 0.
        assert_eq!(strand_specular(t, -Vec3::X, -Vec3::X, 4.0), 0.0);
        // t·h = -0.5: smoothstep gives 0.5, sin^1 = sqrt(0.75).
        let h = Vec3::new(-0.5, 0.75f32.sqrt(), 0.0);
        let expected = 0.5 * 0.75f32.sqrt();
        assert!((strand_specular(t, h, h, 1.0) - expected).abs() < 1e-6);
    }

    #[test]
    fn softened_diffuse_values() {
        let n = Vec3::Z;
        assert!((scheuermann_diffuse(n, Vec3::Z) - 1.0).abs() < 1e-6);
        assert!((scheuermann_diffuse(n, Vec3::X) - 0.25).abs() < 1e-6);
        assert_eq!(scheuermann_diffuse(n, -Vec3::Z), 0.0);
        let third = Vec3::new((8.0f32 / 9.0).sqrt(), 0.0, -1.0 / 3.0);
        assert!(scheuermann_diffuse(n, third).abs() < 1e-6);
        for &l in &sphere(50) {
            assert!((0.0..=1.0).contains(&scheuermann_diffuse(n, l)));
        }
    }

    fn head_on() -> HairSample {
        HairSample {
            tangent: Vec3::X,
            shift_tex: 0.5,
            normal: Vec3::Y,
            spec_mask: 0.5,
            base_color: Vec3::new(0.5, 0.25, 1.0),
            amb_occ: 0.8,
        }
    }

    #[test]
    fn hair_lighting_assembles_the_terms() {
        // l = v = n ⟂ t: diffuse = 1, both unshifted highlights are 1 (h = n ⟂ t).
        let p = HairLighting {
            diffuse_color: Vec3::new(0.1, 0.2, 0.3),
            primary_exponent: 10.0,
            primary_color: Vec3::new(1.0, 0.0, 0.0),
            primary_shift: 0.0,
            secondary_color: Vec3::new(0.0, 1.0, 0.0),
            secondary_exponent: 3.0,
            secondary_shift: 0.0,
        };
        let s = head_on();
        let light = Vec3::new(2.0, 1.0, 0.5);
        let c = hair_lighting(&p, &s, Vec3::Y, light, Vec3::Y);
        // (diffuse + primary + 0.5 · secondary) · base · light · ao
        let expected =
            Vec3::new(0.1 + 1.0, 0.2 + 0.5, 0.3) * Vec3::new(0.5, 0.25, 1.0) * light * 0.8;
        assert!(
            (c - expected).abs().max_element() < 1e-5,
            "{c} vs {expected}"
        );
    }

    #[test]
    fn hair_lighting_limits() {
        let p = HairLighting::default();
        let l = Vec3::new(0.2, 0.9, 0.3).normalize();
        let v = Vec3::new(-0.4, 0.7, 0.5).normalize();
        let s = head_on();
        let occluded = HairSample { amb_occ: 0.0, ..s };
        assert_eq!(hair_lighting(&p, &occluded, l, Vec3::ONE, v), Vec3::ZERO);
        assert_eq!(hair_lighting(&p, &s, l, Vec3::ZERO, v), Vec3::ZERO);
        // Linear in the light color.
        let one = hair_lighting(&p, &s, l, Vec3::ONE, v);
        let three = hair_lighting(&p, &s, l, Vec3::splat(3.0), v);
        assert!((three - 3.0 * one).abs().max_element() < 1e-5);
        // The noise mask only scales the secondary highlight.
        let no_mask = hair_lighting(
            &p,
            &HairSample {
                spec_mask: 0.0,
                ..s
            },
            l,
            Vec3::ONE,
            v,
        );
        let no_secondary = HairLighting {
            secondary_color: Vec3::ZERO,
            ..p
        };
        let reference = hair_lighting(&no_secondary, &s, l, Vec3::ONE, v);
        assert!((no_mask - reference).abs().max_element() < 1e-6);
    }

    #[test]
    fn shift_texture_moves_both_highlights() {
        // shift_tex = 0.5 + x must equal adding x to both shifts.
        let p = HairLighting::default();
        let s = head_on();
        let l = Vec3::new(0.2, 0.9, 0.3).normalize();
        let v = Vec3::new(0.4, 0.7, -0.5).normalize();
        let from_tex = hair_lighting(
            &p,
            &HairSample {
                shift_tex: 0.8,
                ..s
            },
            l,
            Vec3::ONE,
            v,
        );
        let shifted = HairLighting {
            primary_shift: p.primary_shift + 0.3,
            secondary_shift: p.secondary_shift + 0.3,
            ..p
        };
        let from_params = hair_lighting(&shifted, &s, l, Vec3::ONE, v);
        assert!((from_tex - from_params).abs().max_element() < 1e-6);
        assert!((from_tex - hair_lighting(&p, &s, l, Vec3::ONE, v)).length() > 1e-4);
    }
}
