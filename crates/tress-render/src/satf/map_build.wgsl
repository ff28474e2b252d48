// Map construction (Table 1, "C"; Xu et al. 2006 §6.2.2): every texel of every layer's re-map and
// alpha-map from its HSV's records: row r of an HSV's `map_rows` rows takes gamma = r / (rows - 1)
// (1/2 for one row) and equation 7 between record 1 (b_top) and record 2 (b_bottom); a uniform
// HSV has one averaged record swept along it. Column j of a sector is HRIR pixel j. Owner:
// `MapBuild`.

#include "satf/types.wgsl"
#include "satf/online.wgsl"

@group(0) @binding(0) var<uniform> params: SatfParams;
@group(0) @binding(1) var<storage, read> hsvs: array<HsvRecord>;
// unorm16 pairs: alpha[sample][view][pixel] and re[sample][view][light][pixel].
@group(0) @binding(2) var<storage, read> db_alpha: array<u32>;
@group(0) @binding(3) var<storage, read> db_re: array<u32>;
// (re, alpha, 0, 0) per atlas texel.
@group(0) @binding(4) var maps: texture_storage_2d<rgba16float, write>;

fn unorm16(words: u32, index: u32) -> f32 {
    let shift = (index & 1u) * 16u;
    return f32((words >> shift) & 0xffffu) / 65535.0;
}

fn alpha_at(sample: u32, view: u32, pixel: u32) -> f32 {
    let i = (sample * params.view_angles + view) * params.pixels + pixel;
    return unorm16(db_alpha[i >> 1u], i);
}

fn re_at(sample: u32, view: u32, light: u32, pixel: u32) -> f32 {
    let i = ((sample * params.view_angles + view) * params.light_angles + light) * params.pixels + pixel;
    return unorm16(db_re[i >> 1u], i);
}

@compute @workgroup_size(8, 8, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let x = id.x;
    let y = id.y;
    let tile = id.z;
    if x >= params.tile_width || y >= params.tile_height || tile >= params.tile_count {
        return;
    }
    let m = x / params.pixels;
    let j = x % params.pixels;
    let i = y / params.map_rows;
    let r = y % params.map_rows;
    let cluster = tile / params.layers;
    let layer = tile % params.layers;
    let h = cluster * params.st * params.layers * params.su + (i * params.layers + layer) * params.su + m;
    let rec = hsvs[h];
    var gamma = 0.5;
    if params.map_rows > 1u {
        gamma = f32(r) / f32(params.map_rows - 1u);
    }
    let a = satf_interpolate(alpha_at(rec.sample1, rec.view1, j), alpha_at(rec.sample2, rec.view2, j), gamma);
    var re = satf_interpolate(
        re_at(rec.sample1, rec.view1, rec.light1, j),
        re_at(rec.sample2, rec.view2, rec.light2, j),
        gamma,
    );
    if params.straight != 0u {
        re = satf_straight_reflectance(re, a);
    }
    textureStore(maps, satf_atlas_texel(params, tile, x, y), vec4f(re, a, 0.0, 0.0));
}
