//! Settings of the reference tracer ([`TraceSettings`]) and what it writes ([`Aov`]).

use std::fmt;
use std::str::FromStr;

use crate::TraceError;

/// What the image holds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Aov {
    /// Shaded color (linear RGB), composited over the background: `"color"`.
    #[default]
    Color,
    /// Ambient occlusion in `[0, 1]` (1: unoccluded) as grey, background 1: `"ao"`.
    Ao,
    /// Light visibility in `[0, 1]` (1: lit) as grey, averaged over the lights weighted by their
    /// radiance's luminance, background 1: `"shadow"`.
    Shadow,
}

impl Aov {
    /// Every AOV, in the order the CLI lists them.
    pub const ALL: [Aov; 3] = [Aov::Color, Aov::Ao, Aov::Shadow];

    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Color => "color",
            Aov::Ao => "ao",
            Aov::Shadow => "shadow",
        }
    }
}

impl fmt::Display for Aov {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Aov {
    type Err = TraceError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Aov::ALL
            .into_iter()
            .find(|a| a.name() == s)
            .ok_or_else(|| TraceError::Setting {
                key: "aov".into(),
                reason: format!("unknown AOV `{s}` (expected color, ao or shadow)"),
            })
    }
}

/// How wide strands are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StrandWidth {
    /// [`StrandWidth::Thickness`] when the hair has a thickness (the asset's per-vertex thickness
    /// or the material's `thickness`), else [`StrandWidth::Screen`]: `"auto"`.
    #[default]
    Auto,
    /// The physical diameter: the material's `thickness` if set, else the asset's per-vertex
    /// thickness (tapering to the tips): `"thickness"`.
    Thickness,
    /// The GPU rasterizer's screen-space width: `width_px` pixels converted to world units at each
    /// vertex's distance from the camera, with the GPU's `thickness_fade` applied to alpha:
    /// `"screen"`.
    Screen,
}

impl StrandWidth {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            StrandWidth::Auto => "auto",
            StrandWidth::Thickness => "thickness",
            StrandWidth::Screen => "screen",
        }
    }
}

impl FromStr for StrandWidth {
    type Err = TraceError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [
            StrandWidth::Auto,
            StrandWidth::Thickness,
            StrandWidth::Screen,
        ]
        .into_iter()
        .find(|w| w.name() == s)
        .ok_or_else(|| TraceError::Setting {
            key: "width".into(),
            reason: format!("unknown width mode `{s}` (expected auto, thickness or screen)"),
        })
    }
}

/// Settings of the reference tracer. Scene-independent; what the scene decides (camera, lights,
/// material, strand alpha and the GPU's `width_px`) comes from the scene.
///
/// On the command line every field is also `--set trace.NAME=VALUE`.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceSettings {
    /// Camera samples per pixel (`1..=65536`; default 64). Each sample traces one camera path:
    /// one primary ray (continued through rejected translucent strands in the same traversal),
    /// one shadow ray per light and `ao_samples` AO rays.
    pub spp: u32,
    /// Random seed: the same seed gives the same image, whatever the thread count.
    pub seed: u64,
    /// What the image holds.
    pub aov: Aov,
    /// Occluders farther than this (world units) do not count for ambient occlusion
    /// (default 5; `inf` for no limit).
    pub ao_radius: f32,
    /// AO rays per camera sample (`0..=1024`; default 1; 0 turns AO off: AO = 1).
    pub ao_samples: u32,
    /// Ambient light (linear, per channel), multiplied by the AO; `None` (default): the scene's
    /// `ambient`, the one `tress render` shades with.
    pub ambient: Option<f32>,
    /// How wide strands are.
    pub width: StrandWidth,
    /// In [`StrandWidth::Screen`] mode: the strand's width in pixels. `None` (default): half the
    /// scene's `strands.width_px`, the width of a solid line with the same ink as the GPU's
    /// ribbon, whose §3.2 coverage falls linearly from 1 at its centre to 0 at its edges.
    pub width_px: Option<f32>,
    /// Ray-traced shadows from the directional lights (default true).
    pub shadows: bool,
    /// Physically based shading only (`strands.shading = "marschner"`): the most bounces a path
    /// makes after the camera ray's hit (`0..=1024`; 0 is direct light only; default 32, enough
    /// for blond hair, whose paths carry light through tens of fibres; Russian roulette ends
    /// darker paths early).
    pub bounces: u32,
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            spp: 64,
            seed: 0,
            aov: Aov::Color,
            ao_radius: 5.0,
            ao_samples: 1,
            ambient: None,
            width: StrandWidth::Auto,
            width_px: None,
            shadows: true,
            bounces: 32,
        }
    }
}

/// Names accepted by [`TraceSettings::set`].
pub const SETTING_NAMES: [&str; 10] = [
    "spp",
    "seed",
    "aov",
    "ao_radius",
    "ao_samples",
    "ambient",
    "width",
    "width_px",
    "shadows",
    "bounces",
];

impl TraceSettings {
    /// Check every value's range; the error names the setting.
    pub fn validate(&self) -> Result<(), TraceError> {
        let bad = |key: &str, reason: &str| {
            Err(TraceError::Setting {
                key: key.into(),
                reason: reason.into(),
            })
        };
        if !(1..=65536).contains(&self.spp) {
            return bad("spp", "must lie in 1..=65536");
        }
        if self.ao_radius.is_nan() || self.ao_radius <= 0.0 {
            return bad("ao_radius", "must be positive (inf for no limit)");
        }
        if self.ao_samples > 1024 {
            return bad("ao_samples", "must lie in 0..=1024");
        }
        if self.ambient.is_some_and(|a| !(a >= 0.0 && a.is_finite())) {
            return bad("ambient", "must be finite and non-negative");
        }
        if self.bounces > 1024 {
            return bad("bounces", "must lie in 0..=1024");
        }
        if let Some(w) = self.width_px
            && !(w > 0.0 && w <= 64.0)
        {
            return bad("width_px", "must lie in (0, 64]");
        }
        Ok(())
    }

    /// Set one setting from text: `name` is one of [`SETTING_NAMES`] (without a `trace.`
    /// prefix), `value` as on the command line (quotes around strings are optional). The
    /// settings are validated afterwards; on error they are unchanged.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), TraceError> {
        let value = value.trim().trim_matches('"');
        let err = |reason: String| TraceError::Setting {
            key: name.to_owned(),
            reason,
        };
        let num = |v: &str| -> Result<f32, TraceError> {
            v.parse::<f32>()
                .map_err(|_| err(format!("expected a number, got `{v}`")))
        };
        let int = |v: &str| -> Result<u64, TraceError> {
            v.parse::<u64>()
                .map_err(|_| err(format!("expected a non-negative integer, got `{v}`")))
        };
        let mut next = self.clone();
        match name {
            "spp" => next.spp = u32::try_from(int(value)?).map_err(|_| err("too large".into()))?,
            "seed" => next.seed = int(value)?,
            "aov" => next.aov = value.parse()?,
            "ao_radius" => next.ao_radius = num(value)?,
            "ao_samples" => {
                next.ao_samples = u32::try_from(int(value)?).map_err(|_| err("too large".into()))?
            }
            "ambient" => next.ambient = Some(num(value)?),
            "width" => next.width = value.parse()?,
            "width_px" => next.width_px = Some(num(value)?),
            "bounces" => {
                next.bounces = u32::try_from(int(value)?).map_err(|_| err("too large".into()))?
            }
            "shadows" => {
                next.shadows = value
                    .parse::<bool>()
                    .map_err(|_| err(format!("expected true or false, got `{value}`")))?
            }
            _ => {
                return Err(err(format!(
                    "unknown setting (expected one of: {})",
                    SETTING_NAMES.join(", ")
                )));
            }
        }
        next.validate()?;
        *self = next;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_names_parse() {
        TraceSettings::default().validate().unwrap();
        for a in Aov::ALL {
            assert_eq!(a.name().parse::<Aov>().unwrap(), a);
        }
        assert!("normal".parse::<Aov>().is_err());
    }

    #[test]
    fn set_parses_checks_and_names_the_key() {
        let mut s = TraceSettings::default();
        s.set("spp", "16").unwrap();
        s.set("aov", "\"ao\"").unwrap();
        s.set("ao_radius", "inf").unwrap();
        s.set("width", "screen").unwrap();
        s.set("width_px", "2").unwrap();
        s.set("shadows", "false").unwrap();
        s.set("bounces", "8").unwrap();
        assert_eq!(s.bounces, 8);
        assert_eq!(s.spp, 16);
        assert_eq!(s.aov, Aov::Ao);
        assert_eq!(s.ao_radius, f32::INFINITY);
        assert_eq!(s.width, StrandWidth::Screen);
        assert_eq!(s.width_px, Some(2.0));
        assert!(!s.shadows);
        let before = s.clone();
        for (k, v) in [
            ("spp", "0"),
            ("spp", "x"),
            ("ao_radius", "-1"),
            ("bounces", "2000"),
            ("fov", "1"),
        ] {
            let e = s.set(k, v).unwrap_err().to_string();
            assert!(e.contains(k), "{e}");
            assert_eq!(s, before);
        }
    }
}
