// Test harness: evaluates the functions of common/volume.wgsl on a grid of inputs (one invocation
// per case) over a small density volume and its highlights, so tests/volume_shading_gpu.rs can
// compare them with the CPU twins in tress_shading::volume, tress_shading::voxelize and
// tress_shading::highlights.

#include "common/volume.wgsl"

struct Case {
    // voxel position, a step (voxels)
    x: vec4f,
    // unit direction, an offset (voxels)
    l: vec4f,
    // ao radius, ao samples, intensity, alpha
    ao: vec4f,
    // strands, iso, distance, near
    s: vec4f,
    // far, pixel x, pixel y, integer input
    p: vec4f,
}

@group(0) @binding(0) var<storage, read> cases: array<Case>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4f>;
@group(0) @binding(2) var volume: texture_3d<f32>;
@group(0) @binding(3) var volume_sampler: sampler;
@group(0) @binding(4) var highlights: texture_3d<f32>;

const OUTPUTS: u32 = 9u;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let c = cases[i];
    let o = i * OUTPUTS;
    let res = f32(textureDimensions(volume).x);
    // The test volume's texels count quarter strands.
    let vt = VolumeTexels(res, 0.25);
    let x = c.x.xyz;
    let l = c.l.xyz;
    let n = u32(c.p.w);
    results[o + 0u] = vec4f(
        volume_shadow_strands(volume, volume_sampler, vt, x, l, c.x.w, c.l.w, NO_CAP),
        volume_ao(volume, volume_sampler, vt, x, c.ao.x, u32(c.ao.y), c.ao.z, c.ao.w, NO_CAP),
        volume_density(volume, volume_sampler, vt, x),
        fake_transparency_alpha(c.s.x, c.s.y));
    results[o + 1u] = vec4f(density_gradient(volume, volume_sampler, vt, x), lod_factor(c.s.z, c.s.w, c.p.x));
    results[o + 2u] = vec4f(
        density_normal(density_gradient(volume, volume_sampler, vt, x), vec3f(0.0, 0.0, 1.0)),
        dither_threshold(vec2u(u32(c.p.y), u32(c.p.z))));
    results[o + 3u] = vec4f(ao_offset(n % 64u, 64u), f32(isqrt(n * 977u)));
    results[o + 4u] = vec4f(vec3f(quantize_tangent(l)), f32(voxel_hash(n) & 0xffffu));
    results[o + 5u] = vec4f(ray_box(x, l, vec3f(2.0), vec3f(res - 3.0)), dequantize_tangent(vec3f(200.0, 30.0, 510.0), 2.0).xy);
    // Capped at one strand per voxel (the ADSM-style occlusion).
    results[o + 6u] = vec4f(
        volume_shadow_strands(volume, volume_sampler, vt, x, l, c.x.w, c.l.w, 1.0),
        volume_ao(volume, volume_sampler, vt, x, c.ao.x, u32(c.ao.y), c.ao.z, c.ao.w, 1.0),
        composite_transmittance(c.s.x, c.s.y),
        f32(composite_point_reached(c.ao.w, n % 8u, 1u + n % 7u)));
    // ADSM's expected visibility: line width from the AO radius, ln_keep and bias from the
    // intensity and alpha inputs.
    results[o + 7u] = vec4f(
        volume_adsm_visibility(
            volume, volume_sampler, vt, x, l, c.x.w, c.l.w, 0.25 * c.ao.x, -c.ao.z, 2.0 * c.ao.w),
        decode_texel(encode_texel(l * c.ao.w, 1u + n % 300u), 0.5).xyz);
    // The strands' optical depth: no tangent on every eighth case.
    let tangent = select(l * c.ao.w, vec3f(0.0), n % 8u == 0u);
    results[o + 8u] = vec4f(
        strand_optical_depth(c.s.x, tangent, normalize(x - vec3f(8.0)), c.x.w, c.ao.x),
        volume_tangent_coherence(volume, volume_sampler, vt, x),
        volume_highlight(highlights, volume, vt, x, n % 4u),
        f32(quantize_highlight(c.ao.w)) * 1000.0 + f32(highlight_texel(n % 65025u, 255u + n % 65025u)));
}
