//! The HRIR database (HRIR-DB) and the semantics-aware texture function
//! `SATF(b, v, l) = HRIR(ρ_feature(b), θ_v(b), θ_l(b))` (Xu et al. 2006, §4, equation 4; §5;
//! §6.2).
//!
//! [`bake`] draws [`BakeSettings::samples`] random generalized sectors
//! ([`crate::hrir::random_sector`]), computes each one's density grid and feature vector and ray
//! traces it under every view and light bin ([`crate::hrir::trace_sector`]), in parallel on rayon's
//! threads. Sample `i` uses the random stream `Rng::stream(seed, i)`, so the database does not
//! depend on scheduling. Values are stored as 16-bit unsigned normalized integers.
//!
//! # Lookup and the online phase's CPU twins (§6.2)
//!
//! - [`Database::nearest_sample`]: the sample whose features are nearest, by the weighted distance
//!   of [`LookupSettings::feature_weights`]; angles go to the nearest bin ([`crate::hrir::angle_bin`]).
//! - [`params_distance`] and [`is_uniform`]: equation 6, `||Params(b⊤) - Params(b⊥)|| < k_threshold`,
//!   with `Params = (ρ_feature, θ_v, θ_l)`. A choice: the norm weighs features by
//!   `feature_weights` and angles by `angle_weight` per radian (default: one bin of 16 counts 1),
//!   with angle differences wrapped to `[-π, π]`.
//! - [`average_params`]: `Params_ave` of §6.2.2 (feature mean, circular mean of the angles).
//! - [`interpolate`]: equation 7, `c1 (1 - γ) + c2 γ`.
//! - [`Database::hsv_maps`]: an HSV's local re-map and α-map, `rows` rows from `b⊤` (γ = 0) to `b⊥`
//!   (γ = 1): one averaged record swept along the HSV when uniform, else per-row interpolation of
//!   the two boundary records.

use std::f32::consts::{PI, TAU};
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use tress_hair::rng::Rng;

use crate::density::{DensityGrid, DensitySettings};
use crate::error::{SatfError, param};
use crate::hrir::{HrirSettings, angle_bin, random_sector, trace_sector};

/// Everything that determines a database's content.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BakeSettings {
    /// Random generalized sectors. Default 2048 (17 MiB with the default HRIR layout).
    pub samples: u32,
    /// Random seed. Default 0.
    pub seed: u64,
    /// Most strands in a random sector (uniform in `0..=max_strands`). Default 48.
    pub max_strands: u32,
    /// Density field and features (shared with the online index calculation).
    pub density: DensitySettings,
    /// Planar ray tracer and HRIR layout.
    pub hrir: HrirSettings,
}

impl Default for BakeSettings {
    fn default() -> Self {
        BakeSettings {
            samples: 2048,
            seed: 0,
            max_strands: 48,
            density: DensitySettings::default(),
            hrir: HrirSettings::default(),
        }
    }
}

/// Largest accepted sample count.
pub const MAX_SAMPLES: u32 = 1 << 20;
/// Most strands in one random sector.
pub const MAX_SECTOR_STRANDS: u32 = 4096;

impl BakeSettings {
    /// Check every range (see [`DensitySettings::validate`], [`HrirSettings::validate`]), with
    /// 1..=2^20 samples and at most 4096 strands per sector.
    pub fn validate(&self) -> Result<(), SatfError> {
        if !(1..=MAX_SAMPLES).contains(&self.samples) {
            return Err(param(format!(
                "samples must be in 1..={MAX_SAMPLES}, got {}",
                self.samples
            )));
        }
        if self.max_strands > MAX_SECTOR_STRANDS {
            return Err(param(format!(
                "max_strands must be at most {MAX_SECTOR_STRANDS}, got {}",
                self.max_strands
            )));
        }
        self.density.validate()?;
        self.hrir.validate()
    }

    /// Every setting as `(name, value)`, in file order: for mismatch messages.
    pub fn fields(&self) -> Vec<(&'static str, String)> {
        let d = &self.density;
        let h = &self.hrir;
        vec![
            ("samples", self.samples.to_string()),
            ("seed", self.seed.to_string()),
            ("max_strands", self.max_strands.to_string()),
            ("density.grid_s", d.grid_s.to_string()),
            ("density.grid_depth", d.grid_depth.to_string()),
            ("density.depth", format!("{:?}", d.depth)),
            ("density.sigma", format!("{:?}", d.sigma)),
            ("density.strand_mass", format!("{:?}", d.strand_mass)),
            (
                "density.reference_strands",
                format!("{:?}", d.reference_strands),
            ),
            ("density.feature_kind", format!("{:?}", d.feature_kind)),
            ("hrir.pixels", h.pixels.to_string()),
            ("hrir.view_angles", h.view_angles.to_string()),
            ("hrir.light_angles", h.light_angles.to_string()),
            ("hrir.opacity_scale", format!("{:?}", h.opacity_scale)),
            ("hrir.opacity_cutoff", format!("{:?}", h.opacity_cutoff)),
            ("hrir.max_path", format!("{:?}", h.max_path)),
            ("hrir.smoothing_ratio", format!("{:?}", h.smoothing_ratio)),
            ("hrir.phong.ambient", format!("{:?}", h.phong.ambient)),
            ("hrir.phong.diffuse", format!("{:?}", h.phong.diffuse)),
            ("hrir.phong.specular", format!("{:?}", h.phong.specular)),
            ("hrir.phong.exponent", format!("{:?}", h.phong.exponent)),
        ]
    }
}

/// The HRIR database: per sample, a feature vector, `α̂[view][pixel]` and `r̂e[view][light][pixel]`
/// (16-bit unorm).
#[derive(Clone, Debug, PartialEq)]
pub struct Database {
    pub(crate) settings: BakeSettings,
    pub(crate) features: Vec<[f32; 3]>,
    pub(crate) alpha: Vec<u16>,
    pub(crate) re: Vec<u16>,
}

/// An HRIR record decoded to floats: the two 1D arrays of §4.
#[derive(Clone, Debug, PartialEq)]
pub struct HrirRecord {
    /// `r̂e` per pixel (premultiplied by the ray's opacity, see [`crate::hrir`]).
    pub re: Vec<f32>,
    /// `α̂` per pixel.
    pub alpha: Vec<f32>,
}

/// The SATF parameters of a generalized sector: `Params(b) = (ρ_feature(b), θ_v(b), θ_l(b))` (§6.2.1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Params {
    /// `ρ_feature = (ρ_st, ρ_s, ρ_t)`.
    pub features: [f32; 3],
    /// View azimuth (radians, see [`crate::hrir`]).
    pub theta_v: f32,
    /// Light azimuth.
    pub theta_l: f32,
}

/// Settings of the lookup and of equation 6 (online; not stored in the database).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookupSettings {
    /// Weights of `(ρ_st, ρ_s, ρ_t)` in the feature distance. Default `[1, 1, 1]`.
    pub feature_weights: [f32; 3],
    /// Weight of an angle difference per radian in equation 6. Default `16 / 2π` (one bin of 16
    /// counts 1).
    pub angle_weight: f32,
    /// `k_threshold` of equation 6. Default 0.25.
    pub k_threshold: f32,
}

impl Default for LookupSettings {
    fn default() -> Self {
        LookupSettings {
            feature_weights: [1.0; 3],
            angle_weight: 16.0 / TAU,
            k_threshold: 0.25,
        }
    }
}

/// A unorm16 value.
pub(crate) fn to_unorm16(x: f32) -> u16 {
    (x.clamp(0.0, 1.0) * 65535.0).round() as u16
}

/// A unorm16 value decoded.
pub(crate) fn from_unorm16(x: u16) -> f32 {
    f32::from(x) / 65535.0
}

/// Bake a database (see the module docs); `progress(done, total)` is called from rayon's
/// threads after each sample.
pub fn bake(
    settings: &BakeSettings,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<Database, SatfError> {
    settings.validate()?;
    let total = settings.samples as usize;
    let h = &settings.hrir;
    let (np, nv, nl) = (
        h.pixels as usize,
        h.view_angles as usize,
        h.light_angles as usize,
    );
    let done = AtomicUsize::new(0);
    let samples: Vec<([f32; 3], Vec<u16>, Vec<u16>)> = (0..total)
        .into_par_iter()
        .map(|i| {
            let mut rng = Rng::stream(settings.seed, i as u64);
            let points = random_sector(&mut rng, &settings.density, settings.max_strands);
            let grid = DensityGrid::from_points(&points, &settings.density);
            let features = grid.features(&settings.density);
            let out = trace_sector(&grid, &settings.density, h);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(n, total);
            (
                features,
                out.alpha.into_iter().map(to_unorm16).collect(),
                out.re.into_iter().map(to_unorm16).collect(),
            )
        })
        .collect();
    let mut features = Vec::with_capacity(total);
    let mut alpha = Vec::with_capacity(total * nv * np);
    let mut re = Vec::with_capacity(total * nv * nl * np);
    for (f, a, r) in samples {
        features.push(f);
        alpha.extend(a);
        re.extend(r);
    }
    Ok(Database {
        settings: *settings,
        features,
        alpha,
        re,
    })
}

impl Database {
    /// The settings it was baked with.
    pub fn settings(&self) -> &BakeSettings {
        &self.settings
    }

    /// Number of samples (generalized sectors).
    pub fn sample_count(&self) -> usize {
        self.features.len()
    }

    /// Feature vectors of the samples (the index of §5.2).
    pub fn features(&self) -> &[[f32; 3]] {
        &self.features
    }

    /// Raw `α̂`, `samples × view_angles × pixels` unorm16 (for upload to a GPU).
    pub fn alpha_raw(&self) -> &[u16] {
        &self.alpha
    }

    /// Raw `r̂e`, `samples × view_angles × light_angles × pixels` unorm16.
    pub fn re_raw(&self) -> &[u16] {
        &self.re
    }

    /// The sample whose features are nearest to `features` (weighted squared distance; the first
    /// of equals).
    pub fn nearest_sample(&self, features: [f32; 3], weights: [f32; 3]) -> usize {
        let dist = |f: &[f32; 3]| -> f32 {
            (0..3)
                .map(|k| weights[k] * (f[k] - features[k]).powi(2))
                .sum()
        };
        let mut best = (0usize, f32::INFINITY);
        for (i, f) in self.features.iter().enumerate() {
            let d = dist(f);
            if d < best.1 {
                best = (i, d);
            }
        }
        best.0
    }

    /// The record of sample `sample` in view bin `view` and light bin `light`, or `None` when an
    /// index is out of range.
    pub fn record(&self, sample: usize, view: u32, light: u32) -> Option<HrirRecord> {
        let h = &self.settings.hrir;
        if sample >= self.sample_count() || view >= h.view_angles || light >= h.light_angles {
            return None;
        }
        let (np, nv, nl) = (
            h.pixels as usize,
            h.view_angles as usize,
            h.light_angles as usize,
        );
        let (v, l) = (view as usize, light as usize);
        let a0 = (sample * nv + v) * np;
        let r0 = ((sample * nv + v) * nl + l) * np;
        Some(HrirRecord {
            alpha: self.alpha[a0..a0 + np]
                .iter()
                .copied()
                .map(from_unorm16)
                .collect(),
            re: self.re[r0..r0 + np]
                .iter()
                .copied()
                .map(from_unorm16)
                .collect(),
        })
    }

    /// `SATF(b, v, l)` (equation 4): the record of the nearest sample and angle bins.
    pub fn lookup(&self, params: &Params, lookup: &LookupSettings) -> HrirRecord {
        let h = &self.settings.hrir;
        let sample = self.nearest_sample(params.features, lookup.feature_weights);
        let view = angle_bin(params.theta_v, h.view_angles);
        let light = angle_bin(params.theta_l, h.light_angles);
        // In range by construction: a database has at least one sample.
        self.record(sample, view, light)
            .unwrap_or_else(|| HrirRecord {
                re: vec![0.0; h.pixels as usize],
                alpha: vec![0.0; h.pixels as usize],
            })
    }

    /// An HSV's local re-map and α-map (§6.2.2; see the module docs): `rows × pixels`, row-major,
    /// row 0 at `b⊤`. `rows` is at least 1 (one row takes `γ = 1/2`).
    pub fn hsv_maps(
        &self,
        top: &Params,
        bottom: &Params,
        rows: u32,
        lookup: &LookupSettings,
    ) -> HsvMaps {
        let rows = rows.max(1) as usize;
        let uniform = is_uniform(top, bottom, lookup);
        let mut re = Vec::new();
        let mut alpha = Vec::new();
        if uniform {
            let rec = self.lookup(&average_params(top, bottom), lookup);
            for _ in 0..rows {
                re.extend_from_slice(&rec.re);
                alpha.extend_from_slice(&rec.alpha);
            }
        } else {
            let r1 = self.lookup(top, lookup);
            let r2 = self.lookup(bottom, lookup);
            for r in 0..rows {
                let gamma = if rows == 1 {
                    0.5
                } else {
                    r as f32 / (rows - 1) as f32
                };
                re.extend(interpolate(&r1.re, &r2.re, gamma));
                alpha.extend(interpolate(&r1.alpha, &r2.alpha, gamma));
            }
        }
        HsvMaps {
            uniform,
            rows: rows as u32,
            re,
            alpha,
        }
    }
}

/// An HSV's local maps (§6.2.2).
#[derive(Clone, Debug, PartialEq)]
pub struct HsvMaps {
    /// Whether equation 6 held (one averaged record) or not (interpolation by equation 7).
    pub uniform: bool,
    /// Rows from `b⊤` to `b⊥`.
    pub rows: u32,
    /// Re-map, `rows × pixels`.
    pub re: Vec<f32>,
    /// α-map, `rows × pixels`.
    pub alpha: Vec<f32>,
}

/// `a - b` wrapped to `[-π, π]`.
pub fn angle_difference(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(TAU);
    if d > PI { d - TAU } else { d }
}

/// The weighted norm `||Params(a) - Params(b)||` of equation 6 (see the module docs).
pub fn params_distance(a: &Params, b: &Params, lookup: &LookupSettings) -> f32 {
    let w = lookup.feature_weights;
    let f: f32 = (0..3)
        .map(|k| w[k] * (a.features[k] - b.features[k]).powi(2))
        .sum();
    let dv = angle_difference(a.theta_v, b.theta_v);
    let dl = angle_difference(a.theta_l, b.theta_l);
    (f + lookup.angle_weight.powi(2) * (dv * dv + dl * dl)).sqrt()
}

/// Equation 6: whether an HSV's rendering context is uniform.
pub fn is_uniform(top: &Params, bottom: &Params, lookup: &LookupSettings) -> bool {
    params_distance(top, bottom, lookup) < lookup.k_threshold
}

/// `Params_ave = (Params(b⊤) + Params(b⊥)) / 2` (§6.2.2), with the angles averaged on the circle.
pub fn average_params(a: &Params, b: &Params) -> Params {
    let mid = |x: f32, y: f32| x + 0.5 * angle_difference(y, x);
    Params {
        features: [0, 1, 2].map(|k| 0.5 * (a.features[k] + b.features[k])),
        theta_v: mid(a.theta_v, b.theta_v),
        theta_l: mid(a.theta_l, b.theta_l),
    }
}

/// Equation 7 for one value: `l(i, γ) = c1 (1 - γ) + c2 γ`.
pub fn interpolate_value(c1: f32, c2: f32, gamma: f32) -> f32 {
    c1 * (1.0 - gamma) + c2 * gamma
}

/// Equation 7 over two records' arrays (the shorter length).
pub fn interpolate(c1: &[f32], c2: &[f32], gamma: f32) -> Vec<f32> {
    c1.iter()
        .zip(c2)
        .map(|(a, b)| interpolate_value(*a, *b, gamma))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> BakeSettings {
        BakeSettings {
            samples: 24,
            hrir: HrirSettings {
                pixels: 8,
                view_angles: 4,
                light_angles: 4,
                ..Default::default()
            },
            density: DensitySettings {
                grid_s: 16,
                grid_depth: 8,
                sigma: 0.06,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    #[test]
    fn bake_is_deterministic_and_reports_progress() {
        let calls = AtomicUsize::new(0);
        let a = bake(&tiny(), |done, total| {
            assert!(done <= total && total == 24);
            calls.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(calls.load(Ordering::Relaxed), 24);
        let b = bake(&tiny(), |_, _| {}).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.alpha_raw().len(), 24 * 4 * 8);
        assert_eq!(a.re_raw().len(), 24 * 4 * 4 * 8);
        // r̂e ≤ α̂ (k_a + k_d + k_s ≤ 1), up to rounding and smoothing.
        for s in 0..24 {
            for v in 0..4 {
                for l in 0..4 {
                    let r = a.record(s, v, l).unwrap();
                    assert!(r.re.iter().zip(&r.alpha).all(|(re, al)| *re <= al + 1e-3));
                }
            }
        }
        assert!(a.record(24, 0, 0).is_none() && a.record(0, 4, 0).is_none());
        assert!(
            bake(
                &BakeSettings {
                    samples: 0,
                    ..tiny()
                },
                |_, _| {}
            )
            .is_err()
        );
    }

    #[test]
    fn nearest_lookup_finds_the_closest_features() {
        let db = Database {
            settings: tiny(),
            features: vec![
                [0.0, 0.5, 0.5],
                [1.0, 0.5, 0.5],
                [1.0, 0.2, 0.9],
                [2.0, 0.5, 0.5],
            ],
            alpha: (0..4 * 4 * 8).map(|i| i as u16).collect(),
            re: (0..4 * 4 * 4 * 8).map(|i| i as u16).collect(),
        };
        let w = [1.0; 3];
        assert_eq!(db.nearest_sample([0.1, 0.5, 0.5], w), 0);
        assert_eq!(db.nearest_sample([1.1, 0.25, 0.8], w), 2);
        assert_eq!(db.nearest_sample([1.4, 0.5, 0.5], w), 1);
        assert_eq!(db.nearest_sample([9.0, 0.0, 0.0], w), 3);
        // Weights: ignoring ρ_st, [1.9, 0.2, 0.9] is sample 2.
        assert_eq!(db.nearest_sample([1.9, 0.2, 0.9], [0.0, 1.0, 1.0]), 2);
        // Lookup: sample 2, view θ = 0 (bin 2 of 4), light θ = π/2 (bin 3).
        let rec = db.lookup(
            &Params {
                features: [1.0, 0.2, 0.9],
                theta_v: 0.1,
                theta_l: 1.5,
            },
            &LookupSettings::default(),
        );
        let a0 = (2 * 4 + 2) * 8;
        let r0 = ((2 * 4 + 2) * 4 + 3) * 8;
        assert_eq!(rec.alpha[0], from_unorm16(a0 as u16));
        assert_eq!(rec.re[7], from_unorm16((r0 + 7) as u16));
    }

    #[test]
    fn equation_7_and_uniformity() {
        assert_eq!(
            interpolate(&[0.0, 1.0, 0.5], &[1.0, 0.0, 0.5], 0.25),
            vec![0.25, 0.75, 0.5]
        );
        assert_eq!(interpolate_value(2.0, 4.0, 0.0), 2.0);
        assert_eq!(interpolate_value(2.0, 4.0, 1.0), 4.0);
        let l = LookupSettings::default();
        let a = Params {
            features: [1.0, 0.5, 0.5],
            theta_v: PI - 0.05,
            theta_l: 0.0,
        };
        let b = Params {
            features: [1.1, 0.5, 0.5],
            theta_v: -PI + 0.05,
            theta_l: 0.0,
        };
        // Features differ by 0.1, view angles by 0.1 rad across ±π: sqrt(0.01 + (0.1 · 16/2π)²).
        let expected = (0.01f32 + (0.1 * 16.0 / TAU).powi(2)).sqrt();
        assert!((params_distance(&a, &b, &l) - expected).abs() < 1e-4);
        assert!(!is_uniform(&a, &b, &l));
        assert!(is_uniform(&a, &a, &l));
        let m = average_params(&a, &b);
        assert!(
            angle_difference(m.theta_v, PI).abs() < 1e-5 && (m.features[0] - 1.05).abs() < 1e-6
        );
    }

    #[test]
    fn hsv_maps_sweep_or_interpolate() {
        let db = bake(&tiny(), |_, _| {}).unwrap();
        let l = LookupSettings::default();
        let top = Params {
            features: db.features()[3],
            theta_v: 0.0,
            theta_l: 0.5,
        };
        let maps = db.hsv_maps(&top, &top, 3, &l);
        assert!(maps.uniform);
        let rec = db.lookup(&top, &l);
        assert_eq!(&maps.re[16..24], &rec.re[..]);
        let bottom = Params {
            features: [2.0, 0.1, 0.1],
            theta_v: 1.5,
            theta_l: -2.0,
        };
        let maps = db.hsv_maps(&top, &bottom, 3, &l);
        assert!(!maps.uniform);
        let r2 = db.lookup(&bottom, &l);
        assert_eq!(&maps.alpha[..8], &rec.alpha[..]);
        assert_eq!(&maps.alpha[16..], &r2.alpha[..]);
        for j in 0..8 {
            assert!((maps.re[8 + j] - 0.5 * (rec.re[j] + r2.re[j])).abs() < 1e-6);
        }
    }
}
