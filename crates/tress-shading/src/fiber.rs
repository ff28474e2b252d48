//! The physically based hair fibre: absorption `σa` (from melanin, given directly, or from a
//! target color), longitudinal and azimuthal roughness `βm`, `βn`, cuticle tilt `α` and index of
//! refraction `η`. Shared by the real-time Marschner twins ([`crate::marschner`]) and the
//! path-traced reference (`tress-trace`'s Chiang et al. 2016 BSDF).
//!
//! # Units and conventions
//!
//! - `σa` is the absorption coefficient **per fibre radius** (the fibre's cross-section is the unit
//!   circle): light crossing the fibre once at offset `h` travels `2 cos γt / cos θt` radii and is
//!   attenuated by `exp(-σa · 2 cos γt / cos θt)` (Chiang et al. 2016 §3, as pbrt-v3/v4 and
//!   Mitsuba 3's `hair` BSDF use it). The colour of a fibre therefore does not change with its
//!   thickness.
//! - `α` is stored in radians; the scene key `alpha_deg` is in degrees, as every renderer exposes it.
//!
//! # The three ways to give a colour
//!
//! - **Melanin** (d'Eon et al. 2011 §6.1, with the eumelanin and pheomelanin absorption spectra
//!   reduced to linear RGB as pbrt-v3 and Mitsuba 3 do): `σa = c_eu · σ_eu + c_pheo · σ_pheo`
//!   with `σ_eu = (0.419, 0.697, 1.37)` and `σ_pheo = (0.187, 0.4, 1.05)`. Blond hair has
//!   `c_eu ≈ 0.3`, brown `≈ 1.3`, black `≈ 8`; pheomelanin makes hair red.
//! - **`σa` directly**, per channel.
//! - **A target colour** (Chiang et al. 2016 §4.2): the `σa` whose multiple-scattering albedo
//!   is that colour, `σa = (ln c / (5.969 - 0.215 βn + 2.532 βn² - 10.73 βn³ + 5.574 βn⁴ +
//!   0.245 βn⁵))²`, a fit the paper derived by simulation; it depends on the azimuthal roughness.
//!
//! # Roughness
//!
//! Chiang et al. 2016 §4.1 map the user's roughness to the model's: the longitudinal variance of
//! the R lobe `v = (0.726 βm + 0.812 βm² + 3.7 βm²⁰)²` (TT `v/4`, TRT and beyond `4v`, as
//! Marschner et al. 2003's lobe widths `βR`, `βR/2`, `2βR`), and the logistic scale of the
//! azimuthal lobes `s = sqrt(π/8) (0.265 βn + 1.194 βn² + 5.372 βn²²)`. Both models in tress use
//! this `βm`, so the real-time lobes are as wide as the reference's.

use glam::Vec3;

/// Eumelanin absorption per unit concentration and fibre radius, linear RGB (d'Eon et al. 2011
/// §6.1, as reduced to RGB by pbrt-v3 and Mitsuba 3).
pub const EUMELANIN_SIGMA_A: Vec3 = Vec3::new(0.419, 0.697, 1.37);
/// Pheomelanin absorption per unit concentration and fibre radius, linear RGB.
pub const PHEOMELANIN_SIGMA_A: Vec3 = Vec3::new(0.187, 0.4, 1.05);

/// The default cuticle tilt in degrees (human hair: 2–4°).
pub const DEFAULT_ALPHA_DEG: f32 = 2.0;

/// Ranges accepted by [`HairFiber::validate`] (and the scene keys), with the reason for each
/// bound in the field docs of [`HairFiber`].
pub const BETA_RANGE: (f32, f32) = (0.01, 1.0);
/// Accepted `|α|` in radians: 20°.
pub const MAX_ALPHA: f32 = 20.0 * std::f32::consts::PI / 180.0;
/// Accepted index of refraction `(1, 3]`.
pub const ETA_MAX: f32 = 3.0;

/// A hair fibre's optical parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairFiber {
    /// Absorption coefficient per fibre radius, per linear RGB channel (≥ 0).
    pub sigma_a: Vec3,
    /// Longitudinal roughness `βm` in `[0.01, 1]` (below 0.01 the lobes are narrower than f32
    /// resolves near the specular cone).
    pub beta_m: f32,
    /// Azimuthal roughness `βn` in `[0.01, 1]`.
    pub beta_n: f32,
    /// Cuticle scale tilt `α` in radians, `|α| ≤ 20°` (human hair: 2–4°).
    pub alpha: f32,
    /// Index of refraction of the fibre `η` in `(1, 3]` (keratin: 1.55).
    pub eta: f32,
}

impl Default for HairFiber {
    /// Brown hair: eumelanin 1.3, pheomelanin 0.2, `βm = βn = 0.3`, `α = 2°`, `η = 1.55` (the
    /// defaults of Mitsuba 3's `hair` BSDF).
    fn default() -> Self {
        HairFiber {
            sigma_a: sigma_a_from_melanin(1.3, 0.2),
            beta_m: 0.3,
            beta_n: 0.3,
            alpha: DEFAULT_ALPHA_DEG.to_radians(),
            eta: 1.55,
        }
    }
}

/// A fibre parameter out of range: the parameter's name and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{name}: {reason}")]
pub struct FiberError {
    /// The parameter (`sigma_a`, `beta_m`, `beta_n`, `alpha`, `eta`, `eumelanin`, ...).
    pub name: &'static str,
    /// What is wrong.
    pub reason: String,
}

impl HairFiber {
    /// Check every parameter's range (see the field docs). The error names the parameter.
    pub fn validate(&self) -> Result<(), FiberError> {
        let bad = |name, reason: String| Err(FiberError { name, reason });
        if !(self.sigma_a.is_finite() && self.sigma_a.min_element() >= 0.0) {
            return bad(
                "sigma_a",
                format!("must be finite and non-negative, got {}", self.sigma_a),
            );
        }
        for (name, b) in [("beta_m", self.beta_m), ("beta_n", self.beta_n)] {
            if !(BETA_RANGE.0..=BETA_RANGE.1).contains(&b) {
                return bad(name, format!("must lie in [0.01, 1], got {b}"));
            }
        }
        if !(-MAX_ALPHA..=MAX_ALPHA).contains(&self.alpha) {
            return bad(
                "alpha",
                format!(
                    "must lie in [-20, 20] degrees, got {}",
                    self.alpha.to_degrees()
                ),
            );
        }
        if !(self.eta > 1.0 && self.eta <= ETA_MAX) {
            return bad("eta", format!("must lie in (1, 3], got {}", self.eta));
        }
        Ok(())
    }

    /// Chiang et al. 2016 §4.1: the longitudinal variance `v` of the R lobe from `βm`; TT uses
    /// `v / 4` and TRT (and the residual) `4 v`.
    pub fn longitudinal_variance(&self) -> f32 {
        let b = self.beta_m;
        (0.726 * b + 0.812 * b * b + 3.7 * b.powi(20)).powi(2)
    }

    /// Chiang et al. 2016 §4.1: the logistic scale `s` of the azimuthal lobes from `βn`.
    pub fn logistic_scale(&self) -> f32 {
        let b = self.beta_n;
        (std::f32::consts::PI / 8.0).sqrt() * (0.265 * b + 1.194 * b * b + 5.372 * b.powi(22))
    }
}

/// `σa` of a fibre with eumelanin and pheomelanin concentrations `eumelanin`, `pheomelanin`
/// (d'Eon et al. 2011 §6.1): `c_eu · σ_eu + c_pheo · σ_pheo`.
pub fn sigma_a_from_melanin(eumelanin: f32, pheomelanin: f32) -> Vec3 {
    eumelanin * EUMELANIN_SIGMA_A + pheomelanin * PHEOMELANIN_SIGMA_A
}

/// `σa` whose multiple-scattering colour is `color` at azimuthal roughness `beta_n` (Chiang et
/// al. 2016 §4.2): `(ln c / (5.969 - 0.215 βn + 2.532 βn² - 10.73 βn³ + 5.574 βn⁴ + 0.245
/// βn⁵))²` per channel. Precondition: every channel in `(0, 1]` (1 gives `σa = 0`, white).
pub fn sigma_a_from_color(color: Vec3, beta_n: f32) -> Vec3 {
    let b = beta_n;
    let d = 5.969 - 0.215 * b + 2.532 * b.powi(2) - 10.73 * b.powi(3)
        + 5.574 * b.powi(4)
        + 0.245 * b.powi(5);
    Vec3::new(
        (color.x.ln() / d).powi(2),
        (color.y.ln() / d).powi(2),
        (color.z.ln() / d).powi(2),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn melanin_is_linear_and_darkens_blue_most() {
        assert_eq!(sigma_a_from_melanin(0.0, 0.0), Vec3::ZERO);
        assert_eq!(sigma_a_from_melanin(1.0, 0.0), EUMELANIN_SIGMA_A);
        let a = sigma_a_from_melanin(1.3, 0.2);
        let b = sigma_a_from_melanin(2.6, 0.4);
        assert!((b - 2.0 * a).abs().max_element() < 1e-6);
        // Both pigments absorb blue most and red least: hair is never bluish.
        assert!(a.x < a.y && a.y < a.z);
    }

    #[test]
    fn color_mapping_inverts_to_the_log_fit() {
        // White needs no absorption; darker colours need more; the mapping is per channel.
        assert_eq!(sigma_a_from_color(Vec3::ONE, 0.3), Vec3::ZERO);
        let s = sigma_a_from_color(Vec3::new(0.8, 0.5, 0.2), 0.3);
        assert!(s.x < s.y && s.y < s.z, "{s}");
        // Undo the fit by hand: c = exp(-sqrt(σa) · d).
        let b = 0.3f32;
        let d = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b.powi(3)
            + 5.574 * b.powi(4)
            + 0.245 * b.powi(5);
        let c = Vec3::new(
            (-s.x.sqrt() * d).exp(),
            (-s.y.sqrt() * d).exp(),
            (-s.z.sqrt() * d).exp(),
        );
        assert!(
            (c - Vec3::new(0.8, 0.5, 0.2)).abs().max_element() < 1e-5,
            "{c}"
        );
    }

    #[test]
    fn roughness_mappings_grow_and_match_their_small_roughness_slopes() {
        let f = |beta_m, beta_n| HairFiber {
            beta_m,
            beta_n,
            ..HairFiber::default()
        };
        let mut last = (0.0, 0.0);
        for k in 1..=100 {
            let b = k as f32 / 100.0;
            let fib = f(b, b);
            let (v, s) = (fib.longitudinal_variance(), fib.logistic_scale());
            assert!(v > last.0 && s > last.1);
            last = (v, s);
        }
        // For small β the leading terms dominate: sqrt(v) ≈ 0.726 β, s ≈ sqrt(π/8) 0.265 β.
        let small = f(0.01, 0.01);
        assert!((small.longitudinal_variance().sqrt() / 0.01 - 0.734).abs() < 0.01);
        let s_expected = (std::f32::consts::PI / 8.0).sqrt() * (0.265 + 1.194 * 0.01);
        assert!((small.logistic_scale() / 0.01 - s_expected).abs() < 1e-3);
    }

    #[test]
    fn validation_names_the_parameter() {
        HairFiber::default().validate().unwrap();
        let cases: [(HairFiber, &str); 6] = [
            (
                HairFiber {
                    sigma_a: Vec3::new(-1.0, 0.0, 0.0),
                    ..HairFiber::default()
                },
                "sigma_a",
            ),
            (
                HairFiber {
                    beta_m: 0.0,
                    ..HairFiber::default()
                },
                "beta_m",
            ),
            (
                HairFiber {
                    beta_n: 1.5,
                    ..HairFiber::default()
                },
                "beta_n",
            ),
            (
                HairFiber {
                    alpha: 0.5,
                    ..HairFiber::default()
                },
                "alpha",
            ),
            (
                HairFiber {
                    eta: 1.0,
                    ..HairFiber::default()
                },
                "eta",
            ),
            (
                HairFiber {
                    eta: f32::NAN,
                    ..HairFiber::default()
                },
                "eta",
            ),
        ];
        for (fiber, name) in cases {
            let e = fiber.validate().unwrap_err();
            assert_eq!(e.name, name);
            assert!(e.to_string().starts_with(name), "{e}");
        }
    }
}
