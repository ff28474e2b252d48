// LOD blend pass (Jansson 2019 §3 "Overview", §4 Figure 1): the strand rasterizer's and the
// raymarcher's premultiplied layers, rendered into two scratch targets, mixed by the level-of-detail
// factor — alpha-blended, or dithered with a 4x4 Bayer matrix — and composited over the target
// (which holds the head and background both layers were meant to cover). Blending premultiplied
// layers linearly and then compositing equals blending the two composited images. Owner: `LodBlend`.

#include "common/fullscreen.wgsl"
#include "common/volume.wgsl"

// Mirrored by `gpu::types::LodParams`.
struct LodParams {
    // 0: strands only, 1: volume only.
    factor: f32,
    // 0: alpha blend, 1: dither.
    transition: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var strands_layer: texture_2d<f32>;
@group(0) @binding(1) var volume_layer: texture_2d<f32>;
@group(0) @binding(2) var<uniform> lod: LodParams;

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vertex_index);
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<u32>(position.xy);
    let s = textureLoad(strands_layer, px, 0);
    let v = textureLoad(volume_layer, px, 0);
    if lod.transition == 1u {
        return select(s, v, lod.factor > dither_threshold(px));
    }
    return mix(s, v, lod.factor);
}
