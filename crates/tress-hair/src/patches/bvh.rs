//! A small bounding-volume hierarchy over triangles for occlusion rays (the AO bake).
//!
//! Built top-down: each node splits its triangles at the centroid median of the longest axis of
//! their centroid box (a full sort is not needed: `select_nth_unstable` partitions), down to
//! leaves of at most [`LEAF_SIZE`] triangles. Nodes are stored depth-first, the left child right
//! after its parent. Triangles are two-sided and each lets a fraction of the light through (0 for
//! opaque ones). A query returns the fraction that gets through along a ray segment, the product
//! over the triangles it crosses; it stops at the first opaque triangle or once less than
//! [`CUTOFF`] is left, so opaque scenes cost an any-hit query.

use glam::Vec3;

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// A ray whose transmittance falls below this counts as blocked.
const CUTOFF: f32 = 1.0 / 1024.0;
/// Traversal stack depth: median splits halve the count, so 64 covers any triangle count that
/// fits memory.
const STACK: usize = 64;

/// A triangle as the intersection test wants it: a corner and the two edges from it.
#[derive(Clone, Copy, Debug)]
struct Tri {
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    /// Fraction of light let through, in `[0, 1]`.
    transmit: f32,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    /// A leaf: the first triangle; an inner node: the right child (the left one follows).
    index: u32,
    /// Triangles in a leaf; 0 for an inner node.
    count: u32,
}

/// The hierarchy. Empty scenes are allowed (nothing is ever hit).
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    tris: Vec<Tri>,
}

impl Bvh {
    /// A hierarchy over the given triangles, triangle `i` letting `transmit(i)` of the light
    /// through (degenerate triangles are kept; they are never hit).
    pub(crate) fn new(triangles: &[[Vec3; 3]], transmit: impl Fn(usize) -> f32) -> Self {
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let centroids: Vec<Vec3> = triangles
            .iter()
            .map(|t| (t[0] + t[1] + t[2]) / 3.0)
            .collect();
        let mut nodes = Vec::with_capacity(2 * triangles.len() / LEAF_SIZE + 1);
        if !triangles.is_empty() {
            build(triangles, &centroids, &mut order, 0, &mut nodes);
        }
        let tris = order
            .iter()
            .map(|&i| {
                let [a, b, c] = triangles[i as usize];
                Tri {
                    v0: a,
                    e1: b - a,
                    e2: c - a,
                    transmit: transmit(i as usize).clamp(0.0, 1.0),
                }
            })
            .collect();
        Bvh { nodes, tris }
    }

    /// The fraction of light that gets through along the ray `origin + t·dir`,
    /// `t_min < t < t_max`: 1 if it meets nothing, 0 if it meets an opaque triangle (or so many
    /// translucent ones that less than [`CUTOFF`] is left).
    pub(crate) fn transmittance(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> f32 {
        let mut left = 1.0;
        if self.nodes.is_empty() {
            return left;
        }
        let inv = dir.recip();
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let at = stack[top];
            let node = &self.nodes[at as usize];
            if !hits_box(node, origin, inv, t_min, t_max) {
                continue;
            }
            if node.count > 0 {
                let first = node.index as usize;
                for t in &self.tris[first..first + node.count as usize] {
                    if hits_tri(t, origin, dir, t_min, t_max) {
                        left *= t.transmit;
                        if left < CUTOFF {
                            return 0.0;
                        }
                    }
                }
            } else if top + 2 <= STACK {
                // The left child is stored right after its parent.
                stack[top] = node.index;
                stack[top + 1] = at + 1;
                top += 2;
            }
        }
        left
    }
}

/// Build the subtree over `order` (whose entries start at `offset` in the final order) and
/// return its node index.
fn build(
    triangles: &[[Vec3; 3]],
    centroids: &[Vec3],
    order: &mut [u32],
    offset: usize,
    nodes: &mut Vec<Node>,
) -> u32 {
    let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (mut cmin, mut cmax) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for &i in order.iter() {
        for p in triangles[i as usize] {
            min = min.min(p);
            max = max.max(p);
        }
        cmin = cmin.min(centroids[i as usize]);
        cmax = cmax.max(centroids[i as usize]);
    }
    let at = nodes.len() as u32;
    nodes.push(Node {
        min,
        max,
        index: offset as u32,
        count: order.len() as u32,
    });
    let extent = cmax - cmin;
    if order.len() <= LEAF_SIZE || extent.max_element() <= 0.0 {
        return at;
    }
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| {
        centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
    });
    let (left, right) = order.split_at_mut(mid);
    build(triangles, centroids, left, offset, nodes);
    let right_at = build(triangles, centroids, right, offset + mid, nodes);
    nodes[at as usize].index = right_at;
    nodes[at as usize].count = 0;
    at
}

/// Slab test of the ray against a node's box.
fn hits_box(node: &Node, origin: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> bool {
    let t0 = (node.min - origin) * inv;
    let t1 = (node.max - origin) * inv;
    // NaN (0 · ∞ on a slab boundary) is dropped by min/max, which keeps the ray.
    let near = t0.min(t1).max_element().max(t_min);
    let far = t0.max(t1).min_element().min(t_max);
    near <= far
}

/// Möller-Trumbore, two-sided.
fn hits_tri(tri: &Tri, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
    let p = dir.cross(tri.e2);
    let det = tri.e1.dot(p);
    if det.abs() < 1e-12 {
        return false;
    }
    let inv_det = 1.0 / det;
    let s = origin - tri.v0;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = s.cross(tri.e1);
    let v = dir.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = tri.e2.dot(q) * inv_det;
    t > t_min && t < t_max
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// How many triangles the ray crosses.
    fn brute(tris: &[[Vec3; 3]], o: Vec3, d: Vec3, t_max: f32) -> usize {
        tris.iter()
            .filter(|t| {
                hits_tri(
                    &Tri {
                        v0: t[0],
                        e1: t[1] - t[0],
                        e2: t[2] - t[0],
                        transmit: 0.0,
                    },
                    o,
                    d,
                    0.0,
                    t_max,
                )
            })
            .count()
    }

    #[test]
    fn agrees_with_brute_force() {
        let mut rng = Rng::new(3);
        let tris: Vec<[Vec3; 3]> = (0..500)
            .map(|_| {
                let c = rng.on_sphere() * rng.range(0.0, 10.0);
                [0; 3].map(|_| c + rng.on_sphere() * rng.range(0.1, 1.5))
            })
            .collect();
        let bvh = Bvh::new(&tris, |_| 0.0);
        let half = Bvh::new(&tris, |_| 0.5);
        let mut hits = 0;
        for _ in 0..4000 {
            let o = rng.on_sphere() * rng.range(0.0, 12.0);
            let d = rng.on_sphere();
            let t_max = rng.range(0.5, 20.0);
            let crossed = brute(&tris, o, d, t_max);
            let expected = if crossed > 0 { 0.0 } else { 1.0 };
            assert_eq!(
                bvh.transmittance(o, d, 0.0, t_max),
                expected,
                "{o} {d} {t_max}"
            );
            let through = 0.5f32.powi(crossed as i32);
            let expected = if through < CUTOFF { 0.0 } else { through };
            assert_eq!(
                half.transmittance(o, d, 0.0, t_max),
                expected,
                "{crossed} crossed"
            );
            hits += usize::from(crossed > 0);
        }
        assert!(hits > 500 && hits < 3500, "{hits}");
    }

    #[test]
    fn axis_aligned_rays_and_empty_scenes() {
        let quad = [
            [
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
            [
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
        ];
        let bvh = Bvh::new(&quad, |_| 0.0);
        let o = Vec3::new(0.2, 0.3, -2.0);
        assert_eq!(bvh.transmittance(o, Vec3::Z, 0.0, 3.0), 0.0);
        let back = o + 4.0 * Vec3::Z;
        assert_eq!(
            bvh.transmittance(back, Vec3::NEG_Z, 0.0, 3.0),
            0.0,
            "two-sided"
        );
        assert_eq!(bvh.transmittance(o, Vec3::Z, 0.0, 1.5), 1.0, "beyond t_max");
        assert_eq!(bvh.transmittance(o, Vec3::X, 0.0, 10.0), 1.0);
        let empty = Bvh::new(&[], |_| 0.0);
        assert_eq!(empty.transmittance(o, Vec3::Z, 0.0, 10.0), 1.0);
        let tinted = Bvh::new(&quad, |_| 0.25);
        assert_eq!(tinted.transmittance(o, Vec3::Z, 0.0, 3.0), 0.25);
    }
}
