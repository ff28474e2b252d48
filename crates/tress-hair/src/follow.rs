//! Follow-hair generation in the TressFX manner: every guide strand gets `count` followers that
//! copy its shape, offset by a random vector in the plane perpendicular to the guide's root
//! tangent. The offset grows from the root to the tip by the tip-separation factor, so followers
//! fan out: `follower[i] = guide[i] + offset * (1 + tip_separation * i / (n - 1))`.

use glam::Vec3;

use crate::rng::Rng;
use crate::{HairAsset, HairError};

/// Parameters of follow-hair generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowParams {
    /// Followers per guide (`strands = guides * (count + 1)`).
    pub count: u32,
    /// Largest root offset of a follower from its guide (world units).
    pub root_radius: f32,
    /// How much farther apart the tips are than the roots (0: parallel followers).
    pub tip_separation: f32,
    /// Random seed; the same seed gives the same followers.
    pub seed: u64,
}

impl Default for FollowParams {
    /// TressFX's sample defaults: a 0.3-unit root radius and a tip separation of 1.
    fn default() -> Self {
        FollowParams {
            count: 0,
            root_radius: 0.3,
            tip_separation: 1.0,
            seed: 0,
        }
    }
}

impl HairAsset {
    /// The asset with `params.count` followers after each guide strand (guide first, then its
    /// followers). Per-vertex attributes and strand UVs are copied from the guide.
    pub fn with_follow_hairs(&self, params: &FollowParams) -> Result<HairAsset, HairError> {
        if params.count == 0 {
            return Ok(self.clone());
        }
        let valid = |x: f32| x.is_finite() && x >= 0.0;
        if !valid(params.root_radius) || !valid(params.tip_separation) {
            return Err(HairError::Parameter(
                "follow-hair radius and tip separation must be finite and non-negative".into(),
            ));
        }
        let per_guide = params.count as usize + 1;
        let strands = self.strand_count().checked_mul(per_guide);
        let vertices = self.vertex_count().checked_mul(per_guide);
        let (Some(strands), Some(vertices)) = (strands, vertices) else {
            return Err(HairError::Parameter("too many follow hairs".into()));
        };
        if vertices > u32::MAX as usize {
            return Err(HairError::Parameter(format!(
                "{} followers per guide would make {vertices} vertices (more than 2^32)",
                params.count
            )));
        }
        let tangents = self.tangents();
        let mut positions = Vec::with_capacity(vertices);
        let mut counts = Vec::with_capacity(strands);
        for (g, range) in (0..self.strand_count()).map(|g| (g, self.strand_range(g))) {
            let guide = &self.positions()[range.clone()];
            let n = guide.len();
            positions.extend_from_slice(guide);
            counts.push(n as u32);
            let (u, v) = tangents[range.start].any_orthonormal_pair();
            let mut rng = Rng::stream(params.seed, g as u64);
            for _ in 0..params.count {
                let d = rng.in_disk() * params.root_radius;
                let offset: Vec3 = u * d.x + v * d.y;
                let denom = (n.max(2) - 1) as f32;
                positions.extend(
                    guide.iter().enumerate().map(|(i, &p)| {
                        p + offset * (1.0 + params.tip_separation * i as f32 / denom)
                    }),
                );
                counts.push(n as u32);
            }
        }
        let mut out = HairAsset::from_counts(positions, &counts)?;
        let repeat_vertex = |a: &[f32]| -> Vec<f32> { repeat_strands(self, a, per_guide) };
        if let Some(t) = self.thickness() {
            out = out.with_thickness(repeat_vertex(t))?;
        }
        if let Some(t) = self.transparency() {
            out = out.with_transparency(repeat_vertex(t))?;
        }
        if let Some(c) = self.color() {
            out = out.with_color(repeat_strands(self, c, per_guide))?;
        }
        if let Some(uv) = self.strand_uv() {
            out = out.with_strand_uv(
                uv.iter()
                    .flat_map(|&x| std::iter::repeat_n(x, per_guide))
                    .collect(),
            )?;
        }
        Ok(out)
    }
}

/// Repeat each strand's slice of a per-vertex array `per_guide` times.
fn repeat_strands<T: Copy>(asset: &HairAsset, values: &[T], per_guide: usize) -> Vec<T> {
    let mut out = Vec::with_capacity(values.len() * per_guide);
    for s in 0..asset.strand_count() {
        let slice = &values[asset.strand_range(s)];
        for _ in 0..per_guide {
            out.extend_from_slice(slice);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guides() -> HairAsset {
        let mut p = Vec::new();
        for g in 0..3 {
            for i in 0..16 {
                p.push(Vec3::new(g as f32 * 5.0, -(i as f32), 0.0));
            }
        }
        HairAsset::from_counts(p, &[16, 16, 16]).unwrap()
    }

    #[test]
    fn followers_fan_out_around_their_guide() {
        let params = FollowParams {
            count: 4,
            root_radius: 0.5,
            tip_separation: 2.0,
            seed: 9,
        };
        let h = guides().with_follow_hairs(&params).unwrap();
        assert_eq!(h.strand_count(), 3 * 5);
        for g in 0..3 {
            let guide = h.strand(g * 5);
            assert_eq!(guide, guides().strand(g));
            for f in 1..5 {
                let s = h.strand(g * 5 + f);
                let root = s[0] - guide[0];
                let tip = s[15] - guide[15];
                assert!(root.length() <= 0.5 + 1e-5);
                // Offsets lie in the plane perpendicular to the guide (the guide runs along -Y).
                assert!(root.y.abs() < 1e-5);
                assert!((tip.length() - 3.0 * root.length()).abs() < 1e-4);
            }
        }
    }

    #[test]
    fn deterministic_for_a_seed() {
        let p = FollowParams {
            count: 3,
            seed: 1,
            ..Default::default()
        };
        assert_eq!(
            guides().with_follow_hairs(&p).unwrap(),
            guides().with_follow_hairs(&p).unwrap()
        );
        let q = FollowParams { seed: 2, ..p };
        assert_ne!(
            guides().with_follow_hairs(&p).unwrap(),
            guides().with_follow_hairs(&q).unwrap()
        );
    }

    #[test]
    fn rejects_bad_parameters() {
        let p = FollowParams {
            count: 1,
            root_radius: f32::NAN,
            ..Default::default()
        };
        assert!(guides().with_follow_hairs(&p).is_err());
        let p = FollowParams {
            count: u32::MAX,
            ..Default::default()
        };
        assert!(guides().with_follow_hairs(&p).is_err());
    }
}
