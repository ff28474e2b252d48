//! Evenly spread point sets: `k` points in a triangle whose corners are occupied (interpolated
//! followers between three guides) and `k` points in a disk around an occupied centre (offset
//! followers around their guide).

use std::collections::BTreeMap;
use std::f32::consts::TAU;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::rng::Rng;

/// Lloyd iterations of a triangle pattern.
const LLOYD_ITERATIONS: usize = 24;
/// Density samples per site of a triangle pattern.
const SAMPLES_PER_SITE: usize = 32;
/// Above this many points a triangle pattern is a lattice instead of a Lloyd relaxation (the
/// relaxation costs `k²`).
const MAX_LLOYD: usize = 512;
/// The golden angle, in radians.
const GOLDEN_ANGLE: f32 = 2.399_963_2;

/// The canonical triangle the patterns are computed in: equilateral, unit edges.
fn corners() -> [Vec2; 3] {
    [Vec2::ZERO, Vec2::X, Vec2::new(0.5, 0.75f32.sqrt())]
}

/// Barycentric coordinates of `p` in the canonical triangle.
fn barycentric(p: Vec2) -> Vec3 {
    let [a, b, c] = corners();
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let d = v0.perp_dot(v1);
    let l1 = v2.perp_dot(v1) / d;
    let l2 = v0.perp_dot(v2) / d;
    Vec3::new(1.0 - l1 - l2, l1, l2)
}

fn from_barycentric(w: Vec3) -> Vec2 {
    let [a, b, c] = corners();
    a * w.x + b * w.y + c * w.z
}

/// The centroids of the `m × m` subdivision of the canonical triangle into `m²` equal
/// triangles: `m²` points evenly covering it.
fn lattice(m: usize) -> Vec<Vec2> {
    let mut out = Vec::with_capacity(m * m);
    let inv = 1.0 / m as f32;
    for i in 0..m {
        for j in 0..m - i {
            // Upward sub-triangle (i, j) and, where there is one, the downward one beside it.
            let (a, b) = (i as f32, j as f32);
            let rest = (m - i - j) as f32;
            let up = Vec3::new(rest - 2.0 / 3.0, a + 1.0 / 3.0, b + 1.0 / 3.0);
            out.push(from_barycentric(up * inv));
            if i + j + 1 < m {
                let down = Vec3::new(rest - 4.0 / 3.0, a + 2.0 / 3.0, b + 2.0 / 3.0);
                out.push(from_barycentric(down * inv));
            }
        }
    }
    out
}

/// `n` points of the lattice of `⌈√n⌉²` centroids, taken at an even stride.
fn lattice_points(n: usize) -> Vec<Vec2> {
    let m = (n as f32).sqrt().ceil().max(1.0) as usize;
    let all = lattice(m);
    (0..n).map(|i| all[i * all.len() / n]).collect()
}

/// `k` points evenly spread over a triangle whose three corners are already taken (the
/// guides), in barycentric coordinates: a centroidal Voronoi tessellation by Lloyd's algorithm
/// with the corners as fixed sites, so the points keep away from the guides, from each other
/// and from the edges (where the neighbouring triangle's points begin). Deterministic.
pub(super) fn triangle(k: usize) -> Vec<Vec3> {
    if k == 0 {
        return Vec::new();
    }
    if k > MAX_LLOYD {
        return lattice_points(k).into_iter().map(barycentric).collect();
    }
    let samples = lattice(((SAMPLES_PER_SITE * (k + 3)) as f32).sqrt().ceil() as usize);
    let fixed = corners();
    // Start from a low-discrepancy sequence folded into the triangle.
    let mut sites: Vec<Vec2> = (0..k)
        .map(|i| {
            let (a, b) = (
                (0.5 + 0.754_877_7 * (i as f32 + 1.0)).fract(),
                (0.5 + 0.569_840_3 * (i as f32 + 1.0)).fract(),
            );
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            fixed[0] + (fixed[1] - fixed[0]) * a + (fixed[2] - fixed[0]) * b
        })
        .collect();
    let mut sums = vec![(Vec2::ZERO, 0usize); k];
    for _ in 0..LLOYD_ITERATIONS {
        sums.iter_mut().for_each(|s| *s = (Vec2::ZERO, 0));
        for &q in &samples {
            let mut best = (f32::INFINITY, usize::MAX);
            for (i, c) in fixed.iter().enumerate() {
                let d = c.distance_squared(q);
                if d < best.0 {
                    best = (d, usize::MAX - 1 - i);
                }
            }
            for (i, s) in sites.iter().enumerate() {
                let d = s.distance_squared(q);
                if d < best.0 {
                    best = (d, i);
                }
            }
            if best.1 < k {
                sums[best.1].0 += q;
                sums[best.1].1 += 1;
            }
        }
        for (s, &(sum, n)) in sites.iter_mut().zip(&sums) {
            if n > 0 {
                *s = sum / n as f32;
            }
        }
    }
    sites.into_iter().map(barycentric).collect()
}

/// The triangle patterns for every count in `counts`, computed once each (in parallel).
pub(super) fn triangle_patterns(counts: impl Iterator<Item = usize>) -> BTreeMap<usize, Vec<Vec3>> {
    let mut wanted: Vec<usize> = counts.filter(|&k| k > 0).collect();
    wanted.sort_unstable();
    wanted.dedup();
    wanted.into_par_iter().map(|k| (k, triangle(k))).collect()
}

/// A triangle pattern placed at random: its corners permuted, each point moved by up to a tenth
/// of the pattern's spacing, in barycentric coordinates (non-negative, summing to 1).
pub(super) fn jittered(pattern: &[Vec3], rng: &mut Rng) -> Vec<Vec3> {
    let perm = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ][rng.below(6) as usize];
    let amount = 0.1 / ((pattern.len() + 3) as f32).sqrt();
    pattern
        .iter()
        .map(|w| {
            let w = Vec3::new(w[perm[0]], w[perm[1]], w[perm[2]]);
            let d = rng.in_disk() * amount;
            let moved = (w + Vec3::new(d.x, d.y, -d.x - d.y)).max(Vec3::ZERO);
            moved / moved.element_sum().max(f32::MIN_POSITIVE)
        })
        .collect()
}

/// `k` offsets in the unit disk around an occupied centre, evenly spread: a sunflower (Vogel)
/// spiral turned by a random angle, each point jittered within its ring and sector.
pub(super) fn disk(k: usize, rng: &mut Rng) -> Vec<Vec2> {
    let turn = rng.f32() * TAU;
    (0..k)
        .map(|i| {
            let r = ((i as f32 + 0.5 + rng.range(-0.5, 0.5)) / k as f32)
                .clamp(0.0, 1.0)
                .sqrt();
            let a = turn + GOLDEN_ANGLE * i as f32 + rng.range(-0.25, 0.25);
            Vec2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nearest(points: &[Vec2]) -> f32 {
        let mut best = f32::INFINITY;
        for (i, p) in points.iter().enumerate() {
            for q in &points[i + 1..] {
                best = best.min(p.distance(*q));
            }
        }
        best
    }

    #[test]
    fn triangle_patterns_are_even_and_inside() {
        for k in [1usize, 2, 3, 5, 8, 13, 30] {
            let w = triangle(k);
            assert_eq!(w.len(), k);
            assert!(
                w.iter()
                    .all(|w| w.min_element() > 0.0 && (w.element_sum() - 1.0).abs() < 1e-4)
            );
            // With the corners, the k + 3 points are as far apart as 60% of a hexagonal
            // packing of the triangle's area would put them.
            let mut pts: Vec<Vec2> = w.iter().map(|w| from_barycentric(*w)).collect();
            pts.extend(corners());
            let area = 0.75f32.sqrt() / 4.0;
            // Each corner holds a sixth of a point's cell inside the triangle.
            let hex = (2.0 * area / (3f32.sqrt() * (k as f32 + 0.5))).sqrt();
            assert!(
                nearest(&pts) > 0.6 * hex,
                "k = {k}: {} vs {hex}",
                nearest(&pts)
            );
        }
        assert_eq!(triangle(0), Vec::<Vec3>::new());
        assert_eq!(lattice(4).len(), 16);
        assert_eq!(lattice_points(10).len(), 10);
    }

    #[test]
    fn disk_offsets_cover_the_disk_evenly() {
        let mut rng = Rng::new(1);
        let d = disk(40, &mut rng);
        assert!(d.iter().all(|p| p.length() <= 1.0 + 1e-6));
        // Half the points within radius sqrt(1/2), like a uniform distribution.
        let inner = d.iter().filter(|p| p.length() < 0.5f32.sqrt()).count();
        assert!((17..=23).contains(&inner), "{inner}");
        assert!(
            nearest(&d) > 0.3 * (std::f32::consts::PI / 40.0).sqrt(),
            "{}",
            nearest(&d)
        );
    }
}
