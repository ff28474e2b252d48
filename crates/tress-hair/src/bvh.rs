//! The one bounding-volume hierarchy of tress, over primitive boxes ([`Aabb`]), built top-down
//! with one of two split rules ([`Split`]) and traversed with a small fixed stack. The reference
//! ray tracer (`tress-trace`, nearest hits on strands and the head) and the patches' ambient
//! occlusion bake ([`crate::patches::bake_ao`], all hits through translucent patches) both use
//! it, each with the rule that measured faster on it:
//!
//! | workload (`cargo bench`) | [`Split::Median`] | [`Split::Sah`] |
//! | --- | --- | --- |
//! | tracer, full ponytail (136,320 strands) 128² at 1 spp (`-p tress-trace --bench trace`) | **72 ms** | 116–147 ms |
//! | tracer BVH build, ponytail at 10% | **170 ms** | 400–440 ms |
//! | AO bake of the default patch head, 64 rays a hemisphere (`-p tress-hair --bench ao`) | 416 ms | **323 ms** |
//!
//! (The bake's own median-split hierarchy, which this one replaced, took 464 ms.) The strands'
//! capsule boxes are long, thin and overlap; SAH's cheapest cuts leave them in deep, uneven
//! trees, while the bake's small triangles fit SAH's model.
//!
//! # Implementation
//!
//! - **Build.** Top-down. With [`Split::Sah`] a node's primitives are binned by centroid into [`BINS`] slots along
//!   each axis of their centroid box; every boundary between bins is scored with the SAH cost
//!   `C = area(L)·n(L) + area(R)·n(R)` (relative to the parent's area, traversal and intersection
//!   cost taken equal), and the cheapest split wins if it beats making a leaf
//!   (`n · area(parent)`), or always when the node has more than [`MAX_LEAF`] primitives. When
//!   all centroids coincide, or below depth [`SAH_DEPTH`] no longer matters, the node is split at
//!   the median instead, which bounds the depth by `SAH_DEPTH + log2(n)` and so the traversal
//!   stack. Subtrees over more than 8192 primitives are built on rayon's threads.
//! - **Layout.** Nodes are stored depth-first with the left child right after its parent; a leaf
//!   holds a range of [`Bvh::order`], the primitive indices in leaf order (callers reorder their
//!   primitives by it so a leaf's primitives are contiguous in memory).
//! - **Traversal.** Slab tests against the reciprocal direction. The nearest-hit query visits the
//!   nearer child first and skips boxes entered beyond the closest hit so far; the all-hits query
//!   ([`Bvh::for_each_hit`]) visits every box the ray crosses and lets the visitor stop early.

use glam::Vec3;

use crate::Aabb;

/// How [`Bvh::build`] splits a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// At the centroid median of the longest axis (the ray tracer's strands).
    Median,
    /// At the cheapest binned SAH boundary, down to depth [`SAH_DEPTH`] (the AO bake's
    /// triangles).
    Sah,
}

/// Centroid bins per axis.
pub const BINS: usize = 12;
/// A node with at most this many primitives may become a leaf; a leaf never holds more.
pub const MAX_LEAF: usize = 4;
/// Below this depth splits are made at the median instead of by SAH.
pub const SAH_DEPTH: usize = 48;
/// Subtrees over more primitives than this are built in parallel.
const PARALLEL_MIN: usize = 8192;
/// Traversal stack size: at least the deepest tree [`Bvh::build`] makes (`SAH_DEPTH + 32` for
/// up to 2^32 primitives).
const STACK: usize = 96;

/// A ray `origin + t·dir` for `t_min < t < t_max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Hits at or before this distance are ignored.
    pub t_min: f32,
    /// Hits at or after this distance are ignored.
    pub t_max: f32,
}

impl Ray {
    /// A ray over `(t_min, t_max)`; `dir` must be a unit vector.
    pub fn new(origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Self {
        Ray {
            origin,
            dir,
            t_min,
            t_max,
        }
    }

    /// The point at distance `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// Half the surface area (0 for empty or flat boxes is fine: only ratios are used).
fn half_area(b: &Aabb) -> f32 {
    let e = (b.max - b.min).max(Vec3::ZERO);
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// The interval of `t` in which the ray (with `inv_dir = 1 / dir`) is inside the box, clipped
/// to `(t_min, t_max)`: its start, `None` if empty.
#[inline]
fn slab(b: &Aabb, origin: Vec3, inv_dir: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
    let t0 = (b.min - origin) * inv_dir;
    let t1 = (b.max - origin) * inv_dir;
    let near = t0.min(t1).max_element().max(t_min);
    let far = t0.max(t1).min_element().min(t_max);
    (near <= far).then_some(near)
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: first index into `order`; inner node: index of the right child.
    index: u32,
    /// Leaf: number of primitives (> 0); inner node: 0.
    count: u32,
}

/// The hierarchy. Empty (no primitives) is allowed: nothing is ever hit.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

/// What the visitor of [`Bvh::for_each_hit`] tells the traversal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visit {
    /// Keep going.
    Continue,
    /// Stop the traversal.
    Stop,
}

impl Bvh {
    /// Build over primitives with the given boxes (non-finite boxes are treated as empty and
    /// never visited), splitting nodes by `split`.
    pub fn build(bounds: &[Aabb], split: Split) -> Bvh {
        if bounds.is_empty() {
            return Bvh {
                nodes: Vec::new(),
                order: Vec::new(),
            };
        }
        let sah_depth = match split {
            Split::Median => 0,
            Split::Sah => SAH_DEPTH,
        };
        let (nodes, order) = build_all(bounds, sah_depth);
        Bvh { nodes, order }
    }

    /// Primitive indices in leaf order: leaf ranges index this array.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the tree (a single leaf has depth 1; empty has 0).
    pub fn depth(&self) -> usize {
        fn depth(nodes: &[Node], at: usize) -> usize {
            let n = &nodes[at];
            if n.count > 0 {
                1
            } else {
                1 + depth(nodes, at + 1).max(depth(nodes, n.index as usize))
            }
        }
        if self.nodes.is_empty() {
            0
        } else {
            depth(&self.nodes, 0)
        }
    }

    /// The nearest hit: `hit(position, ray)` is called for each primitive (by its position in
    /// [`Bvh::order`]) in a leaf the ray reaches, with `ray.t_max` shrunk to the nearest hit so
    /// far; it returns the hit distance, which must lie inside the ray's interval, and the hit's
    /// data. Returns the nearest.
    pub fn nearest<H>(
        &self,
        ray: &Ray,
        mut hit: impl FnMut(usize, &Ray) -> Option<(f32, H)>,
    ) -> Option<(f32, H)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = ray.dir.recip();
        let mut ray = *ray;
        let mut best: Option<(f32, H)> = None;
        let mut stack = [0u32; STACK];
        let mut top = 0usize;
        let mut at = 0usize;
        slab(&self.nodes[0].bounds, ray.origin, inv, ray.t_min, ray.t_max)?;
        loop {
            let node = self.nodes[at];
            if node.count > 0 {
                let first = node.index as usize;
                for pos in first..first + node.count as usize {
                    if let Some((t, h)) = hit(pos, &ray)
                        && t < ray.t_max
                    {
                        ray.t_max = t;
                        best = Some((t, h));
                    }
                }
            } else {
                let (l, r) = (at + 1, node.index as usize);
                let tl = slab(&self.nodes[l].bounds, ray.origin, inv, ray.t_min, ray.t_max);
                let tr = slab(&self.nodes[r].bounds, ray.origin, inv, ray.t_min, ray.t_max);
                match (tl, tr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, r) } else { (r, l) };
                        if top < STACK {
                            stack[top] = far as u32;
                            top += 1;
                        }
                        at = near;
                        continue;
                    }
                    (Some(_), None) => {
                        at = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        at = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the next node still in front of the nearest hit.
            loop {
                if top == 0 {
                    return best;
                }
                top -= 1;
                let n = stack[top] as usize;
                if slab(&self.nodes[n].bounds, ray.origin, inv, ray.t_min, ray.t_max).is_some() {
                    at = n;
                    break;
                }
            }
        }
    }

    /// Visit every primitive in the leaves whose boxes the ray crosses (in no particular order)
    /// until `visit` returns [`Visit::Stop`].
    pub fn for_each_hit(&self, ray: &Ray, mut visit: impl FnMut(usize) -> Visit) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = ray.dir.recip();
        let mut stack = [0u32; STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let at = stack[top] as usize;
            let node = self.nodes[at];
            if slab(&node.bounds, ray.origin, inv, ray.t_min, ray.t_max).is_none() {
                continue;
            }
            if node.count > 0 {
                let first = node.index as usize;
                for pos in first..first + node.count as usize {
                    if visit(pos) == Visit::Stop {
                        return;
                    }
                }
            } else if top + 2 <= STACK {
                stack[top] = node.index;
                stack[top + 1] = at as u32 + 1;
                top += 2;
            }
        }
    }
}

/// A primitive during the build: its box and its index.
#[derive(Clone, Copy, Debug)]
struct Item {
    bounds: Aabb,
    index: u32,
}

impl Item {
    /// Centroid of the box (the origin for empty boxes, which bin anywhere harmlessly).
    #[inline]
    fn centroid(&self) -> Vec3 {
        let c = self.bounds.center();
        if c.is_finite() { c } else { Vec3::ZERO }
    }
}

/// Build over `bounds`: the nodes (root first) and the leaf order.
fn build_all(bounds: &[Aabb], sah_depth: usize) -> (Vec<Node>, Vec<u32>) {
    let mut items: Vec<Item> = bounds
        .iter()
        .enumerate()
        .map(|(i, b)| Item {
            bounds: if b.min.is_finite() && b.max.is_finite() {
                *b
            } else {
                Aabb::EMPTY
            },
            index: i as u32,
        })
        .collect();
    let mut nodes = Vec::with_capacity(2 * items.len() / MAX_LEAF + 1);
    build_into(&mut items, 0, 0, sah_depth, &mut nodes);
    (nodes, items.iter().map(|i| i.index).collect())
}

/// Append the subtree over `items` (which start at `offset` in the final order) to `nodes`,
/// root first, with node indices relative to the start of `nodes`.
fn build_into(
    items: &mut [Item],
    offset: usize,
    depth: usize,
    sah_depth: usize,
    nodes: &mut Vec<Node>,
) {
    let n = items.len();
    let node_bounds = items
        .iter()
        .fold(Aabb::EMPTY, |acc, it| acc.union(&it.bounds));
    let leaf = Node {
        bounds: node_bounds,
        index: offset as u32,
        count: n as u32,
    };
    if n <= 1 {
        nodes.push(leaf);
        return;
    }
    let centroid_box = items
        .iter()
        .fold(Aabb::EMPTY, |acc, it| acc.grow(it.centroid()));
    let extent = centroid_box.max - centroid_box.min;
    let mid = if depth < sah_depth && extent.max_element() > 0.0 {
        match sah_split(items, &centroid_box, &node_bounds) {
            Some(mid) => mid,
            None if n <= MAX_LEAF => {
                nodes.push(leaf);
                return;
            }
            None => median_split(items, &centroid_box),
        }
    } else if n <= MAX_LEAF {
        nodes.push(leaf);
        return;
    } else {
        median_split(items, &centroid_box)
    };
    let (left, right) = items.split_at_mut(mid);
    let at = nodes.len();
    nodes.push(Node {
        bounds: node_bounds,
        index: 0,
        count: 0,
    });
    if n > PARALLEL_MIN {
        let (mut l, mut r) = rayon::join(
            || {
                let mut v = Vec::new();
                build_into(left, offset, depth + 1, sah_depth, &mut v);
                v
            },
            || {
                let mut v = Vec::new();
                build_into(right, offset + mid, depth + 1, sah_depth, &mut v);
                v
            },
        );
        let shift = |v: &mut Vec<Node>, base: usize| {
            for nd in v.iter_mut().filter(|nd| nd.count == 0) {
                nd.index += base as u32;
            }
        };
        shift(&mut l, at + 1);
        nodes[at].index = (at + 1 + l.len()) as u32;
        shift(&mut r, at + 1 + l.len());
        nodes.append(&mut l);
        nodes.append(&mut r);
    } else {
        build_into(left, offset, depth + 1, sah_depth, nodes);
        nodes[at].index = nodes.len() as u32;
        build_into(right, offset + mid, depth + 1, sah_depth, nodes);
    }
}

/// Partition `items` at the cheapest SAH bin boundary; returns the split position, or `None`
/// when a leaf is cheaper (only allowed for small nodes, see the caller) or no boundary
/// separates anything. All three axes are binned in one pass over the items.
fn sah_split(items: &mut [Item], centroid_box: &Aabb, node_bounds: &Aabb) -> Option<usize> {
    let n = items.len();
    let extent = centroid_box.max - centroid_box.min;
    let scale = Vec3::select(
        extent.cmpgt(Vec3::ZERO),
        Vec3::splat(BINS as f32) / extent,
        Vec3::ZERO,
    );
    let bin_of = |c: Vec3, axis: usize| -> usize {
        (((c[axis] - centroid_box.min[axis]) * scale[axis]) as usize).min(BINS - 1)
    };
    let mut bin_bounds = [[Aabb::EMPTY; BINS]; 3];
    let mut bin_count = [[0usize; BINS]; 3];
    for it in items.iter() {
        let c = it.centroid();
        for axis in 0..3 {
            let b = bin_of(c, axis);
            bin_count[axis][b] += 1;
            bin_bounds[axis][b] = bin_bounds[axis][b].union(&it.bounds);
        }
    }
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        // Sweep from the right to get the right side of every boundary.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for b in (1..BINS).rev() {
            acc = acc.union(&bin_bounds[axis][b]);
            cnt += bin_count[axis][b];
            right_area[b] = half_area(&acc);
            right_count[b] = cnt;
        }
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for b in 0..BINS - 1 {
            acc = acc.union(&bin_bounds[axis][b]);
            cnt += bin_count[axis][b];
            let (rc, ra) = (right_count[b + 1], right_area[b + 1]);
            if cnt == 0 || rc == 0 {
                continue;
            }
            let cost = half_area(&acc) * cnt as f32 + ra * rc as f32;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, b));
            }
        }
    }
    let (cost, axis, boundary) = best?;
    let leaf_cost = half_area(node_bounds) * n as f32;
    if n <= MAX_LEAF && cost >= leaf_cost {
        return None;
    }
    // Partition in place: items in bins <= boundary go left.
    let mut mid = 0;
    for k in 0..n {
        if bin_of(items[k].centroid(), axis) <= boundary {
            items.swap(k, mid);
            mid += 1;
        }
    }
    (mid > 0 && mid < n).then_some(mid)
}

/// Split at the centroid median of the longest axis of the centroid box (at the middle index
/// when the box is a point).
fn median_split(items: &mut [Item], centroid_box: &Aabb) -> usize {
    let mid = items.len() / 2;
    let extent = centroid_box.max - centroid_box.min;
    if extent.max_element().is_nan() || extent.max_element() <= 0.0 {
        return mid;
    }
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    items.select_nth_unstable_by(mid, |a, b| {
        a.centroid()[axis].total_cmp(&b.centroid()[axis])
    });
    mid
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn random_boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Rng::new(seed);
        (0..n)
            .map(|_| {
                let c = Vec3::new(
                    rng.range(-10.0, 10.0),
                    rng.range(-10.0, 10.0),
                    rng.range(-10.0, 10.0),
                );
                let h = Vec3::new(
                    rng.range(0.0, 0.5),
                    rng.range(0.0, 0.5),
                    rng.range(0.0, 0.5),
                );
                Aabb {
                    min: c - h,
                    max: c + h,
                }
            })
            .collect()
    }

    #[test]
    fn every_primitive_is_in_exactly_one_leaf_and_inside_its_boxes() {
        for (n, split) in [0usize, 1, 2, 5, 100, 20_000]
            .into_iter()
            .flat_map(|n| [(n, Split::Median), (n, Split::Sah)])
        {
            let boxes = random_boxes(n, n as u64);
            let bvh = Bvh::build(&boxes, split);
            let mut seen = vec![0u32; n];
            for &i in bvh.order() {
                seen[i as usize] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "n = {n}");
            // Each leaf's primitives lie inside every ancestor's box.
            fn check(bvh: &Bvh, boxes: &[Aabb], at: usize, outer: Aabb) -> usize {
                let node = bvh.nodes[at];
                let inside =
                    |b: &Aabb| b.min.cmpge(outer.min).all() && b.max.cmple(outer.max).all();
                assert!(inside(&node.bounds));
                if node.count > 0 {
                    assert!(node.count as usize <= MAX_LEAF.max(1));
                    for &i in &bvh.order[node.index as usize..(node.index + node.count) as usize] {
                        assert!(inside(&boxes[i as usize]));
                    }
                    node.count as usize
                } else {
                    check(bvh, boxes, at + 1, node.bounds)
                        + check(bvh, boxes, node.index as usize, node.bounds)
                }
            }
            if n > 0 {
                let all = boxes.iter().copied().fold(Aabb::EMPTY, |a, b| a.union(&b));
                assert_eq!(check(&bvh, &boxes, 0, all), n);
                assert!(bvh.depth() <= STACK, "depth {}", bvh.depth());
            } else {
                assert_eq!(bvh.depth(), 0);
            }
        }
    }

    #[test]
    fn identical_boxes_still_build_shallow_enough() {
        let b = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        for split in [Split::Median, Split::Sah] {
            let bvh = Bvh::build(&vec![b; 10_000], split);
            assert_eq!(bvh.order().len(), 10_000);
            assert!(bvh.depth() <= 20, "{}", bvh.depth());
        }
    }

    #[test]
    fn slab_test() {
        let b = Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        let o = Vec3::new(0.0, 0.0, -5.0);
        let inv = Vec3::Z.recip();
        assert_eq!(slab(&b, o, inv, 0.0, 100.0), Some(4.0));
        assert_eq!(slab(&b, o, inv, 0.0, 3.9), None);
        assert_eq!(slab(&b, Vec3::new(2.0, 0.0, -5.0), inv, 0.0, 100.0), None);
        assert_eq!(slab(&b, Vec3::ZERO, inv, 0.0, 100.0), Some(0.0));
    }
}
