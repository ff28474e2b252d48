// Shadowing between clusters (Table 1, "S"): per light, the outermost layer mesh of every cluster
// and the head rasterized from the light with depth test, writing which cluster (index + 1, or
// SATF_HEAD_ID for the head) is nearest the light. The paper casts shadow volumes between
// clusters (§6.4); this shadow map is the documented departure (satf/mod.rs). Owner:
// `ClusterShadow`.

#include "common/camera.wgsl"
#include "satf/types.wgsl"

// The light's orthographic camera.
@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: SatfParams;

struct ShadowVarying {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) id: u32,
}

@vertex
fn vs_layer(
    @location(0) position: vec3f,
    @location(1) u: f32,
    @location(2) tangent: vec3f,
    @location(3) t: f32,
    @location(4) normal: vec3f,
    @location(5) tile: u32,
) -> ShadowVarying {
    _ = u;
    _ = tangent;
    _ = t;
    _ = normal;
    var out: ShadowVarying;
    out.position = camera_clip(camera, position);
    out.id = tile / max(params.layers, 1u) + 1u;
    return out;
}

@vertex
fn vs_head(@location(0) position: vec3f, @location(1) normal: vec3f) -> ShadowVarying {
    _ = normal;
    var out: ShadowVarying;
    out.position = camera_clip(camera, position);
    out.id = 0xffffffffu;
    return out;
}

@fragment
fn fs_main(in: ShadowVarying) -> @location(0) u32 {
    return in.id;
}
