//! Kajiya-Kay strand lighting \[KK89\], the model of Jansson et al. 2019 §3.1.
//!
//! A strand is an infinitely thin cylinder with tangent `t`. Its diffuse term integrates a
//! Lambertian cylinder over its circumference, which gives `sin(t, l)`; its specular term is a
//! Phong lobe around the cone of mirror directions of the cylinder:
//!
//! ```text
//! Ψ_diffuse  = K_d · sin(t, l)                                   (KK89 §4.1, Jansson §3.1)
//! Ψ_specular = K_s · max(0, cos_tr · cos_tv + sin_tl · sin_tv)^p  (KK89 §4.1)
//! cos_tr     = -(t·l),  cos_tv = t·v,  sin_xy = sqrt(1 - cos_xy²)
//! ```
//!
//! # The sign of `t·l` (the choice made here)
//!
//! KK89 prints the specular cosine as `(t·l)(t·e) + sin(t,l) sin(t,e)`, which is the cosine between
//! the eye vector and the nearest direction on the reflection cone when `l` is the direction the
//! light *travels*. Every direction in this crate points *away* from the shaded point (`l` towards
//! the light), so the incident direction is `-l` and the cone holds the directions `r` with
//! `t·r = -(t·l)`: the first product changes sign. This is the usual real-time form (TressFX's hair
//! shader writes the same substitution as `cosTRL = -cosTL`). With it the highlight peaks, as
//! physics says, where `v` lies on the mirror cone; the literal printed form with `l` towards the
//! light would instead peak at retro-reflection (`v = l`). Both forms are unchanged when `t` is
//! flipped, so the tangent's root-to-tip orientation does not matter here.

use glam::Vec3;

use crate::sin_from_cos;

/// Kajiya-Kay parameters: the diffuse and specular colors `K_d`, `K_s` and the Phong exponent `p`
/// (KK89 §4.1). Mirrors the WGSL `struct KajiyaKay` field for field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KajiyaKay {
    /// Diffuse color `K_d` (linear RGB).
    pub diffuse: Vec3,
    /// Specular color `K_s` (linear RGB).
    pub specular: Vec3,
    /// Phong exponent `p` of the specular lobe (> 0).
    pub exponent: f32,
}

impl Default for KajiyaKay {
    /// A dark-brown strand with a white-ish highlight and `p = 80`, a common choice for human hair.
    fn default() -> Self {
        KajiyaKay {
            diffuse: Vec3::new(0.30, 0.20, 0.12),
            specular: Vec3::splat(0.35),
            exponent: 80.0,
        }
    }
}

/// Kajiya-Kay diffuse factor `sin(t, l) = sqrt(1 - (t·l)²)` (KK89 §4.1; Jansson §3.1).
///
/// In `[0, 1]` for unit vectors: 1 when the light is perpendicular to the strand, 0 when it shines
/// along it.
pub fn kajiya_kay_diffuse(t: Vec3, l: Vec3) -> f32 {
    sin_from_cos(t.dot(l))
}

/// Kajiya-Kay specular factor `max(0, -(t·l)(t·v) + sin(t,l) sin(t,v))^exponent` (KK89 §4.1; see
/// the module docs for the sign).
///
/// The base is the cosine between `v` and the nearest direction of the strand's mirror cone, so
/// the result is in `[0, 1]` and equals 1 exactly when `v` lies on the cone. Symmetric in `l` and
/// `v`. Precondition shared with WGSL `pow`: `exponent > 0`.
pub fn kajiya_kay_specular(t: Vec3, l: Vec3, v: Vec3, exponent: f32) -> f32 {
    let cos_tl = t.dot(l);
    let cos_tv = t.dot(v);
    let cos_tr = -cos_tl;
    let cos_cone = cos_tr * cos_tv + sin_from_cos(cos_tl) * sin_from_cos(cos_tv);
    cos_cone.max(0.0).powf(exponent)
}

/// Kajiya-Kay radiance factor for one light: `K_d sin(t,l) + K_s spec(t,l,v,p)` (KK89 §4.1,
/// Jansson §3.1). Multiply by the light's color and any shadowing outside.
pub fn kajiya_kay(kk: &KajiyaKay, t: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    kk.diffuse * kajiya_kay_diffuse(t, l) + kk.specular * kajiya_kay_specular(t, l, v, kk.exponent)
}

/// How fast [`spread_kajiya_kay`] widens the lobe: the exponent is divided by
/// `1 + TANGENT_SPREAD_WIDENING · p · (1 - |mean|)`.
///
/// A tangent tilted by `δ` in the plane of `l` and `v` moves the cone cosine's angle by up to
/// `2δ`, by about `δ` out of it, and `1 - |mean|` of a small spread is half its total variance; 1.5
/// is the factor that fits a Monte Carlo average of the lobe over Gaussian spreads of 0.03–0.35 rad
/// and random geometry best (`spread_lobe_matches_the_mean_of_the_spread_tangents`).
pub const TANGENT_SPREAD_WIDENING: f32 = 1.5;

/// Kajiya-Kay's parameters for a bundle of strands shaded as one with the direction of their
/// mean tangent, whose length `mean_length` (≤ 1) tells how spread their directions are: Toksvig's
/// trick (2005) applied to the cone lobe. The exponent falls to
/// `p' = p / (1 + TANGENT_SPREAD_WIDENING · p · (1 - mean_length))` and the specular colour is
/// scaled by `sqrt(p' / p)`, the peak of a one-dimensional Gaussian lobe widened the same way (so
/// the lobe's energy is kept). `mean_length` 1 (parallel strands) returns `kk` unchanged; it is
/// clamped to `[0, 1]`. The volume raymarcher shades its voxels' mean tangents with it.
pub fn spread_kajiya_kay(kk: &KajiyaKay, mean_length: f32) -> KajiyaKay {
    let spread = 1.0 - mean_length.clamp(0.0, 1.0);
    let exponent = kk.exponent / (1.0 + TANGENT_SPREAD_WIDENING * kk.exponent * spread);
    KajiyaKay {
        diffuse: kk.diffuse,
        specular: kk.specular * (exponent / kk.exponent).sqrt(),
        exponent,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::sphere;

    #[test]
    fn diffuse_is_sine_of_angle() {
        let t = Vec3::X;
        assert!((kajiya_kay_diffuse(t, Vec3::Y) - 1.0).abs() < 1e-6);
        assert!(kajiya_kay_diffuse(t, Vec3::X).abs() < 1e-6);
        let l = Vec3::new(0.5, 3f32.sqrt() / 2.0, 0.0); // 60° from t
        assert!((kajiya_kay_diffuse(t, l) - 60f32.to_radians().sin()).abs() < 1e-6);
    }

    #[test]
    fn specular_is_one_on_the_mirror_cone() {
        let dirs = sphere(40);
        for &t in &dirs[..10] {
            for &l in &dirs {
                let cos_tl = t.dot(l);
                // Every direction with t·v = -(t·l) lies on the mirror cone of -l.
                let (u, w) = t.any_orthonormal_pair();
                for k in 0..6 {
                    let a = k as f32;
                    let perp = u * a.cos() + w * a.sin();
                    let v = (-cos_tl * t + sin_from_cos(cos_tl) * perp).normalize();
                    let s = kajiya_kay_specular(t, l, v, 50.0);
                    assert!((s - 1.0).abs() < 1e-3, "t={t} l={l} v={v}: {s}");
                }
            }
        }
    }

    #[test]
    fn specular_peaks_at_mirror_not_retro_direction() {
        let t = Vec3::X;
        let l = Vec3::new(0.6, 0.8, 0.0);
        let mirror = Vec3::new(-0.6, 0.8, 0.0);
        assert!((kajiya_kay_specular(t, l, mirror, 10.0) - 1.0).abs() < 1e-6);
        // Retro-reflection: base = -0.36 + 0.64 = 0.28.
        assert!((kajiya_kay_specular(t, l, l, 1.0) - 0.28).abs() < 1e-6);
    }

    #[test]
    fn bounded_symmetric_and_tangent_sign_invariant() {
        let dirs = sphere(64);
        for &t in dirs.iter().step_by(7) {
            for &l in dirs.iter().step_by(3) {
                let d = kajiya_kay_diffuse(t, l);
                assert!((0.0..=1.0).contains(&d));
                assert_eq!(d, kajiya_kay_diffuse(-t, l));
                for &v in dirs.iter().step_by(5) {
                    let s = kajiya_kay_specular(t, l, v, 20.0);
                    assert!((0.0..=1.0 + 1e-6).contains(&s), "{s}");
                    assert!((s - kajiya_kay_specular(t, v, l, 20.0)).abs() < 1e-6);
                    assert!((s - kajiya_kay_specular(-t, l, v, 20.0)).abs() < 1e-6);
                }
            }
        }
    }

    #[test]
    fn higher_exponent_narrows_the_lobe() {
        let t = Vec3::X;
        let l = Vec3::Y;
        let v = Vec3::new(0.3, 0.95, 0.0).normalize();
        let wide = kajiya_kay_specular(t, l, v, 4.0);
        let narrow = kajiya_kay_specular(t, l, v, 64.0);
        assert!(narrow < wide && wide < 1.0);
    }

    #[test]
    fn combined_term_weights_colors() {
        let kk = KajiyaKay {
            diffuse: Vec3::new(1.0, 0.0, 0.0),
            specular: Vec3::new(0.0, 0.0, 1.0),
            exponent: 8.0,
        };
        let t = Vec3::X;
        let l = Vec3::new(0.6, 0.8, 0.0);
        let v = Vec3::new(-0.6, 0.8, 0.0);
        let c = kajiya_kay(&kk, t, l, v);
        assert!((c.x - 0.8).abs() < 1e-6);
        assert_eq!(c.y, 0.0);
        assert!((c.z - 1.0).abs() < 1e-6);
    }

    /// Tangents spread about `t0` by a Gaussian of `sigma` radians: the mean lobe of the bundle
    /// against [`spread_kajiya_kay`] of their mean, and against the plain lobe of the mean's
    /// direction (what a volume shading its mean tangent did before). RMS errors over random
    /// geometry.
    fn spread_errors(sigma: f32) -> (f32, f32) {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 + 0.5) / (1u64 << 24) as f32
        };
        let mut gauss = move || {
            let (a, b) = (next(), next());
            (-2.0 * a.ln()).sqrt() * (std::f32::consts::TAU * b).cos()
        };
        let dirs = sphere(24);
        let kk = KajiyaKay {
            diffuse: Vec3::ZERO,
            specular: Vec3::ONE,
            exponent: 80.0,
        };
        let (mut spread_sq, mut plain_sq, mut n) = (0.0, 0.0, 0.0);
        for (i, &t0) in dirs.iter().enumerate() {
            let (u, w) = t0.any_orthonormal_pair();
            let tangents: Vec<Vec3> = (0..4000)
                .map(|_| (t0 + sigma * (gauss() * u + gauss() * w)).normalize())
                .collect();
            let mean = tangents.iter().sum::<Vec3>() / tangents.len() as f32;
            let spread = spread_kajiya_kay(&kk, mean.length());
            for (j, &l) in dirs.iter().enumerate().skip(i % 3).step_by(3) {
                let v = dirs[(i * 7 + j * 5) % dirs.len()];
                let truth = tangents
                    .iter()
                    .map(|&t| kajiya_kay_specular(t, l, v, kk.exponent))
                    .sum::<f32>()
                    / tangents.len() as f32;
                let m = mean.normalize();
                spread_sq += (kajiya_kay(&spread, m, l, v).x - truth).powi(2);
                plain_sq += (kajiya_kay(&kk, m, l, v).x - truth).powi(2);
                n += 1.0;
            }
        }
        ((spread_sq / n).sqrt(), (plain_sq / n).sqrt())
    }

    #[test]
    fn spread_lobe_matches_the_mean_of_the_spread_tangents() {
        for sigma in [0.05, 0.1, 0.2, 0.3] {
            let (spread, plain) = spread_errors(sigma);
            println!("sigma {sigma}: widened {spread:.4}, plain {plain:.4}");
            assert!(
                spread < 0.6 * plain && spread < 0.09,
                "sigma {sigma}: widened lobe off by {spread}, plain lobe by {plain}"
            );
        }
    }

    #[test]
    fn parallel_strands_keep_the_lobe_and_spread_ones_widen_it() {
        let kk = KajiyaKay::default();
        assert_eq!(spread_kajiya_kay(&kk, 1.0), kk);
        assert_eq!(spread_kajiya_kay(&kk, 1.5), kk);
        let half = spread_kajiya_kay(&kk, 1.0 - 1.0 / (TANGENT_SPREAD_WIDENING * kk.exponent));
        assert!((half.exponent - kk.exponent / 2.0).abs() < 1e-3);
        assert!(
            (half.specular - kk.specular * 0.5f32.sqrt())
                .abs()
                .max_element()
                < 1e-5
        );
        assert_eq!(half.diffuse, kk.diffuse);
        let none = spread_kajiya_kay(&kk, -1.0);
        assert!(none.exponent < 1.0 && none.exponent > 0.0);
    }
}
