// Test harness: evaluates every function of marschner.wgsl on a grid of inputs (one invocation
// per case) so tests/marschner_gpu.rs can compare with the CPU twins in tress-shading.

#include "common/marschner.wgsl"

struct Case {
    // tangent, strands in the light's way
    t: vec4f,
    // towards the light, unscattered fraction
    l: vec4f,
    // towards the eye, sin θi for dual_scattering_at
    v: vec4f,
    // Marschner: sigma_a, eta
    m0: vec4f,
    // Marschner: beta, alpha
    m1: vec4f,
    // light color, Gaussian argument x
    c: vec4f,
    // Gaussian width, Fresnel eta, Fresnel cosine, unused
    g: vec4f,
}

@group(0) @binding(0) var<storage, read> cases: array<Case>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4f>;
@group(0) @binding(2) var<uniform> ds: DualScattering;

const OUTPUTS: u32 = 10u;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let c = cases[i];
    let o = i * OUTPUTS;
    let t = c.t.xyz;
    let l = c.l.xyz;
    let v = c.v.xyz;
    let m = Marschner(c.m0.xyz, c.m0.w, c.m1.xyz, c.m1.w);
    let a = hair_angles(t, l, v);
    let at = dual_scattering_at(ds, c.v.w);
    results[o + 0u] = vec4f(a.sin_theta_i, a.sin_theta_o, a.cos_theta_d, a.cos_phi);
    results[o + 1u] = vec4f(
        a.cos_half_phi, a.cos_half_lv, hair_gaussian(c.g.x, c.c.w), fresnel_schlick(c.g.y, c.g.z));
    results[o + 2u] = vec4f(marschner_r(m, a), marschner_tt(m, a));
    results[o + 3u] = vec4f(marschner_trt(m, a), 0.0);
    results[o + 4u] = vec4f(marschner(m, t, l, v), 0.0);
    results[o + 5u] = vec4f(marschner_lighting(m, t, l, c.c.xyz, v), 0.0);
    results[o + 6u] = vec4f(
        dual_scattering_lighting(m, ds, t, l, c.c.xyz, v, c.t.w, c.l.w), 0.0);
    results[o + 7u] = vec4f(at.a_f, at.beta_f2);
    results[o + 8u] = vec4f(at.a_b, at.delta_b.x);
    results[o + 9u] = vec4f(at.sigma_b2, at.delta_b.y);
}
