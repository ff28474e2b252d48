// Test harness: evaluates every function of shading.wgsl on a grid of inputs (one invocation per
// case) so tests/shading_gpu.rs can compare with the CPU twins in tress-shading.

#include "common/shading.wgsl"

struct Case {
    // tangent, specular exponent
    t: vec4f,
    // towards the light, tangent shift
    l: vec4f,
    // towards the eye, alpha
    v: vec4f,
    // normal (perpendicular to t), distance / depth d
    n: vec4f,
    // r, line thickness, strand thickness, shift texture value
    s: vec4f,
    // color, spec mask
    c: vec4f,
    // world point (w = 1)
    p: vec4f,
    // screen fragment (xy), depth-map texel (zw)
    f: vec4f,
    // premultiplied accumulator
    acc: vec4f,
    // PCF kernel radius, fragment depth for PCF, second color (yzw is unused)
    k: vec4f,
}

struct Harness {
    clip_from_world: mat4x4f,
    resolution: vec4f,
    // HairLighting, packed by rows of four
    h0: vec4f,
    h1: vec4f,
    h2: vec4f,
    h3: vec4f,
}

@group(0) @binding(0) var<storage, read> cases: array<Case>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4f>;
@group(0) @binding(2) var<uniform> harness: Harness;
@group(0) @binding(3) var depth_map: texture_depth_2d;

const OUTPUTS: u32 = 12u;

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
    let n = c.n.xyz;
    let exponent = c.t.w;
    let alpha = c.v.w;
    let d = c.n.w;
    let r = c.s.x;
    let line = c.s.y;
    let res = harness.resolution.xy;
    let lighting = HairLighting(
        harness.h0.xyz, harness.h0.w, harness.h1.xyz, harness.h1.w, harness.h2.xyz, harness.h2.w,
        harness.h3.x);
    let kk = KajiyaKay(c.c.xyz, vec3f(0.3, 0.35, 0.4), exponent);
    let sample = HairSample(t, c.s.w, n, c.c.w, c.c.xyz, 0.8);

    results[o + 0u] = vec4f(
        kajiya_kay_diffuse(t, l), kajiya_kay_specular(t, l, v, exponent), scheuermann_diffuse(n, l),
        strand_specular(t, v, l, exponent));
    results[o + 1u] = vec4f(kajiya_kay(kk, t, l, v), sin_from_cos(dot(t, l)));
    results[o + 2u] = vec4f(shift_tangent(t, n, c.l.w), 0.0);
    results[o + 3u] = vec4f(hair_lighting(lighting, sample, l, vec3f(1.0, 0.9, 0.8), v), 0.0);
    results[o + 4u] = vec4f(
        coverage_from_distance(d, line), tip_fade(c.s.z, line), strand_visibility(d * r, alpha),
        adsm_visibility(d, r, alpha));
    results[o + 5u] = vec4f(
        screen_from_clip(harness.clip_from_world * c.p, res),
        strand_coverage(c.f.xy, c.p, harness.clip_from_world, res, line),
        adsm_depth(c.k.y, d));
    results[o + 6u] = blend_under(c.acc, vec4f(c.c.xyz * alpha, alpha));
    results[o + 7u] = blend_front_to_back(c.acc, c.c.xyz, alpha);
    var tail = tail_empty();
    tail = tail_accumulate(tail, c.c.xyz, alpha);
    tail = tail_accumulate(tail, c.k.yzw, c.s.w);
    tail = tail_accumulate(tail, v * 0.5 + 0.5, d);
    results[o + 8u] = vec4f(tail.weighted_color, tail.alpha_sum);
    results[o + 9u] = vec4f(tail_resolve(tail).xyz, tail.transmittance);
    results[o + 10u] = vec4f(composite_over_background(c.acc, c.c.xyz), tail_resolve(tail).w);
    let spread = spread_kajiya_kay(KajiyaKay(c.c.xyz, vec3f(0.7, 0.5, 0.3), c.t.w), c.s.w * 1.2 - 0.1);
    results[o + 11u] = vec4f(
        adsm_pcf(depth_map, vec2i(c.f.zw), i32(c.k.x), c.k.y, r, alpha),
        spread.exponent, spread.specular.y, spread.diffuse.x);
}

// A depth-map writer: a fullscreen triangle whose fragments take their depth from a buffer.
@group(1) @binding(0) var<storage, read> map_depths: array<f32>;

@vertex
fn vs_fill(@builtin(vertex_index) i: u32) -> @builtin(position) vec4f {
    let uv = vec2f(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4f(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_fill(@builtin(position) p: vec4f) -> @builtin(frag_depth) f32 {
    return map_depths[u32(p.y) * 8u + u32(p.x)];
}
