// A fullscreen triangle: draw 3 vertices, no vertex buffers.

fn fullscreen_position(vertex_index: u32) -> vec4<f32> {
    let uv = vec2<f32>(f32((vertex_index << 1u) & 2u), f32(vertex_index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
