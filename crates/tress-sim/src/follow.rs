//! Followers rebuilt from the simulated guides.
//!
//! A follower is bound once, in the rest pose, to its guides: with `interpolate`, the three
//! guides whose roots are nearest to its root, weighted by the barycentric coordinates of its
//! root in their triangle (negative coordinates clamped, inverse distances where the triangle is
//! degenerate); with `offset`, its nearest guide alone. Follower vertex `j` samples each guide
//! at the same fraction `j / (m − 1)` of its length and keeps its rest offset from their blend.
//! Every step it is rebuilt as the blend of the guides now plus that offset turned by the
//! blend of the guides' frames there (each segment's frame: the head's rotation, then the
//! smallest rotation from the head-turned rest direction to the current one), so followers turn
//! with their guides; a root's offset turns with the head alone, so it stays exactly on the
//! head. Last, the follower keeps each rebuilt segment's direction and takes back its rest
//! length from the root out ([`keep_lengths`]): guides that swing apart would otherwise stretch
//! the followers between them.

use glam::{Quat, Vec3};
use rayon::prelude::*;

use crate::settings::FollowMode;

/// A follower's guides and weights (up to 3; unused slots have weight 0 and guide 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binding {
    /// Guide indices (in the simulated strands' order).
    pub guides: [u32; 3],
    /// Weights, summing to 1.
    pub weights: [f32; 3],
}

/// Where a fraction `s` of a strand of `n` vertices falls: the segment and the share along it.
pub fn sample_at(s: f32, n: usize) -> (usize, f32) {
    if n < 2 {
        return (0, 0.0);
    }
    let f = s.clamp(0.0, 1.0) * (n - 1) as f32;
    let seg = (f.floor() as usize).min(n - 2);
    (seg, f - seg as f32)
}

/// The frame of every segment of a strand (see the module docs); `rest` and `now` are the
/// strand's vertices, `head` the head's rotation. A strand of one vertex has the head's frame.
pub fn segment_frames(rest: &[Vec3], now: &[Vec3], head: Quat, out: &mut Vec<Quat>) {
    out.clear();
    for k in 0..rest.len().saturating_sub(1) {
        let r = (head * (rest[k + 1] - rest[k])).normalize_or_zero();
        let c = (now[k + 1] - now[k]).normalize_or_zero();
        let turn = if r == Vec3::ZERO || c == Vec3::ZERO {
            Quat::IDENTITY
        } else {
            Quat::from_rotation_arc(r, c)
        };
        out.push((turn * head).normalize());
    }
    if out.is_empty() {
        out.push(head);
    }
}

/// Bind followers to guides by their roots.
pub fn bind(guide_roots: &[Vec3], follower_roots: &[Vec3], mode: FollowMode) -> Vec<Binding> {
    let index = RootIndex::new(guide_roots);
    follower_roots
        .par_iter()
        .map(|&p| {
            let near = index.nearest(p, if mode == FollowMode::Offset { 1 } else { 3 });
            weights(guide_roots, &near, p)
        })
        .collect()
}

fn weights(roots: &[Vec3], near: &[u32], p: Vec3) -> Binding {
    let mut b = Binding {
        guides: [0; 3],
        weights: [0.0; 3],
    };
    for (k, &g) in near.iter().enumerate() {
        b.guides[k] = g;
    }
    if near.len() < 3 {
        b.weights[0] = 1.0;
        return b;
    }
    let [a, bb, c] = [0, 1, 2].map(|k| roots[near[k] as usize]);
    let n = (bb - a).cross(c - a);
    let area2 = n.length_squared();
    let scale = (bb - a).length_squared().max((c - a).length_squared());
    let w = if area2 > 1e-6 * scale * scale {
        // Barycentric coordinates of p projected onto the triangle's plane.
        let q = p - n * ((p - a).dot(n) / area2);
        let wa = (bb - q).cross(c - q).dot(n) / area2;
        let wb = (c - q).cross(a - q).dot(n) / area2;
        [wa, wb, 1.0 - wa - wb].map(|x| x.max(0.0))
    } else {
        [a, bb, c].map(|r| 1.0 / (r.distance(p) + 1e-6))
    };
    let sum: f32 = w.iter().sum();
    b.weights = if sum > 0.0 {
        w.map(|x| x / sum)
    } else {
        [1.0, 0.0, 0.0]
    };
    b
}

/// Guide roots in a uniform grid of buckets, for nearest-root queries.
struct RootIndex<'a> {
    roots: &'a [Vec3],
    lo: Vec3,
    cell: f32,
    dims: [i32; 3],
    buckets: Vec<Vec<u32>>,
}

impl<'a> RootIndex<'a> {
    fn new(roots: &'a [Vec3]) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for r in roots {
            lo = lo.min(*r);
            hi = hi.max(*r);
        }
        if roots.is_empty() {
            lo = Vec3::ZERO;
            hi = Vec3::ONE;
        }
        // About two roots a bucket over the bounding box's area.
        let size = (hi - lo).max(Vec3::splat(1e-3));
        let area = (size.x * size.y + size.y * size.z + size.z * size.x).max(1e-6);
        let cell = (2.0 * area / roots.len().max(1) as f32)
            .sqrt()
            .max(size.max_element() / 256.0);
        let dims = ((size / cell).floor().as_ivec3() + glam::IVec3::ONE).to_array();
        let mut buckets = vec![Vec::new(); (dims[0] * dims[1] * dims[2]) as usize];
        let mut this = RootIndex {
            roots,
            lo,
            cell,
            dims,
            buckets: Vec::new(),
        };
        for (i, r) in roots.iter().enumerate() {
            buckets[this.bucket(this.coords(*r))].push(i as u32);
        }
        this.buckets = buckets;
        this
    }

    fn coords(&self, p: Vec3) -> [i32; 3] {
        let c = ((p - self.lo) / self.cell).floor().as_ivec3().to_array();
        [0, 1, 2].map(|a| c[a].clamp(0, self.dims[a] - 1))
    }

    fn bucket(&self, c: [i32; 3]) -> usize {
        (c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])) as usize
    }

    /// The `k` roots nearest to `p` (fewer if there are fewer), nearest first; ties by index.
    fn nearest(&self, p: Vec3, k: usize) -> Vec<u32> {
        let c = self.coords(p);
        let mut best: Vec<(f32, u32)> = Vec::new();
        let max_ring = self.dims.iter().copied().max().unwrap_or(1);
        for ring in 0..=max_ring {
            for z in (c[2] - ring).max(0)..=(c[2] + ring).min(self.dims[2] - 1) {
                for y in (c[1] - ring).max(0)..=(c[1] + ring).min(self.dims[1] - 1) {
                    for x in (c[0] - ring).max(0)..=(c[0] + ring).min(self.dims[0] - 1) {
                        let shell = (x - c[0]).abs().max((y - c[1]).abs()).max((z - c[2]).abs());
                        if shell != ring {
                            continue;
                        }
                        for &i in &self.buckets[self.bucket([x, y, z])] {
                            best.push((self.roots[i as usize].distance_squared(p), i));
                        }
                    }
                }
            }
            best.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            best.truncate(k);
            // Every root outside the rings searched is at least `ring` cells away.
            let reach = ring as f32 * self.cell;
            if best.len() == k && best[k - 1].0 <= reach * reach {
                break;
            }
        }
        best.into_iter().map(|(_, i)| i).collect()
    }
}

/// A follower rebuilt from its guides keeps each segment's direction and takes back its rest
/// length, from the root out (its guides may have swung apart, which would stretch or shrink
/// it). The GPU twin is `fix_follower_lengths` in `sim_output.wgsl`.
pub fn keep_lengths(p: &mut [Vec3], rest_len: &[f32]) {
    let Some(&first) = p.first() else { return };
    let (mut before, mut fixed) = (first, first);
    for (x, &len) in p.iter_mut().zip(rest_len).skip(1) {
        let d = *x - before;
        let l = d.length();
        before = *x;
        fixed += if l > 0.0 { d * (len / l) } else { d };
        *x = fixed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_roots_match_a_brute_force_search() {
        let roots: Vec<Vec3> = (0..500)
            .map(|i| {
                let f = i as f32;
                Vec3::new(
                    (f * 0.618).fract() * 10.0,
                    (f * 0.414).fract() * 6.0,
                    (f * 0.732).fract(),
                )
            })
            .collect();
        let index = RootIndex::new(&roots);
        for q in [
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(9.9, 0.1, 0.0),
            Vec3::new(-5.0, 3.0, 2.0),
        ] {
            let mut brute: Vec<(f32, u32)> = roots
                .iter()
                .enumerate()
                .map(|(i, r)| (r.distance_squared(q), i as u32))
                .collect();
            brute.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let want: Vec<u32> = brute.iter().take(3).map(|b| b.1).collect();
            assert_eq!(index.nearest(q, 3), want, "{q}");
        }
    }

    #[test]
    fn keep_lengths_restores_rest_lengths_and_directions() {
        let mut p = vec![
            Vec3::ZERO,
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(3.0, 0.5, 0.0),
        ];
        keep_lengths(&mut p, &[0.0, 1.0, 2.0]);
        assert_eq!(p[0], Vec3::ZERO);
        assert!((p[1] - Vec3::X).length() < 1e-6);
        assert!((p[2] - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn barycentric_weights_reproduce_the_root_inside_the_triangle() {
        let roots = [Vec3::ZERO, Vec3::X, Vec3::Z];
        let p = Vec3::new(0.2, 0.3, 0.5);
        let b = weights(&roots, &[0, 1, 2], p);
        let q: Vec3 = (0..3)
            .map(|k| roots[b.guides[k] as usize] * b.weights[k])
            .sum();
        assert!((q - Vec3::new(0.2, 0.0, 0.5)).length() < 1e-5, "{q}");
        let sum: f32 = b.weights.iter().sum();
        assert!((sum - 1.0).abs() < 1e-6);
    }
}
