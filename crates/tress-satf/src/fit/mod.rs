//! Fitting generalized-cylinder clusters to any strand asset (`.hair`, `.tfx`, generated), so
//! SATF renders the same hair as the other techniques.
//!
//! # Implementation
//!
//! Xu et al. 2006 model hair as clusters whose strands all run inside a generalized cylinder
//! (§3.2, equations 1–2); the paper builds them with a modelling tool. Here they are recovered
//! from strands, which may have very different lengths in one cluster, be very short, fold back
//! on themselves, be perfectly straight, or stand alone.
//!
//! 1. **Resampling.** Every strand is resampled to [`FitSettings::fit_samples`] points evenly
//!    spaced in arc length. A strand whose length is not above 10⁻⁵ of its largest coordinate
//!    (at least 1) has no reliable direction in `f32`: it is left out and counted in
//!    [`SkippedStrands::too_short`].
//! 2. **Grouping.** Strands are grouped by proximity of the points at
//!    [`FitSettings::grouping_samples`] arc-length fractions (1: the roots only; the default 3:
//!    root, middle and tip, so strands that part ways land in different clusters): a k-d split
//!    along the widest coordinate until no group holds more than
//!    [`FitSettings::strands_per_cluster`] strands. The cut lies at the widest gap between
//!    neighbours within the middle half of the sorted strands, so separate bundles are not cut
//!    through while groups stay balanced. Deterministic and `O(n log² n)`.
//! 3. **Trajectory.** A cubic B-spline of [`FitSettings::control_points`] control points is
//!    fitted in the least-squares sense to *every* point of the group, a point at arc length `σ`
//!    from its root taking the parameter `σ / L_max` (`L_max`: the group's longest strand). With
//!    strands of one length this is the fit to the group's mean strand; with strands of very
//!    different lengths, the trajectory runs as far as the longest one and is the mean of the
//!    strands that reach each parameter, instead of a mean that ends at the average tip.
//! 4. **Local coordinates.** Each point is projected onto the trajectory (the closest point,
//!    searched downhill from the trajectory point of its own parameter, so a strand folding back
//!    on itself keeps each leg on its own part of the curve), giving `t` and in-plane offsets
//!    `(x, y)` in the rotation-minimizing frame. Points whose closest point is an end of the
//!    trajectory but lie beyond it (roots spread along the hair's direction, a short strand
//!    starting ahead of the others) would lose that distance; the trajectory is extended along
//!    its end tangents to the farthest such point and the points projected again, so every
//!    point, tips included, lies in a normal plane of the trajectory. The extended trajectory
//!    is refitted to the curve and its straight extensions sampled alike (as densely as the
//!    curve), so it follows them: with one point per extension, the end knot spans had almost
//!    no data and the spline's control point there shot off (on a fan of strands of 6 to 9
//!    units leaving a ponytail's tie, whose mean is short and whose tips lie past both of its
//!    ends, a 51-unit axis: a spike above the crown).
//! 5. **Ellipse.** The offsets are binned in [`FitSettings::profile_bins`] bins of `t`. The twist
//!    `q` is each bin's principal direction (a 2×2 PCA of the second moments about the
//!    trajectory), unwrapped modulo π, taken only from bins elongated enough for a direction to
//!    mean something (anisotropy `(σ₁ - σ₂)/(σ₁ + σ₂) ≥ 0.1`; the others copy their nearest such
//!    bin, and a round cluster gets none), fitted by a spline of
//!    [`FitSettings::profile_control_points`]. The half-axes are then measured *along the fitted
//!    twist's axes*: standard deviations `σ_x`, `σ_y`, scaled by the
//!    [`FitSettings::axis_quantile`] quantile `c` of the points' Mahalanobis radii, so that
//!    fraction of the points lies inside: `A = c σ_x`, `B = c σ_y`. Each is kept in
//!    `[min_radius, 1.25 r_max]`, `r_max` the bin's farthest point from the trajectory. With
//!    [`TwistMode::Phase`] the axes cannot turn: `q = 0`. `A` and `B` are fitted by splines
//!    whose control points are clamped to `[min_radius, 1.25 max r_max]` (a B-spline lies in the hull
//!    of its control points, so no overshoot between or beyond the bins), the two end control
//!    points (which the spline equals at `t = 0` and `t = 1`) to 1.25 times the farthest point
//!    within half a bin of that end, so where roots or tips are staggered the end ring closes on the first
//!    root or the last tip instead of a whole cross-section off it; where the smooth
//!    spline cuts inside a bin's quantile, that bin's half-axes are widened by the shortfall (up
//!    to the limit) and the splines refitted (up to 8 rounds). The shell `v = 1` therefore never
//!    lies farther from the trajectory than 1.25 times the cluster's farthest strand point.
//! 6. **Density level.** Each point's `(v, u)` inverts equation 1; `v` is clamped to 1 for the
//!    points outside the quantile. Every fitted cluster is its own macro-cluster with the identity
//!    transform: arbitrary assets rarely hold exact copies of a geometry.
//! 7. **Splitting where the shell strays.** An ellipse swept along a curve cannot follow a
//!    sheet of hair curved across its width, as the scalp part of a ponytail is where a group's
//!    roots cover a patch of the head: its rim stands off the sheet by the patch's sagitta. So
//!    each fitted group's shell (`v = 1` on 16 points around the root ring and around the rings
//!    at the middles of 16 intervals of `t`; not the tip ring, which closes over staggered tips
//!    whatever the split) is measured against the group's strands, and where some shell point
//!    lies farther from every strand than [`FitSettings::stray_split`] (0.75) of the
//!    cross-section's larger half-axis there (and than ten minimum half-axes: 1% of the hair's
//!    diagonal by default, a pixel or two, not worth a cluster), or farther than twenty minimum
//!    half-axes (2% of the diagonal: a wide, flat root ring across a curved patch, small next
//!    to its own half-axis but pixels off the hair's silhouette), the group is cut in two at its
//!    widest gap (as in step 2) and both halves are fitted again, down to groups of 4 strands
//!    on the first test.
//!    Halving a patch's width quarters its sagitta. A group of fewer than 8 strands is split
//!    only on the second test (a shell point over twenty minimum half-axes from every strand),
//!    down to single strands: a few strands of a fan leaving a ponytail's tie in different
//!    directions span a ribbon across the scalp's curve. The groups are split in rounds, the
//!    worst first (by the larger of the two distances, each over its threshold), each round
//!    only those within a tenth of the worst's score, while the clusters number at most
//!    [`FitSettings::max_clusters`] (512): each cluster's layer mesh takes GPU memory, and
//!    splitting every group of a 50,000-strand asset to the end gives thousands, so the budget
//!    goes to the groups straying most, not to every group straying a little in the first
//!    rounds.
//!
//! A group whose strands give no trajectory (their mean has no length, e.g. strands leaving one
//! root in opposite directions) is fitted strand by strand instead; a strand that cannot carry a
//! cluster even alone is counted in [`SkippedStrands::degenerate`]. Every input strand is thus
//! in a cluster or counted in [`HairVolume::skipped`].
//!
//! **Why the old fit drew fans and spikes.** The half-axes used to be measured along each bin's
//! own principal direction, while the ellipse is drawn along the *fitted twist spline's*
//! direction. In flat, ribbon-like clusters whose principal direction wobbles (near-round bins
//! have a random PCA angle that the unwrapping and the smooth spline carried into their
//! neighbours), the drawn ellipse's short axis lay along the points' long spread, every point
//! then had a radius `v ≫ 1`, and the widening rounds multiplied *both* axes by that ratio: on
//! the demo ponytail one cluster's `A(0)` reached 39 units, more than the head is wide, while its
//! strands lie within 1.7 units of the trajectory. That ellipse swept the spike above the head in
//! the quality report, and on real ponytails the fans from the bottom of the hair. Two more
//! causes drew shells where no strand is: the trajectory was fitted to the mean strand, which for
//! strands of different lengths ends at their average tip (every longer strand's tip was then
//! measured in the end plane, far off-axis), and groups were bounded by count alone, so a group of
//! a few guides could span a patch of scalp far wider than its curvature allows (step 7). The
//! minimum half-axis was also a fixed 0.05 world units, a 5 cm tube around every cluster of an
//! asset modelled in metres; it is now relative to the asset ([`FitSettings::min_radius`]).

mod group;
mod profile;
mod split;
mod stray;
#[cfg(test)]
mod tests;

use glam::{Affine3A, Vec2, Vec3};
use rayon::prelude::*;
use tress_hair::HairAsset;

use crate::bspline::BSpline;
use crate::cylinder::{GeneralizedCylinder, TwistMode, ellipse_vu};
use crate::error::{SatfError, in_open_closed, param};
use crate::hierarchy::{
    Cluster, HairVolume, LocalPoint, LocalStrand, MacroCluster, SkippedStrands,
};

pub use group::{group_strands, resample};

/// Groups are not split below this many strands on the relative stray test (step 7); the
/// absolute one splits down to single strands.
const MIN_SPLIT_STRANDS: usize = 4;
/// Default smallest half-axis, as a fraction of the diagonal of the hair's bounding box.
pub const MIN_RADIUS_FRACTION: f32 = 1e-3;
/// Most control points a trajectory gets when the setting's number misses the strands' mean.
const MAX_TRAJECTORY_CONTROL_POINTS: usize = 64;
/// Polyline samples of a trajectory when it is extended past its ends (step 4).
const EXTENSION_SAMPLES: usize = 64;

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
    /// Control points of `A`, `B` and `q`. Default 8.
    pub profile_control_points: u32,
    /// Bins along `t` for the ellipse fit. Default 16.
    pub profile_bins: u32,
    /// Fraction of the points inside the fitted ellipse. Default 0.95.
    pub axis_quantile: f32,
    /// Smallest half-axis (world units): the tube around a cluster of one strand. Default
    /// `None`: [`MIN_RADIUS_FRACTION`] of the diagonal of the hair's bounding box (0.05 on the
    /// generated ponytail, 1 mm on a head modelled in metres).
    pub min_radius: Option<f32>,
    /// How the twist acts. Default [`TwistMode::RotateAxes`].
    pub twist_mode: TwistMode,
    /// Split a group in two while some point of its shell lies farther from every strand than
    /// this fraction of the cross-section's larger half-axis there (groups of 8 strands or
    /// more), or than twenty minimum half-axes (any group; step 7; 0: never split). Default
    /// 0.75.
    pub stray_split: f32,
    /// Most clusters step 7 splits groups into (each cluster's layer mesh takes GPU memory);
    /// the groups of step 2 are all kept even above it. Default 512.
    pub max_clusters: u32,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            strands_per_cluster: 256,
            grouping_samples: 3,
            fit_samples: 16,
            control_points: 8,
            profile_control_points: 8,
            profile_bins: 16,
            axis_quantile: 0.95,
            min_radius: None,
            twist_mode: TwistMode::RotateAxes,
            stray_split: 0.75,
            max_clusters: 512,
        }
    }
}

impl FitSettings {
    /// Check ranges: group size ≥ 1, 1..=16 grouping samples, 4..=1024 fit samples, control points
    /// in `4..=fit_samples`, profile control points in 4..=64, 1..=256 bins, quantile in `(0, 1]`,
    /// a positive finite minimum radius when one is given.
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
        let radius_ok = self.min_radius.is_none_or(|r| in_open_closed(r, f32::MAX));
        if !in_open_closed(self.axis_quantile, 1.0) || !radius_ok {
            return Err(param(
                "axis_quantile must be in (0, 1] and min_radius positive",
            ));
        }
        if !(self.stray_split.is_finite() && self.stray_split >= 0.0) {
            return Err(param("stray_split must be finite and non-negative"));
        }
        if self.max_clusters == 0 {
            return Err(param("max_clusters must be at least 1"));
        }
        Ok(())
    }
}

/// Fit clusters to every strand of `asset` (see the module docs). Strands left out are counted
/// in the result's [`HairVolume::skipped`]; an asset none of whose strands can be fitted is an
/// error.
pub fn fit_clusters(asset: &HairAsset, settings: &FitSettings) -> Result<HairVolume, SatfError> {
    settings.validate()?;
    let bounds = asset.bounds();
    let settings = FitSettings {
        min_radius: Some(resolved_min_radius(settings, bounds.max - bounds.min)),
        ..*settings
    };
    let n = settings.fit_samples as usize;
    let resampled: Vec<Option<Vec<Vec3>>> = (0..asset.strand_count())
        .into_par_iter()
        .map(|i| {
            let strand = asset.strand(i);
            group::long_enough(strand)
                .then(|| resample(strand, n))
                .flatten()
        })
        .collect();
    let too_short = resampled.iter().filter(|r| r.is_none()).count();
    let kept: Vec<Vec<Vec3>> = resampled.into_iter().flatten().collect();
    if kept.is_empty() {
        return Err(param(format!(
            "none of the {} strands is long enough to fit a cluster to",
            asset.strand_count()
        )));
    }
    let groups = group_strands(&kept, &settings);
    let (macro_clusters, degenerate) = split::fit_groups(&kept, groups, &settings)?;
    Ok(HairVolume {
        macro_clusters,
        skipped: SkippedStrands {
            too_short,
            degenerate,
        },
    })
}

/// The smallest half-axis: the setting, or [`MIN_RADIUS_FRACTION`] of the diagonal `extent`
/// (at least a positive `f32`).
fn resolved_min_radius(settings: &FitSettings, extent: Vec3) -> f32 {
    settings
        .min_radius
        .unwrap_or(MIN_RADIUS_FRACTION * extent.length())
        .max(f32::MIN_POSITIVE)
}

/// Fit one cluster to `strands` (steps 3–6 of the module docs), each strand at least two
/// points, root first, ideally evenly spaced in arc length ([`resample`]). Strands that give no
/// trajectory are a [`SatfError::Degenerate`] error. Without [`FitSettings::min_radius`] the
/// smallest half-axis is [`MIN_RADIUS_FRACTION`] of the strands' own bounding-box diagonal.
pub fn fit_cluster(strands: &[&[Vec3]], settings: &FitSettings) -> Result<MacroCluster, SatfError> {
    if strands.is_empty() {
        return Err(SatfError::Degenerate("a cluster needs a strand".into()));
    }
    if strands.iter().any(|s| s.len() < 2) {
        return Err(param("fit_cluster needs strands of at least two points"));
    }
    let (lo, hi) = strands
        .iter()
        .flat_map(|s| s.iter())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let min_radius = resolved_min_radius(settings, hi - lo);
    let degenerate = |e: SatfError| SatfError::Degenerate(e.to_string());

    // Step 3: every point with parameter σ / L_max.
    let arcs: Vec<Vec<f32>> = strands.iter().map(|s| cumulative_length(s)).collect();
    let l_max = arcs
        .iter()
        .filter_map(|a| a.last().copied())
        .fold(0.0f32, f32::max);
    if !(l_max.is_finite() && l_max > 0.0) {
        return Err(SatfError::Degenerate("the strands have no length".into()));
    }
    let params: Vec<f32> = arcs
        .iter()
        .flat_map(|a| a.iter().map(|s| (s / l_max).clamp(0.0, 1.0)))
        .collect();
    let points: Vec<Vec3> = strands.iter().flat_map(|s| s.iter().copied()).collect();
    // Each point weighs its strand's sample spacing, so every strand counts by its length:
    // sixteen samples of a short strand do not outweigh a long strand's one sample there.
    let weights: Vec<f32> = arcs
        .iter()
        .flat_map(|a| {
            let spacing = a.last().copied().unwrap_or(0.0) / (a.len() - 1).max(1) as f32;
            std::iter::repeat_n((spacing / l_max).max(f32::MIN_POSITIVE), a.len())
        })
        .collect();
    // The setting's control points, but at most three for every four samples of the longest
    // strand (more leave knot spans without data, and the spline wiggles between them); more
    // than the setting, up to that bound, where the spline misses the strands' mean (a fold, a
    // coherent curl).
    let most_samples = strands.iter().map(|s| s.len()).max().unwrap_or(0);
    let bound = (3 * most_samples / 4).max(4);
    let mut n_control = (settings.control_points as usize).min(bound);
    let max_control = bound.min(MAX_TRAJECTORY_CONTROL_POINTS);
    let fit = |n: usize| BSpline::fit_weighted(&params, &points, Some(&weights), n);
    let mut trajectory = fit(n_control)?;
    while n_control < max_control
        && misses_the_mean(&trajectory, &params, &points, &weights, n_control, l_max)
    {
        n_control = (2 * n_control).min(max_control);
        trajectory = fit(n_control)?;
    }
    let axis = axis_only(trajectory, settings.twist_mode).map_err(degenerate)?;
    let hints: Vec<f32> = params.iter().map(|&tau| axis.t_of(tau)).collect();
    // Step 4: project, extend past the ends where points lie beyond them, project again.
    let (axis, hints) = match extension(&axis, &points, &hints) {
        Some((before, after)) => {
            let extended = extend(&axis, before, after, n_control)?;
            let extended = axis_only(extended, settings.twist_mode).map_err(degenerate)?;
            let total = before + axis.length() + after;
            let hints = hints
                .iter()
                .map(|&t| ((before + t * axis.length()) / total).clamp(0.0, 1.0))
                .collect();
            (extended, hints)
        }
        None => (axis, hints),
    };
    let offsets: Vec<profile::Offset> = points
        .iter()
        .zip(&hints)
        .map(|(&p, &hint)| {
            let t = axis.closest_t(p, hint);
            let f = axis.frame(t);
            let d = p - f.position;
            (t, Vec2::new(d.dot(f.normal), d.dot(f.binormal)))
        })
        .collect();

    // Step 5.
    let geometry = profile::fit_profile(axis.trajectory(), &offsets, settings, min_radius)?;

    // Step 6: (v, u) of every point.
    let mut next = offsets.iter();
    let strands = strands
        .iter()
        .map(|s| {
            let points = next
                .by_ref()
                .take(s.len())
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
    Ok(MacroCluster {
        geometry,
        clusters: vec![Cluster::new(Affine3A::IDENTITY, strands)?],
    })
}

/// Whether `trajectory` misses the weighted mean of the `points` (at their parameters): over
/// `2 n_control` bins of the parameter, the mean residual `p - T(τ)` of some bin is longer than
/// 15% of the points' RMS distance from the curve plus 10⁻⁴ of the length. A curve through the strands'
/// mean leaves residuals that average out in every bin; one too stiff for a fold leaves a
/// systematic offset on either side of it.
fn misses_the_mean(
    trajectory: &BSpline<Vec3>,
    params: &[f32],
    points: &[Vec3],
    weights: &[f32],
    n_control: usize,
    length: f32,
) -> bool {
    let bins = 2 * n_control;
    let mut sums = vec![(Vec3::ZERO, 0.0f32); bins];
    let (mut square, mut total) = (0.0f64, 0.0f64);
    for ((&tau, &p), &w) in params.iter().zip(points).zip(weights) {
        let r = p - trajectory.eval(tau);
        square += f64::from(w * r.length_squared());
        total += f64::from(w);
        let b = ((tau * bins as f32) as usize).min(bins - 1);
        sums[b].0 += w * r;
        sums[b].1 += w;
    }
    let rms = (square / total.max(f64::MIN_POSITIVE)).sqrt() as f32;
    let tol = 0.15 * rms + 1e-4 * length;
    sums.iter()
        .any(|&(sum, weight)| weight > 0.0 && (sum / weight).length() > tol)
}

/// The cylinder of unit radius about `trajectory`: its frames, arc length and projections.
fn axis_only(trajectory: BSpline<Vec3>, mode: TwistMode) -> Result<GeneralizedCylinder, SatfError> {
    GeneralizedCylinder::new(
        trajectory,
        BSpline::constant(1.0),
        BSpline::constant(1.0),
        BSpline::constant(0.0),
        mode,
    )
}

/// How far points lie before the trajectory's start and past its end, along the end tangents,
/// among the points whose closest trajectory point is that end; `None` when none lies beyond
/// either end by more than 10⁻⁴ of the trajectory's length.
fn extension(axis: &GeneralizedCylinder, points: &[Vec3], hints: &[f32]) -> Option<(f32, f32)> {
    let (start, end) = (axis.frame(0.0), axis.frame(1.0));
    let (mut before, mut after) = (0.0f32, 0.0f32);
    for (&p, &hint) in points.iter().zip(hints) {
        let t = axis.closest_t(p, hint);
        if t <= 1e-4 {
            before = before.max(-(p - start.position).dot(start.tangent));
        } else if t >= 1.0 - 1e-4 {
            after = after.max((p - end.position).dot(end.tangent));
        }
    }
    let tol = 1e-4 * axis.length();
    (before > tol || after > tol).then_some((before.max(0.0), after.max(0.0)))
}

/// The trajectory extended by `before` along its start tangent and `after` along its end
/// tangent: a spline of `n_control` control points fitted to the extended polyline by chord
/// length.
fn extend(
    axis: &GeneralizedCylinder,
    before: f32,
    after: f32,
    n_control: usize,
) -> Result<BSpline<Vec3>, SatfError> {
    let (start, end) = (axis.frame(0.0), axis.frame(1.0));
    // The straight extensions are sampled as densely as the curve: a single point at the end
    // of a long extension left the end knot spans without data, and the spline's free control
    // point there shot off by several times the strands' length (a spike).
    let step = axis.length() / (EXTENSION_SAMPLES - 1) as f32;
    let samples = |d: f32| (d / step.max(f32::MIN_POSITIVE)).ceil().min(1e4) as usize;
    let (n_before, n_after) = (samples(before), samples(after));
    let mut polyline = Vec::with_capacity(EXTENSION_SAMPLES + n_before + n_after);
    polyline.extend(
        (0..n_before)
            .rev()
            .map(|k| start.position - before * ((k + 1) as f32 / n_before as f32) * start.tangent),
    );
    polyline.extend((0..EXTENSION_SAMPLES).map(|i| {
        axis.frame(i as f32 / (EXTENSION_SAMPLES - 1) as f32)
            .position
    }));
    polyline.extend(
        (1..=n_after).map(|k| end.position + after * (k as f32 / n_after as f32) * end.tangent),
    );
    let arc = cumulative_length(&polyline);
    let total = arc.last().copied().unwrap_or(0.0).max(f32::MIN_POSITIVE);
    let params: Vec<f32> = arc.iter().map(|s| (s / total).clamp(0.0, 1.0)).collect();
    BSpline::fit(&params, &polyline, n_control)
}

/// Arc length from the first point to each point of a polyline.
fn cumulative_length(p: &[Vec3]) -> Vec<f32> {
    let mut acc = 0.0f32;
    let mut out = Vec::with_capacity(p.len());
    out.push(0.0);
    for w in p.windows(2) {
        acc += w[0].distance(w[1]);
        out.push(acc);
    }
    out
}
