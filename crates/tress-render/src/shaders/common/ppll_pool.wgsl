// The PPLL buffers at @group(3), shared by the build and resolve passes: the per-pixel list
// heads, the counters, and the node pool spread over NODE_CHUNKS storage buffers. One storage
// binding holds at most the device's `max_storage_buffer_binding_size` (128 MiB on lavapipe,
// 8.4M nodes), so a pool that holds a paper-scale frame (17M fragments) needs several; node `i`
// lives in chunk `i / per_chunk` (`StrandParams::nodes_per_chunk`).

#include "common/ppll.wgsl"

// Storage buffers the node pool may span (mirrored by `strands::NODE_CHUNKS`).
const NODE_CHUNKS: u32 = 4u;

// Mirrored by `gpu::types::PpllCounters`.
struct PpllCounters {
    requested: atomic<u32>,
    dropped: atomic<u32>,
    // Fragments the resolve merged unsorted behind each pixel's k nearest (the k-buffer's tail).
    tail: atomic<u32>,
    _pad1: u32,
}

// Per pixel: index + 1 of the first node; 0 is an empty list.
@group(3) @binding(0) var<storage, read_write> ppll_heads: array<atomic<u32>>;
@group(3) @binding(1) var<storage, read_write> ppll_counters: PpllCounters;
@group(3) @binding(2) var<storage, read_write> ppll_nodes_0: array<PpllNode>;
@group(3) @binding(3) var<storage, read_write> ppll_nodes_1: array<PpllNode>;
@group(3) @binding(4) var<storage, read_write> ppll_nodes_2: array<PpllNode>;
@group(3) @binding(5) var<storage, read_write> ppll_nodes_3: array<PpllNode>;

// Write node `index` (< the pool's capacity) of a pool with `per_chunk` nodes a binding.
fn ppll_store(index: u32, per_chunk: u32, node: PpllNode) {
    let chunk = index / per_chunk;
    let i = index - chunk * per_chunk;
    switch chunk {
        case 0u: { ppll_nodes_0[i] = node; }
        case 1u: { ppll_nodes_1[i] = node; }
        case 2u: { ppll_nodes_2[i] = node; }
        default: { ppll_nodes_3[i] = node; }
    }
}

// Read node `index` (< the pool's capacity) of a pool with `per_chunk` nodes a binding.
fn ppll_load(index: u32, per_chunk: u32) -> PpllNode {
    let chunk = index / per_chunk;
    let i = index - chunk * per_chunk;
    switch chunk {
        case 0u: { return ppll_nodes_0[i]; }
        case 1u: { return ppll_nodes_1[i]; }
        case 2u: { return ppll_nodes_2[i]; }
        default: { return ppll_nodes_3[i]; }
    }
}
