//! The four-level hierarchy of Xu et al. 2006, §3.1: the hair volume ([`HairVolume`]) is made
//! of macro-clusters ([`MacroCluster`]), each a generalized cylinder shared by its clusters
//! ([`Cluster`]), each placed by a similarity transform and carrying its own density level: the
//! positions of its strands in the cylinder's local coordinates ([`LocalStrand`]).
//!
//! Local coordinates are `(t, v, u)` of equation 1: relative arc length, radius fraction (1 on
//! the cylinder's surface) and phase. World positions are `transform · P(t, v, u)`.

use glam::{Affine3A, Vec2, Vec3};
use rayon::prelude::*;
use tress_hair::HairAsset;

use crate::cylinder::{GeneralizedCylinder, SurfacePoint};
use crate::error::{SatfError, param};
use crate::shell::ShellSampling;

/// A strand sample in a cylinder's local coordinates (equation 1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LocalPoint {
    /// Relative arc length along the trajectory, in `[0, 1]`.
    pub t: f32,
    /// Radius fraction, in `[0, 1]` (1: on the cylinder's surface).
    pub v: f32,
    /// Phase in radians.
    pub u: f32,
}

impl LocalPoint {
    /// The point in the unit disk of the cross-section: `v (cos u, sin u)`.
    pub fn disk(&self) -> Vec2 {
        self.v * Vec2::new(self.u.cos(), self.u.sin())
    }
}

/// One strand of a cluster: its samples in local coordinates, root first.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalStrand {
    points: Vec<LocalPoint>,
}

impl LocalStrand {
    /// A strand from at least two finite samples with `t` and `v` in `[0, 1]`.
    pub fn new(points: Vec<LocalPoint>) -> Result<Self, SatfError> {
        if points.len() < 2 {
            return Err(param("a local strand needs at least two samples"));
        }
        let ok = |p: &LocalPoint| {
            (0.0..=1.0).contains(&p.t) && (0.0..=1.0).contains(&p.v) && p.u.is_finite()
        };
        if let Some(i) = points.iter().position(|p| !ok(p)) {
            return Err(param(format!(
                "local strand sample {i} has t or v outside [0, 1]"
            )));
        }
        Ok(LocalStrand { points })
    }

    /// The samples, root first.
    pub fn points(&self) -> &[LocalPoint] {
        &self.points
    }

    /// Where the strand crosses the cross-section at `t`, as a point of the unit disk
    /// ([`LocalPoint::disk`]): interpolated linearly on the first segment that spans `t`, or the
    /// end sample when `t` lies within `tolerance` beyond the strand's ends. `None` if the strand
    /// does not reach `t`.
    pub fn crossing(&self, t: f32, tolerance: f32) -> Option<Vec2> {
        for w in self.points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (lo, hi) = if a.t <= b.t { (a.t, b.t) } else { (b.t, a.t) };
            if (lo..=hi).contains(&t) {
                let f = if hi > lo {
                    (t - a.t) / (b.t - a.t)
                } else {
                    0.0
                };
                return Some(a.disk().lerp(b.disk(), f));
            }
        }
        let (first, last) = (self.points[0], self.points[self.points.len() - 1]);
        [first, last]
            .into_iter()
            .filter(|p| (p.t - t).abs() <= tolerance)
            .min_by(|p, q| (p.t - t).abs().total_cmp(&(q.t - t).abs()))
            .map(|p| p.disk())
    }
}

/// A hair cluster (third level): a placement of its macro-cluster's geometry and the density
/// level below it.
#[derive(Clone, Debug, PartialEq)]
pub struct Cluster {
    transform: Affine3A,
    strands: Vec<LocalStrand>,
}

impl Cluster {
    /// A cluster placed by `transform`, a similarity (rotation or reflection, uniform scale and
    /// translation: the shared geometry keeps its shape). Other transforms are rejected.
    pub fn new(transform: Affine3A, strands: Vec<LocalStrand>) -> Result<Self, SatfError> {
        let m = transform.matrix3;
        let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
        let s = x.length_squared();
        let tol = 1e-3 * s;
        let similar = transform.is_finite()
            && s > 1e-12
            && (y.length_squared() - s).abs() <= tol
            && (z.length_squared() - s).abs() <= tol
            && x.dot(y).abs() <= tol
            && y.dot(z).abs() <= tol
            && x.dot(z).abs() <= tol;
        if !similar {
            return Err(param(
                "a cluster transform must be a finite similarity transform",
            ));
        }
        Ok(Cluster { transform, strands })
    }

    /// World from the geometry's space.
    pub fn transform(&self) -> Affine3A {
        self.transform
    }

    /// The density level: the strands in local coordinates.
    pub fn strands(&self) -> &[LocalStrand] {
        &self.strands
    }

    /// World position of `P(t, v, u)`.
    pub fn point(&self, geometry: &GeneralizedCylinder, t: f32, v: f32, u: f32) -> Vec3 {
        self.transform.transform_point3(geometry.point(t, v, u))
    }

    /// World surface point (position and unit directions) at `(t, v, u)`.
    pub fn surface(&self, geometry: &GeneralizedCylinder, t: f32, v: f32, u: f32) -> SurfacePoint {
        let s = geometry.surface(t, v, u);
        let dir = |d: Vec3| self.transform.transform_vector3(d).normalize_or(d);
        SurfacePoint {
            position: self.transform.transform_point3(s.position),
            tangent: dir(s.tangent),
            normal: dir(s.normal),
            s_axis: dir(s.s_axis),
        }
    }

    /// The surface point at the middle of the outer arc of boundary sector `(i, layer, m)`:
    /// where the online phase measures the sector's view and light azimuths.
    pub fn sector_surface(
        &self,
        geometry: &GeneralizedCylinder,
        sampling: &ShellSampling,
        i: u32,
        layer: u32,
        m: u32,
    ) -> SurfacePoint {
        let (t, v, u) = sampling.sector_anchor(i, layer, m);
        self.surface(geometry, t, v, u)
    }
}

/// A macro-cluster (second level): clusters sharing one geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct MacroCluster {
    /// The shared generalized cylinder.
    pub geometry: GeneralizedCylinder,
    /// Its placements.
    pub clusters: Vec<Cluster>,
}

/// Counts of the hierarchy (the first rows of the paper's Table 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VolumeStats {
    /// Macro-clusters.
    pub macro_clusters: usize,
    /// Clusters (`C#`).
    pub clusters: usize,
    /// Shell layers over all clusters (`L#`).
    pub layers: usize,
    /// Strands (`S#`).
    pub strands: usize,
    /// Hair shell volumes over all clusters (`H#`).
    pub hsvs: usize,
    /// Strands of the source asset that are in no cluster, by reason.
    pub skipped: SkippedStrands,
}

/// Strands of a source asset that a fit left out of the clusters, by reason
/// ([`crate::fit::fit_clusters`]). Every other strand is in exactly one cluster.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SkippedStrands {
    /// Strands too short to have a direction: length at most 10⁻⁵ of their largest coordinate
    /// (at least 1), a point or nearly one.
    pub too_short: usize,
    /// Strands that could not carry a cluster even alone (a trajectory that degenerates in
    /// `f32`). Expected to stay 0; counted rather than dropped silently.
    pub degenerate: usize,
}

impl SkippedStrands {
    /// All skipped strands.
    pub fn total(&self) -> usize {
        self.too_short + self.degenerate
    }
}

/// The whole hair volume (first level).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HairVolume {
    /// The macro-clusters.
    pub macro_clusters: Vec<MacroCluster>,
    /// Strands of the source asset left out of the clusters (a fitted volume; zero otherwise).
    pub skipped: SkippedStrands,
}

impl HairVolume {
    /// Move every cluster by `affine` (a similarity, as scene transforms are): each cluster's
    /// placement becomes `affine · placement`.
    pub fn transform(&mut self, affine: Affine3A) {
        for m in &mut self.macro_clusters {
            for c in &mut m.clusters {
                c.transform = affine * c.transform;
            }
        }
    }

    /// Every cluster with its geometry.
    pub fn clusters(&self) -> impl Iterator<Item = (&GeneralizedCylinder, &Cluster)> + '_ {
        self.macro_clusters
            .iter()
            .flat_map(|m| m.clusters.iter().map(move |c| (&m.geometry, c)))
    }

    /// Counts of the hierarchy under `sampling`.
    pub fn stats(&self, sampling: &ShellSampling) -> VolumeStats {
        let clusters = self.clusters().count();
        VolumeStats {
            macro_clusters: self.macro_clusters.len(),
            clusters,
            layers: clusters * sampling.layers() as usize,
            strands: self.clusters().map(|(_, c)| c.strands.len()).sum(),
            hsvs: clusters * sampling.hsv_count(),
            skipped: self.skipped,
        }
    }

    /// The strands as a world-space [`HairAsset`], one vertex per local sample: what the other
    /// techniques render, and what [`crate::fit::fit_clusters`] reads back.
    pub fn to_asset(&self) -> Result<HairAsset, SatfError> {
        let clusters: Vec<(&GeneralizedCylinder, &Cluster)> = self.clusters().collect();
        let per_cluster: Vec<(Vec<Vec3>, Vec<u32>)> = clusters
            .par_iter()
            .map(|(g, c)| {
                let mut pos = Vec::new();
                let mut counts = Vec::with_capacity(c.strands.len());
                for s in &c.strands {
                    pos.extend(s.points.iter().map(|p| c.point(g, p.t, p.v, p.u)));
                    counts.push(s.points.len() as u32);
                }
                (pos, counts)
            })
            .collect();
        let mut positions = Vec::new();
        let mut counts = Vec::new();
        for (p, c) in per_cluster {
            positions.extend(p);
            counts.extend(c);
        }
        Ok(HairAsset::from_counts(positions, &counts)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::BSpline;
    use crate::cylinder::TwistMode;

    fn lp(t: f32, v: f32, u: f32) -> LocalPoint {
        LocalPoint { t, v, u }
    }

    #[test]
    fn crossing_interpolates_in_the_disk() {
        let s = LocalStrand::new(vec![
            lp(0.0, 0.5, 0.0),
            lp(0.5, 0.5, std::f32::consts::FRAC_PI_2),
            lp(1.0, 1.0, 0.0),
        ])
        .unwrap();
        let c = s.crossing(0.25, 0.0).unwrap();
        assert!((c - Vec2::new(0.25, 0.25)).length() < 1e-6);
        let c = s.crossing(1.0, 0.0).unwrap();
        assert!((c - Vec2::X).length() < 1e-6);
        let short = LocalStrand::new(vec![lp(0.1, 0.2, 0.0), lp(0.6, 0.2, 0.0)]).unwrap();
        assert!(short.crossing(0.9, 0.05).is_none());
        assert!((short.crossing(0.05, 0.06).unwrap() - Vec2::new(0.2, 0.0)).length() < 1e-6);
        assert!(LocalStrand::new(vec![lp(0.0, 1.5, 0.0), lp(1.0, 0.0, 0.0)]).is_err());
    }

    #[test]
    fn hierarchy_counts_and_world_positions() {
        let g = GeneralizedCylinder::new(
            BSpline::linear(Vec3::ZERO, Vec3::new(0.0, -10.0, 0.0)),
            BSpline::constant(1.0),
            BSpline::constant(1.0),
            BSpline::constant(0.0),
            TwistMode::RotateAxes,
        )
        .unwrap();
        let strand = LocalStrand::new(vec![lp(0.0, 0.0, 0.0), lp(1.0, 0.0, 0.0)]).unwrap();
        let a = Cluster::new(Affine3A::IDENTITY, vec![strand.clone()]).unwrap();
        let b = Cluster::new(
            Affine3A::from_scale_rotation_translation(
                Vec3::splat(2.0),
                glam::Quat::IDENTITY,
                Vec3::X,
            ),
            vec![strand.clone(), strand],
        )
        .unwrap();
        assert!(Cluster::new(Affine3A::from_scale(Vec3::new(1.0, 2.0, 1.0)), vec![]).is_err());
        let vol = HairVolume {
            macro_clusters: vec![MacroCluster {
                geometry: g,
                clusters: vec![a, b],
            }],
            ..Default::default()
        };
        let sampling = ShellSampling {
            st: 4,
            sv: 3,
            su: 6,
            core_rings: 1,
        };
        let st = vol.stats(&sampling);
        assert_eq!(
            (
                st.macro_clusters,
                st.clusters,
                st.strands,
                st.layers,
                st.hsvs
            ),
            (1, 2, 3, 4, 2 * 4 * 2 * 6)
        );
        let asset = vol.to_asset().unwrap();
        assert_eq!(asset.strand_count(), 3);
        assert!((asset.strand(1)[1] - Vec3::new(1.0, -20.0, 0.0)).length() < 1e-3);
    }
}
