// The ShortCut buffers at @group(3) (bounded-memory OIT after TressFX 4.1's "ShortCut"), shared
// by its depth, shade and resolve passes.
//
// `shortcut_keys` holds k layers of one word per pixel (layer-major: word `i * pixels + p` is
// layer `i` of pixel `p`). After the depth pass the layers of a pixel hold the keys of its k
// nearest fragments, nearest first (`common/shortcut_keys.wgsl`). The k-th nearest is the
// tail's threshold (its fragment is the tail's first); the shade pass claims one of the k - 1
// nearer layers whose key equals a fragment's own, adding its alpha to the word's low bits;
// `shortcut_colors` (k - 1 layers, same layout) gets its RGB9E5 color.

#include "common/ppll.wgsl"
#include "common/shortcut_keys.wgsl"

// Mirrored by `gpu::types::PpllCounters` (ShortCut counts fragments; it never drops one).
struct ShortcutCounters {
    requested: atomic<u32>,
    dropped: atomic<u32>,
    // The PPLL's tail count (read back with its layout); ShortCut leaves it 0.
    tail: u32,
    _pad1: u32,
}

// Largest k the ShortCut passes support (mirrored by `strands::MAX_SHORTCUT_K`).
const MAX_SHORTCUT_K: u32 = 16u;

@group(3) @binding(0) var<storage, read_write> shortcut_keys: array<atomic<u32>>;
@group(3) @binding(1) var<storage, read_write> shortcut_colors: array<u32>;
@group(3) @binding(2) var<storage, read_write> shortcut_counters: ShortcutCounters;

#include "common/params.wgsl"

fn shortcut_k(params: StrandParams) -> u32 {
    return clamp(params.shortcut_k, 1u, MAX_SHORTCUT_K);
}

// Pixels of the target: the stride between two layers.
fn shortcut_pixels(params: StrandParams) -> u32 {
    return params.target_width * params.target_height;
}

// Pixel `p`'s tail falloff `1 / (TAIL_SPACINGS * g)`, `g` the mean depth spacing of its k
// layers, from its first and k-th layer words (`far`: the k-th's key); 0 when unknown (k = 1,
// fewer than k fragments, every layer at one depth: the tail then takes the color of the
// fragments at the threshold). CPU twin: `tress_shading::shortcut_tail_falloff`.
fn tail_falloff(params: StrandParams, p: u32, far: u32) -> f32 {
    let k = shortcut_k(params);
    if far == 0u || k < 2u {
        return 0.0;
    }
    let near = atomicLoad(&shortcut_keys[p]) & KEY_MASK;
    let spacing = (shortcut_depth(far) - shortcut_depth(near)) / f32(k - 1u);
    if spacing <= 0.0 {
        return 0.0;
    }
    return 1.0 / (TAIL_SPACINGS * spacing);
}
