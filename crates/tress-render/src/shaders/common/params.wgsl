// Per-frame settings of the strand technique, shared by every pass of a frame.

// Per-frame strand settings (mirrored by `gpu::types::StrandParams`).
struct StrandParams {
    width_px: f32,
    alpha: f32,
    k: u32,
    shading: u32,
    coverage: u32,
    thickness_fade: u32,
    vertex_color: u32,
    node_capacity: u32,
    shadow_r: f32,
    shadow_alpha: f32,
    pcf_radius: i32,
    shadow_bias: f32,
    shadow_map_size: f32,
    shadow_width_px: f32,
    target_width: u32,
    shadows: u32,
    hair_center: vec3<f32>,
    light_count: u32,
    // Thickness that fades nothing in the tip mode (the asset's thickest vertex).
    thickness_ref: f32,
    // PPLL nodes per storage buffer of the pool (`common/ppll_pool.wgsl`).
    nodes_per_chunk: u32,
    // ShortCut's k: nearest fragments per pixel blended in order (`strands/shortcut_*.wgsl`).
    shortcut_k: u32,
    // Height of the color target (ShortCut's buffers hold one layer of width x height per k).
    target_height: u32,
    // A hybrid head of hair in a frame of several: its blend factor, and 1 when its strands and
    // its volume share the frame's pixels by the 4x4 dither (strands where the factor is at most
    // `dither_threshold`, volume elsewhere); 0 for everything else.
    lod_factor: f32,
    lod_dither: u32,
    _pad0: u32,
    _pad1: u32,
}

const THICKNESS_FADE_OFF: u32 = 0u;
const THICKNESS_FADE_TIP: u32 = 1u;
const THICKNESS_FADE_PROJECTED: u32 = 2u;

const SHADING_KAJIYA_KAY: u32 = 0u;
const SHADING_SCHEUERMANN: u32 = 1u;
const SHADING_MARSCHNER: u32 = 2u;
