// Shadow pass: depth of the hair and the head as seen from one directional light, into that
// light's ADSM shadow map (Jansson 2019 §3.4). Depth only: no fragment stage. Owner: `ShadowMap`.

#include "common/strand.wgsl"

// The light's orthographic camera.
@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;

// Ribbons `shadow_width_px` texels wide (six vertices a segment), for widths above one texel.
@vertex
fn vs_strand(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4<f32> {
    return strand_vertex(camera, vertex_index, params.shadow_width_px, THICKNESS_FADE_OFF, 1.0).position;
}

// One-texel lines (two vertices a segment, a line list): the cheapest primitive for the
// default one-texel width, since a depth-only map needs no coverage.
@vertex
fn vs_strand_line(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4<f32> {
    let seg = strand_segments[vertex_index / 2u];
    return camera_clip(camera, strand_vertices[seg.x + vertex_index % 2u].position);
}

@vertex
fn vs_head(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> @builtin(position) vec4<f32> {
    _ = normal;
    return camera_clip(camera, position);
}
