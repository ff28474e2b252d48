// What every strand OIT pass (PPLL build, ShortCut depth and shade) decides per fragment, so all
// of them see exactly the same fragments: the exact test against the head's depth and the
// fragment's opacity with the §3.2 line coverage (Jansson 2019 §3.1-3.2).

#include "common/strand.wgsl"
#include "common/volume.wgsl"

// Fragments fainter than this are not stored (nor counted) by any OIT.
const MIN_FRAGMENT_ALPHA: f32 = 1.0 / 1024.0;

// The opacity a strand fragment contributes, in (MIN_FRAGMENT_ALPHA, 1], or 0 when it lies
// behind the head (the test is done here because the OIT passes' stores are side effects that
// the fixed-function late depth test could not prevent), in a pixel a dithered hybrid gives to
// its volume, or is too faint to store.
fn strand_fragment_alpha(
    in: StrandVarying,
    camera: Camera,
    params: StrandParams,
    head_depth: texture_depth_2d,
) -> f32 {
    let px = vec2<u32>(in.position.xy);
    if in.position.z >= textureLoad(head_depth, px, 0) {
        return 0.0;
    }
    // A dithered hybrid's volume pixel: its raymarch draws there instead.
    if params.lod_dither != 0u && params.lod_factor > dither_threshold(px) {
        return 0.0;
    }
    var alpha = in.color.a * params.alpha;
    if params.coverage != 0u {
        alpha = alpha * strand_coverage(
            in.position.xy, vec4<f32>(in.world_line, 1.0), camera.clip_from_world, camera.viewport,
            params.width_px);
    }
    if alpha <= MIN_FRAGMENT_ALPHA {
        return 0.0;
    }
    return min(alpha, 1.0);
}

// Index of the fragment's pixel in per-pixel buffers (row-major over the target).
fn strand_pixel_index(in: StrandVarying, params: StrandParams) -> u32 {
    let px = vec2<u32>(in.position.xy);
    return px.y * params.target_width + px.x;
}
