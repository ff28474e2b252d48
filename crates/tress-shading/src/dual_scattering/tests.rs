use super::*;
use crate::fiber::{HairFiber, sigma_a_from_melanin};
use crate::marschner::marschner_lighting;

fn lobes(eumelanin: f32) -> Marschner {
    Marschner::from_fiber(&HairFiber {
        sigma_a: sigma_a_from_melanin(eumelanin, 0.1 * eumelanin),
        ..HairFiber::default()
    })
}

fn dir(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin(),
        theta.cos() * phi.cos(),
        theta.cos() * phi.sin(),
    )
}

#[test]
fn zinke_backscatter_terms_by_hand() {
    // a_f = 0.5, a_b = 0.2: A_1 = 0.2·0.25/0.75, A_3 = 0.008·0.25/0.75³.
    let want = 0.2 * 0.25 / 0.75 + 0.008 * 0.25 / 0.421_875;
    assert!((backscatter_attenuation(0.5, 0.2) - want).abs() < 1e-7);
    // Δb = α_b (1 - 2·0.04/0.5625) + α_f (2·0.5625 + 4·0.25·0.04) / 0.421875.
    let (af, ab) = (0.5f32, 0.2f32);
    let want = 0.03 * (1.0 - 0.08 / 0.5625) + (-0.01) * (1.125 + 0.04) / 0.421_875;
    assert!((backscatter_shift(af, ab, -0.01, 0.03) - want).abs() < 1e-7);
    // σb with β_f = 0.1, β_b = 0.2.
    let num = 0.2 * (0.02f32 + 0.04).sqrt() + 0.008 * (0.02f32 + 0.12).sqrt();
    let den = 0.2 + 0.008 * (0.2 + 0.6);
    let want = (1.0 + 0.7 * 0.25) * num / den;
    assert!((backscatter_deviation(af, ab, 0.1, 0.2) - want).abs() < 1e-6);
    // No backward scattering, no backscattered light.
    assert_eq!(backscatter_attenuation(0.7, 0.0), 0.0);
}

#[test]
fn averages_are_fractions_of_the_light() {
    for mel in [0.0f32, 0.3, 1.3, 8.0] {
        let m = lobes(mel);
        let ds = DualScattering::from_marschner(&m);
        for k in 0..DS_TABLE {
            let a = ds.at(table_sin(k));
            for c in 0..3 {
                assert!((0.0..=MAX_A_F).contains(&a.a_f[c]), "melanin {mel}: {a:?}");
                assert!(a.a_b[c] >= 0.0 && a.sigma_b2[c] > 0.0 && a.delta_b[c].is_finite());
            }
            assert!(a.beta_f2 > 0.0);
            // Forward and backward halves together hold at most the incident light (Karis's
            // fits scatter up to 0.5% too much for a white fibre).
            let h = angle_averages(&m, table_sin(k));
            assert!((h.a_f + h.a_b).max_element() <= 1.01, "{h:?}");
        }
        assert!(
            ds.params.x > 0.0 && ds.params.y == DENSITY_FORWARD && ds.params.z == DENSITY_BACKWARD
        );
    }
}

#[test]
fn table_reads_its_entries_and_interpolates_the_integrals() {
    let m = Marschner::default();
    let ds = DualScattering::from_marschner(&m);
    for k in 0..DS_TABLE {
        let a = ds.at(table_sin(k));
        assert!((a.a_f - ds.a_f[k].truncate()).abs().max_element() < 1e-6);
    }
    // Between entries the interpolated a_f is within 3% of the integral at that angle.
    for deg in [-55.0f32, -33.0, -12.0, 5.0, 27.0, 48.0] {
        let s = deg.to_radians().sin();
        let (table, exact) = (ds.at(s).a_f, angle_averages(&m, s).a_f);
        assert!(
            ((table - exact) / exact).abs().max_element() < 0.03,
            "{deg}°: {table} vs {exact}"
        );
    }
    // Beyond the outer entries the table is clamped.
    assert_eq!(ds.at(1.0), ds.at(table_sin(DS_TABLE - 1)));
    assert_eq!(ds.at(-1.0), ds.at(table_sin(0)));
}

#[test]
fn darker_hair_passes_and_returns_less_light() {
    let light = DualScattering::from_marschner(&lobes(0.3)).at(0.1);
    let dark = DualScattering::from_marschner(&lobes(4.0)).at(0.1);
    assert!(dark.a_f.max_element() < light.a_f.min_element());
    assert!(dark.a_b.max_element() < light.a_b.min_element());
    // Melanin passes red best.
    assert!(light.a_f.x > light.a_f.y && light.a_f.y > light.a_f.z);
}

#[test]
fn forward_light_is_carried_by_tt() {
    // The forward half is TT's (shift -α); the backward half R's and TRT's (2α, -4α).
    let m = lobes(0.3);
    let a = angle_averages(&m, 0.0);
    assert!(a.alpha_f < 0.0 && a.alpha_f > -1.5 * m.alpha, "{a:?}");
    assert!(a.beta_f2 < m.beta.x * m.beta.x, "{a:?}");
    assert!(a.beta_b2 > a.beta_f2);
}

#[test]
fn unshadowed_light_adds_only_local_backscatter() {
    let m = lobes(1.3);
    let ds = DualScattering::from_marschner(&m);
    let (t, c) = (Vec3::X, Vec3::new(1.0, 0.9, 0.8));
    for (l, v) in [
        (dir(0.3, 0.0), dir(-0.2, 0.4)),
        (dir(-0.5, 1.0), dir(0.4, 3.0)),
    ] {
        let single = marschner_lighting(&m, t, l, c, v);
        let full = dual_scattering_lighting(&m, &ds, t, l, c, v, 0.0, 1.0);
        let extra = full - single;
        assert!(extra.min_element() >= 0.0, "{extra}");
        // The extra light is the backscatter lobe: at most d_b A_b g_max (times π c / π).
        let at = ds.at(l.x);
        let g_max = (at.sigma_b2 * TAU).powf(-0.5);
        let bound = ds.params.z * at.a_b * g_max * c;
        assert!((extra - bound).max_element() <= 1e-6, "{extra} vs {bound}");
        // The result is linear in the unscattered fraction.
        let at_v = |d: f32| dual_scattering_lighting(&m, &ds, t, l, c, v, 0.0, d);
        let mid = 0.5 * (at_v(0.0) + at_v(1.0));
        assert!((at_v(0.5) - mid).abs().max_element() < 1e-6);
    }
}

#[test]
fn light_fades_with_the_strands_it_crosses() {
    let m = lobes(0.3);
    let ds = DualScattering::from_marschner(&m);
    let (t, l, v) = (Vec3::X, dir(0.2, 0.0), dir(-0.1, 2.8));
    let c = Vec3::ONE;
    let at = |n: f32| dual_scattering_lighting(&m, &ds, t, l, c, v, n, 0.0);
    let mut last = at(1.0);
    assert!(last.min_element() > 0.0);
    for n in [2.0f32, 4.0, 8.0, 16.0, 32.0] {
        let now = at(n);
        assert!(
            now.max_element() < last.max_element(),
            "n {n}: {now} vs {last}"
        );
        last = now;
    }
    assert!(at(400.0).max_element() < 1e-6 * at(1.0).max_element());
    // Light hair lets more through than dark hair.
    let dark = lobes(4.0);
    let dds = DualScattering::from_marschner(&dark);
    let d = dual_scattering_lighting(&dark, &dds, t, l, c, v, 4.0, 0.0);
    assert!(d.max_element() < at(4.0).min_element());
}

#[test]
fn backscatter_lobe_holds_a_b() {
    // ∫ d_b f_back (1 + cos φ)/2π dω = d_b A_b · (the Gaussian's mass over the reachable
    // sin θi + sin θo ∈ [sin θi - 1, sin θi + 1]).
    let m = lobes(0.3);
    let ds = DualScattering::from_marschner(&m);
    let l = dir(0.25, 0.0);
    let at = ds.at(l.x);
    let n = 240;
    let mut sum = Vec3::ZERO;
    for i in 0..n {
        let s = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
        for j in 0..n {
            let phi = TAU * (j as f32 + 0.5) / n as f32;
            let v = dir(s.asin(), phi);
            let full = dual_scattering_lighting(&m, &ds, Vec3::X, l, Vec3::ONE, v, 0.0, 1.0);
            let single = marschner_lighting(&m, Vec3::X, l, Vec3::ONE, v);
            sum += (full - single) / PI;
        }
    }
    let energy = sum * (2.0 / n as f32) * (TAU / n as f32) / ds.params.z;
    let k = 4000;
    let mut mass = Vec3::ZERO;
    for i in 0..k {
        let x = l.x - 1.0 + 2.0 * (i as f32 + 0.5) / k as f32;
        mass += gaussian3(at.sigma_b2, Vec3::splat(x) - at.delta_b) * (2.0 / k as f32);
    }
    let want = at.a_b * mass;
    assert!(
        (energy - want).abs().max_element() < 0.01 * want.max_element(),
        "{energy} vs {want}"
    );
    assert!(mass.min_element() > 0.5 && mass.max_element() < 1.0);
}
