// Z-prime pass (Scheuermann 2004, slide "Optimized Rendering Scheme", pass 1; sketch "Rendering
// with approximate depth sorting"): writes the depth of the opaque parts of the hair, alpha test
// on, no back-face culling, color writes off, "a very simple pixel shader that only returns the
// hair's alpha channel". Owner: `ZPrime`.

#include "patches/geometry.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;

@vertex
fn vs_main(in: PatchVertex) -> PatchVarying {
    return patch_vertex(camera, in);
}

@fragment
fn fs_main(in: PatchVarying) -> @location(0) vec4<f32> {
    let alpha = patch_alpha(in.uv);
    // The alpha test: only opaque pixels pass.
    if alpha < patch_params.alpha_ref {
        discard;
    }
    return vec4<f32>(0.0, 0.0, 0.0, alpha);
}
