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
}
