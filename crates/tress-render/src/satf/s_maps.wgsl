// Shadowing (Table 1, "S"; Xu et al. 2006 §6.4): per texel of every layer, the s-map
// tau_k = exp(-k_shadow sum_{m > k} alpha_m) of equation 12 from the alpha-maps of the outer
// layers at the same texture coordinates, and the visibility of each light through the other
// clusters (the shadow maps of `ClusterShadow`). Owner: `SMaps`.

#include "common/lights.wgsl"
#include "satf/types.wgsl"
#include "satf/online.wgsl"
#include "satf/texel_geometry.wgsl"
#include "satf/shadow_lookup.wgsl"

@group(0) @binding(0) var<uniform> params: SatfParams;
@group(0) @binding(1) var<uniform> lights: Lights;
@group(0) @binding(2) var maps: texture_2d<f32>;
@group(0) @binding(3) var s_map: texture_storage_2d<rgba16float, write>;
// Visibility of lights 0..3 through other clusters.
@group(0) @binding(4) var vis_map: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let x = id.x;
    let y = id.y;
    let tile = id.z;
    if x >= params.tile_width || y >= params.tile_height || tile >= params.tile_count {
        return;
    }
    let cluster = tile / params.layers;
    let layer = tile % params.layers;
    // Equation 12: c(k) = the layers m > k (outer layers cover inner ones).
    var tau = 1.0;
    if params.local_shadows != 0u {
        var sum = 0.0;
        for (var m = layer + 1u; m < params.layers; m = m + 1u) {
            sum = sum + textureLoad(maps, satf_atlas_texel(params, cluster * params.layers + m, x, y), 0).y;
        }
        tau = satf_transmittance(sum, params.k_shadow, params.shadow_approx);
    }
    let texel = satf_atlas_texel(params, tile, x, y);
    textureStore(s_map, texel, vec4f(tau, 0.0, 0.0, 0.0));
    var vis = vec4f(1.0);
    if params.cluster_shadows != 0u {
        let g = satf_texel_geometry(params, tile, x, y);
        for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
            vis[i] = satf_light_visibility(params, lights.lights[i], i, g.position, cluster + 1u);
        }
    }
    textureStore(vis_map, texel, vis);
}
