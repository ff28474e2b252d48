//! Step 5 of the fit: the cross-section profile `A(t)`, `B(t)`, `q(t)` of a cluster from its
//! points' offsets in the trajectory's normal planes (see the parent module's docs).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::FitSettings;
use crate::bspline::BSpline;
use crate::cylinder::{GeneralizedCylinder, TwistMode, ellipse_vu};
use crate::error::SatfError;

/// Rounds of widening the half-axes where the splines cut inside a bin's quantile.
const PROFILE_ROUNDS: usize = 8;
/// Largest half-axis, relative to the farthest point of a bin from the trajectory: an ellipse
/// through a point at distance `r` off its axes has a half-axis longer than `r`, so the bound
/// needs some room; the shell never lies farther than this from the trajectory.
const AXIS_LIMIT: f32 = 1.25;
/// Below this anisotropy `(σ₁ - σ₂) / (σ₁ + σ₂)` a bin's principal direction is noise and does
/// not steer the twist.
const MIN_ANISOTROPY: f32 = 0.1;

/// A point's relative arc length `t` on the trajectory and its in-plane offset `(x, y)` along
/// the frame's normal and binormal.
pub(super) type Offset = (f32, Vec2);

/// The cylinder of `trajectory` whose ellipse holds [`FitSettings::axis_quantile`] of the
/// `offsets` of each bin, with half-axes in `[min_radius, 1.25 r_max]` (`r_max`: the farthest
/// offset of the bin from the trajectory) in every bin, and below `1.25` times the largest
/// `r_max` everywhere.
pub(super) fn fit_profile(
    trajectory: &BSpline<Vec3>,
    offsets: &[Offset],
    settings: &FitSettings,
    min_radius: f32,
) -> Result<GeneralizedCylinder, SatfError> {
    let bins = settings.profile_bins as usize;
    let bin_of = |t: f32| ((t * bins as f32) as usize).min(bins - 1);
    let mut binned: Vec<Vec<Offset>> = vec![Vec::new(); bins];
    for &(t, xy) in offsets {
        binned[bin_of(t)].push((t, xy));
    }
    let centres: Vec<f32> = (0..bins).map(|b| (b as f32 + 0.5) / bins as f32).collect();
    let pc = settings.profile_control_points as usize;
    let mode = settings.twist_mode;

    // The twist: each bin's principal direction, unwrapped modulo π, where the bin is elongated
    // enough for it to mean something; the other bins take their nearest such neighbour's.
    let pca: Vec<Option<(f32, f32)>> = binned.iter().map(|pts| principal_axis(pts)).collect();
    let q_targets = match mode {
        TwistMode::Phase => vec![0.0; bins],
        TwistMode::RotateAxes => twist_targets(&pca),
    };
    let twist = BSpline::fit(&centres, &q_targets, pc)?;

    // Half-axes along the fitted twist's axes (not each bin's own PCA angle: an ellipse measured
    // on other axes than it is drawn on can be wrong by the ratio of its axes).
    let r_max: Vec<Option<f32>> = binned
        .iter()
        .map(|pts| pts.iter().map(|(_, xy)| xy.length()).reduce(f32::max))
        .collect();
    let r_max = fill_nearest(&r_max).unwrap_or_else(|| vec![0.0; bins]);
    let limits: Vec<f32> = r_max
        .iter()
        .map(|r| (AXIS_LIMIT * r).max(min_radius))
        .collect();
    let cap = limits.iter().copied().fold(min_radius, f32::max);
    let axes: Vec<Option<(f32, f32)>> = binned
        .iter()
        .zip(&limits)
        .map(|(pts, &limit)| half_axes(pts, &twist, mode, settings, min_radius, limit))
        .collect();
    let axes = fill_nearest(&axes).unwrap_or_else(|| vec![(min_radius, min_radius); bins]);
    let mut a_vals: Vec<f32> = axes.iter().map(|a| a.0).collect();
    let mut b_vals: Vec<f32> = axes.iter().map(|a| a.1).collect();

    // A B-spline lies in the convex hull of its control points: clamping them bounds A(t) and
    // B(t) by [min_radius, cap] everywhere, between the bins and past the end bins too. Each
    // control point is also held to the limit of the bins around its Greville abscissa (where
    // the spline nearly equals it; exactly at the ends): a wide part of a cluster cannot widen
    // a narrow end, where a cluster starts from one strand or thins to its longest.
    let ends = end_limits(offsets, bins, min_radius);
    let local: Vec<f32> = (0..pc)
        .map(|i| {
            if i == 0 || i == pc - 1 {
                return ends[usize::from(i != 0)];
            }
            let xi = greville(pc, i);
            let b = bin_of(xi);
            limits[b.saturating_sub(1)..=(b + 1).min(bins - 1)]
                .iter()
                .copied()
                .fold(min_radius, f32::max)
        })
        .collect();
    let bounded = |values: &[f32]| -> Result<BSpline<f32>, SatfError> {
        let s = BSpline::fit(&centres, values, pc)?;
        BSpline::new(
            s.control_points()
                .iter()
                .zip(&local)
                .map(|(c, l)| c.clamp(min_radius, cap.min(*l)))
                .collect(),
        )
    };
    let build = |a: &[f32], b: &[f32]| -> Result<GeneralizedCylinder, SatfError> {
        GeneralizedCylinder::new(
            trajectory.clone(),
            bounded(a)?,
            bounded(b)?,
            twist.clone(),
            mode,
        )
    };
    let mut geometry = build(&a_vals, &b_vals)?;
    // The splines smooth over the bins and may cut inside a bin's quantile: widen those bins'
    // targets by the shortfall (never past the bin's farthest point) and refit.
    for _ in 0..PROFILE_ROUNDS {
        let mut radii: Vec<Vec<f32>> = vec![Vec::new(); bins];
        for &(t, xy) in offsets {
            let (a, b, q) = geometry.profile(t);
            radii[bin_of(t)].push(ellipse_vu(mode, a, b, q, xy).0);
        }
        let mut changed = false;
        for (bin, r) in radii.iter_mut().enumerate() {
            let Some(over) = quantile(r, settings.axis_quantile) else {
                continue;
            };
            let limit = limits[bin];
            if over <= 1.0 + 1e-3 || (a_vals[bin] >= limit && b_vals[bin] >= limit) {
                continue;
            }
            // Scaling both axes keeps the bin's aspect; an axis that reaches the limit stays
            // there while the other keeps growing by the shortfall (toward a circle of the
            // limit's radius, which holds every point of the bin).
            a_vals[bin] = (a_vals[bin] * over).min(limit);
            b_vals[bin] = (b_vals[bin] * over).min(limit);
            changed = true;
        }
        if !changed {
            break;
        }
        geometry = build(&a_vals, &b_vals)?;
    }
    Ok(geometry)
}

/// The limits of the end control points, where the spline equals them: [`AXIS_LIMIT`] times
/// the farthest offset among the points within half a bin of each end (at least
/// `min_radius`). Where roots or tips are staggered along the trajectory only the first root
/// and the last tip lie there, so the end rings close on them instead of standing a whole
/// cross-section off them (outside the hair's bounds).
fn end_limits(offsets: &[Offset], bins: usize, min_radius: f32) -> [f32; 2] {
    let window = 0.5 / bins as f32;
    let mut ends = [0.0f32; 2];
    for &(t, xy) in offsets {
        if t <= window {
            ends[0] = ends[0].max(xy.length());
        }
        if t >= 1.0 - window {
            ends[1] = ends[1].max(xy.length());
        }
    }
    ends.map(|r| (AXIS_LIMIT * r).max(min_radius))
}

/// The Greville abscissa of control point `i` of `n` (clamped uniform cubic knots): the mean of
/// its three inner knots.
fn greville(n: usize, i: usize) -> f32 {
    let m = (n - 3) as f32;
    let knot = |k: usize| ((k as f32 - 3.0) / m).clamp(0.0, 1.0);
    (knot(i + 1) + knot(i + 2) + knot(i + 3)) / 3.0
}

/// The principal direction `q` of a bin's offsets about the trajectory and the anisotropy
/// `(σ₁ - σ₂) / (σ₁ + σ₂)` of the second moments; `None` for an empty bin.
fn principal_axis(pts: &[Offset]) -> Option<(f32, f32)> {
    if pts.is_empty() {
        return None;
    }
    let inv = 1.0 / pts.len() as f32;
    let (sxx, syy, sxy) = pts.iter().fold((0.0, 0.0, 0.0), |(a, b, c), (_, p)| {
        (a + p.x * p.x, b + p.y * p.y, c + p.x * p.y)
    });
    let (sxx, syy, sxy) = (sxx * inv, syy * inv, sxy * inv);
    let q = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    // Eigenvalues of the 2×2 moment matrix.
    let mean = 0.5 * (sxx + syy);
    let half_gap = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
    let (s1, s2) = (
        (mean + half_gap).max(0.0).sqrt(),
        (mean - half_gap).max(0.0).sqrt(),
    );
    let aniso = if s1 > 0.0 { (s1 - s2) / (s1 + s2) } else { 0.0 };
    Some((q, aniso))
}

/// Twist targets per bin: the reliable bins' principal directions unwrapped modulo π (so the
/// spline through them turns the short way), the others copied from the nearest reliable bin;
/// all 0 when no bin is reliable (a round cluster has no twist to fit).
fn twist_targets(pca: &[Option<(f32, f32)>]) -> Vec<f32> {
    let reliable: Vec<Option<f32>> = pca
        .iter()
        .map(|p| p.filter(|&(_, aniso)| aniso >= MIN_ANISOTROPY).map(|p| p.0))
        .collect();
    let mut last: Option<f32> = None;
    let unwrapped: Vec<Option<f32>> = reliable
        .iter()
        .map(|q| {
            q.map(|q| {
                let q = match last {
                    Some(prev) => q - PI * ((q - prev) / PI).round(),
                    None => q,
                };
                last = Some(q);
                q
            })
        })
        .collect();
    fill_nearest(&unwrapped).unwrap_or_else(|| vec![0.0; pca.len()])
}

/// `(A, B)` of a bin along the axes turned by the fitted twist: the second moments along them,
/// scaled so [`FitSettings::axis_quantile`] of the points lie inside, each in
/// `[min_radius, limit]`. `None` for an empty bin.
fn half_axes(
    pts: &[Offset],
    twist: &BSpline<f32>,
    mode: TwistMode,
    s: &FitSettings,
    min_radius: f32,
    limit: f32,
) -> Option<(f32, f32)> {
    if pts.is_empty() {
        return None;
    }
    let local: Vec<Vec2> = pts
        .iter()
        .map(|&(t, xy)| match mode {
            TwistMode::RotateAxes => Vec2::from_angle(-twist.eval(t)).rotate(xy),
            TwistMode::Phase => xy,
        })
        .collect();
    let inv = 1.0 / local.len() as f32;
    let floor = 0.5 * min_radius;
    let sx = (local.iter().map(|p| p.x * p.x).sum::<f32>() * inv)
        .sqrt()
        .max(floor);
    let sy = (local.iter().map(|p| p.y * p.y).sum::<f32>() * inv)
        .sqrt()
        .max(floor);
    let mut radii: Vec<f32> = local.iter().map(|p| (p.x / sx).hypot(p.y / sy)).collect();
    let c = quantile(&mut radii, s.axis_quantile)?.max(1e-3);
    let limit = limit.max(min_radius);
    Some((
        (c * sx).clamp(min_radius, limit),
        (c * sy).clamp(min_radius, limit),
    ))
}

/// The `q`-quantile of `values` (reordered), `None` when empty.
pub(super) fn quantile(values: &mut [f32], q: f32) -> Option<f32> {
    if values.is_empty() {
        return None;
    }
    let k = ((q * values.len() as f32).ceil() as usize).clamp(1, values.len()) - 1;
    let (_, x, _) = values.select_nth_unstable_by(k, f32::total_cmp);
    Some(*x)
}

/// Empty entries copy the nearest present one (the lower on ties); `None` if all are empty.
fn fill_nearest<T: Copy>(values: &[Option<T>]) -> Option<Vec<T>> {
    let present: Vec<(usize, T)> = values
        .iter()
        .enumerate()
        .filter_map(|(i, v)| v.map(|v| (i, v)))
        .collect();
    (0..values.len())
        .map(|i| {
            present
                .iter()
                .min_by_key(|(j, _)| j.abs_diff(i))
                .map(|&(_, v)| v)
        })
        .collect()
}
