//! `follow = { ... }` of a `[[hair]]` entry: TressFX-style follow hairs.

use serde::{Deserialize, Serialize};
use tress_hair::{FollowMode, FollowParams, FollowRadius};

use crate::SceneError;
use crate::parts::non_negative;

/// `follow = { count, mode, root_radius, tip_separation, seed }`: follow hairs
/// ([`tress_hair::FollowParams`]); absent fields take its defaults (count 0, mode
/// `"interpolate"`, root radius `"0.7x"`: 0.7 times the guides' root spacing, tip separation 1,
/// seed 0). `root_radius` is a number of world units (`0.25`) or a multiple of the guides' root
/// spacing (`"0.6x"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FollowSpec {
    /// Followers per strand.
    pub count: u32,
    /// `"interpolate"` (blend the three surrounding guides) or `"offset"` (TressFX's copies).
    #[serde(with = "follow_mode")]
    pub mode: FollowMode,
    /// Offset mode: the largest root offset of a follower; interpolated mode: the scale of its
    /// stray toward the tip.
    #[serde(with = "follow_radius")]
    pub root_radius: FollowRadius,
    /// How much farther apart the tips are than the roots (offset), or how far they stray from
    /// the blend in root radii (interpolate).
    pub tip_separation: f32,
    /// Random seed.
    pub seed: u64,
}

impl Default for FollowSpec {
    fn default() -> Self {
        FollowSpec::from(FollowParams::default())
    }
}

impl From<FollowParams> for FollowSpec {
    fn from(p: FollowParams) -> Self {
        FollowSpec {
            count: p.count,
            mode: p.mode,
            root_radius: p.root_radius,
            tip_separation: p.tip_separation,
            seed: p.seed,
        }
    }
}

impl From<&FollowSpec> for FollowParams {
    fn from(f: &FollowSpec) -> Self {
        FollowParams {
            count: f.count,
            mode: f.mode,
            root_radius: f.root_radius,
            tip_separation: f.tip_separation,
            seed: f.seed,
        }
    }
}

impl FollowSpec {
    pub(crate) fn validate(&self, key: &str) -> Result<(), SceneError> {
        let (FollowRadius::World(r) | FollowRadius::Spacing(r)) = self.root_radius;
        non_negative(&format!("{key}.root_radius"), r)?;
        non_negative(&format!("{key}.tip_separation"), self.tip_separation)
    }
}

/// `mode` as its name.
mod follow_mode {
    use serde::{Deserialize, Deserializer, Serializer};
    use tress_hair::FollowMode;

    pub(super) fn serialize<S: Serializer>(m: &FollowMode, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(m.name())
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<FollowMode, D::Error> {
        String::deserialize(d)?
            .parse()
            .map_err(serde::de::Error::custom)
    }
}

/// `root_radius` as a number (world units) or a string `"<k>x"` (times the root spacing).
mod follow_radius {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use tress_hair::FollowRadius;

    #[derive(Serialize, Deserialize)]
    #[serde(untagged)]
    enum Text {
        World(f32),
        Relative(String),
    }

    pub(super) fn serialize<S: Serializer>(r: &FollowRadius, s: S) -> Result<S::Ok, S::Error> {
        match r {
            FollowRadius::World(x) => Text::World(*x),
            FollowRadius::Spacing(_) => Text::Relative(r.to_string()),
        }
        .serialize(s)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<FollowRadius, D::Error> {
        match Text::deserialize(d)? {
            Text::World(x) => Ok(FollowRadius::World(x)),
            Text::Relative(t) => t.parse().map_err(serde::de::Error::custom),
        }
    }
}
