//! Hair rendering intermediate results (HRIRs): planar ray tracing of a generalized sector under
//! a view and a light azimuth (Xu et al. 2006, §4 and §5.1).
//!
//! An HRIR is a pair of 1D arrays over the sector's `s` axis ([`crate::density`]): the reflectance
//! `r̂e` and the opacity `α̂` accumulated along the view rays by equation 5.
//!
//! # Implementation
//!
//! - **Angles.** Both directions lie in the sector's plane (§4). An azimuth `θ` is measured from
//!   the layer's outward normal toward `+s`: a direction `(sin θ, -cos θ)` in canonical `(s, d)`
//!   coordinates (`d` grows inward). The view azimuth `θ_v` is that of the vector toward the
//!   eye, the light azimuth `θ_l` that of the vector toward the light. Bins cover the full circle,
//!   `θ = -π + 2πa / count`, so `θ = 0` (head-on) is a bin for even counts; `|θ_v| > π/2` means the
//!   eye sees the layer from the core's side (the far half of a cluster), and its rays cross the
//!   shell from the inner face to the outer one.
//! - **Rays.** Pixel `j` is the point `s_j = (j + ½) / pixels` of the outer face, where the
//!   online phase's layer mesh lies (§6.1). Its ray runs along `-v` through that point, from where
//!   it enters the sector to where it leaves it, at most [`HrirSettings::max_path`] long (grazing
//!   rays), periodic in `s`. It is sampled at the midpoints of steps of one grid cell: the grid
//!   points the ray meets (§5.1), with bilinear interpolation between them.
//! - **Opacity** is proportional to density (§5.1): `α(h) = min(1, κ ρ(h) Δ)` with
//!   `κ` = [`HrirSettings::opacity_scale`] and the step length `Δ`.
//! - **Reflectance** is Phong with the normal `n = -∇ρ / |∇ρ|` (the paper's "gradient of the local
//!   hair micro-density", signed to point out of the strands, toward lower density), or `v` where
//!   the gradient vanishes (`|∇ρ| σ ≤ 10⁻³ ρ`, inside uniform hair): `re = k_a + k_d max(0, n·l) + k_s max(0, r·v)^p`, `r = 2(n·l)n - l`.
//!   With `k_a + k_d + k_s ≤ 1`, `re ≤ 1` and so `r̂e ≤ α̂ ≤ 1`.
//! - **Accumulation** is equation 5 ([`accumulate`]), front to back, and stops when
//!   `α̂ ≥` [`HrirSettings::opacity_cutoff`] or the ray leaves the sector. No light attenuation
//!   enters an HRIR: shadows are the online phase's (§6.4). So `α̂` does not depend on the
//!   light, and a sector's HRIRs share one alpha array per view azimuth.
//! - **Anti-aliasing** (§5.1): both arrays are smoothed with a periodic 1D Gaussian of standard
//!   deviation [`HrirSettings::smoothing_ratio`] (the paper's 1.5) times the density's `σ`.
//! - **Stored reflectance** is equation 5's `r̂e`, which already carries the ray's opacity
//!   (premultiplied). Equation 14 multiplies by `α` again; [`straight_reflectance`] divides it
//!   out for a renderer that wants straight color.

use std::f32::consts::{PI, TAU};

use glam::Vec2;
use tress_hair::rng::Rng;

use crate::density::{DensityGrid, DensitySettings};
use crate::error::{SatfError, param};

/// Phong coefficients of the planar ray tracer (§5.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongSettings {
    /// Ambient term `k_a`. Default 0.05.
    pub ambient: f32,
    /// Diffuse coefficient `k_d`. Default 0.65.
    pub diffuse: f32,
    /// Specular coefficient `k_s`. Default 0.3.
    pub specular: f32,
    /// Specular exponent `p`. Default 20.
    pub exponent: f32,
}

impl Default for PhongSettings {
    fn default() -> Self {
        PhongSettings {
            ambient: 0.05,
            diffuse: 0.65,
            specular: 0.3,
            exponent: 20.0,
        }
    }
}

/// Settings of the planar ray tracer and of the HRIR layout.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HrirSettings {
    /// Samples (pixels) of each HRIR along `s`. Default 16.
    pub pixels: u32,
    /// View azimuth bins over the full circle. Default 16.
    pub view_angles: u32,
    /// Light azimuth bins over the full circle. Default 16.
    pub light_angles: u32,
    /// `κ` in `α = min(1, κ ρ Δ)`. Default 0.1.
    pub opacity_scale: f32,
    /// A ray stops when its opacity reaches this. Default 0.99.
    pub opacity_cutoff: f32,
    /// Longest ray path through the sector, in sector widths. Default 2.
    pub max_path: f32,
    /// Smoothing `σ` over the density's `σ` (§5.1: 1.5).
    pub smoothing_ratio: f32,
    /// Reflectance model.
    pub phong: PhongSettings,
}

impl Default for HrirSettings {
    fn default() -> Self {
        HrirSettings {
            pixels: 16,
            view_angles: 16,
            light_angles: 16,
            opacity_scale: 0.1,
            opacity_cutoff: 0.99,
            max_path: 2.0,
            smoothing_ratio: 1.5,
            phong: PhongSettings::default(),
        }
    }
}

impl HrirSettings {
    /// Check ranges: 2..=256 pixels, 1..=256 bins each way, positive finite scales, cutoff in
    /// `(0, 1]`, smoothing ratio in `[0, 10]`, Phong coefficients non-negative with
    /// `k_a + k_d + k_s ≤ 1` and exponent in `[1, 1000]`.
    pub fn validate(&self) -> Result<(), SatfError> {
        if !(2..=256).contains(&self.pixels) {
            return Err(param(format!(
                "HRIR pixels must be in 2..=256, got {}",
                self.pixels
            )));
        }
        for (name, n) in [
            ("view_angles", self.view_angles),
            ("light_angles", self.light_angles),
        ] {
            if !(1..=256).contains(&n) {
                return Err(param(format!("{name} must be in 1..=256, got {n}")));
            }
        }
        let pos = |x: f32| x.is_finite() && x > 0.0;
        if !pos(self.opacity_scale) || !pos(self.max_path) || self.max_path > 100.0 {
            return Err(param(
                "opacity_scale must be positive and max_path in (0, 100]",
            ));
        }
        if !(self.opacity_cutoff > 0.0 && self.opacity_cutoff <= 1.0) {
            return Err(param(format!(
                "opacity_cutoff must be in (0, 1], got {}",
                self.opacity_cutoff
            )));
        }
        if !(0.0..=10.0).contains(&self.smoothing_ratio) {
            return Err(param(format!(
                "smoothing_ratio must be in [0, 10], got {}",
                self.smoothing_ratio
            )));
        }
        let p = self.phong;
        let coeffs = [p.ambient, p.diffuse, p.specular];
        if coeffs.iter().any(|c| c.is_nan() || *c < 0.0) || coeffs.iter().sum::<f32>() > 1.0 + 1e-6
        {
            return Err(param(
                "Phong coefficients must be non-negative with k_a + k_d + k_s <= 1",
            ));
        }
        if !(1.0..=1000.0).contains(&p.exponent) {
            return Err(param(format!(
                "Phong exponent must be in [1, 1000], got {}",
                p.exponent
            )));
        }
        Ok(())
    }
}

/// The azimuth of bin `a` of `count` bins over the full circle: `-π + 2πa / count`.
pub fn bin_angle(a: u32, count: u32) -> f32 {
    -PI + TAU * a as f32 / count as f32
}

/// The nearest of `count` bins to azimuth `theta` (any real angle; wraps).
pub fn angle_bin(theta: f32, count: u32) -> u32 {
    let x = ((theta + PI) / TAU * count as f32).round();
    (x.rem_euclid(count as f32) as u32).min(count - 1)
}

/// The in-plane unit vector of azimuth `theta`: `(sin θ, -cos θ)` in `(s, d)`.
pub fn azimuth_dir(theta: f32) -> Vec2 {
    Vec2::new(theta.sin(), -theta.cos())
}

/// Equation 5: one sample `(re, α)` accumulated into a ray's `(r̂e, α̂)`:
/// `r̂e += α re (1 - α̂)`, `α̂ += α (1 - α̂)`.
pub fn accumulate(acc: (f32, f32), re: f32, alpha: f32) -> (f32, f32) {
    let (re_acc, a_acc) = acc;
    (
        re_acc + alpha * re * (1.0 - a_acc),
        a_acc + alpha * (1.0 - a_acc),
    )
}

/// `r̂e / α̂`, the straight (not premultiplied) reflectance of an HRIR value; 0 where `α̂ = 0`.
pub fn straight_reflectance(re: f32, alpha: f32) -> f32 {
    if alpha > 1e-6 {
        (re / alpha).min(1.0)
    } else {
        0.0
    }
}

/// Phong reflectance at a point of normal `n` (unit, or zero to use `v`) lit from `l`, seen from `v`.
pub fn phong(p: &PhongSettings, n: Vec2, l: Vec2, v: Vec2) -> f32 {
    let n = if n == Vec2::ZERO { v } else { n };
    let nl = n.dot(l);
    let r = 2.0 * nl * n - l;
    let spec = if p.specular > 0.0 {
        r.dot(v).max(0.0).powf(p.exponent)
    } else {
        0.0
    };
    p.ambient + p.diffuse * nl.max(0.0) + p.specular * spec
}

/// The HRIRs of one sector: `alpha[view][pixel]` and `re[view][light][pixel]`, flattened.
#[derive(Clone, Debug, PartialEq)]
pub struct SectorHrirs {
    /// `α̂`, `view_angles × pixels`.
    pub alpha: Vec<f32>,
    /// `r̂e`, `view_angles × light_angles × pixels`.
    pub re: Vec<f32>,
}

/// One ray's samples: weight `α_k (1 - α̂_before)` and unit normal (zero: none).
fn march(
    grid: &DensityGrid,
    density: &DensitySettings,
    h: &HrirSettings,
    s0: f32,
    theta_v: f32,
    steps: &mut Vec<(f32, Vec2)>,
) -> f32 {
    steps.clear();
    let v = azimuth_dir(theta_v);
    let dir = -v;
    let cell = density.cell();
    let step = cell.x.min(cell.y);
    let depth = density.depth;
    let o = Vec2::new(s0, 0.0);
    // The path [lam0, lam0 + len] along dir, front (eye side) first.
    let (lam0, len) = if dir.y > 1e-4 {
        (0.0, (depth / dir.y).min(h.max_path))
    } else if dir.y < -1e-4 {
        let len = (depth / -dir.y).min(h.max_path);
        (-len, len)
    } else {
        (0.0, h.max_path)
    };
    let n_steps = (len / step).ceil().max(1.0) as usize;
    let dl = len / n_steps as f32;
    let mut a_acc = 0.0f32;
    for k in 0..n_steps {
        let x = o + dir * (lam0 + (k as f32 + 0.5) * dl);
        let (rho, grad) = grid.sample(x);
        let alpha = (h.opacity_scale * rho * dl).clamp(0.0, 1.0);
        if alpha <= 0.0 {
            continue;
        }
        // The gradient is "zero" relative to ρ/σ, the scale of a single strand's gradient.
        let n = if grad.length() * density.sigma > 1e-3 * rho {
            -grad.normalize()
        } else {
            Vec2::ZERO
        };
        steps.push((alpha * (1.0 - a_acc), n));
        a_acc += alpha * (1.0 - a_acc);
        if a_acc >= h.opacity_cutoff {
            break;
        }
    }
    a_acc
}

/// Planar ray tracing of one sector's density under every view and light bin, smoothed (see the
/// module docs). Settings must be valid.
pub fn trace_sector(
    grid: &DensityGrid,
    density: &DensitySettings,
    h: &HrirSettings,
) -> SectorHrirs {
    let (np, nv, nl) = (
        h.pixels as usize,
        h.view_angles as usize,
        h.light_angles as usize,
    );
    let mut alpha = vec![0.0f32; nv * np];
    let mut re = vec![0.0f32; nv * nl * np];
    let lights: Vec<Vec2> = (0..h.light_angles)
        .map(|b| azimuth_dir(bin_angle(b, h.light_angles)))
        .collect();
    let mut steps = Vec::new();
    for a in 0..nv {
        let theta_v = bin_angle(a as u32, h.view_angles);
        let v = azimuth_dir(theta_v);
        for j in 0..np {
            let s0 = (j as f32 + 0.5) / np as f32;
            alpha[a * np + j] = march(grid, density, h, s0, theta_v, &mut steps);
            for (b, l) in lights.iter().enumerate() {
                re[(a * nl + b) * np + j] = steps
                    .iter()
                    .map(|(w, n)| w * phong(&h.phong, *n, *l, v))
                    .sum();
            }
        }
    }
    let sigma_px = h.smoothing_ratio * density.sigma * np as f32;
    let mut scratch = Vec::new();
    for row in alpha.chunks_mut(np).chain(re.chunks_mut(np)) {
        smooth_periodic(row, sigma_px, &mut scratch);
    }
    SectorHrirs { alpha, re }
}

/// Periodic 1D Gaussian smoothing of standard deviation `sigma` samples (none below 10⁻³).
pub fn smooth_periodic(values: &mut [f32], sigma: f32, scratch: &mut Vec<f32>) {
    if sigma.is_nan() || sigma <= 1e-3 || values.is_empty() {
        return;
    }
    let n = values.len() as isize;
    let radius = (3.0 * sigma).ceil() as isize;
    let weights: Vec<f32> = (-radius..=radius)
        .map(|k| (-0.5 * (k as f32 / sigma).powi(2)).exp())
        .collect();
    let total: f32 = weights.iter().sum();
    scratch.clear();
    scratch.extend_from_slice(values);
    for (i, out) in values.iter_mut().enumerate() {
        let mut acc = 0.0;
        for (w, k) in weights.iter().zip(-radius..=radius) {
            acc += w * scratch[(i as isize + k).rem_euclid(n) as usize];
        }
        *out = acc / total;
    }
}

/// A random generalized sector (§5): the crossing points of up to `max_strands` strands, a
/// random mixture of a uniform spread (denser toward one face by a random power law) and up to
/// three Gaussian clumps, so the features of the samples cover the range of real sectors.
pub fn random_sector(rng: &mut Rng, density: &DensitySettings, max_strands: u32) -> Vec<Vec2> {
    let n = rng.below(u64::from(max_strands) + 1) as usize;
    let clumped = rng.f32();
    let clumps: Vec<(Vec2, f32)> = (0..1 + rng.below(3))
        .map(|_| {
            (
                Vec2::new(rng.f32(), rng.f32() * density.depth),
                rng.range(0.03, 0.15),
            )
        })
        .collect();
    let gamma = rng.range(-1.2, 1.2).exp();
    (0..n)
        .map(|_| {
            if rng.f32() < clumped {
                let (c, sd) = clumps[rng.below(clumps.len() as u64) as usize];
                let p = c + sd * Vec2::new(rng.normal(), rng.normal());
                Vec2::new(p.x.rem_euclid(1.0), p.y.clamp(0.0, density.depth))
            } else {
                Vec2::new(rng.f32(), density.depth * rng.f32().powf(gamma))
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equation_5_by_hand() {
        // Samples (re, α): (0.5, 0.5), (1.0, 0.5), (0.2, 1.0).
        // After 1: r̂e = 0.25, α̂ = 0.5. After 2: r̂e = 0.25 + 0.5·1·0.5 = 0.5, α̂ = 0.75.
        // After 3: r̂e = 0.5 + 1·0.2·0.25 = 0.55, α̂ = 1.
        let mut acc = (0.0, 0.0);
        acc = accumulate(acc, 0.5, 0.5);
        assert_eq!(acc, (0.25, 0.5));
        acc = accumulate(acc, 1.0, 0.5);
        assert_eq!(acc, (0.5, 0.75));
        acc = accumulate(acc, 0.2, 1.0);
        assert!((acc.0 - 0.55).abs() < 1e-6 && acc.1 == 1.0);
    }

    #[test]
    fn uniform_slab_matches_the_closed_form() {
        // A slab of constant density (strands every cell, exactly uniform after summation is not
        // needed: build the grid from a dense lattice) seen head-on: each step has the same α, so
        // α̂ = 1 - (1 - α)^n, and with the normal undefined (zero gradient) re = k_a + k_d + k_s
        // when l = v (n = v, r = v).
        let d = DensitySettings {
            grid_s: 16,
            grid_depth: 8,
            depth: 0.5,
            sigma: 0.08,
            ..Default::default()
        };
        let pts: Vec<Vec2> = (0..16 * 40)
            .map(|i| Vec2::new((i % 16) as f32 / 16.0, -0.6 + 1.7 * (i / 16) as f32 / 39.0))
            .collect();
        let grid = DensityGrid::from_points(&pts, &d);
        let h = HrirSettings {
            pixels: 4,
            view_angles: 2,
            light_angles: 2,
            smoothing_ratio: 0.0,
            opacity_cutoff: 1.0,
            opacity_scale: 0.01,
            ..Default::default()
        };
        let out = trace_sector(&grid, &d, &h);
        // View bin 1 is θ = 0 (head-on). Its rays cross 8 cells of Δ = 1/16.
        let (rho, grad) = grid.sample(Vec2::new(0.3, 0.25));
        assert!(grad.length() < 1e-3 * rho, "uniform interior");
        let alpha = (0.01 * rho / 16.0).min(1.0);
        let expected = 1.0 - (1.0 - alpha).powi(8);
        for j in 0..4 {
            assert!(
                (out.alpha[4 + j] - expected).abs() < 0.01,
                "{} vs {expected}",
                out.alpha[4 + j]
            );
            // Light bin 1 is θ_l = 0 = θ_v.
            let re = out.re[(2 + 1) * 4 + j];
            assert!(
                (re - expected).abs() < 0.01,
                "re {re} vs {expected} (k_a + k_d + k_s = 1)"
            );
        }
    }

    #[test]
    fn empty_sector_is_transparent_and_bins_wrap() {
        let d = DensitySettings::default();
        let grid = DensityGrid::from_points(&[], &d);
        let out = trace_sector(&grid, &d, &HrirSettings::default());
        assert!(out.alpha.iter().chain(&out.re).all(|x| *x == 0.0));
        assert_eq!(angle_bin(0.0, 16), 8);
        assert_eq!(angle_bin(PI - 0.01, 16), 0);
        assert_eq!(angle_bin(-PI, 16), 0);
        assert_eq!(angle_bin(bin_angle(5, 16) + 0.1, 16), 5);
        assert_eq!(angle_bin(bin_angle(5, 16) + TAU, 16), 5);
    }

    #[test]
    fn smoothing_keeps_the_mean_and_a_lit_side_is_brighter() {
        let mut v = vec![0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        smooth_periodic(&mut v, 1.0, &mut Vec::new());
        assert!((v.iter().sum::<f32>() - 4.0).abs() < 1e-5);
        assert!(v[2] < 4.0 && v[1] > 0.0 && (v[1] - v[3]).abs() < 1e-6);
        // One strand in the middle of the sector, seen head-on, lit from +s: the +s half of the
        // strand faces the light, so the pixels right of the centre reflect more.
        let d = DensitySettings::default();
        let grid = DensityGrid::from_points(&[Vec2::new(0.5, 0.25)], &d);
        let h = HrirSettings {
            light_angles: 4,
            smoothing_ratio: 0.0,
            ..Default::default()
        };
        let out = trace_sector(&grid, &d, &h);
        let light = angle_bin(PI / 2.0, 4);
        let row = &out.re[(8 * 4 + light as usize) * 16..][..16];
        assert!(row[9] > row[6], "{row:?}");
    }
}
