//! `[hair.material]`: the shading parameters of one hair entry. Two models read it:
//!
//! - **Kajiya-Kay and Scheuermann** (the papers' models, the default `strands.shading` and
//!   `patches` shading): `base_color`, the two highlights' colours, exponents and shifts.
//! - **Physically based hair** (`strands.shading = "marschner"`, `patches.shading =
//!   "marschner"` and `tress reference` with either): the fibre of
//!   [`tress_shading::fiber::HairFiber`], whose colour comes from exactly one of
//!   - melanin: `eumelanin`, `pheomelanin` (concentrations; absent ones at 1.3 and 0.2, brown),
//!   - `sigma_a`: the absorption per fibre radius (linear RGB),
//!   - `target_color`: the colour the hair should have after multiple scattering (Chiang et al.
//!     2016 §4.2; every channel in `(0, 1]`),
//!
//!   with the roughness `beta_m` (longitudinal), `beta_n` (azimuthal), the cuticle tilt
//!   `alpha_deg` and the index of refraction `eta`.

use glam::Vec3;
use serde::{Deserialize, Serialize};
use tress_shading::fiber::{
    DEFAULT_ALPHA_DEG, HairFiber, sigma_a_from_color, sigma_a_from_melanin,
};
use tress_shading::{HairLighting, KajiyaKay};

use crate::SceneError;
use crate::parts::{color, finite, positive};

/// Default eumelanin concentration (brown hair; Mitsuba 3's `hair` default).
pub const DEFAULT_EUMELANIN: f32 = 1.3;
/// Default pheomelanin concentration.
pub const DEFAULT_PHEOMELANIN: f32 = 0.2;

/// `[hair.material]`: shading parameters of one hair entry (see the module docs). Every key is
/// optional; the Kajiya-Kay / Scheuermann defaults are [`HairLighting::default`]'s and the
/// physically based ones [`HairFiber::default`]'s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Hair color (linear RGB): Scheuermann's base texture, Kajiya-Kay's diffuse color.
    pub base_color: Vec3,
    /// Color of the primary highlight.
    pub primary_color: Vec3,
    /// Exponent of the primary highlight (> 0).
    pub primary_exponent: f32,
    /// Tangent shift of the primary highlight (negative: towards the tip).
    pub primary_shift: f32,
    /// Color of the secondary highlight.
    pub secondary_color: Vec3,
    /// Exponent of the secondary highlight (> 0).
    pub secondary_exponent: f32,
    /// Tangent shift of the secondary highlight (positive: towards the root).
    pub secondary_shift: f32,
    /// Strand diameter (world units) used by the renderer for every strand; absent: the asset's
    /// own per-vertex thickness.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f32>,
    /// Eumelanin concentration (≥ 0; absent: 1.3 unless `sigma_a` or `target_color` is given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eumelanin: Option<f32>,
    /// Pheomelanin concentration (≥ 0; absent: 0.2 unless `sigma_a` or `target_color` is given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pheomelanin: Option<f32>,
    /// Absorption per fibre radius (linear RGB, ≥ 0), instead of melanin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_a: Option<Vec3>,
    /// Multiple-scattering colour (every channel in `(0, 1]`), instead of melanin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target_color: Option<Vec3>,
    /// Longitudinal roughness `βm` in `[0.01, 1]`.
    pub beta_m: f32,
    /// Azimuthal roughness `βn` in `[0.01, 1]`.
    pub beta_n: f32,
    /// Cuticle scale tilt `α` in degrees, `[-20, 20]`.
    pub alpha_deg: f32,
    /// Index of refraction `η` in `(1, 3]`.
    pub eta: f32,
}

impl Default for Material {
    /// Dark brown hair (`[0.3, 0.2, 0.12]`) with [`HairLighting::default`]'s highlights, and the
    /// brown fibre of [`HairFiber::default`].
    fn default() -> Self {
        let h = HairLighting::default();
        let f = HairFiber::default();
        Material {
            base_color: Vec3::new(0.30, 0.20, 0.12),
            primary_color: h.primary_color,
            primary_exponent: h.primary_exponent,
            primary_shift: h.primary_shift,
            secondary_color: h.secondary_color,
            secondary_exponent: h.secondary_exponent,
            secondary_shift: h.secondary_shift,
            thickness: None,
            eumelanin: None,
            pheomelanin: None,
            sigma_a: None,
            target_color: None,
            beta_m: f.beta_m,
            beta_n: f.beta_n,
            alpha_deg: DEFAULT_ALPHA_DEG,
            eta: f.eta,
        }
    }
}

impl Material {
    /// Scheuermann's constants (the base color is a per-fragment input, `HairSample::base_color`;
    /// the diffuse color is white).
    pub fn hair_lighting(&self) -> HairLighting {
        HairLighting {
            diffuse_color: Vec3::ONE,
            primary_exponent: self.primary_exponent,
            primary_color: self.primary_color,
            primary_shift: self.primary_shift,
            secondary_color: self.secondary_color,
            secondary_exponent: self.secondary_exponent,
            secondary_shift: self.secondary_shift,
        }
    }

    /// Kajiya-Kay parameters: the base color as diffuse, the primary highlight as specular.
    pub fn kajiya_kay(&self) -> KajiyaKay {
        KajiyaKay {
            diffuse: self.base_color,
            specular: self.primary_color,
            exponent: self.primary_exponent,
        }
    }

    /// The physically based fibre: `σa` from melanin, `sigma_a` or `target_color` (see the
    /// module docs), the roughness, tilt and index. Errors name the key (without the
    /// `hair.N.material.` prefix; [`Scene::validate`](crate::Scene::validate) adds it).
    pub fn fiber(&self) -> Result<HairFiber, SceneError> {
        let melanin = self.eumelanin.is_some() || self.pheomelanin.is_some();
        let sigma_a = match (melanin, self.sigma_a, self.target_color) {
            (_, Some(_), Some(_)) => {
                return Err(SceneError::invalid(
                    "target_color",
                    "give one of melanin (eumelanin, pheomelanin), sigma_a or target_color",
                ));
            }
            (true, Some(_), None) | (true, None, Some(_)) => {
                let key = if self.sigma_a.is_some() {
                    "sigma_a"
                } else {
                    "target_color"
                };
                return Err(SceneError::invalid(
                    key,
                    "give one of melanin (eumelanin, pheomelanin), sigma_a or target_color",
                ));
            }
            (_, Some(s), None) => s,
            (_, None, Some(c)) => {
                if !(c.is_finite() && c.min_element() > 0.0 && c.max_element() <= 1.0) {
                    return Err(SceneError::invalid(
                        "target_color",
                        format!("every channel must lie in (0, 1], got {c}"),
                    ));
                }
                sigma_a_from_color(c, self.beta_n)
            }
            (_, None, None) => {
                let eu = self.eumelanin.unwrap_or(DEFAULT_EUMELANIN);
                let pheo = self.pheomelanin.unwrap_or(DEFAULT_PHEOMELANIN);
                for (key, c) in [("eumelanin", eu), ("pheomelanin", pheo)] {
                    if !(c.is_finite() && c >= 0.0) {
                        return Err(SceneError::invalid(
                            key,
                            format!("must be finite and non-negative, got {c}"),
                        ));
                    }
                }
                sigma_a_from_melanin(eu, pheo)
            }
        };
        let fiber = HairFiber {
            sigma_a,
            beta_m: self.beta_m,
            beta_n: self.beta_n,
            alpha: self.alpha_deg.to_radians(),
            eta: self.eta,
        };
        fiber.validate().map_err(|e| {
            let key = if e.name == "alpha" {
                "alpha_deg"
            } else {
                e.name
            };
            let reason = match e.name {
                "alpha" => format!("must lie in [-20, 20], got {}", self.alpha_deg),
                _ => e.reason,
            };
            SceneError::invalid(key, reason)
        })?;
        Ok(fiber)
    }

    pub(crate) fn validate(&self, key: &str) -> Result<(), SceneError> {
        color(&format!("{key}.base_color"), self.base_color)?;
        color(&format!("{key}.primary_color"), self.primary_color)?;
        color(&format!("{key}.secondary_color"), self.secondary_color)?;
        positive(&format!("{key}.primary_exponent"), self.primary_exponent)?;
        positive(
            &format!("{key}.secondary_exponent"),
            self.secondary_exponent,
        )?;
        finite(&format!("{key}.primary_shift"), self.primary_shift)?;
        finite(&format!("{key}.secondary_shift"), self.secondary_shift)?;
        if let Some(t) = self.thickness {
            positive(&format!("{key}.thickness"), t)?;
        }
        self.fiber().map(|_| ()).map_err(|e| match e {
            SceneError::Invalid { key: k, reason } => {
                SceneError::invalid(format!("{key}.{k}"), reason)
            }
            e => e,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_fibre_is_brown_melanin() {
        let f = Material::default().fiber().unwrap();
        assert_eq!(f, HairFiber::default());
        assert_eq!(f.sigma_a, sigma_a_from_melanin(1.3, 0.2));
    }

    #[test]
    fn colour_comes_from_exactly_one_source() {
        let m = |eu, s, c| Material {
            eumelanin: eu,
            sigma_a: s,
            target_color: c,
            ..Material::default()
        };
        let s = Vec3::new(0.1, 0.2, 0.3);
        assert_eq!(m(None, Some(s), None).fiber().unwrap().sigma_a, s);
        assert_eq!(
            m(Some(0.5), None, None).fiber().unwrap().sigma_a,
            sigma_a_from_melanin(0.5, 0.2)
        );
        let c = Vec3::new(0.8, 0.6, 0.4);
        assert_eq!(
            m(None, None, Some(c)).fiber().unwrap().sigma_a,
            sigma_a_from_color(c, 0.3)
        );
        for (bad, key) in [
            (m(Some(1.0), Some(s), None), "sigma_a"),
            (m(Some(1.0), None, Some(c)), "target_color"),
            (m(None, Some(s), Some(c)), "target_color"),
            (
                m(None, None, Some(Vec3::new(0.0, 0.5, 0.5))),
                "target_color",
            ),
            (m(Some(-1.0), None, None), "eumelanin"),
            (m(None, Some(-s), None), "sigma_a"),
        ] {
            match bad.fiber().unwrap_err() {
                SceneError::Invalid { key: k, .. } => assert_eq!(k, key),
                e => panic!("{e}"),
            }
        }
    }

    #[test]
    fn fibre_ranges_name_the_scene_key() {
        for (m, key) in [
            (
                Material {
                    beta_m: 0.0,
                    ..Material::default()
                },
                "beta_m",
            ),
            (
                Material {
                    alpha_deg: 45.0,
                    ..Material::default()
                },
                "alpha_deg",
            ),
            (
                Material {
                    eta: 0.9,
                    ..Material::default()
                },
                "eta",
            ),
        ] {
            let e = m.validate("hair.0.material").unwrap_err().to_string();
            assert!(e.starts_with(&format!("hair.0.material.{key}:")), "{e}");
        }
    }

    #[test]
    fn scene_files_and_overrides_reach_the_fibre_keys() {
        let text = "[[hair]]\ngenerator = { style = \"curly\" }\n[hair.material]\n\
                    eumelanin = 0.3\nbeta_m = 0.25\nalpha_deg = 3.0\n";
        let mut scene = crate::Scene::from_str(text, ".").unwrap();
        let f = scene.hair[0].material.fiber().unwrap();
        assert_eq!(f.sigma_a, sigma_a_from_melanin(0.3, DEFAULT_PHEOMELANIN));
        assert_eq!((f.beta_m, f.alpha), (0.25, 3f32.to_radians()));
        let e = scene
            .apply_override("hair.0.material.sigma_a=[1.0,1.0,1.0]")
            .unwrap_err()
            .to_string();
        assert!(e.contains("hair.0.material.sigma_a"), "{e}");
        let e = scene
            .apply_override("hair.0.material.beta_n=2")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("hair.0.material.beta_n: must lie in [0.01, 1]"),
            "{e}"
        );
        scene.apply_override("hair.0.material.eta=1.6").unwrap();
        assert_eq!(scene.hair[0].material.fiber().unwrap().eta, 1.6);
        // The written scene reads back equal.
        let back = crate::Scene::from_str(&scene.to_toml_string().unwrap(), ".").unwrap();
        assert_eq!(back, scene);
    }
}
