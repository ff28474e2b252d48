// The ShortCut buffers at @group(3) (bounded-memory OIT after TressFX 4.1's "ShortCut"), shared
// by its depth, shade and resolve passes.
//
// `shortcut_keys` holds k layers of one word per pixel (layer-major: word `i * pixels + p` is
// layer `i` of pixel `p`). After the depth pass the layers of a pixel hold the keys of its k
// nearest fragments, nearest first; a key is `KEY_MAX - bits(depth)`, so the nearest depth is the
// largest key, atomicMax inserts, and 0 (what a cleared buffer holds) is an empty layer. The shade
// pass claims the layer whose key equals a fragment's own and replaces the key by
// `CLAIMED | bits(alpha)`; `shortcut_colors` (same layout) gets its RGB9E5 color. Depths and
// alphas in [0, 1] have the top bit clear, so a claimed word never equals a key.

#include "common/ppll.wgsl"
#include "common/shortcut_keys.wgsl"

// Mirrored by `gpu::types::PpllCounters` (ShortCut counts fragments; it never drops one).
struct ShortcutCounters {
    requested: atomic<u32>,
    dropped: atomic<u32>,
    _pad0: u32,
    _pad1: u32,
}

// Largest k the ShortCut passes support (mirrored by `strands::MAX_SHORTCUT_K`).
const MAX_SHORTCUT_K: u32 = 16u;
const CLAIMED: u32 = 0x80000000u;

@group(3) @binding(0) var<storage, read_write> shortcut_keys: array<atomic<u32>>;
@group(3) @binding(1) var<storage, read_write> shortcut_colors: array<u32>;
@group(3) @binding(2) var<storage, read_write> shortcut_counters: ShortcutCounters;
// Per pixel, written by the threshold pass before the shade pass claims layers: the key of its
// k-th nearest fragment after the depth pass (0: fewer than k).
@group(3) @binding(5) var<storage, read> shortcut_far: array<u32>;
// Two pixels a word (the top 16 bits of an f32, pixel 2i low): the tail's depth falloff `1 / (TAIL_SPACINGS *
// g)`, `g` the mean depth spacing of the pixel's k layers (0: no falloff known, k = 1 or every
// layer at one depth; the tail then takes the k-th's color).
@group(3) @binding(7) var<storage, read> shortcut_falloff: array<u32>;

// Pixel `p`'s tail falloff.
fn tail_falloff(p: u32) -> f32 {
    let word = shortcut_falloff[p / 2u];
    return bitcast<f32>(select(word << 16u, word & 0xffff0000u, (p & 1u) == 1u));
}

#include "common/params.wgsl"

fn shortcut_k(params: StrandParams) -> u32 {
    return clamp(params.shortcut_k, 1u, MAX_SHORTCUT_K);
}

// Pixels of the target: the stride between two layers.
fn shortcut_pixels(params: StrandParams) -> u32 {
    return params.target_width * params.target_height;
}
