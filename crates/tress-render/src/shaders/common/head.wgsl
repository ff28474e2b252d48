// The head mesh's vertex stage and two-sided normal, shared by every technique's head pass
// (head/head_pass.wgsl, satf/head.wgsl, patches/patch_head.wgsl): each keeps only its lighting.

#include "common/camera.wgsl"

struct HeadVarying {
    @builtin(position) position: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

// The vertex stage of a head vertex (locations 0 and 1 of `gpu::types::HeadVertex`).
fn head_varying(cam: Camera, position: vec3<f32>, normal: vec3<f32>) -> HeadVarying {
    var out: HeadVarying;
    out.position = camera_clip(cam, position);
    out.world = position;
    out.normal = normal;
    return out;
}

// The unit normal facing the eye direction `v` (two-sided: a back face is lit like the front it
// belongs to); `v` itself where the mesh's normal is zero.
fn head_normal(normal: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let len = length(normal);
    let n = select(v, normal / max(len, 1e-20), len > 1e-20);
    return select(n, -n, dot(n, v) < 0.0);
}
