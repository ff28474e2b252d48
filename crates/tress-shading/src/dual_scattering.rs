//! Multiple scattering for the real-time Marschner lobes: a dual-scattering approximation after
//! Zinke et al. 2008 ("Dual Scattering Approximation for Fast Multiple Scattering in Hair", §4),
//! driven by the number of strands between the shaded point and the light. WGSL twin:
//! `dual_scattering_lighting` in `shaders/common/marschner.wgsl`.
//!
//! # Why this and not Karis's term
//!
//! Karis 2016 adds a wrapped-diffuse "multiple scattering" tinted by the shadow value, a look
//! with no input that says how much hair the light crossed. Every tress technique already knows
//! that number: ADSM's `d · r` strands in front, the volume's strand count along the shadow ray.
//! Dual scattering turns it into the light that reaches the point *through* the hair (global
//! forward scattering) plus the light the hair around the point scatters back (local
//! backscattering), which is what makes light-coloured hair bright inside and dark hair dark.
//!
//! # The model (per light)
//!
//! ```text
//! L = π · c_light · (F_direct + F_scatter)
//! F_direct  = V · (S(l, v) + d_b · f_back(σb²) · (1 + cos φ) / 2π)
//! F_scatter = max(T_f - V, 0) · d_f · (S_G(σ̄f²) + d_b · f_back(σb² + σ̄f²) / 2π)
//! T_f = a_f^n,   σ̄f² = n · βf²                                        (Zinke §4.1)
//! f_back(σ²) = A_b · g(σ; sin θi + sin θo - Δb)
//! A_b = a_b a_f² / (1 - a_f²) + a_b³ a_f² / (1 - a_f²)³                (Zinke §4.2)
//! Δb  = α_b (1 - 2 a_b² / (1 - a_f²)²) + α_f (2 (1 - a_f²)² + 4 a_f² a_b²) / (1 - a_f²)³
//! σb  = (1 + d_b a_f²) (a_b sqrt(2βf² + βb²) + a_b³ sqrt(2βf² + 3βb²)) / (a_b + a_b³ (2βf + 3βb))
//! S_G = Σ_p g(sqrt(β_p² + σ̄f²); sin θi + sin θo - α_p) · ⟨N_p A_p⟩_φ
//! ```
//!
//! `a_f`, `βf²`, `A_b`, `Δb` and `σb²` are read at the light's `sin θi` ([`DualScattering::at`]);
//! `n` is the number of strands between the point and the light, `V` the fraction of the light
//! that arrives unscattered (the technique's shadow visibility), `S` the single scattering of
//! [`crate::marschner`], `d_f = d_b = 0.7` Zinke's density factors. The averages come from the
//! lobes themselves ([`DualScattering::from_marschner`], on the CPU once per material): `a_f`,
//! `a_b` are the energies `S` scatters into the forward (`cos φ < 0`) and backward half, `α_f`,
//! `β_f²` (`α_b`, `β_b²`) the lobes' shifts and variances weighted by their share of it, and
//! `⟨N_p A_p⟩_φ` each lobe's azimuthal energy over `2π`.
//!
//! # Departures from Zinke (and why)
//!
//! - **Normalization**: every term is per solid angle like Karis's lobes (`∫ f dω` is the
//!   energy; no `cos θi`, no `1/cos² θd`), so `∫ f_back dω = A_b` less the part of the
//!   Gaussian beyond the reachable `sin θi + sin θo` (`backscatter_lobe_holds_a_b`).
//! - **A small table**: Zinke tabulates `a_f`, `a_b`, ... over `θ` finely; here 16 entries over the
//!   light's `sin θi`, linearly interpolated, fit in one 1072-byte uniform struct per material.
//!   They vary a lot (brown hair's red `a_f` falls from 0.71 at `θi = 0` to 0.48 at 60°) but
//!   smoothly: the table reproduces the integrals at other angles within 3%
//!   (`table_interpolates_the_integrals`).
//! - **Azimuth of the spread light**: Zinke spreads the forward-scattered light uniformly over the
//!   forward half circle and convolves each lobe's `N_p` with it; here the spread light is taken
//!   as isotropic in azimuth (the `⟨N_p A_p⟩_φ` constants), and the direct backscatter lobe uses
//!   the smooth `(1 + cos φ) / 2π` instead of a uniform back half (same integral, no seam).

use std::f32::consts::{PI, TAU};

use glam::{Vec3, Vec4};

use crate::marschner::{
    HairAngles, Marschner, hair_angles, hair_gaussian, marschner_r, marschner_trt, marschner_tt,
};

/// Zinke et al. 2008's forward density factor `d_f`.
pub const DENSITY_FORWARD: f32 = 0.7;
/// Zinke et al. 2008's backward density factor `d_b`.
pub const DENSITY_BACKWARD: f32 = 0.7;
/// `a_f` is clamped below this so `1 - a_f²` stays away from 0.
const MAX_A_F: f32 = 0.98;

/// Light angles tabulated by [`DualScattering`]: `sin θi` at the midpoints of 16 equal steps of
/// `[-1, 1]`.
pub const DS_TABLE: usize = 16;

/// The per-material averages of the dual-scattering approximation, tabulated over the light's
/// `sin θi` ([`DS_TABLE`] entries, read with [`DualScattering::at`]). Mirrors the WGSL `struct
/// DualScattering` field for field (1072 bytes: four `array<vec4f, 16>` and three `vec4f`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DualScattering {
    /// Per light angle: the average forward attenuation `a_f` (rgb) and forward variance `βf²`
    /// (w, in `(sin θi + sin θo)²`).
    pub a_f: [Vec4; DS_TABLE],
    /// Per light angle: the average backscattering attenuation `A_b` (rgb; w 0).
    pub a_b: [Vec4; DS_TABLE],
    /// Per light angle: the average backscattering shift `Δb` (rgb; w 0).
    pub delta_b: [Vec4; DS_TABLE],
    /// Per light angle: the average backscattering variance `σb²` (rgb; w 0).
    pub sigma_b2: [Vec4; DS_TABLE],
    /// `(⟨N_R A_R⟩_φ, d_f, d_b, 0)`: the R lobe's azimuthal energy over `2π` and Zinke's
    /// forward and backward density factors.
    pub params: Vec4,
    /// `⟨N_TT A_TT⟩_φ` (rgb; w 0).
    pub tt_avg: Vec4,
    /// `⟨N_TRT A_TRT⟩_φ` (rgb; w 0).
    pub trt_avg: Vec4,
}

/// [`DualScattering`] at one light angle ([`DualScattering::at`]); mirrors the WGSL `struct
/// DualScatteringAt`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DualScatteringAt {
    /// Average forward attenuation `a_f`.
    pub a_f: Vec3,
    /// Forward variance `βf²`.
    pub beta_f2: f32,
    /// Backscattering attenuation `A_b`.
    pub a_b: Vec3,
    /// Backscattering shift `Δb`.
    pub delta_b: Vec3,
    /// Backscattering variance `σb²`.
    pub sigma_b2: Vec3,
}

/// Zinke et al. 2008 §4.2: the backscattering attenuation `A_b` of the hair around a point, from
/// the average forward and backward attenuations (paths with one and three backward events).
pub fn backscatter_attenuation(a_f: f32, a_b: f32) -> f32 {
    let af2 = a_f * a_f;
    let one = 1.0 - af2;
    a_b * af2 / one + a_b.powi(3) * af2 / one.powi(3)
}

/// Zinke et al. 2008 §4.2: the average longitudinal shift `Δb` of the backscattered light.
pub fn backscatter_shift(a_f: f32, a_b: f32, alpha_f: f32, alpha_b: f32) -> f32 {
    let af2 = a_f * a_f;
    let ab2 = a_b * a_b;
    let one = 1.0 - af2;
    alpha_b * (1.0 - 2.0 * ab2 / (one * one))
        + alpha_f * (2.0 * one * one + 4.0 * af2 * ab2) / one.powi(3)
}

/// Zinke et al. 2008 §4.2: the standard deviation `σb` of the backscattered light.
pub fn backscatter_deviation(a_f: f32, a_b: f32, beta_f: f32, beta_b: f32) -> f32 {
    let ab3 = a_b.powi(3);
    let bf2 = beta_f * beta_f;
    let bb2 = beta_b * beta_b;
    let num = a_b * (2.0 * bf2 + bb2).sqrt() + ab3 * (2.0 * bf2 + 3.0 * bb2).sqrt();
    let den = a_b + ab3 * (2.0 * beta_f + 3.0 * beta_b);
    (1.0 + DENSITY_BACKWARD * a_f * a_f) * num / den.max(1e-12)
}

/// Energies of one light direction: per lobe, the forward and backward halves.
#[derive(Clone, Copy, Default)]
struct HalfEnergies {
    forward: [Vec3; 3],
    backward: [Vec3; 3],
    /// `∫ N_p A_p dφ` per lobe at this light direction, averaged over the eye's `θo`.
    azimuthal: [Vec3; 3],
}

/// `∫ lobe_p dω_v` split into the two azimuthal halves, for the light at `sin θi = sin_theta_i`;
/// midpoint rule in `(sin θo, φ)` (`dω = d(sin θ) dφ`).
fn half_energies(m: &Marschner, sin_theta_i: f32) -> HalfEnergies {
    const N_S: usize = 96;
    const N_PHI: usize = 96;
    let t = Vec3::X;
    let cos_i = (1.0 - sin_theta_i * sin_theta_i).max(0.0).sqrt();
    let l = Vec3::new(sin_theta_i, cos_i, 0.0);
    let mut e = HalfEnergies::default();
    let ds = 2.0 / N_S as f32;
    let dphi = TAU / N_PHI as f32;
    for i in 0..N_S {
        let s = -1.0 + (i as f32 + 0.5) * ds;
        let c = (1.0 - s * s).max(0.0).sqrt();
        for j in 0..N_PHI {
            let phi = (j as f32 + 0.5) * dphi;
            let v = Vec3::new(s, c * phi.cos(), c * phi.sin());
            let a = hair_angles(t, l, v);
            let lobes = [
                Vec3::splat(marschner_r(m, &a)),
                marschner_tt(m, &a),
                marschner_trt(m, &a),
            ];
            let half = if a.cos_phi < 0.0 {
                &mut e.forward
            } else {
                &mut e.backward
            };
            for p in 0..3 {
                half[p] += lobes[p] * (ds * dphi);
            }
        }
    }
    // ⟨N_p A_p⟩: the azimuthal integral with the longitudinal Gaussian taken out, at θo = -θi
    // (where each lobe's energy concentrates) over the eye azimuth.
    for j in 0..N_PHI {
        let phi = (j as f32 + 0.5) * dphi;
        let v = Vec3::new(-sin_theta_i, cos_i * phi.cos(), cos_i * phi.sin());
        let a = hair_angles(t, l, v);
        let unit =
            |beta: f32, shift: f32| hair_gaussian(beta, a.sin_theta_i + a.sin_theta_o - shift);
        let shifts = m.shifts();
        e.azimuthal[0] += Vec3::splat(marschner_r(m, &a) / unit(m.beta.x, shifts.x)) * dphi;
        e.azimuthal[1] += marschner_tt(m, &a) / unit(m.beta.y, shifts.y) * dphi;
        e.azimuthal[2] += marschner_trt(m, &a) / unit(m.beta.z, shifts.z) * dphi;
    }
    e
}

/// The averages of one light angle: `(a_f, a_b)` per channel and the lobe-weighted shifts and
/// variances `(α_f, β_f², α_b, β_b²)` (luminance-weighted over the channels).
#[derive(Clone, Copy, Debug)]
pub(crate) struct AngleAverages {
    pub(crate) a_f: Vec3,
    pub(crate) a_b: Vec3,
    alpha_f: f32,
    beta_f2: f32,
    alpha_b: f32,
    beta_b2: f32,
    azimuthal: [Vec3; 3],
}

pub(crate) fn angle_averages(m: &Marschner, sin_theta_i: f32) -> AngleAverages {
    let e = half_energies(m, sin_theta_i);
    let shifts = m.shifts().to_array();
    let var = (m.beta * m.beta).to_array();
    let lum = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722)).max(1e-12);
    let weighted = |half: &[Vec3; 3]| -> (f32, f32) {
        let total: f32 = half.iter().map(|&x| lum(x)).sum();
        let a = (0..3).map(|p| lum(half[p]) * shifts[p]).sum::<f32>() / total;
        let b = (0..3).map(|p| lum(half[p]) * var[p]).sum::<f32>() / total;
        (a, b)
    };
    let (alpha_f, beta_f2) = weighted(&e.forward);
    let (alpha_b, beta_b2) = weighted(&e.backward);
    AngleAverages {
        a_f: e.forward.iter().copied().sum(),
        a_b: e.backward.iter().copied().sum(),
        alpha_f,
        beta_f2,
        alpha_b,
        beta_b2,
        azimuthal: e.azimuthal,
    }
}

/// `sin θi` of table entry `k`.
fn table_sin(k: usize) -> f32 {
    -1.0 + 2.0 * (k as f32 + 0.5) / DS_TABLE as f32
}

impl DualScattering {
    /// Integrate the lobes of `m` for each tabulated light angle (against 96 × 96 eye directions)
    /// and derive Zinke's backscattering terms. CPU only: run it once per material and upload
    /// the result.
    pub fn from_marschner(m: &Marschner) -> DualScattering {
        let mut ds = DualScattering {
            a_f: [Vec4::ZERO; DS_TABLE],
            a_b: [Vec4::ZERO; DS_TABLE],
            delta_b: [Vec4::ZERO; DS_TABLE],
            sigma_b2: [Vec4::ZERO; DS_TABLE],
            params: Vec4::ZERO,
            tt_avg: Vec4::ZERO,
            trt_avg: Vec4::ZERO,
        };
        let mut azimuthal = [Vec3::ZERO; 3];
        for k in 0..DS_TABLE {
            let a = angle_averages(m, table_sin(k));
            let a_f = a.a_f.min(Vec3::splat(MAX_A_F));
            let a_b = a.a_b;
            let per = |f: &dyn Fn(f32, f32) -> f32| {
                Vec3::new(f(a_f.x, a_b.x), f(a_f.y, a_b.y), f(a_f.z, a_b.z))
            };
            let (beta_f, beta_b) = (a.beta_f2.sqrt(), a.beta_b2.sqrt());
            let sigma_b = per(&|af, ab| backscatter_deviation(af, ab, beta_f, beta_b));
            ds.a_f[k] = a_f.extend(a.beta_f2);
            ds.a_b[k] = per(&backscatter_attenuation).extend(0.0);
            ds.delta_b[k] =
                per(&|af, ab| backscatter_shift(af, ab, a.alpha_f, a.alpha_b)).extend(0.0);
            ds.sigma_b2[k] = (sigma_b * sigma_b).extend(0.0);
            for (sum, lobe) in azimuthal.iter_mut().zip(a.azimuthal) {
                *sum += lobe;
            }
        }
        let avg = |p: usize| azimuthal[p] / (DS_TABLE as f32 * TAU);
        ds.params = Vec4::new(avg(0).x, DENSITY_FORWARD, DENSITY_BACKWARD, 0.0);
        ds.tt_avg = avg(1).extend(0.0);
        ds.trt_avg = avg(2).extend(0.0);
        ds
    }

    /// The table read at `sin θi` (linear between entries, clamped at the ends).
    pub fn at(&self, sin_theta_i: f32) -> DualScatteringAt {
        let x =
            ((sin_theta_i + 1.0) * 0.5 * DS_TABLE as f32 - 0.5).clamp(0.0, (DS_TABLE - 1) as f32);
        let i = (x.floor() as usize).min(DS_TABLE - 1);
        let j = (i + 1).min(DS_TABLE - 1);
        let f = x - i as f32;
        let lerp = |t: &[Vec4; DS_TABLE]| t[i].lerp(t[j], f);
        let a_f = lerp(&self.a_f);
        DualScatteringAt {
            a_f: a_f.truncate(),
            beta_f2: a_f.w,
            a_b: lerp(&self.a_b).truncate(),
            delta_b: lerp(&self.delta_b).truncate(),
            sigma_b2: lerp(&self.sigma_b2).truncate(),
        }
    }
}

impl Default for DualScattering {
    /// The averages of [`Marschner::default`].
    fn default() -> Self {
        DualScattering::from_marschner(&Marschner::default())
    }
}

/// Per-channel `g(sqrt(σ²); x)`.
fn gaussian3(var: Vec3, x: Vec3) -> Vec3 {
    Vec3::new(
        hair_gaussian(var.x.sqrt(), x.x),
        hair_gaussian(var.y.sqrt(), x.y),
        hair_gaussian(var.z.sqrt(), x.z),
    )
}

/// The global single scattering `S_G` of light spread by `spread2 = σ̄f²` (see the module docs).
fn spread_single_scattering(
    m: &Marschner,
    ds: &DualScattering,
    a: &HairAngles,
    spread2: f32,
) -> Vec3 {
    let sum = a.sin_theta_i + a.sin_theta_o;
    let shifts = m.shifts();
    let g = |beta: f32, shift: f32| hair_gaussian((beta * beta + spread2).sqrt(), sum - shift);
    Vec3::splat(g(m.beta.x, shifts.x) * ds.params.x)
        + g(m.beta.y, shifts.y) * ds.tt_avg.truncate()
        + g(m.beta.z, shifts.z) * ds.trt_avg.truncate()
}

/// The radiance towards `v` from one directional light of tress radiance `light_color`, with
/// single and multiple scattering: `strands` hairs lie between the point and the light and a
/// fraction `direct` of the light arrives unscattered (the technique's shadow visibility; 1 when
/// unshadowed). See the module docs for the formula. With `strands = 0` and `direct = 1` this is
/// [`crate::marschner::marschner_lighting`] plus the local backscattering.
#[allow(clippy::too_many_arguments)]
pub fn dual_scattering_lighting(
    m: &Marschner,
    ds: &DualScattering,
    t: Vec3,
    l: Vec3,
    light_color: Vec3,
    v: Vec3,
    strands: f32,
    direct: f32,
) -> Vec3 {
    let a = hair_angles(t, l, v);
    let single = Vec3::splat(marschner_r(m, &a)) + marschner_tt(m, &a) + marschner_trt(m, &a);
    let at = ds.at(a.sin_theta_i);
    let (d_f, d_b) = (ds.params.y, ds.params.z);
    let n = strands.max(0.0);
    let sum = Vec3::splat(a.sin_theta_i + a.sin_theta_o);
    let back = at.a_b * gaussian3(at.sigma_b2, sum - at.delta_b);
    let f_direct = direct * (single + d_b * back * ((1.0 + a.cos_phi) / TAU));
    let a_f = at.a_f.max(Vec3::splat(1e-8));
    let t_f = Vec3::new(a_f.x.powf(n), a_f.y.powf(n), a_f.z.powf(n));
    let spread2 = n * at.beta_f2;
    let back_spread = at.a_b * gaussian3(at.sigma_b2 + Vec3::splat(spread2), sum - at.delta_b);
    let f_scatter = (t_f - Vec3::splat(direct)).max(Vec3::ZERO)
        * d_f
        * (spread_single_scattering(m, ds, &a, spread2) + d_b * back_spread / TAU);
    PI * light_color * (f_direct + f_scatter)
}

#[cfg(test)]
mod tests;
