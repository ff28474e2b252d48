// Physically based hair for the real-time techniques: Marschner's R, TT and TRT lobes with
// Karis 2016's approximations, and a dual-scattering multiple-scattering term after Zinke et al.
// 2008 driven by the strands between the point and the light. WGSL twins of
// tress-shading's marschner.rs and dual_scattering.rs (same names, arguments and fields; the
// formulas, their sources and the choices made are documented there). Directions point away
// from the shaded point; t is the unit tangent from root to tip. Include-only: no bindings.

const MARSCHNER_PI: f32 = 3.14159265358979;
const MARSCHNER_TAU: f32 = 6.28318530717959;

// Per-material lobe parameters (32 bytes): absorption per fibre radius, index of refraction,
// longitudinal widths (R, TT, TRT) and the cuticle tilt in radians.
struct Marschner {
    sigma_a: vec3f,
    eta: f32,
    beta: vec3f,
    alpha: f32,
}

struct HairAngles {
    sin_theta_i: f32,
    sin_theta_o: f32,
    cos_theta_d: f32,
    cos_phi: f32,
    cos_half_phi: f32,
    cos_half_lv: f32,
}

// The angles every lobe needs (Karis's guard keeps cos φ finite along the tangent).
fn hair_angles(t: vec3f, l: vec3f, v: vec3f) -> HairAngles {
    let sin_theta_i = clamp(dot(t, l), -1.0, 1.0);
    let sin_theta_o = clamp(dot(t, v), -1.0, 1.0);
    let cos_theta_i = sqrt(max(1.0 - sin_theta_i * sin_theta_i, 0.0));
    let cos_theta_o = sqrt(max(1.0 - sin_theta_o * sin_theta_o, 0.0));
    let cos_2theta_d = cos_theta_o * cos_theta_i + sin_theta_o * sin_theta_i;
    let cos_theta_d = sqrt(max(0.5 + 0.5 * cos_2theta_d, 0.0));
    let lp = l - sin_theta_i * t;
    let vp = v - sin_theta_o * t;
    let cos_phi = clamp(
        dot(lp, vp) / sqrt(dot(lp, lp) * dot(vp, vp) + 1e-4), -1.0, 1.0);
    return HairAngles(
        sin_theta_i, sin_theta_o, cos_theta_d, cos_phi, sqrt(saturate(0.5 + 0.5 * cos_phi)),
        sqrt(saturate(0.5 + 0.5 * dot(l, v))));
}

// Karis's unit-area Gaussian g(β; x).
fn hair_gaussian(beta: f32, x: f32) -> f32 {
    return exp(-0.5 * x * x / (beta * beta)) / (sqrt(MARSCHNER_TAU) * beta);
}

// Schlick's Fresnel F0 + (1 - F0)(1 - cos)^5, F0 = ((η - 1)/(η + 1))².
fn fresnel_schlick(eta: f32, cos_theta: f32) -> f32 {
    let f0 = pow((eta - 1.0) / (eta + 1.0), 2.0);
    let c = 1.0 - saturate(cos_theta);
    return f0 + (1.0 - f0) * c * c * c * c * c;
}

// 1/η' with Bravais' η' = sqrt(η² - sin² θd) / cos θd.
fn marschner_inv_eta_prime(eta: f32, cos_theta_d: f32) -> f32 {
    let sin2 = 1.0 - cos_theta_d * cos_theta_d;
    return cos_theta_d / sqrt(max(eta * eta - sin2, 1e-8));
}

// Transmittance of one crossing at azimuthal offset h: exp(-σa · 2 cos γt / cos θt).
fn marschner_crossing(m: Marschner, a: HairAngles, h: f32, inv_eta_p: f32) -> vec3f {
    let cos_gamma_t = sqrt(max(1.0 - h * h * inv_eta_p * inv_eta_p, 0.0));
    let sin_theta_d2 = 1.0 - a.cos_theta_d * a.cos_theta_d;
    let cos_theta_t = sqrt(max(1.0 - sin_theta_d2 / (m.eta * m.eta), 1e-8));
    let path_length = 2.0 * cos_gamma_t / cos_theta_t;
    return exp(-m.sigma_a * path_length);
}

// R: M_R N_R A_R.
fn marschner_r(m: Marschner, a: HairAngles) -> f32 {
    let mp = hair_gaussian(m.beta.x, a.sin_theta_i + a.sin_theta_o - 2.0 * m.alpha);
    let np = 0.25 * a.cos_half_phi;
    let ap = fresnel_schlick(m.eta, a.cos_half_lv);
    return mp * np * ap;
}

// TT: M_TT N_TT A_TT.
fn marschner_tt(m: Marschner, a: HairAngles) -> vec3f {
    let mp = hair_gaussian(m.beta.y, a.sin_theta_i + a.sin_theta_o + m.alpha);
    let inv_eta_p = marschner_inv_eta_prime(m.eta, a.cos_theta_d);
    let h = a.cos_half_phi * (1.0 + inv_eta_p * (0.6 - 0.8 * a.cos_phi));
    let f = fresnel_schlick(m.eta, a.cos_theta_d * sqrt(max(1.0 - h * h, 0.0)));
    let np = exp(-3.65 * a.cos_phi - 3.98);
    return mp * np * (1.0 - f) * (1.0 - f) * marschner_crossing(m, a, h, inv_eta_p);
}

// TRT: M_TRT N_TRT A_TRT.
fn marschner_trt(m: Marschner, a: HairAngles) -> vec3f {
    let mp = hair_gaussian(m.beta.z, a.sin_theta_i + a.sin_theta_o + 4.0 * m.alpha);
    let inv_eta_p = marschner_inv_eta_prime(m.eta, a.cos_theta_d);
    let f = fresnel_schlick(m.eta, 0.5 * a.cos_theta_d);
    let tr = marschner_crossing(m, a, 0.5 * sqrt(3.0), inv_eta_p);
    let np = exp(17.0 * a.cos_phi - 16.78);
    return mp * np * (1.0 - f) * (1.0 - f) * f * tr * tr;
}

// S(l, v) = R + TT + TRT, per solid angle.
fn marschner(m: Marschner, t: vec3f, l: vec3f, v: vec3f) -> vec3f {
    let a = hair_angles(t, l, v);
    return vec3f(marschner_r(m, a)) + marschner_tt(m, a) + marschner_trt(m, a);
}

// Radiance from one light of tress radiance light_color: π · S · light_color.
fn marschner_lighting(m: Marschner, t: vec3f, l: vec3f, light_color: vec3f, v: vec3f) -> vec3f {
    return MARSCHNER_PI * marschner(m, t, l, v) * light_color;
}

// Per-material dual-scattering averages over 16 light angles sin θi (1072 bytes):
// a_f (rgb) and βf² (w); A_b; Δb; σb²; (⟨N_R A_R⟩, d_f, d_b, 0); ⟨N_TT A_TT⟩; ⟨N_TRT A_TRT⟩.
struct DualScattering {
    a_f: array<vec4f, 16>,
    a_b: array<vec4f, 16>,
    delta_b: array<vec4f, 16>,
    sigma_b2: array<vec4f, 16>,
    params: vec4f,
    tt_avg: vec4f,
    trt_avg: vec4f,
}

struct DualScatteringAt {
    a_f: vec3f,
    beta_f2: f32,
    a_b: vec3f,
    delta_b: vec3f,
    sigma_b2: vec3f,
}

// The table read at sin θi, linear between entries, clamped at the ends.
fn dual_scattering_at(ds: DualScattering, sin_theta_i: f32) -> DualScatteringAt {
    var table = ds;
    let r = ds_rows(sin_theta_i);
    return ds_table_mix(
        table.a_f[r.i], table.a_f[r.j], table.a_b[r.i], table.a_b[r.j], table.delta_b[r.i],
        table.delta_b[r.j], table.sigma_b2[r.i], table.sigma_b2[r.j], r.f);
}

// The table position of sin θi: entry `floor(x)`, then `fract(x)` of the way to the next.
fn ds_table_x(sin_theta_i: f32) -> f32 {
    return clamp((sin_theta_i + 1.0) * 0.5 * 16.0 - 0.5, 0.0, 15.0);
}

// The two table rows sin θi lies between, `i` and `j` (the next, clamped at the end), and the
// fraction `f` of the way from `i` to `j`.
struct DsRows {
    i: u32,
    j: u32,
    f: f32,
}

fn ds_rows(sin_theta_i: f32) -> DsRows {
    let x = ds_table_x(sin_theta_i);
    let i = min(u32(floor(x)), 15u);
    return DsRows(i, min(i + 1u, 15u), x - f32(i));
}

// The table's rows i and j mixed by f.
fn ds_table_mix(
    a_f_i: vec4f, a_f_j: vec4f, a_b_i: vec4f, a_b_j: vec4f, delta_b_i: vec4f,
    delta_b_j: vec4f, sigma_b2_i: vec4f, sigma_b2_j: vec4f, f: f32) -> DualScatteringAt {
    let a_f = mix(a_f_i, a_f_j, f);
    return DualScatteringAt(
        a_f.xyz, a_f.w, mix(a_b_i, a_b_j, f).xyz, mix(delta_b_i, delta_b_j, f).xyz,
        mix(sigma_b2_i, sigma_b2_j, f).xyz);
}

fn ds_gaussian3(var2: vec3f, x: vec3f) -> vec3f {
    return vec3f(
        hair_gaussian(sqrt(var2.x), x.x), hair_gaussian(sqrt(var2.y), x.y),
        hair_gaussian(sqrt(var2.z), x.z));
}

// The single scattering of light spread by σ̄f² = spread2 (`params`, `tt_avg`, `trt_avg` of
// the material's `DualScattering`).
fn ds_spread_single_scattering(
    m: Marschner, params: vec4f, tt_avg: vec4f, trt_avg: vec4f, a: HairAngles, spread2: f32) -> vec3f {
    let sum = a.sin_theta_i + a.sin_theta_o;
    let shifts = vec3f(2.0 * m.alpha, -m.alpha, -4.0 * m.alpha);
    let g_r = hair_gaussian(sqrt(m.beta.x * m.beta.x + spread2), sum - shifts.x);
    let g_tt = hair_gaussian(sqrt(m.beta.y * m.beta.y + spread2), sum - shifts.y);
    let g_trt = hair_gaussian(sqrt(m.beta.z * m.beta.z + spread2), sum - shifts.z);
    return vec3f(g_r * params.x) + g_tt * tt_avg.xyz + g_trt * trt_avg.xyz;
}

// Radiance from one light with single and multiple scattering: `strands` hairs between the
// point and the light, a fraction `direct` of the light unscattered (the shadow visibility).
fn dual_scattering_lighting(
    m: Marschner, ds: DualScattering, t: vec3f, l: vec3f, light_color: vec3f, v: vec3f,
    strands: f32, direct: f32) -> vec3f {
    let at = dual_scattering_at(ds, hair_angles(t, l, v).sin_theta_i);
    return ds_lighting_at(
        m, ds.params, ds.tt_avg, ds.trt_avg, at, t, l, light_color, v, strands, direct);
}

// `dual_scattering_lighting` with the table already read at the light's sin θi (`at`) and the
// table's `params`, `tt_avg`, `trt_avg`. The render passes call this with the material's rows
// read from the uniform one by one: passing the 1 KB table by value made lavapipe load it for
// every fragment, whatever the shading (the bear's ShortCut shade pass 63 s instead of 10 s).
fn ds_lighting_at(
    m: Marschner, params: vec4f, tt_avg: vec4f, trt_avg: vec4f, at: DualScatteringAt,
    t: vec3f, l: vec3f, light_color: vec3f, v: vec3f, strands: f32, direct: f32) -> vec3f {
    let a = hair_angles(t, l, v);
    let single = vec3f(marschner_r(m, a)) + marschner_tt(m, a) + marschner_trt(m, a);
    let d_f = params.y;
    let d_b = params.z;
    let n = max(strands, 0.0);
    let sum = vec3f(a.sin_theta_i + a.sin_theta_o);
    let back = at.a_b * ds_gaussian3(at.sigma_b2, sum - at.delta_b);
    let f_direct = direct * (single + d_b * back * ((1.0 + a.cos_phi) / MARSCHNER_TAU));
    let t_f = pow(max(at.a_f, vec3f(1e-8)), vec3f(n));
    let spread2 = n * at.beta_f2;
    let back_spread = at.a_b * ds_gaussian3(at.sigma_b2 + vec3f(spread2), sum - at.delta_b);
    let f_scatter = max(t_f - vec3f(direct), vec3f(0.0)) * d_f
        * (ds_spread_single_scattering(m, params, tt_avg, trt_avg, a, spread2)
            + d_b * back_spread / MARSCHNER_TAU);
    return MARSCHNER_PI * light_color * (f_direct + f_scatter);
}
