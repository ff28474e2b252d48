// The SATF technique's GPU structs (Xu et al. 2006 §6), mirrored one for one by
// `gpu/types.rs` (SatfParams, SatfSector, SectorParams, HsvRecord, SatfVertex, SatfCounters) and
// checked by tests/layout.rs. Included by every satf pass; no bindings.

// Per-frame constants of the online phase.
struct SatfParams {
    // Equations 8-11: diffuse, primary and secondary specular.
    f_dif: vec3f,
    k_dif: f32,
    f_spe1: vec3f,
    k_spe1: f32,
    f_spe2: vec3f,
    k_spe2: f32,
    primary_shift: f32,
    secondary_shift: f32,
    k_h: f32,
    // Equation 12.
    k_shadow: f32,
    // Equation 6 and the nearest-record search.
    feature_weights: vec3f,
    k_threshold: f32,
    angle_weight: f32,
    // 0 exponential, 1 linear (tress_satf::online::ShadowApprox).
    shadow_approx: u32,
    // 1: re-maps hold straight reflectance r^e / a^ (0: the HRIR's premultiplied r^e).
    straight: u32,
    sample_count: u32,
    // Database layout.
    view_angles: u32,
    light_angles: u32,
    pixels: u32,
    // Map rows per HSV along t.
    map_rows: u32,
    // Equation 3 sampling: s_t, s_u, shell layers per cluster.
    st: u32,
    su: u32,
    layers: u32,
    cluster_count: u32,
    // Boundary sectors and HSVs over all clusters.
    sector_count: u32,
    hsv_count: u32,
    // One map tile per (cluster, layer): su * pixels by st * map_rows texels.
    tile_width: u32,
    tile_height: u32,
    tiles_per_row: u32,
    // Layer mesh grid per tile: (mesh_nt + 1) x (mesh_nu + 1) vertices.
    mesh_nt: u32,
    mesh_nu: u32,
    light_count: u32,
    // The light whose azimuth indexes the database (theta_l).
    key_light: u32,
    // 1: shadow maps between clusters.
    cluster_shadows: u32,
    pcf_radius: i32,
    shadow_map_size: f32,
    // World units.
    shadow_bias: f32,
    // Light a shadowing cluster blocks, in [0, 1].
    shadow_opacity: f32,
    // 1: equation 12 s-maps (0: tau = 1).
    local_shadows: u32,
    tile_count: u32,
    // Head mesh color (linear RGB).
    head_color: vec3f,
    _pad0: u32,
}

// A boundary generalized sector (static): its anchor on the layer's outer surface (the middle
// of the outer arc) with the surface's frame, and its density features rho_feature (section 5.2).
struct SatfSector {
    position: vec3f,
    cluster: u32,
    normal: vec3f,
    _pad0: u32,
    s_axis: vec3f,
    _pad1: u32,
    features: vec3f,
    _pad2: u32,
}

// Params(b) of a sector this frame (section 6.2.1) and its nearest database sample.
struct SectorParams {
    features: vec3f,
    sample: u32,
    theta_v: f32,
    theta_l: f32,
    _pad0: u32,
    _pad1: u32,
}

// An HSV's records this frame: (sample, view bin, light bin) at b_top (record 1) and b_bottom
// (record 2); both the averaged record when uniform (equation 6).
struct HsvRecord {
    sample1: u32,
    view1: u32,
    light1: u32,
    sample2: u32,
    view2: u32,
    light2: u32,
    uniform: u32,
    _pad: u32,
}

// A vertex of a layer mesh (vertex buffer and storage array): position on the layer's outer
// surface, texture coordinates (u across, t along, both in [0, 1] of the tile), hair tangent,
// outward normal and the tile (cluster * layers + layer).
struct SatfVertex {
    position: vec3f,
    u: f32,
    tangent: vec3f,
    t: f32,
    normal: vec3f,
    tile: u32,
}

// Counters of the index calculation.
struct SatfCounters {
    uniform_hsvs: atomic<u32>,
    interpolated_hsvs: atomic<u32>,
    _pad0: u32,
    _pad1: u32,
}

// The atlas texel of texel (x, y) of tile `tile`.
fn satf_atlas_texel(p: SatfParams, tile: u32, x: u32, y: u32) -> vec2<i32> {
    let col = tile % p.tiles_per_row;
    let row = tile / p.tiles_per_row;
    return vec2<i32>(i32(col * p.tile_width + x), i32(row * p.tile_height + y));
}
