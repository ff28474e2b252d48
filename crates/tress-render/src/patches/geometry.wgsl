// Polygon-patch geometry and material bindings shared by the patch passes (Scheuermann 2004):
// the vertex layout, the technique's constants and textures, and the vertex transform. Owner:
// `PatchGeometry` (geometry.rs) for the vertex layout, `PatchRenderer` for the bindings.
//
// Every pass that includes this file binds the patch material at @group(2).

#include "common/camera.wgsl"
#include "common/shading.wgsl"
#include "common/marschner.wgsl"

// `PatchParams::shading`: Scheuermann's `HairLighting` (the slides) or Marschner's lobes.
const PATCH_SHADING_SCHEUERMANN: u32 = 0u;
const PATCH_SHADING_MARSCHNER: u32 = 1u;

// One patch vertex (vertex buffer; mirrored by `gpu::types::PatchVertex`).
struct PatchVertex {
    @location(0) position: vec3<f32>,
    // Baked per-vertex ambient occlusion (sketch, "Ambient occlusion").
    @location(1) ao: f32,
    @location(2) normal: vec3<f32>,
    // Texture coordinate across the patch.
    @location(3) u: f32,
    // Unit tangent from root to tip.
    @location(4) tangent: vec3<f32>,
    // Texture coordinate from root (0) to tip (1).
    @location(5) v: f32,
}

// The technique's constants (mirrored by `gpu::types::PatchParamsGpu`).
struct PatchParams {
    // The slide's external constants of `HairLighting`.
    lighting: HairLighting,
    // Alpha test reference: alpha >= alpha_ref is an opaque pixel.
    alpha_ref: f32,
    // 1: multiply by the baked ambient occlusion.
    use_ao: u32,
    // The `min_alpha` option: the depth-writing transparent pass drops alpha below it.
    min_alpha: f32,
    // PATCH_SHADING_SCHEUERMANN or PATCH_SHADING_MARSCHNER (`patches.shading`).
    shading: u32,
    // The physically based fibre of `patches.shading = "marschner"` and its dual-scattering
    // table (zero otherwise).
    fiber: Marschner,
    dual: DualScattering,
}

@group(2) @binding(0) var<uniform> patch_params: PatchParams;
@group(2) @binding(1) var base_texture: texture_2d<f32>;
@group(2) @binding(2) var alpha_texture: texture_2d<f32>;
@group(2) @binding(3) var spec_shift_texture: texture_2d<f32>;
@group(2) @binding(4) var spec_noise_texture: texture_2d<f32>;
@group(2) @binding(5) var patch_sampler: sampler;

// What the slides' vertex shader passes down ("Shader Breakdown": tangent, normal, view vector,
// light vector, ambient occlusion); the view and light vectors are formed per pixel from `world`.
struct PatchVarying {
    // Invariant: the Z-prime pass and the Equal-tested opaque pass must compute the same depth.
    @invariant @builtin(position) position: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) ao: f32,
    @location(2) normal: vec3<f32>,
    @location(3) tangent: vec3<f32>,
    @location(4) uv: vec2<f32>,
}

fn patch_vertex(cam: Camera, in: PatchVertex) -> PatchVarying {
    var out: PatchVarying;
    out.position = camera_clip(cam, in.position);
    out.world = in.position;
    out.ao = in.ao;
    out.normal = in.normal;
    out.tangent = in.tangent;
    out.uv = vec2<f32>(in.u, in.v);
    return out;
}

// The alpha texture at `uv` (slide `HairLighting`: `o.a = tex2D(tAlpha, uv)`).
fn patch_alpha(uv: vec2<f32>) -> f32 {
    return textureSample(alpha_texture, patch_sampler, uv).r;
}
