// The head of the SATF technique, drawn first with depth writes: two-sided Lambert plus ambient,
// each light's contribution times its visibility through the clusters (the shadow maps of
// `ClusterShadow`). Owner: `SatfHead`.

#include "common/camera.wgsl"
#include "common/lights.wgsl"
#include "satf/types.wgsl"
#include "satf/shadow_lookup.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> lights: Lights;
@group(0) @binding(2) var<uniform> params: SatfParams;

struct HeadVarying {
    @builtin(position) position: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
}

@vertex
fn vs_main(@location(0) position: vec3f, @location(1) normal: vec3f) -> HeadVarying {
    var out: HeadVarying;
    out.position = camera_clip(camera, position);
    out.world = position;
    out.normal = normal;
    return out;
}

@fragment
fn fs_main(in: HeadVarying) -> @location(0) vec4f {
    let v = camera_to_eye(camera, in.world);
    let len = length(in.normal);
    var n = select(v, in.normal / max(len, 1e-20), len > 1e-20);
    // Two-sided: a back face is lit like the front it belongs to.
    if dot(n, v) < 0.0 {
        n = -n;
    }
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
