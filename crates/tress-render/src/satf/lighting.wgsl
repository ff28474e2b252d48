// Lighting (Table 1, "L"; Xu et al. 2006 §6.3): per texel of every layer, equation 8 (diffuse,
// primary and secondary specular, equations 9-11) at the layer surface point, summed over the
// lights with each light's radiance and its visibility through other clusters, plus the ambient
// light times the diffuse color. Owner: `Lighting`.

#include "common/camera.wgsl"
#include "common/lights.wgsl"
#include "satf/types.wgsl"
#include "satf/online.wgsl"
#include "satf/texel_geometry.wgsl"

@group(0) @binding(0) var<uniform> params: SatfParams;
@group(0) @binding(1) var<uniform> camera: Camera;
@group(0) @binding(2) var<uniform> lights: Lights;
@group(0) @binding(3) var vis_map: texture_2d<f32>;
@group(0) @binding(4) var l_map: texture_storage_2d<rgba16float, write>;

fn material() -> SatfLighting {
    var m: SatfLighting;
    m.k_dif = params.k_dif;
    m.f_dif = params.f_dif;
    m.k_spe1 = params.k_spe1;
    m.f_spe1 = params.f_spe1;
    m.primary_shift = params.primary_shift;
    m.k_spe2 = params.k_spe2;
    m.f_spe2 = params.f_spe2;
    m.secondary_shift = params.secondary_shift;
    m.k_h = params.k_h;
    return m;
}

@compute @workgroup_size(8, 8, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let x = id.x;
    let y = id.y;
    let tile = id.z;
    if x >= params.tile_width || y >= params.tile_height || tile >= params.tile_count {
        return;
    }
    let g = satf_texel_geometry(params, tile, x, y);
    let v = camera_to_eye(camera, g.position);
    let texel = satf_atlas_texel(params, tile, x, y);
    let vis = textureLoad(vis_map, texel, 0);
    let m = material();
    var y_lighting = lights.ambient * params.f_dif;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let li = lights.lights[i];
        y_lighting = y_lighting
            + light_radiance(li) * vis[i] * satf_lighting(m, g.tangent, g.normal, li.to_light, v);
    }
    textureStore(l_map, texel, vec4f(y_lighting, 1.0));
}
