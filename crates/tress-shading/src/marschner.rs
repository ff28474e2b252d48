//! Real-time Marschner hair shading: the R, TT and TRT lobes of Marschner et al. 2003 with Karis
//! 2016's approximations ("Physically Based Hair Shading in Unreal", SIGGRAPH 2016 course
//! *Physically Based Shading in Theory and Practice*), for the GPU techniques. WGSL twin:
//! `shaders/common/marschner.wgsl`.
//!
//! ```text
//! S(l, v) = Σ_p M_p(θi, θo) · N_p(φ) · A_p(θd, φ)                       p ∈ {R, TT, TRT}
//! M_p     = g(β_p; sin θi + sin θo - α_p)      g(β; x) = exp(-x² / 2β²) / (sqrt(2π) β)
//! N_R     = ¼ cos(φ/2)                         A_R   = F(η, cos(½ ∠(l, v)))
//! N_TT    = exp(-3.65 cos φ - 3.98)            A_TT  = (1 - F(η, cos θd sqrt(1 - h_TT²)))² T(h_TT)
//! N_TRT   = exp(17 cos φ - 16.78)              A_TRT = (1 - f)² f T(√3/2)²,  f = F(η, ½ cos θd)
//! h_TT    = cos(φ/2) (1 + a (0.6 - 0.8 cos φ)),   a = 1 / η'
//! T(h)    = exp(-σa · 2 cos γt / cos θt),   cos γt = sqrt(1 - h² a²),   sin θt = sin θd / η
//! ```
//!
//! with `sin θi = t·l`, `sin θo = t·v` (angles from the fibre's normal plane), the half difference
//! `θd = (θo - θi)/2`, the azimuth `φ` between the projections of `l` and `v` on the normal plane
//! (`φ = 0`: the eye on the lit side), Schlick's Fresnel `F`, and Bravais' index for the azimuthal
//! plane `η' = sqrt(η² - sin² θd) / cos θd`. The longitudinal Gaussian in `sin θi + sin θo` and
//! the three azimuthal fits are Karis's; `N_TT` and `N_TRT` are his fits for `η = 1.55` and
//! smooth fibres (`βn` enters only through the colour → `σa` mapping, [`crate::fiber`]).
//!
//! # Choices made here (and why)
//!
//! - **Normalization.** `S` is per solid angle with no cosine, like Chiang et al. 2016's `f`
//!   (`∫ S dω ≤ 1`; `∫ M_p cos θ dθ = 1` and `∫ N_R dφ = 1`): a directional light of irradiance
//!   `E` gives radiance `S · E`. tress's lights carry the radiance of a white Lambertian
//!   surface facing them, so `E = π · color · intensity` ([`marschner_lighting`] applies it).
//! - **Widths and shifts from the fibre.** `β_R = sqrt(v)` with Chiang's longitudinal variance
//!   `v(βm)`, `β_TT = β_R / 2`, `β_TRT = 2 β_R` (Karis: `r²`, `r²/2`, `2r²`; Marschner: `βR`,
//!   `βR/2`, `2βR`), so the real-time lobes are as wide as the reference's. The shifts are
//!   `α_R = 2α`, `α_TT = -α`, `α_TRT = -4α` for the tangent `t` from root to tip, the convention of
//!   pbrt's and Mitsuba 3's hair BSDF with the curve running root to tip (Karis's `N` points to
//!   the root, which flips every sign).
//! - **Absorption and `η'` exactly instead of Karis's fits.** Karis fits `η' ≈ 1.19/cos θd + 0.36
//!   cos θd` for `η = 1.55` and uses `cos θd` for `cos θt`; the exact forms cost one square root
//!   each and hold for any `η`, with `σa` in the reference's units (per fibre radius).
//! - **Multiple scattering** is not part of `S`: see [`crate::dual_scattering`].

use glam::Vec3;

use crate::fiber::HairFiber;
use crate::saturate;

/// The per-material inputs of the Marschner lobes. Mirrors the WGSL `struct Marschner` field for
/// field (32 bytes: `vec3f, f32, vec3f, f32`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marschner {
    /// Absorption per fibre radius, linear RGB.
    pub sigma_a: Vec3,
    /// Index of refraction `η`.
    pub eta: f32,
    /// Longitudinal widths `(β_R, β_TT, β_TRT)` (standard deviations in `sin θi + sin θo`).
    pub beta: Vec3,
    /// Cuticle tilt `α` in radians.
    pub alpha: f32,
}

impl Marschner {
    /// The lobes of a fibre (see the module docs for the widths).
    pub fn from_fiber(fiber: &HairFiber) -> Marschner {
        let beta_r = fiber.longitudinal_variance().sqrt();
        Marschner {
            sigma_a: fiber.sigma_a,
            eta: fiber.eta,
            beta: Vec3::new(beta_r, 0.5 * beta_r, 2.0 * beta_r),
            alpha: fiber.alpha,
        }
    }

    /// The longitudinal shifts `(α_R, α_TT, α_TRT) = (2α, -α, -4α)`.
    pub fn shifts(&self) -> Vec3 {
        Vec3::new(2.0 * self.alpha, -self.alpha, -4.0 * self.alpha)
    }
}

impl Default for Marschner {
    /// The lobes of [`HairFiber::default`].
    fn default() -> Self {
        Marschner::from_fiber(&HairFiber::default())
    }
}

/// The angles every lobe needs, computed once per light. Mirrors the WGSL `struct HairAngles`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairAngles {
    /// `sin θi = t·l`.
    pub sin_theta_i: f32,
    /// `sin θo = t·v`.
    pub sin_theta_o: f32,
    /// `cos θd`, `θd = (θo - θi) / 2`.
    pub cos_theta_d: f32,
    /// `cos φ`, the azimuth between the projections of `l` and `v` on the normal plane.
    pub cos_phi: f32,
    /// `cos(φ/2) = sqrt((1 + cos φ) / 2)` (`φ ∈ [0, π]`).
    pub cos_half_phi: f32,
    /// `cos(½ ∠(l, v)) = sqrt((1 + l·v) / 2)`: the cosine of incidence on the facet that
    /// mirrors `l` into `v` (R's Fresnel).
    pub cos_half_lv: f32,
}

/// The angles of [`HairAngles`] from the unit tangent `t` and the unit directions `l`, `v` (away
/// from the point). `cos φ` uses `dot(l⊥, v⊥) / sqrt(|l⊥|² |v⊥|² + 10⁻⁴)`, Karis's guard, so a
/// direction along the tangent gives `φ = π/2` instead of NaN.
pub fn hair_angles(t: Vec3, l: Vec3, v: Vec3) -> HairAngles {
    let sin_theta_i = t.dot(l).clamp(-1.0, 1.0);
    let sin_theta_o = t.dot(v).clamp(-1.0, 1.0);
    let cos_theta_i = (1.0 - sin_theta_i * sin_theta_i).max(0.0).sqrt();
    let cos_theta_o = (1.0 - sin_theta_o * sin_theta_o).max(0.0).sqrt();
    // cos(θo - θi) = cos θo cos θi + sin θo sin θi; cos θd = sqrt((1 + cos 2θd) / 2).
    let cos_2theta_d = cos_theta_o * cos_theta_i + sin_theta_o * sin_theta_i;
    let cos_theta_d = (0.5 + 0.5 * cos_2theta_d).max(0.0).sqrt();
    let lp = l - sin_theta_i * t;
    let vp = v - sin_theta_o * t;
    let cos_phi =
        (lp.dot(vp) / (lp.length_squared() * vp.length_squared() + 1e-4).sqrt()).clamp(-1.0, 1.0);
    HairAngles {
        sin_theta_i,
        sin_theta_o,
        cos_theta_d,
        cos_phi,
        cos_half_phi: saturate(0.5 + 0.5 * cos_phi).sqrt(),
        cos_half_lv: saturate(0.5 + 0.5 * l.dot(v)).sqrt(),
    }
}

/// Karis's unit-area Gaussian `g(β; x) = exp(-x² / 2β²) / (sqrt(2π) β)`. Precondition `β > 0`.
pub fn hair_gaussian(beta: f32, x: f32) -> f32 {
    (-0.5 * x * x / (beta * beta)).exp() / ((std::f32::consts::TAU).sqrt() * beta)
}

/// Schlick's approximation of the dielectric Fresnel reflectance `F0 + (1 - F0)(1 - cos)⁵`,
/// `F0 = ((η - 1)/(η + 1))²` (Karis 2016 uses it for every lobe). `cos` is clamped to `[0, 1]`.
pub fn fresnel_schlick(eta: f32, cos_theta: f32) -> f32 {
    let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    let c = 1.0 - saturate(cos_theta);
    f0 + (1.0 - f0) * c * c * c * c * c
}

/// The azimuthal-plane index `a = 1/η'` with `η' = sqrt(η² - sin² θd) / cos θd` (Bravais).
fn inv_eta_prime(eta: f32, cos_theta_d: f32) -> f32 {
    let sin2 = 1.0 - cos_theta_d * cos_theta_d;
    cos_theta_d / (eta * eta - sin2).max(1e-8).sqrt()
}

/// The transmittance of one crossing at azimuthal-plane offset `h` (see the module docs).
fn crossing(m: &Marschner, a: &HairAngles, h: f32, inv_eta_p: f32) -> Vec3 {
    let cos_gamma_t = (1.0 - h * h * inv_eta_p * inv_eta_p).max(0.0).sqrt();
    let sin_theta_d2 = 1.0 - a.cos_theta_d * a.cos_theta_d;
    let cos_theta_t = (1.0 - sin_theta_d2 / (m.eta * m.eta)).max(1e-8).sqrt();
    let length = 2.0 * cos_gamma_t / cos_theta_t;
    Vec3::new(
        (-m.sigma_a.x * length).exp(),
        (-m.sigma_a.y * length).exp(),
        (-m.sigma_a.z * length).exp(),
    )
}

/// The R lobe `M_R N_R A_R` (surface reflection, uncoloured).
pub fn marschner_r(m: &Marschner, a: &HairAngles) -> f32 {
    let mp = hair_gaussian(m.beta.x, a.sin_theta_i + a.sin_theta_o - 2.0 * m.alpha);
    let np = 0.25 * a.cos_half_phi;
    let ap = fresnel_schlick(m.eta, a.cos_half_lv);
    mp * np * ap
}

/// The TT lobe `M_TT N_TT A_TT` (transmission through the fibre, the backlit glow).
pub fn marschner_tt(m: &Marschner, a: &HairAngles) -> Vec3 {
    let mp = hair_gaussian(m.beta.y, a.sin_theta_i + a.sin_theta_o + m.alpha);
    let inv_eta_p = inv_eta_prime(m.eta, a.cos_theta_d);
    let h = a.cos_half_phi * (1.0 + inv_eta_p * (0.6 - 0.8 * a.cos_phi));
    let f = fresnel_schlick(m.eta, a.cos_theta_d * (1.0 - h * h).max(0.0).sqrt());
    let np = (-3.65 * a.cos_phi - 3.98).exp();
    mp * np * (1.0 - f) * (1.0 - f) * crossing(m, a, h, inv_eta_p)
}

/// The TRT lobe `M_TRT N_TRT A_TRT` (internal reflection, the coloured secondary highlight).
pub fn marschner_trt(m: &Marschner, a: &HairAngles) -> Vec3 {
    let mp = hair_gaussian(m.beta.z, a.sin_theta_i + a.sin_theta_o + 4.0 * m.alpha);
    let inv_eta_p = inv_eta_prime(m.eta, a.cos_theta_d);
    let f = fresnel_schlick(m.eta, 0.5 * a.cos_theta_d);
    let t = crossing(m, a, 0.5 * 3f32.sqrt(), inv_eta_p);
    let np = (17.0 * a.cos_phi - 16.78).exp();
    mp * np * (1.0 - f) * (1.0 - f) * f * t * t
}

/// `S(l, v) = R + TT + TRT` (1/sr; see the module docs for the normalization).
pub fn marschner(m: &Marschner, t: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    let a = hair_angles(t, l, v);
    Vec3::splat(marschner_r(m, &a)) + marschner_tt(m, &a) + marschner_trt(m, &a)
}

/// The radiance towards `v` from one directional light of tress radiance `light_color` (the
/// radiance of a white Lambertian surface facing it): `π · S(l, v) · light_color`. Multiply by
/// the light's visibility outside, or use [`crate::dual_scattering::dual_scattering_lighting`]
/// for the shadowed light with multiple scattering.
pub fn marschner_lighting(m: &Marschner, t: Vec3, l: Vec3, light_color: Vec3, v: Vec3) -> Vec3 {
    std::f32::consts::PI * marschner(m, t, l, v) * light_color
}

#[cfg(test)]
mod tests;
