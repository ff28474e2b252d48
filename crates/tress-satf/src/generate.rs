//! A generator of clustered hair styles on the generated head ([`Head`]), built the way the
//! paper's hierarchy is meant to be used (§3.1): a few distinct cluster geometries
//! (macro-clusters), each placed several times around the head by simple transforms.
//!
//! # Implementation
//!
//! - **Templates.** Macro-cluster `m` roots at the scalp point of coordinate
//!   `((m + ½ + jitter) / M, v)` with a random `v` in `[0.25, 0.85]` ([`Head::scalp_point`]). Its
//!   axis rises along the scalp normal and bends down under gravity in 24 steps of
//!   `length / 23`, each pushed out of the head's ellipsoid to keep the cluster's root radius
//!   clear of it. A cubic B-spline of 8 control points is fitted to that polyline
//!   ([`BSpline::fit`]). `A(t)` tapers linearly from `root_radius` to `tip_radius`,
//!   `B = aspect · A`, and `q(t)` turns linearly by `twist` turns.
//! - **Placements.** Cluster `c` of a macro-cluster is its template rotated about the head's
//!   vertical axis by `c / C` of the azimuth gap between templates, and uniformly scaled about the
//!   head's centre so that its root lands on the ellipsoid again: a similarity transform, as
//!   §3.1 asks ("geometries … derived from each other via simple transformations").
//! - **Density level.** Each cluster's strands root uniformly over the ellipse (`v = √ξ`) and
//!   drift by up to `strand_jitter` in `v` and `2 · strand_jitter` radians in `u` from root to
//!   tip, sampled at `samples` values of `t`.
//!
//! Every template and every cluster draws from its own [`Rng::stream`], so results do not
//! depend on scheduling.

use std::f32::consts::TAU;

use glam::{Affine3A, Quat, Vec2, Vec3};
use rayon::prelude::*;
use tress_hair::generate::Head;
use tress_hair::rng::Rng;

use crate::bspline::BSpline;
use crate::cylinder::{GeneralizedCylinder, TwistMode};
use crate::error::{SatfError, in_open_closed, param};
use crate::hierarchy::{Cluster, HairVolume, LocalPoint, LocalStrand, MacroCluster};

/// Steps of the template polyline.
const TEMPLATE_STEPS: usize = 24;
/// Control points of a template trajectory.
const TEMPLATE_CONTROL_POINTS: usize = 8;
/// Cluster streams start here, apart from the template streams.
const CLUSTER_STREAMS: u64 = 1 << 40;

/// Parameters of a generated clustered style (world units are the head's, centimetre-like).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterStyle {
    /// Distinct cluster geometries (macro-clusters). Default 12.
    pub macro_clusters: u32,
    /// Placements of each geometry. Default 5.
    pub clusters_per_macro: u32,
    /// Strands per cluster. Default 150.
    pub strands_per_cluster: u32,
    /// Trajectory length. Default 26.
    pub length: f32,
    /// Half-axis `A` at the root. Default 1.2.
    pub root_radius: f32,
    /// Half-axis `A` at the tip. Default 0.5.
    pub tip_radius: f32,
    /// `B / A`, in `(0, 1]`. Default 0.6.
    pub aspect: f32,
    /// Turns of the twist `q` from root to tip. Default 0.25.
    pub twist: f32,
    /// Largest drift of a strand in `v` from root to tip. Default 0.15.
    pub strand_jitter: f32,
    /// Samples per strand. Default 24.
    pub samples: u32,
    /// How the twist acts. Default [`TwistMode::RotateAxes`].
    pub twist_mode: TwistMode,
    /// Random seed. Default 0.
    pub seed: u64,
}

impl Default for ClusterStyle {
    fn default() -> Self {
        ClusterStyle {
            macro_clusters: 12,
            clusters_per_macro: 5,
            strands_per_cluster: 150,
            length: 26.0,
            root_radius: 1.2,
            tip_radius: 0.5,
            aspect: 0.6,
            twist: 0.25,
            strand_jitter: 0.15,
            samples: 24,
            twist_mode: TwistMode::RotateAxes,
            seed: 0,
        }
    }
}

impl ClusterStyle {
    /// Check ranges: 1..=4096 macro-clusters and placements each, 1..=100,000 strands per
    /// cluster and at most 2^24 strands in all, 2..=1024 samples, positive finite radii and
    /// length (at most 10^4), aspect in `(0, 1]`, finite twist and jitter in `[0, 1]`.
    pub fn validate(&self) -> Result<(), SatfError> {
        let count_ok = |n: u32, max: u32| (1..=max).contains(&n);
        if !count_ok(self.macro_clusters, 4096) || !count_ok(self.clusters_per_macro, 4096) {
            return Err(param(
                "macro_clusters and clusters_per_macro must be in 1..=4096",
            ));
        }
        if !count_ok(self.strands_per_cluster, 100_000) || !(2..=1024).contains(&self.samples) {
            return Err(param(
                "strands_per_cluster must be in 1..=100000 and samples in 2..=1024",
            ));
        }
        let total = u64::from(self.macro_clusters)
            * u64::from(self.clusters_per_macro)
            * u64::from(self.strands_per_cluster);
        if total > 1 << 24 {
            return Err(param(format!("{total} strands in all is more than 2^24")));
        }
        for (name, x) in [
            ("length", self.length),
            ("root_radius", self.root_radius),
            ("tip_radius", self.tip_radius),
        ] {
            if !(x.is_finite() && x > 0.0 && x <= 1e4) {
                return Err(param(format!(
                    "{name} must be positive and at most 10^4, got {x}"
                )));
            }
        }
        if !in_open_closed(self.aspect, 1.0)
            || !self.twist.is_finite()
            || !(0.0..=1.0).contains(&self.strand_jitter)
        {
            return Err(param(
                "aspect must be in (0, 1], twist finite and strand_jitter in [0, 1]",
            ));
        }
        Ok(())
    }
}

/// Generate a clustered hair volume on `head` (see the module docs).
pub fn generate_clusters(head: &Head, style: &ClusterStyle) -> Result<HairVolume, SatfError> {
    head.validate()?;
    style.validate()?;
    let m_count = style.macro_clusters;
    let macro_clusters = (0..m_count)
        .into_par_iter()
        .map(|m| {
            let mut rng = Rng::stream(style.seed, u64::from(m));
            let uv = Vec2::new(
                (m as f32 + 0.5 + rng.range(-0.3, 0.3)) / m_count as f32,
                rng.range(0.25, 0.85),
            );
            let root = head.scalp_point(uv);
            let geometry = template(head, root.position, root.normal, style)?;
            let clusters = (0..style.clusters_per_macro)
                .map(|c| {
                    let index = u64::from(m) * u64::from(style.clusters_per_macro) + u64::from(c);
                    let mut rng = Rng::stream(style.seed, CLUSTER_STREAMS | index);
                    let delta = c as f32 / style.clusters_per_macro as f32 * TAU / m_count as f32;
                    Cluster::new(
                        placement(head, geometry.point(0.0, 0.0, 0.0), delta),
                        strands(&mut rng, style)?,
                    )
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok(MacroCluster { geometry, clusters })
        })
        .collect::<Result<Vec<_>, SatfError>>()?;
    Ok(HairVolume {
        macro_clusters,
        ..Default::default()
    })
}

/// `p` moved out along its ellipsoid direction to level `target` if it lies below it.
fn push_out(head: &Head, p: Vec3, target: f32) -> Vec3 {
    let q = (p - head.center) / head.radii;
    let level = q.length();
    if level >= target || level < 1e-6 {
        p
    } else {
        head.center + head.radii * q * (target / level)
    }
}

fn template(
    head: &Head,
    root: Vec3,
    normal: Vec3,
    style: &ClusterStyle,
) -> Result<GeneralizedCylinder, SatfError> {
    let step = style.length / (TEMPLATE_STEPS - 1) as f32;
    let clear = 1.0 + 1.2 * style.root_radius / head.radii.min_element();
    let gravity = Vec3::new(0.0, -0.35, -0.05);
    let mut points = Vec::with_capacity(TEMPLATE_STEPS);
    let mut p = root;
    let mut dir = normal;
    points.push(p);
    for _ in 1..TEMPLATE_STEPS {
        dir = (dir + gravity).normalize_or(Vec3::NEG_Y);
        let next = push_out(head, p + dir * step, clear);
        dir = (next - p).normalize_or(dir);
        p = next;
        points.push(p);
    }
    let mut params = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    params.push(0.0);
    for w in points.windows(2) {
        acc += w[0].distance(w[1]);
        params.push(acc);
    }
    for t in &mut params {
        *t /= acc.max(1e-12);
    }
    let trajectory = BSpline::fit(&params, &points, TEMPLATE_CONTROL_POINTS)?;
    GeneralizedCylinder::new(
        trajectory,
        BSpline::linear(style.root_radius, style.tip_radius),
        BSpline::linear(
            style.root_radius * style.aspect,
            style.tip_radius * style.aspect,
        ),
        BSpline::linear(0.0, style.twist * TAU),
        style.twist_mode,
    )
}

/// Rotation about the head's vertical axis by `delta`, scaled about its centre so that `root`
/// lands on the ellipsoid again.
fn placement(head: &Head, root: Vec3, delta: f32) -> Affine3A {
    let rot = Quat::from_rotation_y(delta);
    let moved = rot * (root - head.center);
    let level = (moved / head.radii).length();
    let scale = if level > 1e-6 { 1.0 / level } else { 1.0 };
    Affine3A::from_translation(head.center)
        * Affine3A::from_scale_rotation_translation(Vec3::splat(scale), rot, Vec3::ZERO)
        * Affine3A::from_translation(-head.center)
}

fn strands(rng: &mut Rng, style: &ClusterStyle) -> Result<Vec<LocalStrand>, SatfError> {
    let n = style.samples as usize;
    (0..style.strands_per_cluster)
        .map(|_| {
            let v0 = rng.f32().sqrt();
            let u0 = rng.f32() * TAU;
            let dv = style.strand_jitter * rng.range(-1.0, 1.0);
            let du = 2.0 * style.strand_jitter * rng.range(-1.0, 1.0);
            let points = (0..n)
                .map(|k| {
                    let t = k as f32 / (n - 1) as f32;
                    LocalPoint {
                        t,
                        v: (v0 + dv * t).clamp(0.0, 1.0),
                        u: u0 + du * t,
                    }
                })
                .collect();
            LocalStrand::new(points)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shell::ShellSampling;

    #[test]
    fn generates_the_hierarchy_deterministically() {
        let style = ClusterStyle {
            macro_clusters: 4,
            clusters_per_macro: 3,
            strands_per_cluster: 20,
            ..Default::default()
        };
        let head = Head::default();
        let vol = generate_clusters(&head, &style).unwrap();
        let stats = vol.stats(&ShellSampling::default());
        assert_eq!(
            (stats.macro_clusters, stats.clusters, stats.strands),
            (4, 12, 240)
        );
        assert_eq!(vol, generate_clusters(&head, &style).unwrap());
        for (g, c) in vol.clusters() {
            // Roots on the scalp, the trajectory outside the head after the root.
            let root = c.point(g, 0.0, 0.0, 0.0);
            assert!(
                (head.level(root) - 1.0).abs() < 1e-3,
                "{}",
                head.level(root)
            );
            for i in 2..=10 {
                assert!(head.level(c.point(g, i as f32 / 10.0, 0.0, 0.0)) > 1.0);
            }
            let len = g.length() * c.transform().matrix3.x_axis.length();
            assert!((20.0..32.0).contains(&len), "length {len}");
        }
        let asset = vol.to_asset().unwrap();
        assert_eq!(asset.strand_count(), 240);
        assert_eq!(asset.vertex_count(), 240 * 24);
        assert!(
            generate_clusters(
                &head,
                &ClusterStyle {
                    aspect: 0.0,
                    ..style
                }
            )
            .is_err()
        );
    }
}
