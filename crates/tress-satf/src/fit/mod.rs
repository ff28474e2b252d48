//! Fitting generalized-cylinder clusters to any strand asset (`.hair`, `.tfx`, generated), so
//! SATF renders the same hair as the other techniques.
//!
//! # Implementation
//!
//! 1. **Resampling.** Every strand is resampled to [`FitSettings::fit_samples`] points evenly
//!    spaced in arc length. Strands shorter than 10⁻⁶ are left out (they have no direction).
//! 2. **Grouping.** Strands are grouped by proximity of the points at
//!    [`FitSettings::grouping_samples`] arc-length fractions (1: the roots only; the default 3:
//!    root, middle and tip, so strands that part ways land in different clusters): a k-d split
//!    along the widest coordinate until no group holds more than
//!    [`FitSettings::strands_per_cluster`] strands. The cut lies at the widest gap between
//!    neighbours within the middle half of the sorted strands, so separate bundles are not cut
//!    through while groups stay balanced. Deterministic and `O(n log² n)`.
//! 3. **Trajectory.** The group's mean strand (the average of corresponding resampled points) is
//!    fitted in the least-squares sense by a cubic B-spline of [`FitSettings::control_points`]
//!    control points, parameterized by its chord length.
//! 4. **Local coordinates.** Each resampled point is projected onto the trajectory (closest point,
//!    searched from the point's own arc-length fraction) giving `t` and in-plane offsets `(x, y)`
//!    in the rotation-minimizing frame.
//! 5. **Ellipse.** The offsets are binned in [`FitSettings::profile_bins`] bins of `t`. In each
//!    bin, the principal axes of the second moments about the trajectory (a 2×2 PCA) give the twist
//!    `q` (unwrapped modulo π from bin to bin) and standard deviations `σ₁ ≥ σ₂`; the half-axes are
//!    `A = c σ₁`, `B = c σ₂` with `c` the [`FitSettings::axis_quantile`] quantile of the points'
//!    Mahalanobis radii, so that fraction of the points lies inside, and neither is below
//!    [`FitSettings::min_radius`]. With [`TwistMode::Phase`] the axes cannot turn: `q = 0` and the
//!    moments are taken along the frame's axes. Empty bins copy their nearest neighbour.
//!    `A`, `B` and `q` are fitted by splines of [`FitSettings::profile_control_points`]; where
//!    the smooth spline cuts inside a bin's quantile, that bin's half-axes are widened by the
//!    shortfall and the splines refitted (up to 3 rounds).
//! 6. **Density level.** Each point's `(v, u)` inverts equation 1; `v` is clamped to 1 for the
//!    points outside the quantile. Every fitted cluster is its own macro-cluster with the identity
//!    transform: arbitrary assets rarely hold exact copies of a geometry.

use std::f32::consts::PI;

use glam::{Affine3A, Vec2, Vec3};
use rayon::prelude::*;
use tress_hair::HairAsset;

use crate::bspline::BSpline;
use crate::cylinder::{GeneralizedCylinder, TwistMode, ellipse_vu};
use crate::error::{SatfError, in_open_closed, param};
use crate::hierarchy::{Cluster, HairVolume, LocalPoint, LocalStrand, MacroCluster};

/// Rounds of widening the half-axes where the splines cut inside a bin's quantile.
const PROFILE_ROUNDS: usize = 3;

/// Settings of [`fit_clusters`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSettings {
    /// Largest group of strands per cluster. Default 256.
    pub strands_per_cluster: u32,
    /// Points per strand used for grouping (1: roots only). Default 3.
    pub grouping_samples: u32,
    /// Points per strand after resampling. Default 16.
    pub fit_samples: u32,
    /// Control points of the trajectory. Default 8.
    pub control_points: u32,
    /// Control points of `A`, `B` and `q`. Default 4.
    pub profile_control_points: u32,
    /// Bins along `t` for the ellipse fit. Default 8.
    pub profile_bins: u32,
    /// Fraction of the points inside the fitted ellipse. Default 0.95.
    pub axis_quantile: f32,
    /// Smallest half-axis (world units). Default 0.05.
    pub min_radius: f32,
    /// How the twist acts. Default [`TwistMode::RotateAxes`].
    pub twist_mode: TwistMode,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            strands_per_cluster: 256,
            grouping_samples: 3,
            fit_samples: 16,
            control_points: 8,
            profile_control_points: 4,
            profile_bins: 8,
            axis_quantile: 0.95,
            min_radius: 0.05,
            twist_mode: TwistMode::RotateAxes,
        }
    }
}

impl FitSettings {
    /// Check ranges: group size ≥ 1, 1..=16 grouping samples, 4..=1024 fit samples, control points
    /// in `4..=fit_samples`, profile control points in 4..=64, 1..=256 bins, quantile in `(0, 1]`,
    /// positive finite minimum radius.
    pub fn validate(&self) -> Result<(), SatfError> {
        if self.strands_per_cluster == 0 || !(1..=16).contains(&self.grouping_samples) {
            return Err(param(
                "strands_per_cluster must be at least 1 and grouping_samples in 1..=16",
            ));
        }
        if !(4..=1024).contains(&self.fit_samples)
            || !(4..=self.fit_samples).contains(&self.control_points)
        {
            return Err(param(
                "fit_samples must be in 4..=1024 and control_points in 4..=fit_samples",
            ));
        }
        if !(4..=64).contains(&self.profile_control_points)
            || !(1..=256).contains(&self.profile_bins)
        {
            return Err(param(
                "profile_control_points must be in 4..=64 and profile_bins in 1..=256",
            ));
        }
        if !in_open_closed(self.axis_quantile, 1.0) || !in_open_closed(self.min_radius, f32::MAX) {
            return Err(param(
                "axis_quantile must be in (0, 1] and min_radius positive",
            ));
        }
        Ok(())
    }
}

/// `n ≥ 2` points evenly spaced in arc length along `strand`, or `None` for a strand shorter than 10⁻⁶.
pub fn resample(strand: &[Vec3], n: usize) -> Option<Vec<Vec3>> {
    let mut cum = Vec::with_capacity(strand.len());
    let mut acc = 0.0f32;
    cum.push(0.0);
    for w in strand.windows(2) {
        acc += w[0].distance(w[1]);
        cum.push(acc);
    }
    if !acc.is_finite() || acc < 1e-6 {
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

/// Group strand indices (see the module docs, step 2). `resampled[i]` holds strand `i`'s points.
pub fn group_strands(resampled: &[Vec<Vec3>], settings: &FitSettings) -> Vec<Vec<u32>> {
    let g = settings.grouping_samples as usize;
    let key = |s: &Vec<Vec3>| -> Vec<f32> {
        let n = s.len();
        (0..g)
            .flat_map(|k| {
                let idx = if g == 1 { 0 } else { k * (n - 1) / (g - 1) };
                s[idx].to_array()
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

/// Fit clusters to every strand of `asset` (see the module docs).
pub fn fit_clusters(asset: &HairAsset, settings: &FitSettings) -> Result<HairVolume, SatfError> {
    settings.validate()?;
    let n = settings.fit_samples as usize;
    let resampled: Vec<Option<Vec<Vec3>>> = (0..asset.strand_count())
        .into_par_iter()
        .map(|i| resample(asset.strand(i), n))
        .collect();
    let kept: Vec<Vec<Vec3>> = resampled.into_iter().flatten().collect();
    if kept.is_empty() {
        return Err(param("no strand of the asset is longer than 1e-6"));
    }
    let groups = group_strands(&kept, settings);
    let macro_clusters = groups
        .par_iter()
        .map(|g| {
            let strands: Vec<&[Vec3]> = g.iter().map(|&i| kept[i as usize].as_slice()).collect();
            fit_cluster(&strands, settings)
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .flatten()
        .collect();
    Ok(HairVolume { macro_clusters })
}

/// Fit one cluster to strands resampled to the same count (steps 3–6); `None` when the group's
/// mean strand has no length.
pub fn fit_cluster(
    strands: &[&[Vec3]],
    settings: &FitSettings,
) -> Result<Option<MacroCluster>, SatfError> {
    let Some(first) = strands.first() else {
        return Ok(None);
    };
    let n = first.len();
    if n < 2 || strands.iter().any(|s| s.len() != n) {
        return Err(param(
            "fit_cluster needs strands of one common sample count (at least 2)",
        ));
    }
    let inv = 1.0 / strands.len() as f32;
    let mut mean: Vec<Vec3> = (0..n)
        .map(|k| strands.iter().map(|s| s[k]).sum::<Vec3>() * inv)
        .collect();
    if polyline_length(&mean) < 1e-6 {
        mean = first.to_vec();
    }
    let Some(params) = chord_params(&mean) else {
        return Ok(None);
    };
    let trajectory = BSpline::fit(
        &params,
        &mean,
        (settings.control_points as usize).min(n).max(4),
    )?;
    let one = BSpline::constant(1.0);
    let zero = BSpline::constant(0.0);
    let Ok(frame_only) = GeneralizedCylinder::new(
        trajectory.clone(),
        one.clone(),
        one,
        zero,
        settings.twist_mode,
    ) else {
        return Ok(None);
    };
    // Step 4: t and in-plane offsets of every point.
    let local: Vec<Vec<(f32, Vec2)>> = strands
        .iter()
        .map(|s| {
            s.iter()
                .enumerate()
                .map(|(k, p)| {
                    let t = frame_only.closest_t(*p, k as f32 / (n - 1) as f32);
                    let f = frame_only.frame(t);
                    let d = *p - f.position;
                    (t, Vec2::new(d.dot(f.normal), d.dot(f.binormal)))
                })
                .collect()
        })
        .collect();
    // Step 5: the ellipse per bin.
    let bins = settings.profile_bins as usize;
    let mut binned: Vec<Vec<Vec2>> = vec![Vec::new(); bins];
    for (t, xy) in local.iter().flatten() {
        binned[((t * bins as f32) as usize).min(bins - 1)].push(*xy);
    }
    let fits: Vec<Option<(f32, f32, f32)>> = binned
        .iter()
        .map(|pts| ellipse_fit(pts, settings))
        .collect();
    let Some(filled) = fill_empty(&fits) else {
        return Ok(None);
    };
    let centres: Vec<f32> = (0..bins).map(|b| (b as f32 + 0.5) / bins as f32).collect();
    let mut q: Vec<f32> = filled.iter().map(|f| f.2).collect();
    for b in 1..bins {
        q[b] -= PI * ((q[b] - q[b - 1]) / PI).round();
    }
    let pc = settings.profile_control_points as usize;
    let mut a_vals: Vec<f32> = filled.iter().map(|f| f.0).collect();
    let mut b_vals: Vec<f32> = filled.iter().map(|f| f.1).collect();
    let floor = |s: BSpline<f32>| -> Result<BSpline<f32>, SatfError> {
        BSpline::new(
            s.control_points()
                .iter()
                .map(|c| c.max(settings.min_radius))
                .collect(),
        )
    };
    let twist = BSpline::fit(&centres, &q, pc)?;
    let build = |a: &[f32], b: &[f32]| -> Result<GeneralizedCylinder, SatfError> {
        GeneralizedCylinder::new(
            trajectory.clone(),
            floor(BSpline::fit(&centres, a, pc)?)?,
            floor(BSpline::fit(&centres, b, pc)?)?,
            twist.clone(),
            settings.twist_mode,
        )
    };
    let mut geometry = build(&a_vals, &b_vals)?;
    // The splines smooth over the bins and may cut inside a bin's quantile: widen those bins'
    // targets by the shortfall and refit (a few rounds).
    for _ in 0..PROFILE_ROUNDS {
        let mut radii: Vec<Vec<f32>> = vec![Vec::new(); bins];
        for &(t, xy) in local.iter().flatten() {
            let (a, b, q) = geometry.profile(t);
            radii[((t * bins as f32) as usize).min(bins - 1)]
                .push(ellipse_vu(settings.twist_mode, a, b, q, xy).0);
        }
        let mut changed = false;
        for (bin, r) in radii.iter_mut().enumerate() {
            let Some(over) = quantile(r, settings.axis_quantile) else {
                continue;
            };
            if over > 1.0 + 1e-3 {
                a_vals[bin] *= over;
                b_vals[bin] *= over;
                changed = true;
            }
        }
        if !changed {
            break;
        }
        geometry = build(&a_vals, &b_vals)?;
    }
    // Step 6: (v, u) of every point.
    let strands = local
        .iter()
        .map(|pts| {
            let points = pts
                .iter()
                .map(|&(t, xy)| {
                    let (a, b, q) = geometry.profile(t);
                    let (v, u) = ellipse_vu(settings.twist_mode, a, b, q, xy);
                    LocalPoint {
                        t: t.clamp(0.0, 1.0),
                        v: v.min(1.0),
                        u,
                    }
                })
                .collect();
            LocalStrand::new(points)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Some(MacroCluster {
        geometry,
        clusters: vec![Cluster::new(Affine3A::IDENTITY, strands)?],
    }))
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

fn polyline_length(p: &[Vec3]) -> f32 {
    p.windows(2).map(|w| w[0].distance(w[1])).sum()
}

fn chord_params(p: &[Vec3]) -> Option<Vec<f32>> {
    let total = polyline_length(p);
    if !total.is_finite() || total < 1e-6 {
        return None;
    }
    let mut acc = 0.0;
    let mut out = vec![0.0];
    for w in p.windows(2) {
        acc += w[0].distance(w[1]);
        out.push((acc / total).min(1.0));
    }
    Some(out)
}

/// The `q`-quantile of `values` (reordered), `None` when empty.
fn quantile(values: &mut [f32], q: f32) -> Option<f32> {
    if values.is_empty() {
        return None;
    }
    let k = ((q * values.len() as f32).ceil() as usize).clamp(1, values.len()) - 1;
    let (_, x, _) = values.select_nth_unstable_by(k, f32::total_cmp);
    Some(*x)
}

/// `(A, B, q)` of one bin's offsets (step 5), or `None` for an empty bin.
fn ellipse_fit(pts: &[Vec2], s: &FitSettings) -> Option<(f32, f32, f32)> {
    if pts.is_empty() {
        return None;
    }
    let inv = 1.0 / pts.len() as f32;
    let sxx = pts.iter().map(|p| p.x * p.x).sum::<f32>() * inv;
    let syy = pts.iter().map(|p| p.y * p.y).sum::<f32>() * inv;
    let sxy = pts.iter().map(|p| p.x * p.y).sum::<f32>() * inv;
    let q = match s.twist_mode {
        TwistMode::RotateAxes => 0.5 * (2.0 * sxy).atan2(sxx - syy),
        TwistMode::Phase => 0.0,
    };
    let (c, sn) = (q.cos(), q.sin());
    let var1 = c * c * sxx + 2.0 * c * sn * sxy + sn * sn * syy;
    let var2 = sn * sn * sxx - 2.0 * c * sn * sxy + c * c * syy;
    let floor = 0.5 * s.min_radius;
    let (s1, s2) = (
        var1.max(0.0).sqrt().max(floor),
        var2.max(0.0).sqrt().max(floor),
    );
    let mut radii: Vec<f32> = pts
        .iter()
        .map(|p| {
            let r = Vec2::from_angle(-q).rotate(*p);
            (r.x / s1).hypot(r.y / s2)
        })
        .collect();
    let c_q = quantile(&mut radii, s.axis_quantile)?.max(1e-3);
    Some((
        (c_q * s1).max(s.min_radius),
        (c_q * s2).max(s.min_radius),
        q,
    ))
}

/// Empty bins copy the nearest non-empty one; `None` if all are empty.
fn fill_empty(fits: &[Option<(f32, f32, f32)>]) -> Option<Vec<(f32, f32, f32)>> {
    let present: Vec<usize> = (0..fits.len()).filter(|&i| fits[i].is_some()).collect();
    if present.is_empty() {
        return None;
    }
    Some(
        (0..fits.len())
            .map(|i| {
                let j = present
                    .iter()
                    .copied()
                    .min_by_key(|&j| j.abs_diff(i))
                    .unwrap_or(i);
                fits[j].unwrap_or((1.0, 1.0, 0.0))
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use tress_hair::rng::Rng;

    /// Strands uniformly filling a straight elliptic tube along -y: half-axes 2 and 1, major
    /// axis turned 30° from +x toward +z.
    fn tube(count: usize) -> Vec<Vec<Vec3>> {
        let mut rng = Rng::new(3);
        let q = 30f32.to_radians();
        (0..count)
            .map(|_| {
                let d = rng.in_disk();
                let xy = Vec2::from_angle(q).rotate(Vec2::new(2.0 * d.x, d.y));
                (0..16)
                    .map(|k| Vec3::new(5.0 + xy.x, -(k as f32), xy.y))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn resample_by_arc_length() {
        let s = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 3.0, 0.0)];
        let r = resample(&s, 5).unwrap();
        assert_eq!(r[0], Vec3::ZERO);
        assert!((r[1] - Vec3::X).length() < 1e-6);
        assert!((r[2] - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6);
        assert!((r[4] - s[2]).length() < 1e-6);
        assert!(resample(&[Vec3::ONE, Vec3::ONE], 4).is_none());
    }

    #[test]
    fn grouping_splits_at_medians() {
        // 8 strands whose roots sit at x = 0..8: groups of at most 2 are consecutive pairs.
        let strands: Vec<Vec<Vec3>> = (0..8)
            .map(|i| {
                vec![
                    Vec3::new(i as f32, 0.0, 0.0),
                    Vec3::new(i as f32, -1.0, 0.0),
                ]
            })
            .collect();
        let s = FitSettings {
            strands_per_cluster: 2,
            grouping_samples: 1,
            ..Default::default()
        };
        let mut groups = group_strands(&strands, &s);
        for g in &mut groups {
            g.sort();
        }
        groups.sort();
        assert_eq!(groups, vec![vec![0, 1], vec![2, 3], vec![4, 5], vec![6, 7]]);
    }

    #[test]
    fn fits_an_elliptic_tube() {
        let strands = tube(400);
        let refs: Vec<&[Vec3]> = strands.iter().map(|s| s.as_slice()).collect();
        let s = FitSettings {
            axis_quantile: 1.0,
            ..Default::default()
        };
        let m = fit_cluster(&refs, &s).unwrap().unwrap();
        let g = &m.geometry;
        assert!((g.length() - 15.0).abs() < 0.2, "length {}", g.length());
        let (a, b, q) = g.profile(0.5);
        assert!(
            (a - 2.0).abs() < 0.15 && (b - 1.0).abs() < 0.1,
            "A {a} B {b}"
        );
        // The major axis direction (cos q n + sin q b) is ±(cos 30°, 0, sin 30°).
        let f = g.frame(0.5);
        let axis = q.cos() * f.normal + q.sin() * f.binormal;
        let want = Vec3::new(30f32.to_radians().cos(), 0.0, 30f32.to_radians().sin());
        assert!(axis.dot(want).abs() > 0.995, "axis {axis}");
        // Every strand point maps back to itself through (t, v, u).
        let c = &m.clusters[0];
        for (strand, local) in strands.iter().zip(c.strands()) {
            for (p, l) in strand.iter().zip(local.points()) {
                assert!(l.v <= 1.0);
                assert!(
                    (c.point(g, l.t, l.v, l.u) - *p).length() < 0.02,
                    "{p} vs {l:?}"
                );
            }
        }
    }

    #[test]
    fn fits_a_generated_volume_and_reconstructs_its_strands() {
        use crate::generate::{ClusterStyle, generate_clusters};
        let style = ClusterStyle {
            macro_clusters: 3,
            clusters_per_macro: 2,
            strands_per_cluster: 60,
            ..Default::default()
        };
        let asset = generate_clusters(&tress_hair::generate::Head::default(), &style)
            .unwrap()
            .to_asset()
            .unwrap();
        let s = FitSettings {
            strands_per_cluster: 60,
            axis_quantile: 1.0,
            ..Default::default()
        };
        let vol = fit_clusters(&asset, &s).unwrap();
        let stats = vol.stats(&crate::shell::ShellSampling::default());
        assert_eq!(stats.strands, 360);
        // The cuts fall in the gaps between bundles: the generator's 6 clusters of 60 come back.
        assert_eq!(stats.clusters, 6);
        assert!(vol.clusters().all(|(_, c)| c.strands().len() == 60));
        // Reconstruction: every resampled point is P(t, v, u) of its local coordinates.
        let mut worst = 0.0f32;
        for (g, c) in vol.clusters() {
            for l in c.strands() {
                let p = l.points()[8];
                let q = c.point(g, p.t, p.v, p.u);
                // The nearest original strand point, for the error.
                let d = (0..asset.strand_count())
                    .flat_map(|i| {
                        asset
                            .strand(i)
                            .windows(2)
                            .map(|w| seg_dist(q, w[0], w[1]))
                            .collect::<Vec<_>>()
                    })
                    .fold(f32::INFINITY, f32::min);
                worst = worst.max(d);
            }
        }
        assert!(worst < 0.05, "worst reconstruction error {worst}");
        assert!(
            fit_clusters(
                &asset,
                &FitSettings {
                    control_points: 2,
                    ..s
                }
            )
            .is_err()
        );
    }

    fn seg_dist(p: Vec3, a: Vec3, b: Vec3) -> f32 {
        let ab = b - a;
        let f = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
        (a + ab * f).distance(p)
    }
}
