//! A static k-d tree over points for nearest-neighbour queries (follow hairs: root spacing and
//! the neighbours of a guide root).
//!
//! Implicit and balanced: the points' indices are permuted so that each node is the median of
//! its range along the axis of the range's largest extent, with the two halves on either side
//! (the layout of "kdbush"-style trees). Building is `O(n log n)` (the halves in parallel);
//! a query for the `k` nearest is `O(k log n)` on well-spread points.

use glam::Vec3;

/// Ranges at most this long are scanned instead of split.
const LEAF: usize = 8;
/// Ranges longer than this are split on two threads.
const PARALLEL: usize = 16_384;

/// A k-d tree over a point set (see the module docs).
pub(crate) struct KdTree<'a> {
    points: &'a [Vec3],
    /// Point indices in tree order.
    order: Vec<u32>,
    /// The split axis of the node at each position of `order` (unused at leaves).
    axis: Vec<u8>,
}

impl<'a> KdTree<'a> {
    /// A tree over `points` (fewer than 2³² of them).
    pub(crate) fn new(points: &'a [Vec3]) -> Self {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        let mut axis = vec![0u8; points.len()];
        build(points, &mut order, &mut axis);
        KdTree {
            points,
            order,
            axis,
        }
    }

    /// The `k` points nearest `q` other than those `skip` accepts, nearest first, as
    /// `(index, squared distance)`; fewer when the tree holds fewer.
    pub(crate) fn nearest(&self, q: Vec3, k: usize, skip: impl Fn(u32) -> bool) -> Vec<(u32, f32)> {
        let mut best: Vec<(u32, f32)> = Vec::with_capacity(k + 1);
        if k > 0 {
            self.visit(0, self.order.len(), q, k, &skip, &mut best);
        }
        best
    }

    fn visit(
        &self,
        lo: usize,
        hi: usize,
        q: Vec3,
        k: usize,
        skip: &impl Fn(u32) -> bool,
        best: &mut Vec<(u32, f32)>,
    ) {
        if hi - lo <= LEAF {
            for &i in &self.order[lo..hi] {
                offer(
                    best,
                    k,
                    i,
                    self.points[i as usize].distance_squared(q),
                    skip,
                );
            }
            return;
        }
        let mid = (lo + hi) / 2;
        let i = self.order[mid];
        let p = self.points[i as usize];
        offer(best, k, i, p.distance_squared(q), skip);
        let a = self.axis[mid] as usize;
        let diff = q[a] - p[a];
        let (first, second) = if diff < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.visit(first.0, first.1, q, k, skip, best);
        let worst = if best.len() < k {
            f32::INFINITY
        } else {
            best[best.len() - 1].1
        };
        if diff * diff < worst {
            self.visit(second.0, second.1, q, k, skip, best);
        }
    }
}

/// Insert `(i, d2)` into the sorted list of the `k` best.
fn offer(best: &mut Vec<(u32, f32)>, k: usize, i: u32, d2: f32, skip: &impl Fn(u32) -> bool) {
    if best.len() == k && d2 >= best[k - 1].1 || skip(i) {
        return;
    }
    let at = best.partition_point(|&(j, e)| e < d2 || (e == d2 && j < i));
    best.insert(at, (i, d2));
    best.truncate(k);
}

fn build(points: &[Vec3], order: &mut [u32], axis: &mut [u8]) {
    let n = order.len();
    if n <= LEAF {
        return;
    }
    let (lo, hi) = order
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &i| {
            let p = points[i as usize];
            (lo.min(p), hi.max(p))
        });
    let extent = hi - lo;
    let a = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = n / 2;
    order.select_nth_unstable_by(mid, |&i, &j| {
        points[i as usize][a]
            .total_cmp(&points[j as usize][a])
            .then(i.cmp(&j))
    });
    axis[mid] = a as u8;
    let (left, rest) = order.split_at_mut(mid);
    let right = &mut rest[1..];
    let (axis_left, axis_rest) = axis.split_at_mut(mid);
    let axis_right = &mut axis_rest[1..];
    if n > PARALLEL {
        rayon::join(
            || build(points, left, axis_left),
            || build(points, right, axis_right),
        );
    } else {
        build(points, left, axis_left);
        build(points, right, axis_right);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn nearest_matches_brute_force() {
        let mut rng = Rng::new(4);
        let points: Vec<Vec3> = (0..3000)
            .map(|_| {
                Vec3::new(
                    rng.range(-5.0, 5.0),
                    rng.range(0.0, 1.0),
                    rng.range(-2.0, 2.0),
                )
            })
            .collect();
        let tree = KdTree::new(&points);
        for q in 0..200 {
            let query = points[q * 7] + Vec3::splat(0.01);
            let got = tree.nearest(query, 6, |i| i as usize == q * 7);
            let mut want: Vec<(u32, f32)> = (0..points.len() as u32)
                .filter(|&i| i as usize != q * 7)
                .map(|i| (i, points[i as usize].distance_squared(query)))
                .collect();
            want.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            want.truncate(6);
            assert_eq!(got, want);
        }
        // Fewer points than asked for, and an empty tree.
        assert_eq!(
            KdTree::new(&points[..3])
                .nearest(Vec3::ZERO, 5, |_| false)
                .len(),
            3
        );
        assert!(
            KdTree::new(&[])
                .nearest(Vec3::ZERO, 5, |_| false)
                .is_empty()
        );
    }
}
