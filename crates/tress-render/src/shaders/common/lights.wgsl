// Directional lights (mirrored by `gpu::types::LightUniform` / `LightsUniform`).

const MAX_LIGHTS: u32 = 4u;

struct DirectionalLight {
    // Orthographic projection of the light's shadow map: xy in [-1, 1], depth in [0, 1].
    light_from_world: mat4x4<f32>,
    // Unit vector from the scene towards the light (`l` in the shading formulas).
    to_light: vec3<f32>,
    intensity: f32,
    // Linear RGB color.
    color: vec3<f32>,
    // World-space length of the shadow map's depth range [0, 1].
    depth_range: f32,
}

struct Lights {
    // Ambient light (linear RGB), added unshadowed.
    ambient: vec3<f32>,
    count: u32,
    lights: array<DirectionalLight, 4>,
}

// Radiance scale of a light: color * intensity.
fn light_radiance(light: DirectionalLight) -> vec3<f32> {
    return light.color * light.intensity;
}

// Shadow-map texel (x, y) and normalized light depth of world point `p` for a map of `size`
// texels; `xy` outside [0, size) means outside the map.
fn light_texel(light: DirectionalLight, p: vec3<f32>, size: f32) -> vec3<f32> {
    let c = light.light_from_world * vec4<f32>(p, 1.0);
    let ndc = c.xyz / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    return vec3<f32>(floor(uv * size), ndc.z);
}
