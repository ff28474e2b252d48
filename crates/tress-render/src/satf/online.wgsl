// The online phase's per-point math (Xu et al. 2006 §6.2-6.5, equations 6-14): the WGSL twins of
// tress_satf::online, tress_satf::database (eq. 6-7) and tress_satf::hrir (angle bins, straight
// reflectance). Same names with a `satf_` prefix, same arguments; tests/satf_math.rs evaluates
// each on the GPU and compares with the CPU. Pure functions only: no bindings.
//
// Conventions (see tress_satf::online): directions point away from the shaded point (l to the
// light, v to the eye), t is the unit hair tangent root to tip, n the layer's unit outward
// normal. Azimuths are measured in the normal plane from n toward the sector's s axis.

#include "common/shading.wgsl"

const SATF_PI: f32 = 3.14159265358979;
const SATF_TAU: f32 = 6.28318530717959;

// Params(b) = (rho_feature, theta_v, theta_l) (section 6.2.1).
struct HsvParams {
    features: vec3f,
    theta_v: f32,
    theta_l: f32,
}

// Rust's f32::round: half away from zero (WGSL's round is half to even).
fn satf_round(x: f32) -> f32 {
    return sign(x) * floor(abs(x) + 0.5);
}

// online::azimuth: the azimuth of `dir` in the normal plane, in (-pi, pi].
fn satf_azimuth(dir: vec3f, normal: vec3f, s_axis: vec3f) -> f32 {
    return atan2(dot(dir, s_axis), dot(dir, normal));
}

// hrir::angle_bin: the nearest of `count` bins -pi + 2 pi a / count to `theta` (wraps).
fn satf_angle_bin(theta: f32, count: u32) -> u32 {
    let c = f32(count);
    let x = satf_round((theta + SATF_PI) / SATF_TAU * c);
    let w = x - c * floor(x / c);
    return min(u32(w), count - 1u);
}

// database::angle_difference: a - b wrapped to [-pi, pi].
fn satf_angle_difference(a: f32, b: f32) -> f32 {
    let d0 = a - b;
    var d = d0 - SATF_TAU * floor(d0 / SATF_TAU);
    if d > SATF_PI {
        d = d - SATF_TAU;
    }
    return d;
}

// database::params_distance: the weighted norm ||Params(a) - Params(b)|| of equation 6.
fn satf_params_distance(a: HsvParams, b: HsvParams, weights: vec3f, angle_weight: f32) -> f32 {
    let df = a.features - b.features;
    let f = weights.x * df.x * df.x + weights.y * df.y * df.y + weights.z * df.z * df.z;
    let dv = satf_angle_difference(a.theta_v, b.theta_v);
    let dl = satf_angle_difference(a.theta_l, b.theta_l);
    return sqrt(f + angle_weight * angle_weight * (dv * dv + dl * dl));
}

// Equation 6 (database::is_uniform): ||Params(b_top) - Params(b_bottom)|| < k_threshold.
fn satf_is_uniform(top: HsvParams, bottom: HsvParams, weights: vec3f, angle_weight: f32, k_threshold: f32) -> bool {
    return satf_params_distance(top, bottom, weights, angle_weight) < k_threshold;
}

// database::average_params: Params_ave of section 6.2.2 (angles averaged on the circle).
fn satf_average_params(a: HsvParams, b: HsvParams) -> HsvParams {
    var out: HsvParams;
    out.features = 0.5 * (a.features + b.features);
    out.theta_v = a.theta_v + 0.5 * satf_angle_difference(b.theta_v, a.theta_v);
    out.theta_l = a.theta_l + 0.5 * satf_angle_difference(b.theta_l, a.theta_l);
    return out;
}

// Equation 7 (database::interpolate_value): l(i, gamma) = c1 (1 - gamma) + c2 gamma.
fn satf_interpolate(c1: f32, c2: f32, gamma: f32) -> f32 {
    return c1 * (1.0 - gamma) + c2 * gamma;
}

// hrir::straight_reflectance: r^e / a^ clamped to 1; 0 where a^ = 0.
fn satf_straight_reflectance(re: f32, alpha: f32) -> f32 {
    if alpha > 1e-6 {
        return min(re / alpha, 1.0);
    }
    return 0.0;
}

// Equation 9: Y_dif = k_dif sin(t, l) f_dif.
fn satf_diffuse(t: vec3f, l: vec3f, k_dif: f32, f_dif: vec3f) -> vec3f {
    return k_dif * kajiya_kay_diffuse(t, l) * f_dif;
}

// Equation 10: the primary highlight with t~ = normalize(t + s n) (toward the tip).
fn satf_primary_specular(t: vec3f, n: vec3f, s: f32, l: vec3f, v: vec3f, k_spe: f32, k_h: f32, f_spe: vec3f) -> vec3f {
    let t_shift = shift_tangent(t, n, s);
    return k_spe * kajiya_kay_specular(t_shift, l, v, k_h) * f_spe;
}

// Equation 11: the secondary highlight with t~ = normalize(t - s n) (toward the root).
fn satf_secondary_specular(t: vec3f, n: vec3f, s: f32, l: vec3f, v: vec3f, k_spe: f32, k_h: f32, f_spe: vec3f) -> vec3f {
    let t_shift = shift_tangent(t, n, -s);
    return k_spe * kajiya_kay_specular(t_shift, l, v, k_h) * f_spe;
}

// The material of equations 8-11 (online::SatfLighting).
struct SatfLighting {
    k_dif: f32,
    f_dif: vec3f,
    k_spe1: f32,
    f_spe1: vec3f,
    primary_shift: f32,
    k_spe2: f32,
    f_spe2: vec3f,
    secondary_shift: f32,
    k_h: f32,
}

// Equation 8: Y_lighting = Y_dif + Y_speI + Y_speII for one light.
fn satf_lighting(p: SatfLighting, t: vec3f, n: vec3f, l: vec3f, v: vec3f) -> vec3f {
    return satf_diffuse(t, l, p.k_dif, p.f_dif)
        + satf_primary_specular(t, n, p.primary_shift, l, v, p.k_spe1, p.k_h, p.f_spe1)
        + satf_secondary_specular(t, n, p.secondary_shift, l, v, p.k_spe2, p.k_h, p.f_spe2);
}

// Equation 12 (online::transmittance) given the sum of the outer layers' alphas:
// approx 0: exp(-k_shadow sum); 1: max(0, 1 - k_shadow sum).
fn satf_transmittance(alpha_sum: f32, k_shadow: f32, approx: u32) -> f32 {
    if approx == 1u {
        return max(1.0 - k_shadow * alpha_sum, 0.0);
    }
    return exp(-k_shadow * alpha_sum);
}

// Equation 13: Y_shading = Y_lighting re tau.
fn satf_shading(lighting: vec3f, re: f32, tau: f32) -> vec3f {
    return lighting * re * tau;
}

// One step of equation 14 (online::blend_over): acc (1 - a) + Y a. The layer pass draws the
// premultiplied (Y a, a) with blend One / OneMinusSrcAlpha, which is this step.
fn satf_blend_over(acc: vec3f, color: vec3f, alpha: f32) -> vec3f {
    return acc * (1.0 - alpha) + color * alpha;
}
