// The viewer's presentation: the renderer's frame (linear, premultiplied, cleared opaque to the
// scene's background) copied texel for texel onto the window's surface. `fs_srgb` encodes sRGB
// for plain 8-bit surfaces; `fs_linear` leaves it to an sRGB surface format. No shading happens
// here: this is what any image viewer does with a linear image.

@group(0) @binding(0) var frame: texture_2d<f32>;

// One triangle covering the viewport.
@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// The frame's texel under a fragment, composited over black and clamped to [0, 1].
fn texel(position: vec4<f32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(frame));
    let p = clamp(vec2<i32>(position.xy), vec2<i32>(0), size - 1);
    return clamp(textureLoad(frame, p, 0).rgb, vec3<f32>(0.0), vec3<f32>(1.0));
}

// The sRGB transfer function (IEC 61966-2-1), as `tress_render::gpu::linear_to_srgb`.
fn srgb_from_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

@fragment
fn fs_srgb(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(srgb_from_linear(texel(position)), 1.0);
}

@fragment
fn fs_linear(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(texel(position), 1.0);
}
