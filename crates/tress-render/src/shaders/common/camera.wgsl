// The camera uniform shared by every pass (mirrored by `gpu::types::CameraUniform`).
//
// Clip space is wgpu's: depth 0 at the near plane, 1 at the far plane. Screen coordinates are
// pixels with the origin at the top-left and y down, what `@builtin(position)` holds.

struct Camera {
    clip_from_world: mat4x4<f32>,
    // Eye position (perspective) in world space.
    eye: vec3<f32>,
    // Pixels covered by one world unit at clip w = 1: a length L at clip w spans
    // L * pixels_per_unit / w pixels.
    pixels_per_unit: f32,
    // Viewport size in pixels.
    viewport: vec2<f32>,
    // 1 for an orthographic camera (the view direction is `forward` everywhere).
    orthographic: u32,
    _pad0: u32,
    // Unit view direction (from the eye into the scene).
    forward: vec3<f32>,
    _pad1: f32,
}

fn camera_clip(cam: Camera, p: vec3<f32>) -> vec4<f32> {
    return cam.clip_from_world * vec4<f32>(p, 1.0);
}

// Unit vector from `p` towards the eye (`v` in the shading formulas).
fn camera_to_eye(cam: Camera, p: vec3<f32>) -> vec3<f32> {
    if cam.orthographic != 0u {
        return -cam.forward;
    }
    let d = cam.eye - p;
    let len = length(d);
    if len < 1e-20 {
        return -cam.forward;
    }
    return d / len;
}
