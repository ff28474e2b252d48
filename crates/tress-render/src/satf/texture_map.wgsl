// Texture mapping (Table 1, "M"; Xu et al. 2006 §6.5): every layer mesh rasterized with its
// re-map, alpha-map, s-map and lighting map, bilinear in the tile (wrapping around the cluster in
// u, clamped in t). Shading is equation 13, Y = Y_lighting re tau; the fragment is the
// premultiplied (Y alpha, alpha), and blend One / OneMinusSrcAlpha over what lies behind (the
// background, the head, the core and the layers drawn before) is one step of equation 14.
// `vs_main` / `fs_main` serve both the back-face and the front-face pipelines. Owner: `TextureMap`.

#include "common/camera.wgsl"
#include "satf/types.wgsl"
#include "satf/online.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: SatfParams;
@group(0) @binding(2) var maps: texture_2d<f32>;
@group(0) @binding(3) var s_map: texture_2d<f32>;
@group(0) @binding(4) var l_map: texture_2d<f32>;

struct LayerVarying {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
    @location(1) @interpolate(flat) tile: u32,
}

@vertex
fn vs_main(
    @location(0) position: vec3f,
    @location(1) u: f32,
    @location(2) tangent: vec3f,
    @location(3) t: f32,
    @location(4) normal: vec3f,
    @location(5) tile: u32,
) -> LayerVarying {
    _ = tangent;
    _ = normal;
    var out: LayerVarying;
    out.position = camera_clip(camera, position);
    out.uv = vec2f(u, t);
    out.tile = tile;
    return out;
}

// The four texels around tile coordinates `uv` and their bilinear weights.
struct Taps {
    t00: vec2<i32>,
    t10: vec2<i32>,
    t01: vec2<i32>,
    t11: vec2<i32>,
    w: vec4f,
}

fn taps(tile: u32, uv: vec2f) -> Taps {
    let w = params.tile_width;
    let h = params.tile_height;
    let fx = uv.x * f32(w) - 0.5;
    let fy = clamp(uv.y * f32(h) - 0.5, 0.0, f32(h - 1u));
    let x0f = floor(fx);
    let y0f = floor(fy);
    let ax = fx - x0f;
    let ay = fy - y0f;
    // Wrap around the cluster in u.
    let xi = i32(x0f);
    let x0 = u32(((xi % i32(w)) + i32(w)) % i32(w));
    let x1 = (x0 + 1u) % w;
    let y0 = min(u32(y0f), h - 1u);
    let y1 = min(y0 + 1u, h - 1u);
    var out: Taps;
    out.t00 = satf_atlas_texel(params, tile, x0, y0);
    out.t10 = satf_atlas_texel(params, tile, x1, y0);
    out.t01 = satf_atlas_texel(params, tile, x0, y1);
    out.t11 = satf_atlas_texel(params, tile, x1, y1);
    out.w = vec4f((1.0 - ax) * (1.0 - ay), ax * (1.0 - ay), (1.0 - ax) * ay, ax * ay);
    return out;
}

fn bilinear_maps(k: Taps) -> vec4f {
    return k.w.x * textureLoad(maps, k.t00, 0) + k.w.y * textureLoad(maps, k.t10, 0)
        + k.w.z * textureLoad(maps, k.t01, 0) + k.w.w * textureLoad(maps, k.t11, 0);
}

fn bilinear_s(k: Taps) -> f32 {
    return k.w.x * textureLoad(s_map, k.t00, 0).x + k.w.y * textureLoad(s_map, k.t10, 0).x
        + k.w.z * textureLoad(s_map, k.t01, 0).x + k.w.w * textureLoad(s_map, k.t11, 0).x;
}

fn bilinear_l(k: Taps) -> vec3f {
    return k.w.x * textureLoad(l_map, k.t00, 0).xyz + k.w.y * textureLoad(l_map, k.t10, 0).xyz
        + k.w.z * textureLoad(l_map, k.t01, 0).xyz + k.w.w * textureLoad(l_map, k.t11, 0).xyz;
}

@fragment
fn fs_main(in: LayerVarying) -> @location(0) vec4f {
    let k = taps(in.tile, in.uv);
    let m = bilinear_maps(k);
    let re = m.x;
    let alpha = clamp(m.y, 0.0, 1.0);
    let y_shading = satf_shading(bilinear_l(k), re, bilinear_s(k));
    return vec4f(y_shading * alpha, alpha);
}
