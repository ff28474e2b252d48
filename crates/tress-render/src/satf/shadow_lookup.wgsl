// Shadows between clusters (the departure from the paper's shadow volumes, see satf/mod.rs): per
// light, the depth of the nearest cluster surface or head seen from the light and which cluster
// it belongs to. Declares bindings 11 and 12 of group 0.

#include "common/lights.wgsl"
#include "satf/types.wgsl"

@group(0) @binding(11) var shadow_depth: texture_depth_2d_array;
@group(0) @binding(12) var shadow_ids: texture_2d_array<u32>;

// The id the head writes; clusters write cluster index + 1; 0 is empty.
const SATF_HEAD_ID: u32 = 0xffffffffu;

// Fraction of the (2 r + 1)^2 PCF taps around world point `pos` where something other than
// `self_id` lies between `pos` and light `i` by more than the bias.
fn satf_cluster_occlusion(p: SatfParams, light: DirectionalLight, i: u32, pos: vec3f, self_id: u32) -> f32 {
    let size = p.shadow_map_size;
    let c = light_texel(light, pos, size);
    let bias = p.shadow_bias / max(light.depth_range, 1e-20);
    let r = clamp(p.pcf_radius, 0, 8);
    let edge = i32(size);
    var hits = 0.0;
    var taps = 0.0;
    for (var dy = -r; dy <= r; dy = dy + 1) {
        for (var dx = -r; dx <= r; dx = dx + 1) {
            taps = taps + 1.0;
            let q = vec2<i32>(i32(c.x) + dx, i32(c.y) + dy);
            if q.x < 0 || q.y < 0 || q.x >= edge || q.y >= edge {
                continue;
            }
            let id = textureLoad(shadow_ids, q, i32(i), 0).x;
            let d = textureLoad(shadow_depth, q, i32(i), 0);
            if id != 0u && id != self_id && c.z - bias > d {
                hits = hits + 1.0;
            }
        }
    }
    return hits / taps;
}

// Light visibility of `pos` for light i: 1 - shadow_opacity * occlusion (1 when shadows between
// clusters are off).
fn satf_light_visibility(p: SatfParams, light: DirectionalLight, i: u32, pos: vec3f, self_id: u32) -> f32 {
    if p.cluster_shadows == 0u {
        return 1.0;
    }
    return 1.0 - p.shadow_opacity * satf_cluster_occlusion(p, light, i, pos, self_id);
}
