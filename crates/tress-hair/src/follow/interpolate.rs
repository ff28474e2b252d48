//! Where the interpolated followers' roots go: the guides' triangle fans merged into one set of
//! triangles, each guide's followers shared out over its fan by area, and evenly spread points
//! in every triangle (see the parent module's docs).

use glam::Vec3;
use rayon::prelude::*;

use super::pattern;
use super::roots::Roots;
use crate::rng::Rng;

/// Seed stream of the triangles' pattern placement (apart from the guides' streams).
const TRIANGLE_STREAM: u64 = 0x7472_6961_6e67_6c65;

/// One interpolated follower's root: the triangle of guides it lies in (sorted guide indices)
/// and its barycentric weights over those three guides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Blend {
    pub(super) guides: [u32; 3],
    pub(super) weights: Vec3,
}

/// The blended followers of every guide (`count` each), or `None` for a guide that is the
/// corner of no triangle (an isolated root, a single row of roots): its followers are offset.
pub(super) fn plan(roots: &Roots<'_>, count: u32, seed: u64) -> Vec<Option<Vec<Blend>>> {
    let guides = roots.points.len();
    let fans: Vec<Vec<[u32; 3]>> = (0..guides).into_par_iter().map(|g| roots.fan(g)).collect();
    let mut triangles: Vec<[u32; 3]> = fans.iter().flatten().copied().collect();
    triangles.par_sort_unstable();
    triangles.dedup();
    let incident: Vec<Vec<u32>> = fans
        .par_iter()
        .map(|fan| {
            fan.iter()
                .filter_map(|t| triangles.binary_search(t).ok().map(|i| i as u32))
                .collect()
        })
        .collect();
    let area: Vec<f32> = triangles
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| roots.points[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .collect();
    // Each guide spreads its followers over its own fan in proportion to area, so a triangle
    // expects count · area · Σ 1 / (fan area) over the guides whose fan holds it.
    let mut target = vec![0.0f64; triangles.len()];
    for fan in &incident {
        let total: f64 = fan.iter().map(|&t| f64::from(area[t as usize])).sum();
        if total > 0.0 {
            for &t in fan {
                target[t as usize] += f64::from(count) * f64::from(area[t as usize]) / total;
            }
        }
    }
    // Guide by guide, each follower goes to the triangle of its fan furthest below its target:
    // the counts stay within one of the targets, and neighbours' shares do not pile up.
    let mut assigned = vec![0u32; triangles.len()];
    let mut owners: Vec<Vec<(u32, u32)>> = vec![Vec::new(); triangles.len()];
    for (g, fan) in incident.iter().enumerate() {
        let mut mine: Vec<(u32, u32)> = fan.iter().map(|&t| (t, 0)).collect();
        if mine.is_empty() {
            continue;
        }
        for _ in 0..count {
            let Some(best) = (0..mine.len()).max_by(|&a, &b| {
                let deficit =
                    |k: usize| target[mine[k].0 as usize] - f64::from(assigned[mine[k].0 as usize]);
                deficit(a).total_cmp(&deficit(b)).then(b.cmp(&a))
            }) else {
                break;
            };
            mine[best].1 += 1;
            assigned[mine[best].0 as usize] += 1;
        }
        for (t, n) in mine.into_iter().filter(|&(_, n)| n > 0) {
            owners[t as usize].push((g as u32, n));
        }
    }
    let patterns = pattern::triangle_patterns(assigned.iter().map(|&k| k as usize));
    // Per triangle: its pattern placed at random, then shared among its owners, each taking
    // the points nearest its own corner (highest weight) from those left.
    let placed: Vec<Vec<(u32, Blend)>> = triangles
        .par_iter()
        .zip(&owners)
        .map(|(&t, owners)| {
            let k: u32 = owners.iter().map(|&(_, n)| n).sum();
            let Some(base) = patterns.get(&(k as usize)) else {
                return Vec::new();
            };
            let key = (u64::from(t[0]) << 42) ^ (u64::from(t[1]) << 21) ^ u64::from(t[2]);
            let mut rng = Rng::stream(seed ^ TRIANGLE_STREAM, key);
            let mut left = pattern::jittered(base, &mut rng);
            let mut out = Vec::with_capacity(k as usize);
            for &(g, n) in owners {
                let corner = t.iter().position(|&c| c == g).unwrap_or(0);
                for _ in 0..n {
                    let Some(best) = (0..left.len()).max_by(|&a, &b| {
                        left[a][corner].total_cmp(&left[b][corner]).then(b.cmp(&a))
                    }) else {
                        break;
                    };
                    out.push((
                        g,
                        Blend {
                            guides: t,
                            weights: left.swap_remove(best),
                        },
                    ));
                }
            }
            out
        })
        .collect();
    let mut per_guide: Vec<Option<Vec<Blend>>> = incident
        .iter()
        .map(|fan| (!fan.is_empty()).then(Vec::new))
        .collect();
    for (g, blend) in placed.into_iter().flatten() {
        if let Some(list) = per_guide[g as usize].as_mut() {
            list.push(blend);
        }
    }
    per_guide
}
