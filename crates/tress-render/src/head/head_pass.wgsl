// Head pass: the opaque head mesh, drawn first with depth writes, Lambert-lit with ADSM shadows
// from the hair (Jansson 2019 §3.4: the shadow map holds hair and head depth). Owner: `HeadPass`.

#include "common/head.wgsl"
#include "common/lighting.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> HeadVarying {
    return head_varying(camera, position, normal);
}

@fragment
fn fs_main(in: HeadVarying) -> @location(0) vec4<f32> {
    let v = camera_to_eye(camera, in.world);
    let n = head_normal(in.normal, v);
    var light = lights.ambient;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let dl = lights.lights[i];
        let n_dot_l = max(dot(n, dl.to_light), 0.0);
        if n_dot_l > 0.0 {
            light = light + light_radiance(dl) * n_dot_l * shadow_visibility(i, in.world, params);
        }
    }
    return vec4<f32>(material.head_color * light, 1.0);
}
