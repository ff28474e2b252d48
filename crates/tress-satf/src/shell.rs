//! Shells, hair shell volumes and generalized sectors (Xu et al. 2006, §3.2, equation 3).
//!
//! The sampling `S = {t_i} × {v_j} × {u_k}` with `t_i = i / s_t` (`i = 0..=s_t`),
//! `v_j = j / s_v` (`j = 0..=s_v`) and `u_k = 2πk / s_u` (`k = 0..s_u`) cuts a cluster into
//! rings `[v_j, v_{j+1}]` ("generalized tracks"), angular sectors `[u_k, u_{k+1}]` and slabs
//! `[t_i, t_{i+1}]`.
//!
//! # Choices
//!
//! - **Core**: the paper's Figure 1 shows a transparent interior core inside the shells but does
//!   not say where it ends. Here the innermost [`ShellSampling::core_rings`] rings form the core and
//!   the remaining `s_v - core_rings` rings are the shell layers, so `S` stays exactly equation 3.
//!   Layer `k = 0` is the innermost shell and `k = layers - 1` the outermost, the order of
//!   equations 12 and 14 (layers `m > k` cover layer `k`).
//! - **HSV**: a hair shell volume is `[t_i, t_{i+1}] × ring × [u_k, u_{k+1}]`; its two boundary
//!   generalized sectors are the annular sectors at `t_i` (the paper's top, `b⊤`) and `t_{i+1}`
//!   (bottom, `b⊥`).
//! - **Canonical coordinates** of a strand crossing the sector of ring `[v_j, v_{j+1}]` and phase
//!   `[u_k, u_{k+1}]` at `(v, u)`: `s = (u - u_k) / Δu` and `d = depth · (v_{j+1} - v) / Δv`
//!   (see [`crate::density`]): `d = 0` on the layer's outer surface, where the online phase's
//!   layer mesh lies (§6.1). Crossings are found with a tolerance of half a `t` step at the
//!   strands' ends, so a fitted strand whose root sits just above `t = 0` still counts there.

use std::f32::consts::TAU;

use glam::Vec2;
use rayon::prelude::*;

use crate::density::{DensityGrid, DensitySettings};
use crate::error::{SatfError, param};
use crate::hierarchy::{Cluster, LocalStrand};

/// The sampling of equation 3 and the core/shell split.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShellSampling {
    /// `s_t`: steps along the trajectory (`s_t + 1` cross-sections). Default 16.
    pub st: u32,
    /// `s_v`: radial steps (rings). Default 4.
    pub sv: u32,
    /// `s_u`: angular steps (sectors per ring). Default 8.
    pub su: u32,
    /// Innermost rings that form the transparent core. Default 1.
    pub core_rings: u32,
}

impl Default for ShellSampling {
    fn default() -> Self {
        ShellSampling {
            st: 16,
            sv: 4,
            su: 8,
            core_rings: 1,
        }
    }
}

impl ShellSampling {
    /// Check ranges: `s_t` in 1..=4096, `s_v` in 1..=64, `s_u` in 3..=256, at least one layer.
    pub fn validate(&self) -> Result<(), SatfError> {
        if !(1..=4096).contains(&self.st)
            || !(1..=64).contains(&self.sv)
            || !(3..=256).contains(&self.su)
        {
            return Err(param(format!(
                "shell sampling s_t = {}, s_v = {}, s_u = {} out of range (1..=4096, 1..=64, 3..=256)",
                self.st, self.sv, self.su
            )));
        }
        if self.core_rings >= self.sv {
            return Err(param(format!(
                "{} core rings leave no shell layer of {} rings",
                self.core_rings, self.sv
            )));
        }
        Ok(())
    }

    /// `t_i = i / s_t`.
    pub fn t(&self, i: u32) -> f32 {
        i as f32 / self.st as f32
    }
    /// `v_j = j / s_v`.
    pub fn v(&self, j: u32) -> f32 {
        j as f32 / self.sv as f32
    }
    /// `u_k = 2πk / s_u`.
    pub fn u(&self, k: u32) -> f32 {
        TAU * k as f32 / self.su as f32
    }

    /// `|S| = (s_t + 1)(s_v + 1) s_u`, the number of sampling points of equation 3.
    pub fn point_count(&self) -> usize {
        (self.st as usize + 1) * (self.sv as usize + 1) * self.su as usize
    }

    /// Shell layers per cluster (`s_v - core_rings`).
    pub fn layers(&self) -> u32 {
        self.sv - self.core_rings
    }

    /// The ring `j` of layer `k` (`core_rings + k`).
    pub fn ring_of_layer(&self, layer: u32) -> u32 {
        self.core_rings + layer
    }

    /// Generalized sectors per cross-section (`layers · s_u`).
    pub fn sectors_per_section(&self) -> usize {
        self.layers() as usize * self.su as usize
    }

    /// Boundary generalized sectors per cluster (`(s_t + 1) · layers · s_u`).
    pub fn sector_count(&self) -> usize {
        (self.st as usize + 1) * self.sectors_per_section()
    }

    /// Hair shell volumes per cluster (`s_t · layers · s_u`).
    pub fn hsv_count(&self) -> usize {
        self.st as usize * self.sectors_per_section()
    }

    /// Index of boundary sector `(i, layer, m)`: `(i · layers + layer) · s_u + m`.
    pub fn sector_index(&self, i: u32, layer: u32, m: u32) -> usize {
        (i as usize * self.layers() as usize + layer as usize) * self.su as usize + m as usize
    }

    /// The two boundary sectors of HSV `(i, layer, m)` (`i < s_t`): top at `t_i`, bottom at `t_{i+1}`.
    pub fn hsv_sectors(&self, i: u32, layer: u32, m: u32) -> (usize, usize) {
        (
            self.sector_index(i, layer, m),
            self.sector_index(i + 1, layer, m),
        )
    }

    /// `(t, v, u)` of the middle of the outer arc of sector `(i, layer, m)`.
    pub fn sector_anchor(&self, i: u32, layer: u32, m: u32) -> (f32, f32, f32) {
        let j = self.ring_of_layer(layer);
        (
            self.t(i),
            self.v(j + 1),
            TAU * (m as f32 + 0.5) / self.su as f32,
        )
    }

    /// Canonical `(s, d)` of a cross-section point `disk = v (cos u, sin u)` and the sector
    /// `(layer, m)` it falls in; `None` inside the core (or at `v > 1`, which is clamped to 1 first).
    pub fn canonical(&self, disk: Vec2, depth: f32) -> Option<(u32, u32, Vec2)> {
        let v = disk.length().min(1.0);
        let u = disk.y.atan2(disk.x).rem_euclid(TAU);
        let ring = ((v * self.sv as f32) as u32).min(self.sv - 1);
        if ring < self.core_rings {
            return None;
        }
        let x = u / TAU * self.su as f32;
        let m = (x as u32).min(self.su - 1);
        let s = (x - m as f32).clamp(0.0, 1.0);
        let d = depth * ((self.v(ring + 1) - v) * self.sv as f32).clamp(0.0, 1.0);
        Some((ring - self.core_rings, m, Vec2::new(s, d)))
    }

    /// The canonical crossing points of `strands` in every sector of cross-section `i`, indexed
    /// `layer · s_u + m`.
    pub fn section_points(&self, strands: &[LocalStrand], i: u32, depth: f32) -> Vec<Vec<Vec2>> {
        let mut out = vec![Vec::new(); self.sectors_per_section()];
        let t = self.t(i);
        let tol = 0.5 / self.st as f32;
        for s in strands {
            if let Some((layer, m, p)) = s.crossing(t, tol).and_then(|d| self.canonical(d, depth)) {
                out[(layer * self.su + m) as usize].push(p);
            }
        }
        out
    }
}

/// The feature vector `ρ_feature` (§5.2) of every boundary sector of a cluster, indexed by
/// [`ShellSampling::sector_index`]: the online phase's "index calculation" (Table 1, I).
/// Sampling and density settings must be valid.
pub fn cluster_features(
    cluster: &Cluster,
    sampling: &ShellSampling,
    density: &DensitySettings,
) -> Vec<[f32; 3]> {
    (0..=sampling.st)
        .into_par_iter()
        .flat_map_iter(|i| {
            sampling
                .section_points(cluster.strands(), i, density.depth)
                .into_iter()
                .map(|pts| DensityGrid::from_points(&pts, density).features(density))
                .collect::<Vec<_>>()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use glam::Affine3A;

    use super::*;
    use crate::hierarchy::LocalPoint;

    #[test]
    fn sampling_counts() {
        let s = ShellSampling {
            st: 10,
            sv: 4,
            su: 6,
            core_rings: 1,
        };
        s.validate().unwrap();
        // Equation 3: 11 × 5 × 6 points.
        assert_eq!(s.point_count(), 330);
        assert_eq!(s.layers(), 3);
        assert_eq!(s.sectors_per_section(), 18);
        assert_eq!(s.sector_count(), 11 * 18);
        assert_eq!(s.hsv_count(), 10 * 18);
        assert_eq!(s.hsv_sectors(2, 1, 3), (2 * 18 + 6 + 3, 3 * 18 + 6 + 3));
        assert_eq!(s.sector_index(10, 2, 5), s.sector_count() - 1);
        assert!((s.u(3) - std::f32::consts::PI).abs() < 1e-6 && s.v(4) == 1.0 && s.t(10) == 1.0);
        assert!(ShellSampling { core_rings: 4, ..s }.validate().is_err());
        assert!(ShellSampling { su: 2, ..s }.validate().is_err());
    }

    #[test]
    fn canonical_coordinates_by_hand() {
        let s = ShellSampling {
            st: 4,
            sv: 4,
            su: 4,
            core_rings: 1,
        };
        // v = 0.875, u = π/8: ring 3 (layer 2), sector 0 (of width π/2), s = 0.25, d = depth · 0.5.
        let a = std::f32::consts::FRAC_PI_8;
        let (layer, m, p) = s
            .canonical(0.875 * Vec2::new(a.cos(), a.sin()), 0.5)
            .unwrap();
        assert_eq!((layer, m), (2, 0));
        assert!((p - Vec2::new(0.25, 0.25)).length() < 1e-5);
        // Inside the core.
        assert!(s.canonical(Vec2::new(0.1, 0.1), 0.5).is_none());
        // Outside the cylinder: clamped onto the outer surface.
        let (layer, m, p) = s.canonical(Vec2::new(0.0, -2.0), 0.5).unwrap();
        assert_eq!((layer, m), (2, 3));
        assert!((p - Vec2::new(0.0, 0.0)).length() < 1e-5);
    }

    #[test]
    fn features_follow_the_strands() {
        let s = ShellSampling {
            st: 2,
            sv: 2,
            su: 4,
            core_rings: 1,
        };
        let d = DensitySettings::default();
        // Twelve straight strands in sector 1 (u in [π/2, π)), ring 1, at every t.
        let strands: Vec<LocalStrand> = (0..12)
            .map(|k| {
                let u = std::f32::consts::FRAC_PI_2 * (1.2 + 0.05 * k as f32);
                LocalStrand::new(vec![
                    LocalPoint { t: 0.0, v: 0.8, u },
                    LocalPoint { t: 1.0, v: 0.8, u },
                ])
                .unwrap()
            })
            .collect();
        let c = Cluster::new(Affine3A::IDENTITY, strands).unwrap();
        let f = cluster_features(&c, &s, &d);
        assert_eq!(f.len(), s.sector_count());
        for i in 0..=2 {
            assert_eq!(f[s.sector_index(i, 0, 0)], [0.0, 0.5, 0.5]);
            let g = f[s.sector_index(i, 0, 1)];
            // 12 of the 24 reference strands; mean d = 0.4 of the depth.
            assert!(
                (g[0] - 0.5).abs() < 0.02 && (g[2] - 0.4).abs() < 0.02,
                "{g:?}"
            );
        }
    }
}
