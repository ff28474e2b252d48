// The lighting bind group (@group(1)) shared by the head pass and the strand passes: lights,
// material and one ADSM shadow map per light (Jansson 2019 §3.4).

#include "common/lights.wgsl"
#include "common/shading.wgsl"
#include "common/params.wgsl"

// Mirrored by `gpu::types::MaterialUniform`.
struct Material {
    // Scheuermann's constants; Kajiya-Kay uses the primary color and exponent.
    lighting: HairLighting,
    base_color: vec3<f32>,
    _pad0: f32,
    head_color: vec3<f32>,
    _pad1: f32,
}

@group(1) @binding(0) var<uniform> lights: Lights;
@group(1) @binding(1) var<uniform> material: Material;
@group(1) @binding(2) var shadow_map_0: texture_depth_2d;
@group(1) @binding(3) var shadow_map_1: texture_depth_2d;
@group(1) @binding(4) var shadow_map_2: texture_depth_2d;
@group(1) @binding(5) var shadow_map_3: texture_depth_2d;

// ADSM visibility of world point `p` from light `i` (1: lit). Points outside the light's map are
// lit. `r` is given per world unit and scaled to the map's normalized depth; the bias (world
// units) is subtracted from the fragment's depth before `d = max(0, f - s)`.
fn shadow_visibility(i: u32, p: vec3<f32>, params: StrandParams) -> f32 {
    if params.shadows == 0u {
        return 1.0;
    }
    let light = lights.lights[i];
    let t = light_texel(light, p, params.shadow_map_size);
    if t.x < 0.0 || t.y < 0.0 || t.x >= params.shadow_map_size || t.y >= params.shadow_map_size
        || t.z < 0.0 || t.z > 1.0 {
        return 1.0;
    }
    let range = max(light.depth_range, 1e-6);
    let r = params.shadow_r * range;
    let f = t.z - params.shadow_bias / range;
    let texel = vec2<i32>(t.xy);
    switch i {
        case 0u: { return adsm_pcf(shadow_map_0, texel, params.pcf_radius, f, r, params.shadow_alpha); }
        case 1u: { return adsm_pcf(shadow_map_1, texel, params.pcf_radius, f, r, params.shadow_alpha); }
        case 2u: { return adsm_pcf(shadow_map_2, texel, params.pcf_radius, f, r, params.shadow_alpha); }
        default: { return adsm_pcf(shadow_map_3, texel, params.pcf_radius, f, r, params.shadow_alpha); }
    }
}
