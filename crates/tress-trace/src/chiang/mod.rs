//! Chiang et al. 2016's hair BSDF ("A Practical and Controllable Hair and Fur Model for
//! Production Path Tracing", EGSR 2016), the reference's physically based fibre: the near-field
//! scattering of one ray hitting a dielectric cylinder at offset `h`, as pbrt-v3/v4's `HairBxDF`
//! and Mitsuba 3's `hair` BSDF implement it.
//!
//! ```text
//! f(ωo, ωi) = Σ_{p=0}^{2} M_p(θi, θo') A_p(θo, h) N_p(φi - φo) + M_3(θi, θo) A_3 / 2π
//! ```
//!
//! - `M_p`: d'Eon et al. 2011's longitudinal term (`terms::mp`) with variance `v` for R, `v/4`
//!   for TT and `4v` for TRT and the residual (`v(βm)` of [`HairFiber::longitudinal_variance`]);
//!   `θo'` is `θo` tilted by the cuticle scales: `θo - 2α` (R), `θo + α` (TT), `θo + 4α` (TRT).
//! - `A_p`: Fresnel at `cos θo cos γo` and the transmittance `T = exp(-σa · 2 cos γt / cos θt)`
//!   of one crossing (`σa` per fibre radius), with the residual `A_3` of all longer paths
//!   (`terms::attenuation`).
//! - `N_p`: the trimmed logistic of scale `s(βn)` about the perfect-specular azimuth
//!   `Φ(p) = 2p γt - 2γo + pπ` (`terms::np`), `sin γo = h`, `sin γt = h / η'` with Bravais'
//!   index `η' = sqrt(η² - sin² θo) / cos θo`.
//!
//! The terms (`M_p`, `A_p`, `N_p`) are crate-private functions in `src/chiang/terms.rs`.
//!
//! `f` is per solid angle with no cosine factor (pbrt's `f · |cos θ|`, Mitsuba's `eval`):
//! `∫ f dω = Σ_p A_p`, which is 1 for `σa = 0` (the white furnace). Radiance from a directional
//! light of irradiance `E` is `f · E`; a path's throughput is multiplied by `f / pdf`.
//!
//! **Importance sampling** (Chiang §3.3, as pbrt): choose a lobe `p` with probability
//! `A_p`'s luminance share; sample `θi` from `M_p` exactly (a von Mises-Fisher direction about the
//! specular cone, whose elevation has density `M_p cos θ`); sample `φ` from the trimmed logistic
//! about `Φ(p)` (uniform for the residual). [`ChiangBsdf::pdf`] is the density of exactly this
//! procedure, so `f / pdf` is 1 for every sample of a white fibre.
//!
//! # Frame
//!
//! Local directions have `x` along the fibre tangent (root to tip) and the azimuth
//! `φ = atan2(z, y)` in the normal plane. [`FiberFrame`] builds the frame of a ray hit: `y` is
//! the projection of `ωo`, `z = x × y`, and `h = -(n · z)` for the unit surface normal `n` at the
//! hit, the sign that makes the R lobe the mirror reflection about `n` (tested).

pub(crate) mod terms;

use std::f32::consts::TAU;

use glam::Vec3;
use tress_shading::fiber::HairFiber;

use terms::{attenuation, mp, np, phi, safe_asin, safe_sqrt, sample_trimmed_logistic};

/// Lobes evaluated explicitly before the residual.
const P_MAX: usize = 3;

/// Luminance weights (Rec. 709) used to choose a lobe.
const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// The BSDF of one ray–fibre intersection: the fibre's material and the offset `h ∈ [-1, 1]`.
#[derive(Clone, Copy, Debug)]
pub struct ChiangBsdf {
    h: f32,
    gamma_o: f32,
    eta: f32,
    sigma_a: Vec3,
    /// Longitudinal variances of R, TT, TRT and the residual.
    v: [f32; P_MAX + 1],
    /// Logistic scale `s`.
    s: f32,
    /// `sin(2^k α)`, `cos(2^k α)` for `k = 0, 1, 2`.
    sin_2k_alpha: [f32; 3],
    cos_2k_alpha: [f32; 3],
}

/// A direction sampled from [`ChiangBsdf::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled incident direction (local frame).
    pub wi: Vec3,
    /// `f(ωo, ωi)`.
    pub f: Vec3,
    /// The density of `wi` per solid angle.
    pub pdf: f32,
}

/// `(sin θ, cos θ, φ)` of a local direction.
fn angles(w: Vec3) -> (f32, f32, f32) {
    let sin_theta = w.x.clamp(-1.0, 1.0);
    (
        sin_theta,
        safe_sqrt(1.0 - sin_theta * sin_theta),
        w.z.atan2(w.y),
    )
}

impl ChiangBsdf {
    /// The BSDF of `fiber` hit at offset `h` (clamped to `[-1, 1]`). The fibre must be valid
    /// ([`HairFiber::validate`]).
    pub fn new(fiber: &HairFiber, h: f32) -> ChiangBsdf {
        let h = h.clamp(-1.0, 1.0);
        let v0 = fiber.longitudinal_variance();
        let mut sin_2k_alpha = [fiber.alpha.sin(), 0.0, 0.0];
        let mut cos_2k_alpha = [safe_sqrt(1.0 - sin_2k_alpha[0] * sin_2k_alpha[0]), 0.0, 0.0];
        for i in 1..3 {
            sin_2k_alpha[i] = 2.0 * cos_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
            cos_2k_alpha[i] = cos_2k_alpha[i - 1] * cos_2k_alpha[i - 1]
                - sin_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
        }
        ChiangBsdf {
            h,
            gamma_o: safe_asin(h),
            eta: fiber.eta,
            sigma_a: fiber.sigma_a,
            v: [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0],
            s: fiber.logistic_scale(),
            sin_2k_alpha,
            cos_2k_alpha,
        }
    }

    /// `θo` tilted for lobe `p` by the cuticle scales: `(sin θo', |cos θo'|)`.
    fn tilted(&self, p: usize, sin_theta_o: f32, cos_theta_o: f32) -> (f32, f32) {
        let (s, c) = (self.sin_2k_alpha, self.cos_2k_alpha);
        let (sin_p, cos_p) = match p {
            0 => (
                sin_theta_o * c[1] - cos_theta_o * s[1],
                cos_theta_o * c[1] + sin_theta_o * s[1],
            ),
            1 => (
                sin_theta_o * c[0] + cos_theta_o * s[0],
                cos_theta_o * c[0] - sin_theta_o * s[0],
            ),
            2 => (
                sin_theta_o * c[2] + cos_theta_o * s[2],
                cos_theta_o * c[2] - sin_theta_o * s[2],
            ),
            _ => (sin_theta_o, cos_theta_o),
        };
        (sin_p, cos_p.abs())
    }

    /// `γt` and the transmittance of one crossing for the eye at `(sin θo, cos θo)`.
    fn transmission(&self, sin_theta_o: f32, cos_theta_o: f32) -> (f32, [f32; 3]) {
        let sin_theta_t = sin_theta_o / self.eta;
        let cos_theta_t = safe_sqrt(1.0 - sin_theta_t * sin_theta_t);
        let eta_p =
            safe_sqrt(self.eta * self.eta - sin_theta_o * sin_theta_o) / cos_theta_o.max(1e-6);
        let sin_gamma_t = self.h / eta_p;
        let cos_gamma_t = safe_sqrt(1.0 - sin_gamma_t * sin_gamma_t);
        let length = 2.0 * cos_gamma_t / cos_theta_t.max(1e-6);
        let t = (-self.sigma_a * length).to_array().map(f32::exp);
        (safe_asin(sin_gamma_t), t)
    }

    /// The attenuations and `γt` for the eye at `(sin θo, cos θo)`.
    fn lobes(&self, sin_theta_o: f32, cos_theta_o: f32) -> ([[f32; 3]; 4], f32) {
        let (gamma_t, t) = self.transmission(sin_theta_o, cos_theta_o);
        (attenuation(cos_theta_o, self.eta, self.h, t), gamma_t)
    }

    /// The probability of choosing each lobe: its attenuation's luminance share.
    fn lobe_pdf(ap: &[[f32; 3]; 4]) -> [f32; 4] {
        let y = ap.map(|a| Vec3::from_array(a).dot(LUMINANCE).max(0.0));
        let sum: f32 = y.iter().sum();
        if sum > 0.0 {
            y.map(|x| x / sum)
        } else {
            [1.0, 0.0, 0.0, 0.0]
        }
    }

    /// Sum over the lobes of `M_p · weight_p · N_p` (the residual with `1 / 2π`): `f` with the
    /// attenuations as weights, the pdf with the lobe probabilities.
    fn sum_lobes<W: Copy + std::ops::Mul<f32, Output = W> + std::ops::Add<Output = W>>(
        &self,
        wo: Vec3,
        wi: Vec3,
        weight: impl Fn(usize) -> W,
        zero: W,
        gamma_t: f32,
    ) -> W {
        let (sin_o, cos_o, phi_o) = angles(wo);
        let (sin_i, cos_i, phi_i) = angles(wi);
        let dphi = phi_i - phi_o;
        let mut sum = zero;
        for p in 0..P_MAX {
            let (sin_op, cos_op) = self.tilted(p, sin_o, cos_o);
            let m = mp(cos_i, cos_op, sin_i, sin_op, self.v[p]);
            let n = np(dphi, p as u32, self.s, self.gamma_o, gamma_t);
            sum = sum + weight(p) * (m * n);
        }
        let m = mp(cos_i, cos_o, sin_i, sin_o, self.v[P_MAX]);
        sum + weight(P_MAX) * (m / TAU)
    }

    /// `f(ωo, ωi)` per channel (local frame, unit vectors; see the module docs).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let (sin_o, cos_o, _) = angles(wo);
        let (ap, gamma_t) = self.lobes(sin_o, cos_o);
        let f = self.sum_lobes(wo, wi, |p| Vec3::from_array(ap[p]), Vec3::ZERO, gamma_t);
        if f.is_finite() {
            f.max(Vec3::ZERO)
        } else {
            Vec3::ZERO
        }
    }

    /// The density per solid angle with which [`ChiangBsdf::sample`] returns `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (sin_o, cos_o, _) = angles(wo);
        let (ap, gamma_t) = self.lobes(sin_o, cos_o);
        let pdf = Self::lobe_pdf(&ap);
        let p = self.sum_lobes(wo, wi, |p| pdf[p], 0.0, gamma_t);
        if p.is_finite() { p.max(0.0) } else { 0.0 }
    }

    /// Sample `ωi` for `ωo` from three uniform numbers in `[0, 1)`: `u0` chooses the lobe (and
    /// is reused, rescaled, for the azimuth), `u1` and `u2` the longitudinal angle. `None` when
    /// the density at the sample is 0.
    pub fn sample(&self, wo: Vec3, u0: f32, u1: f32, u2: f32) -> Option<BsdfSample> {
        let (sin_o, cos_o, phi_o) = angles(wo);
        let (ap, gamma_t) = self.lobes(sin_o, cos_o);
        let pdf = Self::lobe_pdf(&ap);
        // Choose the lobe and rescale u0 to [0, 1) within it.
        let mut u = u0;
        let mut p = P_MAX;
        for (k, &q) in pdf.iter().enumerate().take(P_MAX) {
            if u < q {
                p = k;
                break;
            }
            u -= q;
        }
        let u = if pdf[p] > 0.0 {
            (u / pdf[p]).clamp(0.0, 1.0 - f32::EPSILON)
        } else {
            0.0
        };
        // M_p: a vMF direction about the specular cone of the tilted θo.
        let (sin_op, cos_op) = self.tilted(p, sin_o, cos_o);
        let v = self.v[p];
        let u1 = u1.max(1e-5);
        let cos_theta = 1.0 + v * (u1 + (1.0 - u1) * (-2.0 / v).exp()).ln();
        let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
        let cos_phi = (TAU * u2).cos();
        let sin_i = (-cos_theta * sin_op + sin_theta * cos_phi * cos_op).clamp(-1.0, 1.0);
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        // N_p: the trimmed logistic about Φ(p), uniform for the residual.
        let dphi = if p < P_MAX {
            phi(p as u32, self.gamma_o, gamma_t) + sample_trimmed_logistic(u, self.s)
        } else {
            TAU * u
        };
        let phi_i = phi_o + dphi;
        let wi = Vec3::new(sin_i, cos_i * phi_i.cos(), cos_i * phi_i.sin());
        let pdf = self.pdf(wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            f: self.eval(wo, wi),
            pdf,
        })
    }
}

/// The local frame of a ray–fibre hit and the offset `h` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FiberFrame {
    /// The fibre tangent (local `x`).
    pub x: Vec3,
    /// Local `y`: the projection of `ωo` on the normal plane.
    pub y: Vec3,
    /// Local `z = x × y`.
    pub z: Vec3,
    /// The offset `h ∈ [-1, 1]` of the hit across the fibre as seen from `ωo`.
    pub h: f32,
}

impl FiberFrame {
    /// The frame for the unit tangent `t`, the unit direction `wo` towards the eye and the unit
    /// surface normal `n` at the hit. `None` when `wo` runs along the tangent.
    pub fn new(t: Vec3, wo: Vec3, n: Vec3) -> Option<FiberFrame> {
        let y = (wo - wo.dot(t) * t).try_normalize()?;
        let z = t.cross(y);
        let n_perp = (n - n.dot(t) * t).try_normalize().unwrap_or(y);
        Some(FiberFrame {
            x: t,
            y,
            z,
            h: (-n_perp.dot(z)).clamp(-1.0, 1.0),
        })
    }

    /// A world direction in this frame.
    pub fn to_local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.x), w.dot(self.y), w.dot(self.z))
    }

    /// A local direction in world space.
    pub fn to_world(&self, w: Vec3) -> Vec3 {
        self.x * w.x + self.y * w.y + self.z * w.z
    }
}

#[cfg(test)]
mod tests;
