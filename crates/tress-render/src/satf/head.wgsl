// The head of the SATF technique, drawn first with depth writes: two-sided Lambert plus ambient,
// each light's contribution times its visibility through the clusters (the shadow maps of
// `ClusterShadow`). Owner: `SatfHead`.

#include "common/head.wgsl"
#include "common/lights.wgsl"
#include "satf/types.wgsl"
#include "satf/shadow_lookup.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> lights: Lights;
@group(0) @binding(2) var<uniform> params: SatfParams;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> HeadVarying {
    return head_varying(camera, position, normal);
}

@fragment
fn fs_main(in: HeadVarying) -> @location(0) vec4f {
    let v = camera_to_eye(camera, in.world);
    let n = head_normal(in.normal, v);
    var light = lights.ambient;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let dl = lights.lights[i];
        let n_dot_l = max(dot(n, dl.to_light), 0.0);
        if n_dot_l > 0.0 {
            light = light + light_radiance(dl) * n_dot_l
                * satf_light_visibility(params, dl, i, in.world, SATF_HEAD_ID);
        }
    }
    return vec4f(params.head_color * light, 1.0);
}
