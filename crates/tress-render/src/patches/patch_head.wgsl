// The head of the patch technique, drawn first with depth writes (Scheuermann 2004, slide
// "Performance Tuning": "usually half the hair is hidden behind the head – draw head first"):
// two-sided Lambert plus ambient, unshadowed (the patches' self-shadowing is their baked AO).
// Owner: `HeadPass` (built by `patches::patch_head`).

#include "common/head.wgsl"
#include "common/lights.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(1) @binding(0) var<uniform> lights: Lights;
// Linear RGB in xyz.
@group(1) @binding(1) var<uniform> head_color: vec4<f32>;

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
        light = light + light_radiance(dl) * max(dot(n, dl.to_light), 0.0);
    }
    return vec4<f32>(head_color.xyz * light, 1.0);
}
