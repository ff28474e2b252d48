// ShortCut threshold pass (after TressFX 4.1's "ResolveDepth"): after the depth pass, copy each
// pixel's k-th nearest key (layer k - 1) into `shortcut_far`, so the shade pass tells a tail
// fragment (farther than the k-th) with one load, before the layers are claimed, and the tail's
// depth falloff from the k layers' mean spacing (`common/shortcut.wgsl`). A compute pass over
// pairs of pixels; k and the pixel count come from the buffers' lengths. Owner:
// `ShortcutThreshold`.

#include "common/shortcut_keys.wgsl"

@group(0) @binding(0) var<storage, read_write> shortcut_keys: array<atomic<u32>>;
@group(0) @binding(1) var<storage, read_write> shortcut_far: array<u32>;
@group(0) @binding(2) var<storage, read_write> shortcut_falloff: array<u32>;

// Pixel `p`'s k-th key (copied to `shortcut_far`) and its tail falloff.
fn threshold(p: u32, pixels: u32, k: u32) -> f32 {
    let far = atomicLoad(&shortcut_keys[(k - 1u) * pixels + p]);
    shortcut_far[p] = far;
    if far == 0u || k < 2u {
        return 0.0;
    }
    let near = atomicLoad(&shortcut_keys[p]);
    let spacing = (shortcut_depth(far) - shortcut_depth(near)) / f32(k - 1u);
    if spacing <= 0.0 {
        return 0.0;
    }
    return 1.0 / (TAIL_SPACINGS * spacing);
}

// One invocation a pair of pixels (their falloffs share a word).
@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixels = arrayLength(&shortcut_far);
    let pair = id.x + id.y * 65535u * 64u;
    let p = pair * 2u;
    if p >= pixels {
        return;
    }
    let k = arrayLength(&shortcut_keys) / pixels;
    let low = threshold(p, pixels, k);
    var high = 0.0;
    if p + 1u < pixels {
        high = threshold(p + 1u, pixels, k);
    }
    shortcut_falloff[pair] = falloff_bits(low) | (falloff_bits(high) << 16u);
}
