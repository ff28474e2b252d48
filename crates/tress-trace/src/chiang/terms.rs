//! The factors of Chiang et al. 2016's fibre BSDF: the longitudinal term `M_p` (d'Eon et al.
//! 2011), the attenuations `A_p`, the azimuthal term `N_p` (the trimmed logistic of Chiang §3.2),
//! the perfect-specular azimuths `Φ(p)` and the dielectric Fresnel reflectance.

use std::f32::consts::{PI, TAU};

/// `sqrt(max(x, 0))`.
pub(crate) fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// `asin` of `x` clamped to `[-1, 1]`.
pub(crate) fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}

/// The modified Bessel function of the first kind `I0(x) = Σ (x²/4)^i / (i!)²`, summed until the
/// terms stop mattering (at most 64; `x ≤ 12` here, see [`log_i0`]).
pub(crate) fn i0(x: f32) -> f32 {
    let y = f64::from(x) * f64::from(x) * 0.25;
    let mut term = 1.0f64;
    let mut sum = 1.0f64;
    for i in 1..64 {
        term *= y / f64::from(i * i);
        sum += term;
        if term < sum * 1e-9 {
            break;
        }
    }
    sum as f32
}

/// `ln I0(x)`: the series below 12, above it the asymptotic expansion `x - ½ ln(2πx) +
/// ln(1 + 1/(8x) + 9/(128x²))` (d'Eon et al. 2011 §4 evaluate `M_p` in log space for small
/// variances), so `M_p` stays finite for small variances. pbrt's version keeps only `1/(16x)`
/// of the correction, half of its first term, which leaves `∫ M_p cos θ dθ` 0.3% short for
/// `v = 0.005` at grazing angles.
pub(crate) fn log_i0(x: f32) -> f32 {
    if x > 12.0 {
        let inv = 1.0 / x;
        x - 0.5 * (TAU * x).ln() + (1.0 + inv / 8.0 + 9.0 / 128.0 * inv * inv).ln()
    } else {
        i0(x).ln()
    }
}

/// d'Eon et al. 2011's longitudinal scattering function (§4 there; Chiang et al. 2016 §3)
///
/// ```text
/// M_p(θi, θo) = exp(-sin θi sin θo / v) · I0(cos θi cos θo / v) / (2 v sinh(1/v))
/// ```
///
/// normalized so `∫ M_p cos θi dθi = 1`. For `v ≤ 0.1` it is evaluated in log space with
/// [`log_i0`] (`1 / (2v sinh(1/v)) → exp(-1/v) / v`); both branches agree at `v = 0.1`.
pub(crate) fn mp(
    cos_theta_i: f32,
    cos_theta_o: f32,
    sin_theta_i: f32,
    sin_theta_o: f32,
    v: f32,
) -> f32 {
    let a = cos_theta_i * cos_theta_o / v;
    let b = sin_theta_i * sin_theta_o / v;
    if v <= 0.1 {
        (log_i0(a) - b - 1.0 / v + std::f32::consts::LN_2 + (1.0 / (2.0 * v)).ln()).exp()
    } else {
        (-b).exp() * i0(a) / ((1.0 / v).sinh() * 2.0 * v)
    }
}

/// The unpolarized Fresnel reflectance of a dielectric of relative index `eta` at incidence
/// cosine `cos_theta_i` (from outside; 1 on total internal reflection).
pub(crate) fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let c = cos_theta_i.clamp(0.0, 1.0);
    let sin_t = safe_sqrt(1.0 - c * c) / eta;
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = safe_sqrt(1.0 - sin_t * sin_t);
    let r_parl = (eta * c - cos_t) / (eta * c + cos_t);
    let r_perp = (c - eta * cos_t) / (c + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// Chiang et al. 2016 §3: the attenuation of each lobe, `A_0 = f`, `A_1 = (1 - f)² T`,
/// `A_2 = A_1 T f`, and the residual of every longer path `A_3 = A_2 f T / (1 - T f)`, with the
/// Fresnel reflectance `f` at `cos θo cos γo` and the transmittance `T` of one crossing (per
/// channel).
pub(crate) fn attenuation(cos_theta_o: f32, eta: f32, h: f32, t: [f32; 3]) -> [[f32; 3]; 4] {
    let cos_gamma_o = safe_sqrt(1.0 - h * h);
    let f = fresnel_dielectric(cos_theta_o * cos_gamma_o, eta);
    let mut ap = [[0.0; 3]; 4];
    for c in 0..3 {
        ap[0][c] = f;
        ap[1][c] = (1.0 - f) * (1.0 - f) * t[c];
        ap[2][c] = ap[1][c] * t[c] * f;
        ap[3][c] = ap[2][c] * f * t[c] / (1.0 - t[c] * f);
    }
    ap
}

/// The azimuth of perfect specular scattering of lobe `p` (Marschner et al. 2003 §4, for the
/// azimuth measured from `ωo`): `Φ(p) = 2p γt - 2γo + pπ`.
pub(crate) fn phi(p: u32, gamma_o: f32, gamma_t: f32) -> f32 {
    let p = p as f32;
    2.0 * p * gamma_t - 2.0 * gamma_o + p * PI
}

/// The logistic density `e^{-|x|/s} / (s (1 + e^{-|x|/s})²)`.
pub(crate) fn logistic(x: f32, s: f32) -> f32 {
    let e = (-x.abs() / s).exp();
    e / (s * (1.0 + e) * (1.0 + e))
}

/// The logistic CDF `1 / (1 + e^{-x/s})`.
pub(crate) fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// Chiang et al. 2016 §3.2: the logistic trimmed to `[-π, π]` and renormalized.
pub(crate) fn trimmed_logistic(x: f32, s: f32) -> f32 {
    logistic(x, s) / (logistic_cdf(PI, s) - logistic_cdf(-PI, s))
}

/// Sample [`trimmed_logistic`] by inverting its CDF at `u ∈ [0, 1)`.
pub(crate) fn sample_trimmed_logistic(u: f32, s: f32) -> f32 {
    let k = logistic_cdf(PI, s) - logistic_cdf(-PI, s);
    let x = -s * (1.0 / (u * k + logistic_cdf(-PI, s)) - 1.0).ln();
    x.clamp(-PI, PI)
}

/// Chiang et al. 2016 §3.2: `N_p(φ) = trimmed_logistic(φ - Φ(p))` with the difference wrapped
/// to `[-π, π]`.
pub(crate) fn np(phi_rel: f32, p: u32, s: f32, gamma_o: f32, gamma_t: f32) -> f32 {
    let mut d = phi_rel - phi(p, gamma_o, gamma_t);
    d = (d + PI).rem_euclid(TAU) - PI;
    trimmed_logistic(d, s)
}
