//! The guides' roots on the scalp: their spacing, the scalp's normal at each, and a local
//! Delaunay triangulation of their neighbourhoods (see the parent module's docs).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::kdtree::KdTree;

/// Neighbours a guide's scalp plane and triangle fan are computed from.
const NEIGHBOURS: usize = 12;
/// A triangle is kept when its longest edge is at most this many times the local root spacing
/// (the largest nearest-neighbour distance of its corners): longer ones bridge a gap, a parting
/// or the outside of a concave border.
const EDGE_FACTOR: f32 = 3.0;
/// A triangle is kept when its area is at least this fraction of its longest edge squared
/// (an equilateral one has 0.43, a right isosceles one 0.25): slivers carry no area to fill.
const MIN_SHAPE: f32 = 0.05;

/// The guides' roots with what both follow modes need: each root's nearest neighbours, the
/// distance to the nearest, and the scalp's normal there.
pub(super) struct Roots<'a> {
    pub(super) points: &'a [Vec3],
    /// The [`NEIGHBOURS`] roots nearest each root that do not coincide with it, nearest first.
    neighbours: Vec<Vec<u32>>,
    /// Distance from each root to the nearest other (non-coincident) root; 0 when none.
    pub(super) nearest: Vec<f32>,
    /// The scalp's unit normal at each root (the normal of the plane fitted to it and its
    /// neighbours, turned toward `up`); `None` when they are (nearly) collinear or too few.
    pub(super) normals: Vec<Option<Vec3>>,
}

impl<'a> Roots<'a> {
    /// The roots `points` of guides whose root tangents are `up`.
    pub(super) fn new(points: &'a [Vec3], up: &[Vec3]) -> Self {
        let tree = KdTree::new(points);
        let neighbours: Vec<Vec<u32>> = points
            .par_iter()
            .enumerate()
            .map(|(i, &p)| {
                tree.nearest(p, NEIGHBOURS, |j| {
                    j as usize == i || points[j as usize].distance_squared(p) == 0.0
                })
                .into_iter()
                .map(|(j, _)| j)
                .collect()
            })
            .collect();
        let nearest = neighbours
            .par_iter()
            .enumerate()
            .map(|(i, n)| {
                n.first()
                    .map_or(0.0, |&j| points[j as usize].distance(points[i]))
            })
            .collect();
        let normals = neighbours
            .par_iter()
            .enumerate()
            .map(|(i, n)| {
                let pts: Vec<Vec3> = std::iter::once(points[i])
                    .chain(n.iter().map(|&j| points[j as usize]))
                    .collect();
                let up = up.get(i).copied().unwrap_or(Vec3::Y);
                plane_normal(&pts).map(|n| if n.dot(up) < 0.0 { -n } else { n })
            })
            .collect();
        Roots {
            points,
            neighbours,
            nearest,
            normals,
        }
    }

    /// The median distance from a root to the nearest other root (over the roots that have
    /// one); `None` when no two roots are apart.
    pub(super) fn median_spacing(&self) -> Option<f32> {
        let mut d: Vec<f32> = self.nearest.iter().copied().filter(|&d| d > 0.0).collect();
        if d.is_empty() {
            return None;
        }
        let mid = d.len() / 2;
        let (_, m, _) = d.select_nth_unstable_by(mid, f32::total_cmp);
        Some(*m)
    }

    /// The triangles of the local Delaunay triangulation around root `i` that have it as a
    /// corner (its "fan"), as sorted global index triples; empty where the neighbourhood has no
    /// plane or no triangle passes the shape tests.
    pub(super) fn fan(&self, i: usize) -> Vec<[u32; 3]> {
        let Some(n) = self.normals[i] else {
            return Vec::new();
        };
        let p = self.points[i];
        let (u, v) = n.any_orthonormal_pair();
        let ids: Vec<u32> = std::iter::once(i as u32)
            .chain(self.neighbours[i].iter().copied())
            .collect();
        let flat: Vec<Vec2> = ids
            .iter()
            .map(|&j| {
                let q = self.points[j as usize] - p;
                Vec2::new(q.dot(u), q.dot(v))
            })
            .collect();
        let mut out: Vec<[u32; 3]> = delaunay(&flat, &ids)
            .into_iter()
            .filter(|t| t.contains(&0))
            .map(|t| {
                let mut g = t.map(|k| ids[k]);
                g.sort_unstable();
                g
            })
            .filter(|g| self.well_shaped(g))
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The shape tests of [`EDGE_FACTOR`] and [`MIN_SHAPE`].
    fn well_shaped(&self, t: &[u32; 3]) -> bool {
        let [a, b, c] = t.map(|i| self.points[i as usize]);
        let longest = a.distance(b).max(b.distance(c)).max(c.distance(a));
        let local = t
            .iter()
            .map(|&i| self.nearest[i as usize])
            .fold(0.0f32, f32::max);
        let area = 0.5 * (b - a).cross(c - a).length();
        longest > 0.0 && longest <= EDGE_FACTOR * local && area >= MIN_SHAPE * longest * longest
    }
}

/// The unit normal of the least-squares plane through `pts` (the eigenvector of the smallest
/// eigenvalue of their covariance, from the largest of the three 2×2 minors' determinants);
/// `None` for fewer than three points or (nearly) collinear ones.
pub(super) fn plane_normal(pts: &[Vec3]) -> Option<Vec3> {
    if pts.len() < 3 {
        return None;
    }
    let centre = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
    let (mut xx, mut xy, mut xz, mut yy, mut yz, mut zz) = (0.0f64, 0.0, 0.0, 0.0, 0.0, 0.0);
    for p in pts {
        let r = (*p - centre).as_dvec3();
        xx += r.x * r.x;
        xy += r.x * r.y;
        xz += r.x * r.z;
        yy += r.y * r.y;
        yz += r.y * r.z;
        zz += r.z * r.z;
    }
    let det_x = yy * zz - yz * yz;
    let det_y = xx * zz - xz * xz;
    let det_z = xx * yy - xy * xy;
    let max = det_x.max(det_y).max(det_z);
    let trace = xx + yy + zz;
    // Collinear points leave every minor near zero: relative to the spread squared.
    if max.is_nan() || max <= 1e-6 * trace * trace {
        return None;
    }
    let n = if max == det_x {
        glam::DVec3::new(det_x, xz * yz - xy * zz, xy * yz - xz * yy)
    } else if max == det_y {
        glam::DVec3::new(xz * yz - xy * zz, det_y, xy * xz - yz * xx)
    } else {
        glam::DVec3::new(xy * yz - xz * yy, xy * xz - yz * xx, det_z)
    };
    n.try_normalize().map(|n| n.as_vec3())
}

/// Delaunay triangles (local index triples) of `pts` by Bowyer–Watson. Co-circular points are
/// decided by a symbolic perturbation on the global `ids` (each point's lifted height
/// `x² + y²` raised by `ε^id`: the lowest id dominates), so neighbouring roots, each
/// triangulating its own projection and inserting its neighbours in its own order, pick the
/// same diagonal ([`perturbed_inside`]).
fn delaunay(pts: &[Vec2], ids: &[u32]) -> Vec<[usize; 3]> {
    let n = pts.len();
    if n < 3 {
        return Vec::new();
    }
    let (lo, hi) = pts
        .iter()
        .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let span = (hi - lo).max_element().max(f32::MIN_POSITIVE);
    let mid = 0.5 * (lo + hi);
    // The super-triangle's corners are indices n, n + 1, n + 2.
    let mut all: Vec<Vec2> = pts.to_vec();
    all.push(mid + Vec2::new(-20.0 * span, -10.0 * span));
    all.push(mid + Vec2::new(20.0 * span, -10.0 * span));
    all.push(mid + Vec2::new(0.0, 20.0 * span));
    let id = |k: usize| if k < n { ids[k] } else { u32::MAX };
    let mut tris: Vec<[usize; 3]> = vec![[n, n + 1, n + 2]];
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for k in 0..n {
        let p = all[k];
        // Remove the triangles whose circumcircle holds p; the cavity's boundary is the edges
        // of exactly one of them.
        edges.clear();
        tris.retain(|t| {
            let inside = match in_circle(all[t[0]], all[t[1]], all[t[2]], p, span) {
                Some(inside) => inside,
                None => perturbed_inside(t.map(|c| (all[c], id(c))), (p, id(k))),
            };
            if inside {
                for e in [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]] {
                    let key = [e[0].min(e[1]), e[0].max(e[1])];
                    if let Some(at) = edges.iter().position(|x| *x == key) {
                        edges.swap_remove(at);
                    } else {
                        edges.push(key);
                    }
                }
            }
            !inside
        });
        tris.extend(edges.iter().map(|&[a, b]| [a, b, k]));
    }
    tris.into_iter()
        .filter(|t| t.iter().all(|&c| c < n))
        .collect()
}

/// The in-circle test for `d` on the circumcircle of the triangle `t` (points with ids) under
/// the perturbation of [`delaunay`]: raising the lowest-id point `m` of the four decides. If
/// `m` is `d`, it rises above the lifted plane: outside. If `m` is a corner, the plane rises
/// where `m`'s barycentric weight is positive: `d` is inside when it lies on `m`'s side of the
/// line through the other two corners.
fn perturbed_inside(t: [(Vec2, u32); 3], d: (Vec2, u32)) -> bool {
    let Some(m) = (0..3).min_by_key(|&i| t[i].1) else {
        return false;
    };
    if d.1 < t[m].1 {
        return false;
    }
    let (o1, o2) = (t[(m + 1) % 3].0, t[(m + 2) % 3].0);
    let side = |p: Vec2| (o2 - o1).perp_dot(p - o1);
    side(t[m].0) * side(d.0) > 0.0
}

/// Whether `d` lies inside the circumcircle of `a, b, c` (either orientation); `None` when it
/// is on it to rounding (relative to `span`).
fn in_circle(a: Vec2, b: Vec2, c: Vec2, d: Vec2, span: f32) -> Option<bool> {
    let [a, b, c, d] = [a, b, c, d].map(|p| p.as_dvec2());
    let (ax, ay) = (a.x - d.x, a.y - d.y);
    let (bx, by) = (b.x - d.x, b.y - d.y);
    let (cx, cy) = (c.x - d.x, c.y - d.y);
    let det = (ax * ax + ay * ay) * (bx * cy - cx * by) - (bx * bx + by * by) * (ax * cy - cx * ay)
        + (cx * cx + cy * cy) * (ax * by - bx * ay);
    let orient = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    let scale = f64::from(span).powi(4);
    if det.abs() <= 1e-9 * scale || orient == 0.0 {
        return None;
    }
    Some((det > 0.0) == (orient > 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delaunay_of_a_square_grid_does_not_depend_on_the_projection() {
        // A 4×4 grid: every cell is co-circular, so the diagonals are decided by the roots'
        // ids, the same whatever the projection (mirrored, turned) and insertion order.
        let pts: Vec<Vec2> = (0..16)
            .map(|i| Vec2::new((i % 4) as f32, (i / 4) as f32))
            .collect();
        let ids: Vec<u32> = (0..16).collect();
        let global = |pts: &[Vec2], ids: &[u32]| {
            let mut t: Vec<[u32; 3]> = delaunay(pts, ids)
                .into_iter()
                .map(|t| {
                    let mut g = t.map(|k| ids[k]);
                    g.sort_unstable();
                    g
                })
                .collect();
            t.sort_unstable();
            t
        };
        let a = global(&pts, &ids);
        assert_eq!(a.len(), 18, "{a:?}");
        let turn = Vec2::from_angle(0.7);
        let mirrored: Vec<Vec2> = pts
            .iter()
            .map(|p| turn.rotate(Vec2::new(-p.x, p.y)))
            .collect();
        assert_eq!(global(&mirrored, &ids), a);
        // Inserted in another order (as each root's neighbours come, nearest first).
        let order: Vec<usize> = (0..16).map(|i| (i * 7 + 5) % 16).collect();
        let shuffled: Vec<Vec2> = order.iter().map(|&i| mirrored[i]).collect();
        let shuffled_ids: Vec<u32> = order.iter().map(|&i| ids[i]).collect();
        assert_eq!(global(&shuffled, &shuffled_ids), a);
    }

    #[test]
    fn plane_normal_of_a_tilted_plane() {
        let n = Vec3::new(1.0, 2.0, 3.0).normalize();
        let (u, v) = n.any_orthonormal_pair();
        let pts: Vec<Vec3> = (0..20)
            .map(|i| Vec3::ONE + u * (i % 5) as f32 + v * (i / 5) as f32 * 0.7)
            .collect();
        assert!(plane_normal(&pts).unwrap().dot(n).abs() > 0.9999);
        let line: Vec<Vec3> = (0..5).map(|i| Vec3::X * i as f32).collect();
        assert!(plane_normal(&line).is_none());
    }
}
