//! Steps 1–2 of the fit: resampling strands by arc length and grouping them by proximity.

use glam::Vec3;
use rayon::prelude::*;

use super::FitSettings;

/// Smallest strand length the fit accepts, relative to the strand's largest absolute coordinate
/// (at least 1): below it an `f32` strand has no reliable direction. Ten times the generalized
/// cylinder's bound on its trajectory, so a strand that passes here can carry a cluster alone.
pub(super) const MIN_RELATIVE_LENGTH: f32 = 1e-5;

/// Whether `strand` is long enough to fit: its length exceeds [`MIN_RELATIVE_LENGTH`] times its
/// largest absolute coordinate (at least 1).
pub(super) fn long_enough(strand: &[Vec3]) -> bool {
    let scale = strand
        .iter()
        .fold(1.0f32, |m, p| m.max(p.abs().max_element()));
    let length = polyline_length(strand);
    length.is_finite() && length > MIN_RELATIVE_LENGTH * scale
}

/// The length of a polyline.
pub(super) fn polyline_length(p: &[Vec3]) -> f32 {
    p.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// `n ≥ 2` points evenly spaced in arc length along `strand`, or `None` for a strand shorter
/// than 10⁻⁶ (no direction).
pub fn resample(strand: &[Vec3], n: usize) -> Option<Vec<Vec3>> {
    let mut cum = Vec::with_capacity(strand.len());
    let mut acc = 0.0f32;
    cum.push(0.0);
    for w in strand.windows(2) {
        acc += w[0].distance(w[1]);
        cum.push(acc);
    }
    if !acc.is_finite() || acc < 1e-6 || n < 2 {
        return None;
    }
    let mut seg = 0usize;
    Some(
        (0..n)
            .map(|k| {
                let target = acc * k as f32 / (n - 1) as f32;
                while seg + 2 < cum.len() && cum[seg + 1] < target {
                    seg += 1;
                }
                let (a, b) = (cum[seg], cum[seg + 1]);
                let f = if b > a {
                    ((target - a) / (b - a)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                strand[seg].lerp(strand[seg + 1], f)
            })
            .collect(),
    )
}

/// Group strand indices (see the module docs, step 2). `resampled[i]` holds strand `i`'s points
/// (at least one each).
pub fn group_strands(resampled: &[Vec<Vec3>], settings: &FitSettings) -> Vec<Vec<u32>> {
    let g = settings.grouping_samples as usize;
    let key = |s: &Vec<Vec3>| -> Vec<f32> {
        let n = s.len();
        (0..g)
            .flat_map(|k| {
                let idx = if g == 1 || n == 0 {
                    0
                } else {
                    k * (n - 1) / (g - 1)
                };
                s.get(idx).copied().unwrap_or_default().to_array()
            })
            .collect()
    };
    let keys: Vec<Vec<f32>> = resampled.par_iter().map(key).collect();
    let dims = 3 * g;
    let max = settings.strands_per_cluster as usize;
    let mut out = Vec::new();
    let mut stack = vec![(0..resampled.len() as u32).collect::<Vec<u32>>()];
    while let Some(mut group) = stack.pop() {
        if group.len() <= max {
            if !group.is_empty() {
                out.push(group);
            }
            continue;
        }
        let widest = (0..dims)
            .max_by(|&a, &b| {
                let ext = |d: usize| {
                    let (lo, hi) =
                        group
                            .iter()
                            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &i| {
                                let x = keys[i as usize][d];
                                (lo.min(x), hi.max(x))
                            });
                    hi - lo
                };
                ext(a).total_cmp(&ext(b))
            })
            .unwrap_or(0);
        group.sort_unstable_by(|&a, &b| {
            keys[a as usize][widest]
                .total_cmp(&keys[b as usize][widest])
                .then(a.cmp(&b))
        });
        let mid = split_index(&group, |i| keys[i as usize][widest]);
        let right = group.split_off(mid);
        stack.push(right);
        stack.push(group);
    }
    out
}

/// Where to cut a group sorted by `key`: at the widest gap between neighbours among the middle
/// half of the positions (nearest the median among equals), so natural bundles stay whole.
fn split_index(sorted: &[u32], key: impl Fn(u32) -> f32) -> usize {
    let n = sorted.len();
    let (lo, hi) = ((n / 4).max(1), (3 * n).div_ceil(4).min(n - 1));
    let mid = n / 2;
    (lo..=hi)
        .map(|i| (i, key(sorted[i]) - key(sorted[i - 1])))
        .max_by(|a, b| {
            a.1.total_cmp(&b.1)
                .then(b.0.abs_diff(mid).cmp(&a.0.abs_diff(mid)))
        })
        .map_or(mid, |(i, _)| i)
}
