//! The tests pbrt-v4 has for its `HairBxDF` (white furnace, sampled furnace, sample weights,
//! sampling consistency), a χ² test of the sampling against the evaluated pdf, energy for any
//! absorption, reciprocity where the model has it, and the geometry of the lobes.

use std::f32::consts::{PI, TAU};

use glam::Vec3;
use tress_hair::rng::Rng;
use tress_shading::fiber::{HairFiber, sigma_a_from_melanin};

use super::terms::*;
use super::*;

fn fiber(beta_m: f32, beta_n: f32, sigma_a: Vec3, alpha_deg: f32) -> HairFiber {
    HairFiber {
        sigma_a,
        beta_m,
        beta_n,
        alpha: alpha_deg.to_radians(),
        eta: 1.55,
    }
}

/// A local direction at `sin θ = s`, azimuth `phi`.
fn local(s: f32, phi: f32) -> Vec3 {
    let c = safe_sqrt(1.0 - s * s);
    Vec3::new(s, c * phi.cos(), c * phi.sin())
}

/// `∫ f dω` over the sphere by the midpoint rule in `(sin θi, φi)` (`dω = d(sin θ) dφ`),
/// averaged over `n_h` stratified offsets `h`; per channel, in f64.
fn albedo(f: &HairFiber, wo: Vec3, n_h: usize, n_s: usize, n_phi: usize) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for k in 0..n_h {
        let h = -1.0 + 2.0 * (k as f32 + 0.5) / n_h as f32;
        let bsdf = ChiangBsdf::new(f, h);
        for i in 0..n_s {
            let s = -1.0 + 2.0 * (i as f32 + 0.5) / n_s as f32;
            for j in 0..n_phi {
                let phi = TAU * (j as f32 + 0.5) / n_phi as f32;
                let v = bsdf.eval(wo, local(s, phi));
                for c in 0..3 {
                    sum[c] += f64::from(v[c]);
                }
            }
        }
    }
    let dw = 2.0 / n_s as f64 * std::f64::consts::TAU / n_phi as f64 / n_h as f64;
    sum.map(|x| x * dw)
}

#[test]
fn mp_is_normalized_and_continuous_between_its_branches() {
    for v in [0.005f32, 0.03, 0.1, 0.25, 1.0] {
        for theta_o in [-1.2f32, -0.4, 0.0, 0.7, 1.4] {
            let (so, co) = theta_o.sin_cos();
            let n = 20_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let th = -PI / 2.0 + PI * (i as f32 + 0.5) / n as f32;
                let (si, ci) = th.sin_cos();
                sum += f64::from(mp(ci, co, si, so, v) * ci) * f64::from(PI) / n as f64;
            }
            assert!((sum - 1.0).abs() < 2e-3, "v {v} θo {theta_o}: {sum}");
        }
    }
    // The log-space branch (v ≤ 0.1) and the direct one agree at the switch.
    let (si, ci) = 0.3f32.sin_cos();
    let (so, co) = (-0.25f32).sin_cos();
    let below = mp(ci, co, si, so, 0.1);
    let above = mp(ci, co, si, so, 0.100_001);
    assert!((below - above).abs() < 1e-3 * below, "{below} vs {above}");
    // ln I0 switches to its asymptotic expansion at 12 without a jump.
    assert!((log_i0(12.0) - log_i0(12.0001)).abs() < 2e-4);
    assert!((i0(0.0) - 1.0).abs() < 1e-7);
    assert!((i0(3.0) - 4.880_793).abs() < 1e-4);
}

#[test]
fn trimmed_logistic_is_a_density_and_its_sampling_inverts_the_cdf() {
    for s in [0.05f32, 0.2, 0.6, 2.0] {
        let n = 40_000;
        let area: f32 = (0..n)
            .map(|i| trimmed_logistic(-PI + TAU * (i as f32 + 0.5) / n as f32, s))
            .sum::<f32>()
            * TAU
            / n as f32;
        assert!((area - 1.0).abs() < 1e-3, "s {s}: {area}");
        let k = logistic_cdf(PI, s) - logistic_cdf(-PI, s);
        for u in [0.01f32, 0.3, 0.5, 0.77, 0.99] {
            let x = sample_trimmed_logistic(u, s);
            let cdf = (logistic_cdf(x, s) - logistic_cdf(-PI, s)) / k;
            assert!((cdf - u).abs() < 1e-4, "s {s} u {u}: {cdf}");
        }
    }
}

#[test]
fn attenuations_sum_to_one_without_absorption() {
    for h in [-0.99f32, -0.5, 0.0, 0.3, 0.9] {
        for cos_o in [0.1f32, 0.5, 1.0] {
            let ap = attenuation(cos_o, 1.55, h, [1.0; 3]);
            let sum: f32 = ap.iter().map(|a| a[0]).sum();
            assert!((sum - 1.0).abs() < 1e-6, "h {h} cos θo {cos_o}: {sum}");
            let dark = attenuation(cos_o, 1.55, h, [0.3, 0.5, 0.9]);
            for c in 0..3 {
                assert!(dark.iter().map(|a| a[c]).sum::<f32>() < 1.0);
            }
        }
    }
    // Fresnel: 4.65% at normal incidence for η = 1.55, 1 at grazing.
    assert!((fresnel_dielectric(1.0, 1.55) - 0.046_5).abs() < 1e-4);
    assert!((fresnel_dielectric(0.0, 1.55) - 1.0).abs() < 1e-6);
}

#[test]
fn white_furnace_integrates_to_one() {
    // σa = 0: Σ A_p = 1, so ∫ f dω = 1 for any ωo, roughness and tilt (pbrt-v4's WhiteFurnace,
    // by quadrature instead of 300k random samples).
    let mut rng = Rng::new(7);
    for beta_m in [0.1f32, 0.4, 0.9] {
        for beta_n in [0.1f32, 0.4, 0.9] {
            for alpha in [0.0f32, 2.0] {
                let wo = rng.on_sphere();
                if wo.x.abs() > 0.95 {
                    continue;
                }
                let f = fiber(beta_m, beta_n, Vec3::ZERO, alpha);
                let e = albedo(&f, wo, 8, 160, 720);
                assert!(
                    (e[0] - 1.0).abs() < 0.02,
                    "βm {beta_m} βn {beta_n} α {alpha}: {e:?}"
                );
            }
        }
    }
}

#[test]
fn every_sample_of_a_white_fibre_weighs_one() {
    // pbrt-v4's SamplingWeights and WhiteFurnaceSampled: with σa = 0 the lobe probabilities are
    // the attenuations, so f / pdf = Σ A_p = 1 for every sample, whatever βm, βn, h, ωo.
    let mut rng = Rng::new(11);
    for beta_m in [0.1f32, 0.3, 0.7] {
        for beta_n in [0.2f32, 0.5, 0.9] {
            let f = fiber(beta_m, beta_n, Vec3::ZERO, 2.0);
            for _ in 0..2000 {
                let bsdf = ChiangBsdf::new(&f, rng.range(-1.0, 1.0));
                let wo = rng.on_sphere();
                if let Some(s) = bsdf.sample(wo, rng.f32(), rng.f32(), rng.f32()) {
                    let w = s.f / s.pdf;
                    assert!(
                        (w - Vec3::ONE).abs().max_element() < 2e-3,
                        "βm {beta_m} βn {beta_n}: {w}"
                    );
                    assert!((s.wi.length() - 1.0).abs() < 1e-4);
                }
            }
        }
    }
}

#[test]
fn energy_never_exceeds_one() {
    let mut rng = Rng::new(3);
    for _ in 0..12 {
        let sigma_a = Vec3::new(
            rng.range(0.0, 5.0),
            rng.range(0.0, 5.0),
            rng.range(0.0, 5.0),
        );
        let f = fiber(
            rng.range(0.1, 1.0),
            rng.range(0.1, 1.0),
            sigma_a,
            rng.range(-5.0, 5.0),
        );
        let wo = rng.on_sphere();
        if wo.x.abs() > 0.95 {
            continue;
        }
        let e = albedo(&f, wo, 6, 120, 480);
        for c in e {
            assert!(c <= 1.0 + 2e-3, "{f:?} {wo}: {e:?}");
        }
    }
}

#[test]
fn reciprocal_where_the_model_is() {
    // The near-field model is not reciprocal in general (pbrt disables its reciprocity test):
    // A_p depends on θo and h. It is where those agree: α = 0, |sin θi| = |sin θo|, and either
    // h = 0 (every lobe's Φ is 0 or π), or only R survives with h ↔ -h (the mirror path).
    let mut rng = Rng::new(5);
    for _ in 0..500 {
        let s = rng.range(-0.95, 0.95);
        let sign = if rng.f32() < 0.5 { 1.0 } else { -1.0 };
        let wo = local(s, rng.range(-PI, PI));
        let wi = local(sign * s, rng.range(-PI, PI));
        let f = fiber(
            rng.range(0.2, 0.9),
            rng.range(0.2, 0.9),
            Vec3::splat(rng.range(0.0, 3.0)),
            0.0,
        );
        let b = ChiangBsdf::new(&f, 0.0);
        let (x, y) = (b.eval(wo, wi), b.eval(wi, wo));
        assert!(
            (x - y).abs().max_element() <= 1e-4 * x.max_element().max(1e-3),
            "{x} vs {y}"
        );
        let r_only = fiber(f.beta_m, f.beta_n, Vec3::splat(1e4), 0.0);
        let h = rng.range(-1.0, 1.0);
        let x = ChiangBsdf::new(&r_only, h).eval(wo, wi);
        let y = ChiangBsdf::new(&r_only, -h).eval(wi, wo);
        assert!(
            (x - y).abs().max_element() <= 1e-4 * x.max_element().max(1e-3),
            "h {h}: {x} vs {y}"
        );
    }
}

/// Trace a 2D ray through the unit circle (index `eta_p`) entering at offset `h` and return the
/// azimuth change after `p` internal segments (p = 0: reflection), from Snell's law alone.
/// 2D vectors hold the local `(y, z)` components; the eye is at azimuth 0 (`+y`), and the
/// outward normal at the entry point is `(sqrt(1 - h²), -h)`, [`FiberFrame`]'s convention.
fn traced_deflection(h: f32, eta_p: f32, p: u32) -> f32 {
    use glam::Vec2;
    let reflect = |d: Vec2, n: Vec2| d - 2.0 * d.dot(n) * n;
    // n faces against d; eta = n_from / n_to.
    let refract = |d: Vec2, n: Vec2, eta: f32| {
        let c = -d.dot(n);
        let k = 1.0 - eta * eta * (1.0 - c * c);
        eta * d + (eta * c - k.max(0.0).sqrt()) * n
    };
    let d0 = Vec2::new(-1.0, 0.0);
    let entry = Vec2::new(safe_sqrt(1.0 - h * h), -h);
    let out = if p == 0 {
        reflect(d0, entry)
    } else {
        let mut d = refract(d0, entry, 1.0 / eta_p).normalize();
        let mut at = entry;
        for k in 0..p {
            at += -2.0 * at.dot(d) * d;
            d = if k + 1 == p {
                refract(d, -at, eta_p).normalize()
            } else {
                reflect(d, at)
            };
        }
        d
    };
    out.y.atan2(out.x)
}

#[test]
fn perfect_specular_azimuths_follow_snells_law() {
    // Φ(p) = 2p γt - 2γo + pπ against a ray traced through the circle.
    for h in [-0.9f32, -0.5, -0.1, 0.0, 0.2, 0.6, 0.95] {
        let eta_p = 1.6f32;
        let (gamma_o, gamma_t) = (safe_asin(h), safe_asin(h / eta_p));
        for p in 0..3 {
            let want = traced_deflection(h, eta_p, p);
            let got = (phi(p, gamma_o, gamma_t) + PI).rem_euclid(TAU) - PI;
            let d = (want - got + PI).rem_euclid(TAU) - PI;
            assert!(d.abs() < 1e-4, "h {h} p {p}: traced {want}, Φ {got}");
        }
    }
}

#[test]
fn r_lobe_is_the_mirror_reflection_about_the_hit_normal() {
    // A smooth opaque fibre (only R survives): every sampled direction lies within a degree of
    // the mirror direction of the camera ray about the surface normal at the hit, so the frame's
    // h has the right sign.
    let f = fiber(0.01, 0.01, Vec3::splat(1e4), 0.0);
    let mut rng = Rng::new(9);
    for _ in 0..300 {
        let t = rng.on_sphere();
        let (u, w) = t.any_orthonormal_pair();
        let a = rng.range(0.0, TAU);
        let n = u * a.cos() + w * a.sin();
        // An eye direction on the normal's side, not along the tangent.
        let mut wo = (rng.on_sphere() + n * 1.2).normalize();
        wo = (wo - 0.7 * wo.dot(t) * t).normalize();
        if wo.dot(n) < 0.05 {
            continue;
        }
        let frame = FiberFrame::new(t, wo, n).expect("frame");
        let bsdf = ChiangBsdf::new(&f, frame.h);
        let mirror = -wo + 2.0 * wo.dot(n) * n;
        for _ in 0..4 {
            let s = bsdf
                .sample(frame.to_local(wo), rng.f32(), rng.f32(), rng.f32())
                .expect("sample");
            let wi = frame.to_world(s.wi);
            let angle = wi.angle_between(mirror).to_degrees();
            assert!(angle < 1.5, "h {}: {angle}°", frame.h);
        }
    }
}

/// `√(2/(9k))`-based Wilson–Hilferty quantile of the χ² distribution with `k` degrees of freedom
/// at the standard-normal quantile `z`.
fn chi2_quantile(k: f64, z: f64) -> f64 {
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3)
}

#[test]
fn sampled_directions_follow_the_evaluated_pdf() {
    // χ² test: 200,000 samples binned in (sin θi, φi - φo) against the pdf integrated over each
    // bin; bins expecting under 5 are pooled. Rejects at significance 1e-4.
    const N_S: usize = 12;
    const N_PHI: usize = 24;
    const SUB: usize = 12;
    const SAMPLES: usize = 200_000;
    let cases = [
        (
            0.3f32,
            0.3f32,
            sigma_a_from_melanin(1.3, 0.2),
            2.0f32,
            0.3f32,
            Vec3::new(0.2, 0.9, 0.3),
        ),
        (0.6, 0.5, Vec3::ZERO, 3.0, -0.7, Vec3::new(-0.5, 0.4, -0.7)),
        (
            0.2,
            0.8,
            sigma_a_from_melanin(0.3, 0.0),
            -2.0,
            0.95,
            Vec3::new(0.7, -0.1, 0.7),
        ),
        (
            0.9,
            0.2,
            Vec3::new(0.1, 0.5, 2.0),
            1.0,
            0.0,
            Vec3::new(0.0, 0.3, -0.95),
        ),
    ];
    let mut rng = Rng::new(17);
    for (beta_m, beta_n, sigma_a, alpha, h, wo) in cases {
        let wo = wo.normalize();
        let bsdf = ChiangBsdf::new(&fiber(beta_m, beta_n, sigma_a, alpha), h);
        let phi_o = wo.z.atan2(wo.y);
        let bin = |w: Vec3| -> usize {
            let s = ((w.x + 1.0) * 0.5 * N_S as f32) as usize;
            let d = (w.z.atan2(w.y) - phi_o + PI).rem_euclid(TAU);
            let p = (d / TAU * N_PHI as f32) as usize;
            s.min(N_S - 1) * N_PHI + p.min(N_PHI - 1)
        };
        let mut observed = vec![0.0f64; N_S * N_PHI];
        for _ in 0..SAMPLES {
            if let Some(s) = bsdf.sample(wo, rng.f32(), rng.f32(), rng.f32()) {
                observed[bin(s.wi)] += 1.0;
            }
        }
        let mut expected = vec![0.0f64; N_S * N_PHI];
        for i in 0..N_S * SUB {
            let s = -1.0 + 2.0 * (i as f32 + 0.5) / (N_S * SUB) as f32;
            for j in 0..N_PHI * SUB {
                let d = TAU * (j as f32 + 0.5) / (N_PHI * SUB) as f32;
                let w = local(s, phi_o - PI + d);
                let dw = 2.0 / (N_S * SUB) as f64 * std::f64::consts::TAU / (N_PHI * SUB) as f64;
                expected[(i / SUB) * N_PHI + j / SUB] += f64::from(bsdf.pdf(wo, w)) * dw;
            }
        }
        let total: f64 = expected.iter().sum();
        assert!((total - 1.0).abs() < 5e-3, "∫ pdf = {total}");
        let (mut chi2, mut dof, mut pooled_o, mut pooled_e) = (0.0, 0usize, 0.0, 0.0);
        for (o, e) in observed.iter().zip(&expected) {
            let e = e * SAMPLES as f64;
            if e < 5.0 {
                pooled_o += o;
                pooled_e += e;
            } else {
                chi2 += (o - e) * (o - e) / e;
                dof += 1;
            }
        }
        if pooled_e >= 5.0 {
            chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
            dof += 1;
        }
        let k = (dof - 1) as f64;
        let limit = chi2_quantile(k, 3.719);
        assert!(
            chi2 < limit,
            "βm {beta_m} βn {beta_n} h {h}: χ² {chi2:.1} > {limit:.1} ({k} dof)"
        );
    }
}

#[test]
fn absorption_only_takes_light_away() {
    // Per channel: R alone (an opaque fibre) ≤ brown ≤ clear in every direction; the light
    // through the fibre (TT) is red-brown.
    let opaque = ChiangBsdf::new(&fiber(0.3, 0.3, Vec3::splat(1e4), 2.0), 0.2);
    let brown = ChiangBsdf::new(&fiber(0.3, 0.3, sigma_a_from_melanin(1.3, 0.2), 2.0), 0.2);
    let clear = ChiangBsdf::new(&fiber(0.3, 0.3, Vec3::ZERO, 2.0), 0.2);
    let wo = local(0.1, 0.0);
    for i in 0..20 {
        for j in 0..40 {
            let wi = local(-0.95 + 0.1 * i as f32, TAU * j as f32 / 40.0);
            let (r, b, c) = (opaque.eval(wo, wi), brown.eval(wo, wi), clear.eval(wo, wi));
            let tol = 1e-6 * c.max_element();
            assert!(
                (r - b).max_element() <= tol && (b - c).max_element() <= tol,
                "{r} {b} {c}"
            );
        }
    }
    let tt = brown.eval(wo, local(-0.1, PI - 0.3));
    assert!(tt.x > tt.y && tt.y > tt.z, "{tt}");
}

#[test]
fn karis_and_chiang_tilt_the_r_lobe_the_same_way() {
    // The real-time R lobe (tress-shading's Karis twin) and the reference's move their peak by
    // the same amount in the same direction when the cuticle tilts, for the tangent from root
    // to tip: the two models share the sign convention.
    use tress_shading::marschner::{Marschner, hair_angles, marschner_r};
    let peak = |f: &dyn Fn(f32) -> f32| -> f32 {
        (-900..=900)
            .map(|k| k as f32 / 1000.0)
            .max_by(|&a, &b| f(a).total_cmp(&f(b)))
            .unwrap()
    };
    for theta_o in [-0.5f32, -0.1, 0.3] {
        let wo = local(theta_o.sin(), 0.0);
        let at = |alpha: f32| {
            let fib = fiber(0.2, 0.3, Vec3::splat(1e4), alpha);
            let bsdf = ChiangBsdf::new(&fib, 0.0);
            let m = Marschner::from_fiber(&fib);
            let chiang = peak(&|s| bsdf.eval(wo, local(s, 0.0)).x);
            let karis = peak(&|s| marschner_r(&m, &hair_angles(Vec3::X, local(s, 0.0), wo)));
            (chiang, karis)
        };
        let (c0, k0) = at(0.0);
        let (c3, k3) = at(3.0);
        let (dc, dk) = (c3 - c0, k3 - k0);
        assert!(
            dc > 0.0 && dk > 0.0,
            "θo {theta_o}: chiang {dc}, karis {dk}"
        );
        assert!(
            (dc - dk).abs() < 0.3 * dk,
            "θo {theta_o}: chiang {dc}, karis {dk}"
        );
        // Untilted, both peak on the specular cone sin θi = -sin θo.
        assert!((c0 + theta_o.sin()).abs() < 0.02 && (k0 + theta_o.sin()).abs() < 0.02);
    }
}
