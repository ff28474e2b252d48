// ShortCut depth pass (bounded-memory OIT after TressFX 4.1's "ShortCut"): every strand fragment
// the PPLL would store (same head test, same alpha threshold: `common/strand_fragment.wgsl`)
// inserts its depth into its pixel's k nearest with a chain of atomicMax on the layer keys
// (`common/shortcut.wgsl`), and is counted. Depth only: nothing is shaded. Owner: `ShortcutDepth`.

#include "common/strand_fragment.wgsl"
#include "common/shortcut.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;
@group(3) @binding(3) var head_depth: texture_depth_2d;

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> StrandVarying {
    return strand_vertex(
        camera,
        vertex_index,
        params.width_px,
        params.thickness_fade,
        params.thickness_ref,
    );
}

@fragment
fn fs_main(in: StrandVarying) {
    if strand_fragment_alpha(in, camera, params, head_depth) <= 0.0 {
        return;
    }
    atomicAdd(&shortcut_counters.requested, 1u);
    let pixels = shortcut_pixels(params);
    let p = strand_pixel_index(in, params);
    // Insertion into the sorted layers: each atomicMax keeps the nearer of the two keys in the
    // layer and passes the farther one on; an empty layer (0) ends the chain.
    var key = shortcut_key(in.position.z);
    // The k nearest so far are all at least as near: this fragment is a tail fragment, and the
    // layers only ever get nearer (one load instead of k atomics for most of a dense pixel).
    let kth = shortcut_k(params) - 1u;
    if atomicLoad(&shortcut_keys[kth * pixels + p]) >= key {
        return;
    }
    for (var i = 0u; i < shortcut_k(params); i = i + 1u) {
        let prev = atomicMax(&shortcut_keys[i * pixels + p], key);
        if prev == 0u {
            break;
        }
        key = min(prev, key);
    }
}
