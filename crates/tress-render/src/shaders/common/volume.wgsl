// The hair volume shared by the voxelizer, the raymarcher and the rasterizer's volume shadows and
// ambient occlusion (Jansson 2019 §3.3-3.4). The functions are the WGSL twins of
// tress_shading::voxelize and tress_shading::volume (same names and arguments; the maths and the
// reasons live in those modules' docs). Positions given as `x` are voxel coordinates of the grid:
// (p - origin) * scale, voxel i spanning [i, i + 1).

#include "common/shading.wgsl"

// The grid fitted to the hair every frame by volume_bounds.wgsl (mirrored by
// `gpu::types::VolumeGrid`).
struct VolumeGrid {
    // World position of the corner of voxel (0, 0, 0).
    origin: vec3<f32>,
    // Voxels per world unit.
    scale: f32,
    // The hair's axis-aligned bounding box (the raymarcher's proxy geometry).
    bounds_min: vec3<f32>,
    voxel_size: f32,
    bounds_max: vec3<f32>,
    // Voxels per axis.
    res: u32,
    // The voxels this frame's resolve writes from the counters, [box_min, box_max): those the
    // hair's box touches, grown by the reconstruction filter's radius (every texel outside holds
    // zero).
    box_min: vec3<u32>,
    // 1 when the hair has vertices (the box is valid).
    occupied: u32,
    box_max: vec3<u32>,
    // Strands per level of the texture's 8-bit density: 1 in the segments mode (the texel holds
    // the count), the filter's weight over its box in the vertices mode (the texel holds the
    // box's summed count).
    density_unit: f32,
}

// What the voxelizer counts (mirrored by `gpu::types::VoxelStats`): samples deposited and
// dropped at a full counter (voxelize), filter boxes clamped to the texel's 255 (resolve).
struct VoxelStats {
    deposits: atomic<u32>,
    dropped: atomic<u32>,
    saturated: atomic<u32>,
    _pad0: u32,
}

// Where the resolve runs (mirrored by `gpu::types::ResolveArgs`): `groups` are the indirect
// dispatch's workgroup counts (4³ voxels each) over [origin, end), the union of this frame's and
// the last frame's boxes (so what the last frame wrote outside this frame's box is zeroed).
struct ResolveArgs {
    groups: vec3<u32>,
    _pad0: u32,
    origin: vec3<u32>,
    _pad1: u32,
    end: vec3<u32>,
    _pad2: u32,
}

// Per-frame settings of the volume passes (mirrored by `gpu::types::VolumeParams`).
struct VolumeParams {
    // World from clip of the frame's camera (the raymarcher's eye rays).
    world_from_clip: mat4x4<f32>,
    // Raymarch: constant steps across the box diagonal; strands to a solid surface.
    steps: u32,
    iso: f32,
    // 1: skip empty blocks of the occupancy volume.
    skip_empty: u32,
    // Shading model (params.wgsl SHADING_*).
    shading: u32,
    // Shadows of the rasterizer and the head: SHADOW_MODE_*.
    raster_shadow_mode: u32,
    // Opacity of one occluding strand (volume shadows and ambient occlusion).
    shadow_alpha: f32,
    // Shadow march step and start offset in voxels.
    shadow_step: f32,
    shadow_offset: f32,
    // 1: the rasterizer multiplies its color by the volume's ambient occlusion.
    raster_ao: u32,
    // Local ambient occlusion: radius in world units, samples, intensity.
    ao_radius: f32,
    ao_samples: u32,
    ao_intensity: f32,
    // VOXELIZE_*; resolve filter radius (vertices mode); per-voxel capacity.
    voxelize: u32,
    reconstruction_radius: u32,
    capacity: u32,
    // Mean segment length in world units (weight of a vertex in the vertices mode).
    mean_segment_length: f32,
    segment_count: u32,
    vertex_count: u32,
    // Occupancy blocks per axis (ceil(resolution / OCCUPANCY_BLOCK)).
    occupancy_res: u32,
    // Voxels per axis.
    resolution: u32,
    // 1: volume shadows / ambient occlusion in the raymarcher.
    march_shadows: u32,
    march_ao: u32,
    // Effective strand width in world units: a strand crossing a voxel blocks a ray through it
    // with probability strand_width / voxel_size (shadows and ambient occlusion count those).
    strand_width: f32,
    // OCCLUSION_*: how shadows and ambient occlusion turn the volume into strands in the way.
    occlusion: u32,
    // OCCLUSION_ADSM: strands in the way per world unit of path inside the hair (ADSM's r).
    occlusion_r: f32,
    // Thickness that fades nothing (the strands' tip fade; 0: no fade): the voxelizer weighs each
    // sample's tangent by `thickness / fade_ref`, so the mean tangent's length is the strands'
    // mean opacity fade (times their coherence).
    fade_ref: f32,
    // OCCLUSION_ADSM: width in world units of a shadow-map line (`shadow_width_px` texels) and
    // ADSM's depth bias.
    occlusion_width: f32,
    occlusion_bias: f32,
    // Raymarch: points shaded per pixel, 1..=MAX_SHADE_SAMPLES.
    shade_samples: u32,
    // Raymarch under `volume.opacity = "strands"`: optical width of a strand line in pixels
    // (tress_shading::line_optical_width); 0: the paper's `iso` count.
    optical_width: f32,
    // 1: the voxelizer integrates the strands' Kajiya-Kay highlights per voxel for this frame's
    // view and lights, and the raymarcher shades with them (`volume.highlights = "strands"`;
    // tress_shading::highlights); their exponent.
    highlights: u32,
    highlight_exponent: f32,
    // Voxels a texel of the ambient-occlusion texture baked after each voxelization, which the
    // strands and the raymarcher read local AO from (`volume.ao_texel`); 0: they evaluate it at
    // every shaded point.
    ao_texel: u32,
    // The frame's eye (perspective) or view direction (orthographic) and the lights' unit
    // directions, for the highlights.
    view_eye: vec3<f32>,
    view_orthographic: u32,
    view_forward: vec3<f32>,
    light_count: u32,
    light_dirs: array<vec4<f32>, 4>,
}

const MAX_SHADE_SAMPLES: u32 = 8u;

const VOXELIZE_VERTICES: u32 = 0u;
const VOXELIZE_SEGMENTS: u32 = 1u;
const SHADOW_MODE_ADSM: u32 = 0u;
const SHADOW_MODE_VOLUME: u32 = 1u;
const GRID_PAD: u32 = 2u;
const SUBVOXEL: u32 = 16u;
const SUBVOXEL_BITS: u32 = 4u;
const TANGENT_LEVELS: f32 = 255.0;
const TEXEL_TANGENT_ZERO: f32 = 128.0;
const TEXEL_TANGENT_SCALE: f32 = 127.0;
const TEXEL_MAX_COUNT: u32 = 255u;
const MAX_MARCH_STEPS: u32 = 4096u;
const MAX_AO_SAMPLES: u32 = 64u;
// The cap of volume_shadow_strands and volume_ao that caps nothing (tress_shading::NO_CAP).
const NO_CAP: f32 = 1e30;
// VolumeParams.occlusion: strands passed times strand_width / voxel size (the strand model),
// or ADSM's r times the path's length inside the hair (voxels holding a strand or more).
const OCCLUSION_STRANDS: u32 = 0u;
const OCCLUSION_ADSM: u32 = 1u;
const GOLDEN_ANGLE: f32 = 2.3999633;
const GOLDEN_RATIO_CONJUGATE: f32 = 0.618034;
// Edge of an occupancy block in voxels.
const OCCUPANCY_BLOCK: u32 = 8u;

// ---------------------------------------------------------------------------------------------
// Voxelization (tress_shading::voxelize)

fn voxel_hash(x: u32) -> u32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    return (h >> 22u) ^ h;
}

fn isqrt(x: u32) -> u32 {
    var r = u32(sqrt(f32(x)));
    while r > 0u && r * r > x {
        r = r - 1u;
    }
    while (r + 1u) * (r + 1u) <= x {
        r = r + 1u;
    }
    return r;
}

fn quantize_tangent(t: vec3<f32>) -> vec3<u32> {
    return vec3<u32>(floor(saturate(t * 0.5 + 0.5) * TANGENT_LEVELS + 0.5));
}

fn dequantize_tangent(sum: vec3<f32>, count: f32) -> vec3<f32> {
    if count <= 0.0 {
        return vec3<f32>(0.0);
    }
    return sum / count / TANGENT_LEVELS * 2.0 - vec3<f32>(1.0);
}

// The volume texture's texels (rgba8unorm, 4 bytes a voxel): rgb the mean tangent `t` stored as
// `u = t / |t|^(2/3)` (so `|u| = |t|^(1/3)`), each channel 128 + floor(127 u + 1/2): a short mean
// tangent (spread directions, faded tips) keeps its direction to about a degree where a linear
// 8-bit store would turn it by ten; a the clamped count (segments mode) or the filter box's summed
// count (vertices mode), at most 255.
fn encode_texel(tangent: vec3<f32>, count: u32) -> vec4<f32> {
    let len = length(tangent);
    let u = select(vec3<f32>(0.0), tangent * pow(max(len, 1e-30), -2.0 / 3.0), len > 0.0);
    let c = clamp(u, vec3<f32>(-1.0), vec3<f32>(1.0));
    let t = TEXEL_TANGENT_ZERO + floor(c * TEXEL_TANGENT_SCALE + 0.5);
    return vec4<f32>(t, f32(min(count, TEXEL_MAX_COUNT))) / 255.0;
}

// A texel as loaded (normalized) as the mean tangent and the density in strands. A texel without
// strands has no tangent, whatever its rgb (the resolve and a new texture write zeros).
fn decode_texel(raw: vec4<f32>, density_unit: f32) -> vec4<f32> {
    let b = floor(raw * 255.0 + 0.5);
    let u = (b.rgb - vec3<f32>(TEXEL_TANGENT_ZERO)) / TEXEL_TANGENT_SCALE;
    let t = select(vec3<f32>(0.0), u * dot(u, u), b.a > 0.0);
    return vec4<f32>(t, b.a * density_unit);
}

fn segment_tangent(p0: vec3<f32>, p1: vec3<f32>) -> vec3<f32> {
    let d = p1 - p0;
    let len = length(d);
    return select(vec3<f32>(0.0, 1.0, 0.0), d / len, len > 1e-20);
}

fn voxel_from_world(grid: VolumeGrid, p: vec3<f32>) -> vec3<f32> {
    return (p - grid.origin) * grid.scale;
}

fn fixed_point(grid: VolumeGrid, p: vec3<f32>) -> vec3<u32> {
    let f = (p - grid.origin) * (grid.scale * f32(SUBVOXEL));
    let hi = f32(grid.res * SUBVOXEL - 1u);
    return vec3<u32>(clamp(floor(f), vec3<f32>(0.0), vec3<f32>(hi)));
}

fn voxel_index(res: u32, v: vec3<u32>) -> u32 {
    return v.x + res * (v.y + res * v.z);
}

fn segment_sample_count(q0: vec3<u32>, q1: vec3<u32>, segment: u32) -> u32 {
    let d = vec3<i32>(q1) - vec3<i32>(q0);
    let d2 = u32(d.x * d.x + d.y * d.y + d.z * d.z);
    let len = isqrt(d2);
    var n = len >> SUBVOXEL_BITS;
    if (len & (SUBVOXEL - 1u)) > (voxel_hash(segment) & (SUBVOXEL - 1u)) {
        n = n + 1u;
    }
    return n;
}

fn segment_sample(a: vec3<i32>, d: vec3<i32>, k: u32, n: u32) -> vec3<u32> {
    let two_n = 2 * i32(n);
    let num = a * two_n + d * (2 * i32(k) + 1);
    return vec3<u32>(num / two_n);
}

// ---------------------------------------------------------------------------------------------
// Volume shading (tress_shading::volume). `tex` holds texels as `encode_texel` writes them, `vt`
// says how they read; `samp` is linear and clamps to the edge.

// How the texels of a volume read: its voxels per axis and density unit.
struct VolumeTexels {
    res: f32,
    density_unit: f32,
}

fn volume_texels(grid: VolumeGrid) -> VolumeTexels {
    return VolumeTexels(f32(grid.res), grid.density_unit);
}

// The eight texels around voxel position `x` (the corners `i0` and `i1`, clamped to the edge)
// and the trilinear weights `w` of the `i1` side (texel centres at `i + 1/2`).
struct TrilinearCell {
    i0: vec3<i32>,
    i1: vec3<i32>,
    w: vec3<f32>,
}

fn trilinear_cell(vt: VolumeTexels, x: vec3<f32>) -> TrilinearCell {
    let p = x - vec3<f32>(0.5);
    let f = floor(p);
    let last = vec3<i32>(i32(vt.res) - 1);
    return TrilinearCell(
        clamp(vec3<i32>(f), vec3<i32>(0), last),
        clamp(vec3<i32>(f) + vec3<i32>(1), vec3<i32>(0), last),
        p - f,
    );
}

// The mean tangent (rgb) and the density (a) at voxel position `x`, trilinearly filtered in the
// shader from the eight texels around it (clamped to the edge, as the sampler would), each decoded
// first: the texels' tangents are not linear in what they hold, and hardware filters of 8-bit
// texels may round the result to 8 bits (lavapipe does), which would round every density between
// two voxels to a whole strand. `samp` is unused (kept for the callers' one signature).
fn volume_sample(tex: texture_3d<f32>, samp: sampler, vt: VolumeTexels, x: vec3<f32>) -> vec4<f32> {
    let cell = trilinear_cell(vt, x);
    let i0 = cell.i0;
    let i1 = cell.i1;
    let w = cell.w;
    let u = vt.density_unit;
    let c000 = decode_texel(textureLoad(tex, vec3<i32>(i0.x, i0.y, i0.z), 0), u);
    let c100 = decode_texel(textureLoad(tex, vec3<i32>(i1.x, i0.y, i0.z), 0), u);
    let c010 = decode_texel(textureLoad(tex, vec3<i32>(i0.x, i1.y, i0.z), 0), u);
    let c110 = decode_texel(textureLoad(tex, vec3<i32>(i1.x, i1.y, i0.z), 0), u);
    let c001 = decode_texel(textureLoad(tex, vec3<i32>(i0.x, i0.y, i1.z), 0), u);
    let c101 = decode_texel(textureLoad(tex, vec3<i32>(i1.x, i0.y, i1.z), 0), u);
    let c011 = decode_texel(textureLoad(tex, vec3<i32>(i0.x, i1.y, i1.z), 0), u);
    let c111 = decode_texel(textureLoad(tex, vec3<i32>(i1.x, i1.y, i1.z), 0), u);
    let c00 = mix(c000, c100, w.x);
    let c10 = mix(c010, c110, w.x);
    let c01 = mix(c001, c101, w.x);
    let c11 = mix(c011, c111, w.x);
    return mix(mix(c00, c10, w.y), mix(c01, c11, w.y), w.z);
}

// How parallel the strands around `x` run: the length of the density-weighted trilinear mean of
// the eight nearest texels' tangent directions (1: all along one line; the tip fade that scales the
// texels' tangents does not enter).
fn volume_tangent_coherence(tex: texture_3d<f32>, samp: sampler, vt: VolumeTexels, x: vec3<f32>) -> f32 {
    let cell = trilinear_cell(vt, x);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var k = 0u; k < 8u; k = k + 1u) {
        let c = vec3<u32>(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
        let i = select(cell.i0, cell.i1, c == vec3<u32>(1u));
        let tw = select(vec3<f32>(1.0) - cell.w, cell.w, c == vec3<u32>(1u));
        let texel = decode_texel(textureLoad(tex, i, 0), vt.density_unit);
        let len = length(texel.rgb);
        if len > 1e-6 {
            let wd = tw.x * tw.y * tw.z * texel.a;
            sum = sum + wd * texel.rgb / len;
            weight = weight + wd;
        }
    }
    return select(1.0, length(sum) / weight, weight > 0.0);
}

fn volume_density(tex: texture_3d<f32>, samp: sampler, vt: VolumeTexels, x: vec3<f32>) -> f32 {
    return volume_sample(tex, samp, vt, x).a;
}

fn ray_box(o: vec3<f32>, d: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec2<f32> {
    let inv = vec3<f32>(1.0) / d;
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let near = min(a, b);
    let far = max(a, b);
    return vec2<f32>(max(max(near.x, near.y), near.z), min(min(far.x, far.y), far.z));
}

fn volume_shadow_strands(
    tex: texture_3d<f32>,
    samp: sampler,
    vt: VolumeTexels,
    x: vec3<f32>,
    l: vec3<f32>,
    step: f32,
    offset: f32,
    cap: f32,
) -> f32 {
    let span = ray_box(x, l, vec3<f32>(0.0), vec3<f32>(vt.res));
    var t = max(offset, span.x);
    var n = 0.0;
    var i = 0u;
    while i < MAX_MARCH_STEPS && t < span.y {
        n = n + min(volume_density(tex, samp, vt, x + l * t), cap) * step;
        t = t + step;
        i = i + 1u;
    }
    return n;
}

fn ao_offset(i: u32, n: u32) -> vec3<f32> {
    let fi = f32(i) + 0.5;
    let nf = f32(max(n, 1u));
    let z = 1.0 - 2.0 * fi / nf;
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = GOLDEN_ANGLE * f32(i);
    let u = fi * GOLDEN_RATIO_CONJUGATE;
    let radius = pow(u - floor(u), 1.0 / 3.0);
    return vec3<f32>(r * cos(phi), r * sin(phi), z) * radius;
}

fn volume_ao(
    tex: texture_3d<f32>,
    samp: sampler,
    vt: VolumeTexels,
    x: vec3<f32>,
    radius: f32,
    samples: u32,
    intensity: f32,
    alpha: f32,
    cap: f32,
) -> f32 {
    let n = min(samples, MAX_AO_SAMPLES);
    if n == 0u || radius <= 0.0 {
        return 1.0;
    }
    var sum = 0.0;
    for (var i = 0u; i < n; i = i + 1u) {
        sum = sum + min(volume_density(tex, samp, vt, x + ao_offset(i, n) * radius), cap);
    }
    let mean = sum / f32(n);
    return strand_visibility(intensity * mean * radius, alpha);
}

// The most a voxel counts in shadows and AO under `params.occlusion`: every strand
// (OCCLUSION_STRANDS), or one (ADSM: the march measures the path's length inside the hair).
fn occlusion_cap(params: VolumeParams) -> f32 {
    return select(NO_CAP, 1.0, params.occlusion == OCCLUSION_ADSM);
}

// What turns a march's count into strands in the way, on a grid of `scale` voxels per world unit:
// the share of the strands crossing a voxel that a ray through it meets (strand width over voxel
// size), or ADSM's r per voxel of path inside the hair (r times the voxel size).
fn occlusion_hit_fraction(params: VolumeParams, scale: f32) -> f32 {
    if params.occlusion == OCCLUSION_ADSM {
        return params.occlusion_r / scale;
    }
    return params.strand_width * scale;
}

// Local ambient occlusion (§3.4) at voxel position `x` of `grid` with the settings of `params`
// (the ball's radius in world units): the one definition the baked texture and the per-point
// evaluation share.
fn local_ao(tex: texture_3d<f32>, samp: sampler, grid: VolumeGrid, params: VolumeParams, x: vec3<f32>) -> f32 {
    return volume_ao(
        tex, samp, volume_texels(grid), x, params.ao_radius * grid.scale, params.ao_samples,
        params.ao_intensity * occlusion_hit_fraction(params, grid.scale), params.shadow_alpha,
        occlusion_cap(params));
}

fn density_gradient(tex: texture_3d<f32>, samp: sampler, vt: VolumeTexels, x: vec3<f32>) -> vec3<f32> {
    let ex = vec3<f32>(1.0, 0.0, 0.0);
    let ey = vec3<f32>(0.0, 1.0, 0.0);
    let ez = vec3<f32>(0.0, 0.0, 1.0);
    return vec3<f32>(
        volume_density(tex, samp, vt, x + ex) - volume_density(tex, samp, vt, x - ex),
        volume_density(tex, samp, vt, x + ey) - volume_density(tex, samp, vt, x - ey),
        volume_density(tex, samp, vt, x + ez) - volume_density(tex, samp, vt, x - ez),
    ) * 0.5;
}

fn density_normal(gradient: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len = length(gradient);
    return select(fallback, -gradient / len, len > 1e-12);
}

// Transmittance of the hair after `strands` (opacity-weighted) strands along an eye ray:
// `256^(-strands / iso)`, 1/256 at the isosurface; 0 when `iso <= 0`.
fn composite_transmittance(strands: f32, iso: f32) -> f32 {
    if iso <= 0.0 {
        return 0.0;
    }
    return exp2(-8.0 * max(strands, 0.0) / iso);
}

// Optical depth of `strands` met along an eye ray of direction `dir`, drawn as lines of optical
// width `optical_width` pixels where a pixel spans `pixel_voxels` voxels: the projected length
// `strands |t x dir|` (t the normalized mean `tangent`; none counts as across) times the width.
fn strand_optical_depth(
    strands: f32, tangent: vec3<f32>, dir: vec3<f32>, pixel_voxels: f32, optical_width: f32,
) -> f32 {
    let len = length(tangent);
    let across = select(1.0, length(cross(tangent / len, dir)), len > 1e-6);
    return strands * across * pixel_voxels * optical_width;
}

// Opacity of a ray that met `strands` strands without reaching the isosurface (fake transparency,
// §3.3): `1 - composite_transmittance`; 1 when `iso <= 0`.
fn fake_transparency_alpha(strands: f32, iso: f32) -> f32 {
    return 1.0 - composite_transmittance(strands, iso);
}

// Whether the transmittance `tr` has fallen to shading point `m` of `k`: the points split the
// composite's weight `1 - tr` into `k` equal parts, each shaded at its middle.
fn composite_point_reached(tr: f32, m: u32, k: u32) -> bool {
    return tr <= 1.0 - (f32(m) + 0.5) / f32(max(k, 1u));
}

// ADSM's visibility `(1 - alpha)^(r (d - bias))` at voxel position `x` towards `l`, in expectation
// over where the first strand seen from the light lies (`d`: the distance from it, in voxels as
// `t`): marching out from the point, each step holds a strand of a shadow-map line `width` voxels
// wide with probability `1 - exp(-density · step · width)`, and a farther one replaces a nearer.
// `ln_keep` is `r · ln(1 - alpha)` per voxel, `bias` in voxels.
fn volume_adsm_visibility(
    tex: texture_3d<f32>,
    samp: sampler,
    vt: VolumeTexels,
    x: vec3<f32>,
    l: vec3<f32>,
    step: f32,
    offset: f32,
    width: f32,
    ln_keep: f32,
    bias: f32,
) -> f32 {
    let span = ray_box(x, l, vec3<f32>(0.0), vec3<f32>(vt.res));
    var t = max(offset, span.x);
    var seen = 0.0;
    var none = 1.0;
    var i = 0u;
    while i < MAX_MARCH_STEPS && t < span.y {
        let p = 1.0 - exp(-volume_density(tex, samp, vt, x + l * t) * step * width);
        seen = seen * (1.0 - p) + p * exp(ln_keep * max(t - bias, 0.0));
        none = none * (1.0 - p);
        t = t + step;
        i = i + 1u;
    }
    return seen + none;
}

fn lod_factor(distance: f32, near: f32, far: f32) -> f32 {
    if far <= near {
        return select(0.0, 1.0, distance >= near);
    }
    return smoothstep(near, far, distance);
}

fn dither_threshold(px: vec2<u32>) -> f32 {
    var bayer = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    let b = bayer[(px.y & 3u) * 4u + (px.x & 3u)];
    return (f32(b) + 0.5) / 16.0;
}

// ---------------------------------------------------------------------------------------------
// Pre-integrated highlights (tress_shading::highlights)

const HIGHLIGHT_LEVELS: f32 = 255.0;

// One specular value in [0, 1] as floor(s * 255 + 1/2).
fn quantize_highlight(s: f32) -> u32 {
    return u32(floor(clamp(s, 0.0, 1.0) * HIGHLIGHT_LEVELS + 0.5));
}

// The texel byte of a voxel's highlight: the fade-weighted mean of its samples, their quantized
// fade * spec summing to `sum` over quantized fades summing to `fades`, to the nearest level in
// integers; 0 without fade.
fn highlight_texel(sum: u32, fades: u32) -> u32 {
    if fades == 0u {
        return 0u;
    }
    return min((510u * sum + fades) / (2u * fades), 255u);
}

// The highlight of light `light` at voxel position `x`: the density-weighted trilinear mean of
// the eight highlight texels around it (the densities from the volume texture's counts), in
// [0, 1]; 0 where none holds strands.
fn volume_highlight(
    highlights: texture_3d<f32>, volume: texture_3d<f32>, vt: VolumeTexels, x: vec3<f32>, light: u32,
) -> f32 {
    let cell = trilinear_cell(vt, x);
    var sum = 0.0;
    var weight = 0.0;
    for (var k = 0u; k < 8u; k = k + 1u) {
        let c = vec3<u32>(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
        let i = select(cell.i0, cell.i1, c == vec3<u32>(1u));
        let tw = select(vec3<f32>(1.0) - cell.w, cell.w, c == vec3<u32>(1u));
        let density = floor(textureLoad(volume, i, 0).a * 255.0 + 0.5) * vt.density_unit;
        let h = floor(textureLoad(highlights, i, 0)[min(light, 3u)] * 255.0 + 0.5);
        let w = tw.x * tw.y * tw.z * density;
        sum = sum + w * h;
        weight = weight + w;
    }
    return select(0.0, sum / weight / HIGHLIGHT_LEVELS, weight > 0.0);
}
