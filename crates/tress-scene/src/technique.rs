//! The rendering techniques by name: [`TechniqueKind`] is the one list of them, the scene's
//! `technique` key, the CLI's `--technique` and every front end's technique switch.

use std::fmt;
use std::str::FromStr;

/// A rendering technique, spelt as in scene files (`technique = "strands"`) and on the command
/// line. `Display` writes that name and `FromStr` reads it back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TechniqueKind {
    /// The strand rasterizer (Jansson et al. 2019), `"strands"`.
    #[default]
    Strands,
    /// The volume raymarcher (Jansson et al. 2019), `"volume"`.
    Volume,
    /// Strands near, volume far, blended by distance, `"hybrid"`.
    Hybrid,
    /// Scheuermann 2004's polygon patches, `"patches"`.
    Patches,
    /// Xu et al. 2006's semantics-aware texture function, `"satf"`.
    Satf,
    /// Per head of hair and per frame, from its size on screen: strands near, volume far, the
    /// hybrid's blend between (`[hybrid]` `auto_near_px`, `auto_far_px`), `"auto"`. Not in
    /// [`TechniqueKind::ALL`]: it chooses among strands, volume and hybrid rather than drawing
    /// on its own.
    Auto,
}

impl TechniqueKind {
    /// Every technique, in the order front ends list and cycle them.
    pub const ALL: [TechniqueKind; 5] = [
        TechniqueKind::Strands,
        TechniqueKind::Volume,
        TechniqueKind::Hybrid,
        TechniqueKind::Patches,
        TechniqueKind::Satf,
    ];

    /// The technique's name (also its settings table, `[strands]`, `[volume]`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            TechniqueKind::Strands => "strands",
            TechniqueKind::Volume => "volume",
            TechniqueKind::Hybrid => "hybrid",
            TechniqueKind::Patches => "patches",
            TechniqueKind::Satf => "satf",
            TechniqueKind::Auto => "auto",
        }
    }

    /// Every name [`FromStr`] reads: [`TechniqueKind::ALL`], then `auto`.
    pub const NAMES: [&'static str; 6] = [
        TECHNIQUES[0],
        TECHNIQUES[1],
        TECHNIQUES[2],
        TECHNIQUES[3],
        TECHNIQUES[4],
        TechniqueKind::Auto.name(),
    ];

    /// Whether the technique can be given per head of hair (`[[hair]] technique`): the strand
    /// renderer's strands, volume, hybrid and auto. Patches and SATF draw the whole scene.
    pub const fn per_object(self) -> bool {
        matches!(
            self,
            TechniqueKind::Strands
                | TechniqueKind::Volume
                | TechniqueKind::Hybrid
                | TechniqueKind::Auto
        )
    }

    /// Whether the technique draws the hair's strands as loaded (strands, volume, hybrid, auto),
    /// so that moving them moves what it draws; patches and SATF build their own geometry.
    pub const fn draws_strands(self) -> bool {
        self.per_object()
    }
}

/// The names of [`TechniqueKind::ALL`], in that order.
pub const TECHNIQUES: [&str; 5] = [
    TechniqueKind::ALL[0].name(),
    TechniqueKind::ALL[1].name(),
    TechniqueKind::ALL[2].name(),
    TechniqueKind::ALL[3].name(),
    TechniqueKind::ALL[4].name(),
];

impl fmt::Display for TechniqueKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no technique.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown technique `{0}` (expected one of: strands, volume, hybrid, patches, satf, auto)")]
pub struct UnknownTechnique(pub String);

impl FromStr for TechniqueKind {
    type Err = UnknownTechnique;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TechniqueKind::ALL
            .into_iter()
            .chain([TechniqueKind::Auto])
            .find(|t| t.name() == s)
            .ok_or_else(|| UnknownTechnique(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_round_trips() {
        for t in TechniqueKind::ALL.into_iter().chain([TechniqueKind::Auto]) {
            assert_eq!(t.to_string().parse::<TechniqueKind>(), Ok(t));
            assert_eq!(t.to_string(), t.name());
            assert!(TechniqueKind::NAMES.contains(&t.name()));
        }
        assert_eq!(TechniqueKind::NAMES.len(), TechniqueKind::ALL.len() + 1);
        assert_eq!(
            TECHNIQUES,
            ["strands", "volume", "hybrid", "patches", "satf"]
        );
        let names: std::collections::HashSet<_> = TECHNIQUES.iter().collect();
        assert_eq!(names.len(), TechniqueKind::ALL.len(), "names are distinct");
    }

    #[test]
    fn an_unknown_name_is_an_error_listing_every_technique() {
        let e = "raytrace".parse::<TechniqueKind>().unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "unknown technique `raytrace` (expected one of: {})",
                TechniqueKind::NAMES.join(", ")
            )
        );
        assert!(
            "Strands".parse::<TechniqueKind>().is_err(),
            "names are case-sensitive"
        );
    }
}
