//! The hair density field of a generalized sector (Xu et al. 2006, §3.3) and its feature vector
//! `ρ_feature = (ρ_st, ρ_s, ρ_t)` (§5.2).
//!
//! # The canonical sector
//!
//! Every generalized sector, whether cut from a real cluster ([`crate::shell`]) or drawn at
//! random for the database ([`crate::hrir`]), is mapped to the same canonical domain: a rectangle
//! of width 1 along `s` (across the sector, the direction of increasing `u`) and depth
//! [`DensitySettings::depth`] along `d` (`d = 0` on the shell's outer surface, growing inward).
//! Its curvature is ignored: the paper's HSVs are small (§6.4). The domain is periodic in `s`, so
//! a sector tiles with copies of itself, which stands for its neighbours in the ray tracer.
//!
//! # Density (§3.3)
//!
//! Each strand crossing the sector is a point `x_i` and contributes a normalized 2D Gaussian of
//! standard deviation `σ` ([`DensitySettings::sigma`]) and mass `m`:
//! `ρ(x) = Σ_i m / (2πσ²) · exp(-|x - x_i|² / 2σ²)`, evaluated at the cell centres of a
//! `grid_s × grid_depth` grid (the paper's "grid map") with the minimum-image distance in `s` and
//! truncated at `4σ`. The gradient `∇ρ` is evaluated analytically at the same points, for the
//! normals of the ray tracer (§5.1).
//!
//! # Features (§5.2), a choice
//!
//! `ρ_st` is the average density over the grid, divided by the average density of a sector holding
//! [`DensitySettings::reference_strands`] strands, so that features are of order 1. The paper
//! defines `ρ_s` and `ρ_t` as "the average values" of the density histograms along `s` and `t`
//! (here `d`). Read as the mean height of each histogram, both equal `ρ_st` times a constant and
//! carry no information; [`FeatureKind::Centroid`] (the default) reads them as the mean *position*
//! of each histogram, the density-weighted mean `s` and `d / depth` (both in `[0, 1]`, 0.5 for an
//! empty sector). [`FeatureKind::HistogramMean`] keeps the literal reading.

use glam::Vec2;

use crate::error::{SatfError, param};

/// Gaussians are truncated at this many standard deviations.
pub const GAUSSIAN_CUTOFF: f32 = 4.0;

/// How `ρ_s` and `ρ_t` are computed (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FeatureKind {
    /// Density-weighted mean position along `s` and along `d` (default).
    #[default]
    Centroid,
    /// Mean height of the projected histograms, normalized like `ρ_st` (degenerate: both equal
    /// `ρ_st`; kept for fidelity to the paper's wording).
    HistogramMean,
}

/// The density field's settings, shared by the bake and the online index calculation: a
/// database only matches sectors whose features were computed with the same ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensitySettings {
    /// Grid points across the sector (`s`). Default 32.
    pub grid_s: u32,
    /// Grid points through the shell (`d`). Default 16.
    pub grid_depth: u32,
    /// Depth of the canonical sector relative to its width. Default 0.5.
    pub depth: f32,
    /// Standard deviation `σ` of a strand's Gaussian, in sector widths (§3.3). Default 0.04.
    pub sigma: f32,
    /// Mass `m` of a strand's Gaussian. Default 1.
    pub strand_mass: f32,
    /// Strand count whose average density makes `ρ_st = 1`. Default 24.
    pub reference_strands: f32,
    /// How `ρ_s`, `ρ_t` are computed. Default [`FeatureKind::Centroid`].
    pub feature_kind: FeatureKind,
}

impl Default for DensitySettings {
    fn default() -> Self {
        DensitySettings {
            grid_s: 32,
            grid_depth: 16,
            depth: 0.5,
            sigma: 0.04,
            strand_mass: 1.0,
            reference_strands: 24.0,
            feature_kind: FeatureKind::Centroid,
        }
    }
}

impl DensitySettings {
    /// Check ranges: grid 2..=256 each way, depth in `[0.05, 4]`, `σ` in `(0, 0.12]` (so the
    /// `4σ` support is narrower than half the periodic width), mass and reference positive.
    pub fn validate(&self) -> Result<(), SatfError> {
        for (name, n) in [("grid_s", self.grid_s), ("grid_depth", self.grid_depth)] {
            if !(2..=256).contains(&n) {
                return Err(param(format!("density {name} must be in 2..=256, got {n}")));
            }
        }
        if !(0.05..=4.0).contains(&self.depth) {
            return Err(param(format!(
                "sector depth must be in [0.05, 4], got {}",
                self.depth
            )));
        }
        if !(self.sigma > 0.0 && self.sigma <= 0.12) {
            return Err(param(format!(
                "density sigma must be in (0, 0.12], got {}",
                self.sigma
            )));
        }
        for (name, x) in [
            ("strand_mass", self.strand_mass),
            ("reference_strands", self.reference_strands),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err(param(format!("density {name} must be positive, got {x}")));
            }
        }
        Ok(())
    }

    /// Size of a grid cell `(Δs, Δd)`.
    pub fn cell(&self) -> Vec2 {
        Vec2::new(
            1.0 / self.grid_s as f32,
            self.depth / self.grid_depth as f32,
        )
    }

    /// The average density of a sector holding `reference_strands` strands.
    pub fn reference_density(&self) -> f32 {
        self.reference_strands * self.strand_mass / self.depth
    }
}

/// A sector's density (and its gradient) at the grid's cell centres, row-major in `s`
/// (`index = b * grid_s + a`).
#[derive(Clone, Debug, PartialEq)]
pub struct DensityGrid {
    grid_s: usize,
    grid_depth: usize,
    cell: Vec2,
    values: Vec<f32>,
    gradient: Vec<Vec2>,
}

impl DensityGrid {
    /// The density of strands crossing the sector at `points` (canonical coordinates `(s, d)`,
    /// `s` taken modulo 1). Settings must be valid ([`DensitySettings::validate`]).
    pub fn from_points(points: &[Vec2], settings: &DensitySettings) -> DensityGrid {
        let (gs, gd) = (settings.grid_s as usize, settings.grid_depth as usize);
        let cell = settings.cell();
        let sigma = settings.sigma;
        let norm = settings.strand_mass / (std::f32::consts::TAU * sigma * sigma);
        let inv_2s2 = 0.5 / (sigma * sigma);
        let reach = GAUSSIAN_CUTOFF * sigma;
        let mut values = vec![0.0f32; gs * gd];
        let mut gradient = vec![Vec2::ZERO; gs * gd];
        for p in points {
            let ps = p.x.rem_euclid(1.0);
            let b0 = ((p.y - reach) / cell.y - 0.5).ceil().max(0.0) as usize;
            let b1 = ((p.y + reach) / cell.y - 0.5).floor().min(gd as f32 - 1.0);
            if b1 < 0.0 {
                continue;
            }
            let a0 = ((ps - reach) / cell.x - 0.5).ceil() as isize;
            let a1 = ((ps + reach) / cell.x - 0.5).floor() as isize;
            for b in b0..=b1 as usize {
                let dd = (b as f32 + 0.5) * cell.y - p.y;
                for a in a0..=a1 {
                    let ds = (a as f32 + 0.5) * cell.x - ps;
                    let r2 = ds * ds + dd * dd;
                    if r2 > reach * reach {
                        continue;
                    }
                    let g = norm * (-r2 * inv_2s2).exp();
                    let i = b * gs + a.rem_euclid(gs as isize) as usize;
                    values[i] += g;
                    gradient[i] -= Vec2::new(ds, dd) * (g / (sigma * sigma));
                }
            }
        }
        DensityGrid {
            grid_s: gs,
            grid_depth: gd,
            cell,
            values,
            gradient,
        }
    }

    /// Grid points across (`s`) and through (`d`).
    pub fn size(&self) -> (usize, usize) {
        (self.grid_s, self.grid_depth)
    }

    /// Cell size `(Δs, Δd)`.
    pub fn cell(&self) -> Vec2 {
        self.cell
    }

    /// Density values, row-major in `s`.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// `∇ρ` at the grid points, same layout.
    pub fn gradient(&self) -> &[Vec2] {
        &self.gradient
    }

    /// `∫ρ` over the sector by the midpoint rule.
    pub fn integral(&self) -> f32 {
        self.values.iter().sum::<f32>() * self.cell.x * self.cell.y
    }

    /// Bilinear density and gradient at canonical `(s, d)`: periodic in `s`, clamped in `d`.
    pub fn sample(&self, p: Vec2) -> (f32, Vec2) {
        let x = p.x.rem_euclid(1.0) / self.cell.x - 0.5;
        let y = (p.y / self.cell.y - 0.5).clamp(0.0, (self.grid_depth - 1) as f32);
        let a0 = x.floor();
        let fx = x - a0;
        let b0 = (y.floor() as usize).min(self.grid_depth - 2);
        let fy = y - b0 as f32;
        let gs = self.grid_s as isize;
        let a0i = (a0 as isize).rem_euclid(gs) as usize;
        let a1i = (a0 as isize + 1).rem_euclid(gs) as usize;
        let idx = |a: usize, b: usize| b * self.grid_s + a;
        let w = [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ];
        let ids = [
            idx(a0i, b0),
            idx(a1i, b0),
            idx(a0i, b0 + 1),
            idx(a1i, b0 + 1),
        ];
        let mut rho = 0.0;
        let mut grad = Vec2::ZERO;
        for (wi, i) in w.iter().zip(ids) {
            rho += wi * self.values[i];
            grad += *wi * self.gradient[i];
        }
        (rho, grad)
    }

    /// The feature vector `ρ_feature = (ρ_st, ρ_s, ρ_t)` (§5.2; see the module docs).
    pub fn features(&self, settings: &DensitySettings) -> [f32; 3] {
        let total: f32 = self.values.iter().sum();
        let count = self.values.len() as f32;
        let rho_ref = settings.reference_density();
        let rho_st = total / count / rho_ref;
        match settings.feature_kind {
            FeatureKind::Centroid => {
                if total <= 0.0 {
                    return [rho_st, 0.5, 0.5];
                }
                let (mut ms, mut md) = (0.0f32, 0.0f32);
                for (i, &r) in self.values.iter().enumerate() {
                    let (a, b) = (i % self.grid_s, i / self.grid_s);
                    ms += r * (a as f32 + 0.5) / self.grid_s as f32;
                    md += r * (b as f32 + 0.5) / self.grid_depth as f32;
                }
                [rho_st, ms / total, md / total]
            }
            FeatureKind::HistogramMean => {
                // h_s(s_a) = Σ_b ρ Δd, averaged over a; h_t(d_b) = Σ_a ρ Δs, averaged over b;
                // each normalized by the same quantity for the reference density.
                let h_s = total * self.cell.y / self.grid_s as f32;
                let h_t = total * self.cell.x / self.grid_depth as f32;
                let ref_s = rho_ref * settings.depth;
                let ref_t = rho_ref;
                [rho_st, h_s / ref_s, h_t / ref_t]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fine() -> DensitySettings {
        DensitySettings {
            grid_s: 128,
            grid_depth: 128,
            depth: 1.0,
            sigma: 0.03,
            ..Default::default()
        }
    }

    #[test]
    fn sum_of_gaussians_integrates_to_strand_count_times_mass() {
        let s = DensitySettings {
            strand_mass: 2.5,
            ..fine()
        };
        // Interior points (≥ 4σ from the depth faces); s wraps, so points near s = 0 or 1 keep
        // all their mass too.
        let points = [
            Vec2::new(0.5, 0.5),
            Vec2::new(0.01, 0.3),
            Vec2::new(0.97, 0.8),
            Vec2::new(0.3, 0.2),
            Vec2::new(1.4, 0.6),
        ];
        let g = DensityGrid::from_points(&points, &s);
        let expected = points.len() as f32 * 2.5;
        // The truncation at 4σ loses e^-8 ≈ 3.4e-4 of each mass.
        assert!(
            (g.integral() - expected).abs() < 2e-3 * expected,
            "{} vs {expected}",
            g.integral()
        );
        // A point on the outer face keeps half its mass.
        let g = DensityGrid::from_points(&[Vec2::new(0.5, 0.0)], &s);
        assert!((g.integral() - 1.25).abs() < 0.03, "{}", g.integral());
    }

    #[test]
    fn peak_value_and_gradient_direction() {
        let s = fine();
        let g = DensityGrid::from_points(&[Vec2::new(0.5 + 1.0 / 256.0, 0.5 + 1.0 / 256.0)], &s);
        // The point sits on a cell centre: the peak is m / (2πσ²).
        let peak = 1.0 / (std::f32::consts::TAU * 0.03 * 0.03);
        let (rho, grad) = g.sample(Vec2::new(0.5 + 1.0 / 256.0, 0.5 + 1.0 / 256.0));
        assert!((rho - peak).abs() < 1e-3 * peak);
        assert!(grad.length() < 1e-3 * peak);
        // Left of the strand the density grows toward it (+s).
        let (_, grad) = g.sample(Vec2::new(0.45, 0.5 + 1.0 / 256.0));
        assert!(grad.x > 0.0 && grad.y.abs() < 1e-3 * grad.x);
    }

    #[test]
    fn features_by_hand() {
        let s = DensitySettings::default();
        let empty = DensityGrid::from_points(&[], &s);
        assert_eq!(empty.features(&s), [0.0, 0.5, 0.5]);
        // 24 strands spread over the interior: ρ_st ≈ 1 (all their mass inside).
        let pts: Vec<Vec2> = (0..24)
            .map(|i| Vec2::new((i % 8) as f32 / 8.0 + 0.06, 0.2 + 0.05 * (i / 8) as f32))
            .collect();
        let g = DensityGrid::from_points(&pts, &s);
        let f = g.features(&s);
        assert!((f[0] - 1.0).abs() < 0.01, "{f:?}");
        // Mean depth 0.25 of a depth of 0.5: ρ_t = 0.5; mean s = 0.5 + 0.06 - 1/16 ≈ 0.4975.
        assert!(
            (f[2] - 0.5).abs() < 0.01 && (f[1] - 0.4975).abs() < 0.01,
            "{f:?}"
        );
        // Mass near the outer face and to the left.
        let g = DensityGrid::from_points(&[Vec2::new(0.25, 0.1)], &s);
        let f = g.features(&s);
        assert!(
            (f[1] - 0.25).abs() < 0.01 && (f[2] - 0.2).abs() < 0.01,
            "{f:?}"
        );
        let lit = DensitySettings {
            feature_kind: FeatureKind::HistogramMean,
            ..s
        };
        let f = g.features(&lit);
        assert!(
            (f[1] - f[0]).abs() < 1e-5 && (f[2] - f[0]).abs() < 1e-5,
            "literal reading: {f:?}"
        );
    }

    #[test]
    fn settings_are_checked() {
        assert!(DensitySettings::default().validate().is_ok());
        assert!(
            DensitySettings {
                sigma: 0.5,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            DensitySettings {
                grid_s: 1,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            DensitySettings {
                strand_mass: f32::NAN,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
