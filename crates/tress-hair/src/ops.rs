//! Operations on hair assets: transform, resample, subset.
//!
//! Resampling places the new vertices uniformly by arc length along each strand's polyline and
//! interpolates every per-vertex attribute (thickness, transparency, color) linearly between the
//! two source vertices around each new vertex; strand UVs are kept. Subsets are a deterministic
//! shuffle of the strand indices, so they nest: for one seed, the strands kept at a smaller ratio
//! are also kept at every larger ratio, which makes `subset` a level-of-detail tool.

use glam::{Affine3A, Vec3};
use rayon::prelude::*;

use crate::rng::Rng;
use crate::{HairAsset, HairError};

/// Largest vertex count an operation or generator will produce (2^31): beyond it the request is
/// refused before anything is allocated.
pub(crate) const MAX_VERTICES: u64 = 1 << 31;

/// A resampled vertex: a point between source vertices `a` and `b` (global indices, `b` is `a`
/// or `a + 1` within the same strand) at fraction `f` from `a`.
#[derive(Clone, Copy, Debug, Default)]
struct Sample {
    a: u32,
    b: u32,
    f: f32,
}

impl HairAsset {
    /// Apply an affine transform to every vertex position.
    ///
    /// Per-vertex thickness is left unchanged: it is a fibre diameter in world units, and a
    /// non-uniform scale has no single factor for it. Scale it yourself if you scale the asset.
    /// Tangents follow from the new positions. Nothing changes and an error is returned if the
    /// transform is not finite or would move a vertex to a non-finite position.
    pub fn transform(&mut self, m: Affine3A) -> Result<(), HairError> {
        if !m.is_finite() {
            return Err(HairError::Parameter("the transform is not finite".into()));
        }
        let moved: Vec<Vec3> = self
            .positions()
            .par_iter()
            .map(|&p| m.transform_point3(p))
            .collect();
        if let Some(i) = moved.iter().position(|p| !p.is_finite()) {
            return Err(HairError::Parameter(format!(
                "the transform moves vertex {i} to a non-finite position"
            )));
        }
        self.positions_mut().copy_from_slice(&moved);
        Ok(())
    }

    /// Every strand resampled to `n` vertices (`n >= 2`), placed uniformly by arc length: the
    /// first and last vertices are the strand's own root and tip, the segments in between have
    /// equal length. Per-vertex attributes are interpolated, strand UVs kept. A strand of zero
    /// length (or a single vertex) becomes `n` copies of its root.
    pub fn resample_count(&self, n: u32) -> Result<HairAsset, HairError> {
        if n < 2 {
            return Err(HairError::Parameter(format!(
                "a resampled strand needs at least 2 vertices, got {n}"
            )));
        }
        let total = self.strand_count() as u64 * u64::from(n);
        if total > MAX_VERTICES {
            return Err(HairError::Parameter(format!(
                "{} strands of {n} vertices is {total} vertices, more than 2^31",
                self.strand_count()
            )));
        }
        self.resample_to(vec![n; self.strand_count()])
    }

    /// Every strand resampled to `ceil(length / segment_length)` equal segments (at least one),
    /// placed uniformly by arc length as in [`HairAsset::resample_count`]. A ratio within 1e-4
    /// of a whole number counts as that number, so rounding in the summed strand length does not
    /// add a tiny extra segment. `segment_length` is in world units, finite and positive.
    pub fn resample_length(&self, segment_length: f32) -> Result<HairAsset, HairError> {
        if !(segment_length.is_finite() && segment_length > 0.0) {
            return Err(HairError::Parameter(format!(
                "segment length must be finite and positive, got {segment_length}"
            )));
        }
        let mut counts = Vec::with_capacity(self.strand_count());
        let mut total: u64 = 0;
        for length in self.strand_lengths() {
            let segments = (f64::from(length) / f64::from(segment_length) - 1e-4)
                .ceil()
                .max(1.0);
            // `segments` is at least 1 and may be huge or infinite: compare before converting.
            if segments >= MAX_VERTICES as f64 {
                return Err(too_many(segment_length));
            }
            let vertices = segments as u64 + 1;
            total += vertices;
            if total > MAX_VERTICES {
                return Err(too_many(segment_length));
            }
            counts.push(vertices as u32);
        }
        self.resample_to(counts)
    }

    /// A level-of-detail subset: the first `round(ratio * strands)` strands (at least one) of a
    /// shuffle of the strand indices determined by `seed`, kept in their original order, with
    /// their attributes. For one seed, a smaller ratio's subset is contained in a larger one's.
    /// `ratio` must lie in `[0, 1]`.
    pub fn subset(&self, ratio: f32, seed: u64) -> Result<HairAsset, HairError> {
        if !(0.0..=1.0).contains(&ratio) {
            return Err(HairError::Parameter(format!(
                "subset ratio must lie in [0, 1], got {ratio}"
            )));
        }
        let n = self.strand_count();
        let keep = ((f64::from(ratio) * n as f64).round() as usize).clamp(1, n);
        // A partial Fisher-Yates shuffle: its first `keep` entries do not depend on `keep`, so
        // subsets of one seed nest.
        let mut order: Vec<u32> = (0..n as u32).collect();
        let mut rng = Rng::new(seed);
        for i in 0..keep {
            let j = i + rng.below((n - i) as u64) as usize;
            order.swap(i, j);
        }
        let mut kept = order[..keep].to_vec();
        kept.sort_unstable();
        self.select_strands(&kept)
    }

    /// The strands `strands` (a range of strand indices) as an asset of their own, with their
    /// attributes: one `[[hair]]` entry of an asset the entries were merged into.
    pub fn strand_span(&self, strands: std::ops::Range<usize>) -> Result<HairAsset, HairError> {
        if strands.is_empty() || strands.end > self.strand_count() {
            return Err(HairError::Parameter(format!(
                "strands {}..{} of an asset with {}",
                strands.start,
                strands.end,
                self.strand_count()
            )));
        }
        let kept: Vec<u32> = (strands.start as u32..strands.end as u32).collect();
        self.select_strands(&kept)
    }

    /// The strands with the given indices (sorted, in range), with their attributes.
    fn select_strands(&self, kept: &[u32]) -> Result<HairAsset, HairError> {
        let ranges: Vec<std::ops::Range<usize>> = kept
            .iter()
            .map(|&s| self.strand_range(s as usize))
            .collect();
        fn gather<T: Copy>(values: &[T], ranges: &[std::ops::Range<usize>]) -> Vec<T> {
            ranges
                .iter()
                .flat_map(|r| values[r.clone()].iter().copied())
                .collect()
        }
        let counts: Vec<u32> = ranges.iter().map(|r| r.len() as u32).collect();
        let mut out = HairAsset::from_counts(gather(self.positions(), &ranges), &counts)?;
        if let Some(t) = self.thickness() {
            out = out.with_thickness(gather(t, &ranges))?;
        }
        if let Some(t) = self.transparency() {
            out = out.with_transparency(gather(t, &ranges))?;
        }
        if let Some(c) = self.color() {
            out = out.with_color(gather(c, &ranges))?;
        }
        if let Some(uv) = self.strand_uv() {
            out = out.with_strand_uv(kept.iter().map(|&s| uv[s as usize]).collect())?;
        }
        Ok(out)
    }

    /// Resample strand `i` to `counts[i]` vertices (each at least 2; the total already checked).
    fn resample_to(&self, counts: Vec<u32>) -> Result<HairAsset, HairError> {
        let total: usize = counts.iter().map(|&c| c as usize).sum();
        let mut samples = vec![Sample::default(); total];
        // One mutable slice of `samples` per strand, filled in parallel.
        let mut slices = Vec::with_capacity(counts.len());
        let mut rest = samples.as_mut_slice();
        for &c in &counts {
            let (head, tail) = rest.split_at_mut(c as usize);
            slices.push(head);
            rest = tail;
        }
        slices.into_par_iter().enumerate().for_each(|(s, out)| {
            let range = self.strand_range(s);
            arc_length_samples(&self.positions()[range.clone()], range.start as u32, out);
        });

        let positions = interpolate(self.positions(), &samples, |a, b, f| a.lerp(b, f));
        let mut out = HairAsset::from_counts(positions, &counts)?;
        if let Some(t) = self.thickness() {
            out = out.with_thickness(interpolate(t, &samples, lerp_f32))?;
        }
        if let Some(t) = self.transparency() {
            out = out.with_transparency(interpolate(t, &samples, lerp_f32))?;
        }
        if let Some(c) = self.color() {
            out = out.with_color(interpolate(c, &samples, |a, b, f| a.lerp(b, f)))?;
        }
        if let Some(uv) = self.strand_uv() {
            out = out.with_strand_uv(uv.to_vec())?;
        }
        Ok(out)
    }
}

fn too_many(segment_length: f32) -> HairError {
    HairError::Parameter(format!(
        "segments of length {segment_length} would make more than 2^31 vertices"
    ))
}

fn lerp_f32(a: f32, b: f32, f: f32) -> f32 {
    a + (b - a) * f
}

fn interpolate<T: Copy + Send + Sync>(
    values: &[T],
    samples: &[Sample],
    lerp: impl Fn(T, T, f32) -> T + Sync,
) -> Vec<T> {
    samples
        .par_iter()
        .map(|s| {
            let a = values[s.a as usize];
            if s.f == 0.0 {
                a
            } else {
                lerp(a, values[s.b as usize], s.f)
            }
        })
        .collect()
}

/// Fill `out` (at least 2 entries) with samples spaced uniformly by arc length along `strand`,
/// whose first vertex has global index `first`. The first and last samples hit the root and tip
/// exactly.
fn arc_length_samples(strand: &[Vec3], first: u32, out: &mut [Sample]) {
    let last = strand.len() - 1;
    let length: f32 = strand.windows(2).map(|w| w[0].distance(w[1])).sum();
    let steps = (out.len() - 1) as f32;
    let n = out.len();
    // Walk the segments once: `seg` is the current segment, `start` the arc length at its root.
    let (mut seg, mut start) = (0usize, 0.0f32);
    for (k, sample) in out.iter_mut().enumerate() {
        let vertex = |i: usize| first + i as u32;
        if k == 0 || length == 0.0 {
            *sample = Sample {
                a: first,
                b: first,
                f: 0.0,
            };
            continue;
        }
        if k == n - 1 {
            *sample = Sample {
                a: vertex(last),
                b: vertex(last),
                f: 0.0,
            };
            continue;
        }
        let target = length * k as f32 / steps;
        let mut seg_len = strand[seg].distance(strand[seg + 1]);
        while seg + 1 < last && start + seg_len < target {
            start += seg_len;
            seg += 1;
            seg_len = strand[seg].distance(strand[seg + 1]);
        }
        let f = if seg_len > 0.0 {
            ((target - start) / seg_len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        *sample = Sample {
            a: vertex(seg),
            b: vertex(seg + 1),
            f,
        };
    }
}

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec2};
    use proptest::prelude::*;

    use super::*;

    /// A straight strand along +X from 0 to 10 with uneven vertex spacing, and an L-shaped one.
    fn uneven() -> HairAsset {
        let p = vec![
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.5, 0.0, 0.0),
            Vec3::new(7.0, 0.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 5.0, 0.0),
            Vec3::new(0.0, 5.0, 3.0),
            Vec3::new(4.0, 5.0, 3.0),
        ];
        HairAsset::from_counts(p, &[5, 3])
            .unwrap()
            .with_thickness(vec![1.0, 0.9, 0.85, 0.3, 0.0, 2.0, 2.0, 2.0])
            .unwrap()
            .with_color(vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::X,
                Vec3::X,
                Vec3::ONE,
                Vec3::Y,
                Vec3::Y,
                Vec3::Y,
            ])
            .unwrap()
            .with_strand_uv(vec![Vec2::new(0.1, 0.2), Vec2::new(0.3, 0.4)])
            .unwrap()
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        a.distance(b) < 1e-4
    }

    #[test]
    fn transform_moves_positions_and_keeps_thickness() {
        let mut h = uneven();
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
            Vec3::new(1.0, 2.0, 3.0),
        );
        h.transform(m).unwrap();
        // Rotating +X by 90 degrees about Z gives +Y; scaled by 2, then translated.
        assert!(close(h.positions()[4], Vec3::new(1.0, 22.0, 3.0)));
        assert!(close(h.positions()[6], Vec3::new(-9.0, 2.0, 9.0)));
        assert_eq!(h.thickness(), uneven().thickness());
        assert!((h.length_stats().total - 2.0 * uneven().length_stats().total).abs() < 1e-3);
    }

    #[test]
    fn transform_rejects_non_finite_results_without_change() {
        let mut h = uneven();
        assert!(
            h.transform(Affine3A::from_scale(Vec3::splat(f32::NAN)))
                .is_err()
        );
        assert!(
            h.transform(Affine3A::from_scale(Vec3::splat(f32::MAX)))
                .is_err()
        );
        assert_eq!(h, uneven());
    }

    #[test]
    fn resample_count_spaces_vertices_evenly() {
        let r = uneven().resample_count(6).unwrap();
        assert_eq!(r.strand_count(), 2);
        assert_eq!(r.vertices_per_strand_range(), (6, 6));
        // The straight strand of length 10: vertices every 2 units from the root to the tip.
        for (k, p) in r.strand(0).iter().enumerate() {
            assert!(close(*p, Vec3::new(2.0 * k as f32, 0.0, 0.0)), "{k}: {p}");
        }
        // The L-shaped strand (lengths 3 + 4 = 7): same endpoints, equal steps of 7/5 along it;
        // the corner is cut, so chords are no longer than the step.
        let s = r.strand(1);
        assert_eq!(s[0], Vec3::new(0.0, 5.0, 0.0));
        assert_eq!(s[5], Vec3::new(4.0, 5.0, 3.0));
        assert!(close(s[1], Vec3::new(0.0, 5.0, 1.4)));
        assert!(close(s[3], Vec3::new(1.2, 5.0, 3.0)));
        for w in s.windows(2) {
            assert!(w[0].distance(w[1]) <= 1.4 + 1e-4);
        }
        // Attributes interpolated at the same arc-length positions: at x = 2 the thickness lies
        // between 0.85 (x = 1.5) and 0.3 (x = 7), a tenth of the way.
        let t = r.thickness().unwrap();
        assert_eq!(t[0], 1.0);
        assert!((t[1] - (0.85 - 0.55 * 0.5 / 5.5)).abs() < 1e-5, "{}", t[1]);
        assert_eq!(t[5], 0.0);
        assert_eq!(&t[6..], &[2.0; 6]);
        let c = r.color().unwrap();
        assert_eq!(c[0], Vec3::ZERO);
        assert_eq!(c[5], Vec3::ONE);
        assert_eq!(r.strand_uv(), uneven().strand_uv());
    }

    #[test]
    fn resample_handles_degenerate_strands() {
        let h =
            HairAsset::from_counts(vec![Vec3::ONE, Vec3::X, Vec3::X, Vec3::X], &[1, 3]).unwrap();
        let r = h.resample_count(4).unwrap();
        assert_eq!(r.strand(0), &[Vec3::ONE; 4]);
        assert_eq!(r.strand(1), &[Vec3::X; 4]);
        let r = h.resample_length(0.5).unwrap();
        assert_eq!(r.vertices_per_strand_range(), (2, 2));
    }

    #[test]
    fn resample_length_picks_the_segment_count() {
        let r = uneven().resample_length(3.0).unwrap();
        // ceil(10 / 3) = 4 segments, ceil(7 / 3) = 3 segments.
        assert_eq!(r.vertex_counts().collect::<Vec<_>>(), vec![5, 4]);
        let r = uneven().resample_length(2.0).unwrap();
        // Exactly 5 segments of 2 for the first strand, not a sixth for rounding.
        assert_eq!(r.vertex_counts().collect::<Vec<_>>(), vec![6, 5]);
        for w in r.strand(0).windows(2) {
            assert!((w[0].distance(w[1]) - 2.0).abs() < 1e-4);
        }
        let r = uneven().resample_length(100.0).unwrap();
        assert_eq!(r.vertex_counts().collect::<Vec<_>>(), vec![2, 2]);
        assert_eq!(r.strand(0), &[Vec3::ZERO, Vec3::new(10.0, 0.0, 0.0)]);
    }

    #[test]
    fn resample_rejects_bad_parameters() {
        let h = uneven();
        assert!(h.resample_count(1).is_err());
        assert!(h.resample_count(u32::MAX).is_err());
        assert!(h.resample_length(0.0).is_err());
        assert!(h.resample_length(-1.0).is_err());
        assert!(h.resample_length(f32::NAN).is_err());
        assert!(h.resample_length(1e-30).is_err());
        assert!(h.resample_length(1e-9).is_err());
    }

    fn many(n: usize) -> HairAsset {
        let p: Vec<Vec3> = (0..n)
            .flat_map(|i| [Vec3::new(i as f32, 0.0, 0.0), Vec3::new(i as f32, 1.0, 0.0)])
            .collect();
        let uv: Vec<Vec2> = (0..n).map(|i| Vec2::new(i as f32, 0.0)).collect();
        HairAsset::from_counts(p, &vec![2; n])
            .unwrap()
            .with_strand_uv(uv)
            .unwrap()
    }

    /// The original index of every strand of a subset of `many`, read from its position.
    fn indices(h: &HairAsset) -> Vec<usize> {
        h.strands().map(|s| s[0].x as usize).collect()
    }

    #[test]
    fn subsets_nest_and_keep_order() {
        let h = many(1000);
        let mut previous: Vec<usize> = Vec::new();
        for ratio in [0.0, 0.01, 0.1, 0.25, 0.5, 0.9, 1.0] {
            let s = h.subset(ratio, 42).unwrap();
            let idx = indices(&s);
            assert_eq!(idx.len(), ((ratio * 1000.0).round() as usize).max(1));
            assert!(idx.windows(2).all(|w| w[0] < w[1]), "original order");
            assert!(
                previous.iter().all(|i| idx.binary_search(i).is_ok()),
                "nested at {ratio}"
            );
            let uv: Vec<usize> = s
                .strand_uv()
                .unwrap()
                .iter()
                .map(|u| u.x as usize)
                .collect();
            assert_eq!(uv, idx);
            previous = idx;
        }
        assert_eq!(h.subset(1.0, 42).unwrap(), h);
        assert_eq!(h.subset(0.3, 7).unwrap(), h.subset(0.3, 7).unwrap());
        assert_ne!(
            indices(&h.subset(0.3, 7).unwrap()),
            indices(&h.subset(0.3, 8).unwrap())
        );
    }

    #[test]
    fn subset_is_spread_over_the_asset() {
        // A shuffle, not a prefix: a 10% subset draws from every tenth of the strands.
        let idx = indices(&many(10_000).subset(0.1, 3).unwrap());
        for decile in 0..10 {
            let count = idx.iter().filter(|&&i| i / 1000 == decile).count();
            assert!((60..140).contains(&count), "decile {decile}: {count}");
        }
    }

    #[test]
    fn subset_rejects_bad_ratios() {
        let h = many(3);
        assert!(h.subset(-0.1, 0).is_err());
        assert!(h.subset(1.5, 0).is_err());
        assert!(h.subset(f32::NAN, 0).is_err());
        assert_eq!(h.subset(0.0, 0).unwrap().strand_count(), 1);
    }

    /// Distance from `p` to the polyline `line`.
    fn distance_to_polyline(p: Vec3, line: &[Vec3]) -> f32 {
        line.windows(2)
            .map(|w| {
                let d = w[1] - w[0];
                let t = if d.length_squared() > 0.0 {
                    ((p - w[0]).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p.distance(w[0] + d * t)
            })
            .fold(f32::INFINITY, f32::min)
    }

    proptest! {
        #[test]
        fn resampled_vertices_lie_on_the_strand_evenly_spaced(
            points in prop::collection::vec(prop::array::uniform3(-10.0f32..10.0), 2..12),
            n in 2u32..40,
        ) {
            let p: Vec<Vec3> = points.into_iter().map(Vec3::from_array).collect();
            let h = HairAsset::from_counts(p.clone(), &[p.len() as u32]).unwrap();
            let r = h.resample_count(n).unwrap();
            let s = r.strand(0);
            prop_assert_eq!(s.len(), n as usize);
            prop_assert_eq!(s[0], p[0]);
            prop_assert_eq!(s[s.len() - 1], p[p.len() - 1]);
            let length = h.strand_lengths()[0];
            let step = length / (n - 1) as f32;
            let eps = 1e-4 * (1.0 + length);
            for q in s {
                prop_assert!(distance_to_polyline(*q, &p) < eps, "{} is off the strand", q);
            }
            // Chords of equal arcs: no longer than the arc step.
            for w in s.windows(2) {
                prop_assert!(w[0].distance(w[1]) <= step + eps);
            }
        }
    }
}
