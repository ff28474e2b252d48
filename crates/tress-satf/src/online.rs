//! CPU twins of the online phase's per-point math (Xu et al. 2006, §6, equations 8–14): what the
//! GPU shaders of `tress-render/src/satf/` compute, as pure functions to test them against.
//!
//! # Conventions and choices
//!
//! - Directions point *away* from the shaded point: `l` toward the light, `v` toward the eye; `t`
//!   is the unit hair tangent from root to tip and `n` the unit outward normal of the cluster's
//!   layer surface. The azimuths that index the database are those of `v` and `l` in the normal
//!   plane ([`azimuth`], matching [`crate::hrir`]).
//! - **Specular lobes (equations 10–11).** The paper prints Kajiya-Kay's cosine
//!   `(t̃·l)(t̃·v) + sin(t̃, l) sin(t̃, v)`, written for `l` the direction the light travels. With
//!   `l` toward the light the first product changes sign; this crate uses
//!   [`tress_shading::kajiya_kay_specular`], which makes that substitution and clamps the base at
//!   0 (see its docs), so the lobe peaks on the mirror cone as the paper intends.
//! - **Shift signs.** Equation 10 shifts the primary tangent by `+s n` "toward the tip" and
//!   equation 11 the secondary by `-s n` "toward the root", `s > 0`. With `t` from root to tip and
//!   `n` outward this holds: on hair curving over a surface, `t̃ ⟂ h` (the lobe's peak, `h` the
//!   half vector) moves to where `t·h = -s (n·h) < 0`, i.e. past the point of normal reflection
//!   toward the tip. The shifts are [`SatfLighting::primary_shift`] and
//!   [`SatfLighting::secondary_shift`], applied with the paper's signs.
//! - **Shadows (equation 12)**: [`ShadowApprox::Exponential`] is the definition
//!   `τ = exp(-k_shadow Σ α_m)`, [`ShadowApprox::Linear`] the paper's first-order form
//!   `1 - k_shadow Σ α_m`, clamped at 0.
//! - **Blending (equation 14)**: layer `0` is the innermost, `n - 1` the outermost (drawn last,
//!   on top), the background `Y_bk` the light through the core.

use glam::Vec3;
use tress_shading::{kajiya_kay_diffuse, kajiya_kay_specular, shift_tangent};

use crate::cylinder::SurfacePoint;
use crate::database::Params;

/// The material of the online lighting (equations 8–11).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SatfLighting {
    /// `k_dif`, the diffuse coefficient. Default 0.8.
    pub k_dif: f32,
    /// `f_dif`, the hair's diffuse color (linear RGB). Default dark brown (0.30, 0.20, 0.12).
    pub f_dif: Vec3,
    /// `k_speI`, the primary specular coefficient. Default 0.25.
    pub k_spe1: f32,
    /// `f_speI`, the primary highlight's color (the light's color, §6.3). Default white.
    pub f_spe1: Vec3,
    /// `s` of equation 10 (> 0, toward the tip). Default 0.1.
    pub primary_shift: f32,
    /// `k_speII`, the secondary specular coefficient. Default 0.5.
    pub k_spe2: f32,
    /// `f_speII`, the secondary highlight's color (the hair's color, §6.3). Default
    /// (0.30, 0.20, 0.12).
    pub f_spe2: Vec3,
    /// `s` of equation 11 (> 0, toward the root). Default 0.1.
    pub secondary_shift: f32,
    /// `k_h`, the specular exponent shared by both lobes. Default 60.
    pub k_h: f32,
}

impl Default for SatfLighting {
    fn default() -> Self {
        let hair = Vec3::new(0.30, 0.20, 0.12);
        SatfLighting {
            k_dif: 0.8,
            f_dif: hair,
            k_spe1: 0.25,
            f_spe1: Vec3::ONE,
            primary_shift: 0.1,
            k_spe2: 0.5,
            f_spe2: hair,
            secondary_shift: 0.1,
            k_h: 60.0,
        }
    }
}

/// Equation 9: `Y_dif = k_dif sin(t, l) f_dif`.
pub fn diffuse(t: Vec3, l: Vec3, k_dif: f32, f_dif: Vec3) -> Vec3 {
    k_dif * kajiya_kay_diffuse(t, l) * f_dif
}

/// Equation 10: the primary highlight with `t̃ = normalize(t + s n)`.
#[expect(
    clippy::too_many_arguments,
    reason = "the paper's symbols one for one, like the WGSL twin"
)]
pub fn primary_specular(
    t: Vec3,
    n: Vec3,
    s: f32,
    l: Vec3,
    v: Vec3,
    k_spe: f32,
    k_h: f32,
    f_spe: Vec3,
) -> Vec3 {
    let t_shift = shift_tangent(t, n, s);
    k_spe * kajiya_kay_specular(t_shift, l, v, k_h) * f_spe
}

/// Equation 11: the secondary highlight with `t̃ = normalize(t - s n)`.
#[expect(
    clippy::too_many_arguments,
    reason = "the paper's symbols one for one, like the WGSL twin"
)]
pub fn secondary_specular(
    t: Vec3,
    n: Vec3,
    s: f32,
    l: Vec3,
    v: Vec3,
    k_spe: f32,
    k_h: f32,
    f_spe: Vec3,
) -> Vec3 {
    let t_shift = shift_tangent(t, n, -s);
    k_spe * kajiya_kay_specular(t_shift, l, v, k_h) * f_spe
}

/// Equation 8: `Y_lighting = Y_dif + Y_speI + Y_speII`.
pub fn lighting(p: &SatfLighting, t: Vec3, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    diffuse(t, l, p.k_dif, p.f_dif)
        + primary_specular(t, n, p.primary_shift, l, v, p.k_spe1, p.k_h, p.f_spe1)
        + secondary_specular(t, n, p.secondary_shift, l, v, p.k_spe2, p.k_h, p.f_spe2)
}

/// How equation 12 is evaluated (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowApprox {
    /// `exp(-k_shadow Σ α_m)` (default).
    #[default]
    Exponential,
    /// `max(0, 1 - k_shadow Σ α_m)`.
    Linear,
}

/// Equation 12: the light transmittance `τ` of a point under outer layers of opacities
/// `outer_alphas` (the α-maps of the layers in `c(k)` at the same texture coordinates).
pub fn transmittance(outer_alphas: &[f32], k_shadow: f32, approx: ShadowApprox) -> f32 {
    let sum: f32 = outer_alphas.iter().sum();
    match approx {
        ShadowApprox::Exponential => (-k_shadow * sum).exp(),
        ShadowApprox::Linear => (1.0 - k_shadow * sum).max(0.0),
    }
}

/// The s-map values of every layer at one texel: `alphas[k]` is layer `k`'s α-map value
/// (innermost first); `τ_k` sums the layers `m > k` (suffix sums, what one shader pass computes).
pub fn s_maps(alphas: &[f32], k_shadow: f32, approx: ShadowApprox) -> Vec<f32> {
    let mut out = vec![0.0; alphas.len()];
    let mut sum = 0.0;
    for k in (0..alphas.len()).rev() {
        out[k] = transmittance(&[sum], k_shadow, approx);
        sum += alphas[k];
    }
    out
}

/// Equation 13: `Y_shading = Y_lighting · re · τ`.
pub fn shading(lighting: Vec3, re: f32, tau: f32) -> Vec3 {
    lighting * re * tau
}

/// Equation 14 evaluated as written: `Y_bk Π_k (1 - α_k) + Σ_k Y_k α_k Π_{j>k} (1 - α_j)`, for
/// `layers[k] = (Y_shading, α)`, innermost first.
pub fn blend_layers(background: Vec3, layers: &[(Vec3, f32)]) -> Vec3 {
    let through = |from: usize| layers[from..].iter().map(|(_, a)| 1.0 - a).product::<f32>();
    let mut out = background * through(0);
    for (k, (color, alpha)) in layers.iter().enumerate() {
        out += *color * *alpha * through(k + 1);
    }
    out
}

/// One step of equation 14 as a GPU draws it, innermost layer first: `acc (1 - α) + Y α`.
/// Folding it over the layers from `acc = Y_bk` gives [`blend_layers`].
pub fn blend_over(acc: Vec3, color: Vec3, alpha: f32) -> Vec3 {
    acc * (1.0 - alpha) + color * alpha
}

/// The azimuth of direction `dir` in the normal plane at a shell point, measured from the outward
/// normal toward the `s` axis, in `(-π, π]` (0 when `dir` runs along the hair).
pub fn azimuth(dir: Vec3, surface: &SurfacePoint) -> f32 {
    dir.dot(surface.s_axis).atan2(dir.dot(surface.normal))
}

/// `Params(b)` of a boundary sector (§6.2.1): its features and the azimuths of the directions to
/// the eye and to the light at its anchor ([`crate::hierarchy::Cluster::sector_surface`]).
pub fn sector_params(
    features: [f32; 3],
    surface: &SurfacePoint,
    to_eye: Vec3,
    to_light: Vec3,
) -> Params {
    Params {
        features,
        theta_v: azimuth(to_eye, surface),
        theta_l: azimuth(to_light, surface),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn lighting_terms_by_hand() {
        let t = Vec3::Y;
        let n = Vec3::Z;
        // Light perpendicular to the hair: sin = 1; along it: 0.
        assert!(close(diffuse(t, Vec3::Z, 0.5, Vec3::ONE), Vec3::splat(0.5)));
        assert!(close(diffuse(t, Vec3::Y, 0.5, Vec3::ONE), Vec3::ZERO));
        // Zero shift, l = v = n (mirror cone contains v): the lobe base is 1.
        let f = Vec3::new(1.0, 0.5, 0.25);
        assert!(close(
            primary_specular(t, n, 0.0, n, n, 0.3, 50.0, f),
            0.3 * f
        ));
        // Shift s: t̃ = (t + s n)/|…| makes angle atan(s) with t; for l = v = n the base is
        // -(t̃·n)² + (1 - (t̃·n)²) = 1 - 2 sin²(atan s) = cos(2 atan s).
        let s = 0.2f32;
        let base = (2.0 * s.atan()).cos();
        let expect = 0.3 * base.powf(10.0) * f;
        assert!(close(primary_specular(t, n, s, n, n, 0.3, 10.0, f), expect));
        assert!(
            close(secondary_specular(t, n, s, n, n, 0.3, 10.0, f), expect),
            "symmetric for l = v = n"
        );
        let p = SatfLighting::default();
        let sum = diffuse(t, n, p.k_dif, p.f_dif)
            + primary_specular(t, n, p.primary_shift, n, n, p.k_spe1, p.k_h, p.f_spe1)
            + secondary_specular(t, n, p.secondary_shift, n, n, p.k_spe2, p.k_h, p.f_spe2);
        assert!(close(lighting(&p, t, n, n, n), sum));
    }

    #[test]
    fn shifts_move_the_highlight_toward_tip_and_root() {
        // Hair over the top of a sphere: at angle φ along it, t = (cos φ, -sin φ, 0), n = (sin φ,
        // cos φ, 0); root at φ < 0, tip at φ > 0. Light and eye straight above.
        let up = Vec3::Y;
        let peak = |secondary: bool| {
            (-60..=60)
                .map(|i| (i as f32).to_radians())
                .max_by(|&a, &b| {
                    let val = |phi: f32| {
                        let t = Vec3::new(phi.cos(), -phi.sin(), 0.0);
                        let n = Vec3::new(phi.sin(), phi.cos(), 0.0);
                        if secondary {
                            secondary_specular(t, n, 0.2, up, up, 1.0, 80.0, Vec3::ONE).x
                        } else {
                            primary_specular(t, n, 0.2, up, up, 1.0, 80.0, Vec3::ONE).x
                        }
                    };
                    val(a).total_cmp(&val(b))
                })
                .unwrap_or(0.0)
        };
        assert!(
            peak(false) > 0.05,
            "primary toward the tip: {}",
            peak(false)
        );
        assert!(
            peak(true) < -0.05,
            "secondary toward the root: {}",
            peak(true)
        );
    }

    #[test]
    fn equation_12_against_direct_evaluation() {
        // Three layers, innermost first: α = 0.2, 0.5, 0.4; k_shadow = 0.8.
        let alphas = [0.2, 0.5, 0.4];
        let s = s_maps(&alphas, 0.8, ShadowApprox::Exponential);
        assert!(
            (s[2] - 1.0).abs() < 1e-6,
            "nothing covers the outermost layer"
        );
        assert!((s[1] - (-0.8f32 * 0.4).exp()).abs() < 1e-6);
        assert!((s[0] - (-0.8f32 * 0.9).exp()).abs() < 1e-6);
        let lin = s_maps(&alphas, 0.8, ShadowApprox::Linear);
        assert!((lin[0] - (1.0 - 0.72)).abs() < 1e-6 && (lin[1] - 0.68).abs() < 1e-6);
        assert_eq!(transmittance(&[0.9, 0.9], 1.0, ShadowApprox::Linear), 0.0);
        // The linear form is the exponential's first order for small sums.
        let small = [0.01, 0.02];
        let e = transmittance(&small, 1.0, ShadowApprox::Exponential);
        let l = transmittance(&small, 1.0, ShadowApprox::Linear);
        assert!((e - l).abs() < 0.0005);
        assert!(close(
            shading(Vec3::new(1.0, 0.5, 0.2), 0.5, 0.5),
            Vec3::new(0.25, 0.125, 0.05)
        ));
    }

    #[test]
    fn equation_14_against_direct_evaluation() {
        // By hand, two layers over a background of 1: inner (0.5, α 0.5), outer (0.2, α 0.25):
        // 1 · 0.5 · 0.75 + 0.5 · 0.5 · 0.75 + 0.2 · 0.25 = 0.375 + 0.1875 + 0.05 = 0.6125.
        let layers = [(Vec3::splat(0.5), 0.5), (Vec3::splat(0.2), 0.25)];
        assert!(close(blend_layers(Vec3::ONE, &layers), Vec3::splat(0.6125)));
        let mut rng = tress_hair::rng::Rng::new(5);
        for _ in 0..50 {
            let layers: Vec<(Vec3, f32)> = (0..rng.below(8) as usize)
                .map(|_| (Vec3::new(rng.f32(), rng.f32(), rng.f32()), rng.f32()))
                .collect();
            let bk = Vec3::new(rng.f32(), rng.f32(), rng.f32());
            let folded = layers
                .iter()
                .fold(bk, |acc, (c, a)| blend_over(acc, *c, *a));
            assert!(close(folded, blend_layers(bk, &layers)));
        }
        assert!(close(blend_layers(Vec3::X, &[]), Vec3::X));
    }

    #[test]
    fn azimuths_in_the_normal_plane() {
        let s = SurfacePoint {
            position: Vec3::ZERO,
            tangent: Vec3::Y,
            normal: Vec3::Z,
            s_axis: Vec3::X,
        };
        assert_eq!(azimuth(Vec3::Z, &s), 0.0);
        assert!((azimuth(Vec3::X, &s) - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        assert!((azimuth(Vec3::new(0.0, 5.0, -1.0), &s).abs() - std::f32::consts::PI).abs() < 1e-6);
        let p = sector_params([1.0, 0.5, 0.5], &s, Vec3::new(1.0, 0.3, 1.0), -Vec3::X);
        assert!((p.theta_v - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
        assert!((p.theta_l + std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }
}
