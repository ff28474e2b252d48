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

// Write node `index` (< the pool's capacity) of a pool with `per_chunk` nodes a binding. The
// chunk is found by comparisons, not `index / per_chunk`: an integer division per node is a
// measurable share of a pass that does little else per fragment on a CPU Vulkan.
fn ppll_store(index: u32, per_chunk: u32, node: PpllNode) {
    if index < per_chunk {
        ppll_nodes_0[index] = node;
        return;
    }
    let i1 = index - per_chunk;
    if i1 < per_chunk {
        ppll_nodes_1[i1] = node;
        return;
    }
    let i2 = i1 - per_chunk;
    if i2 < per_chunk {
        ppll_nodes_2[i2] = node;
        return;
    }
    ppll_nodes_3[i2 - per_chunk] = node;
}

// Read node `index` (< the pool's capacity) of a pool with `per_chunk` nodes a binding (chunk by
// comparisons, as `ppll_store`).
fn ppll_load(index: u32, per_chunk: u32) -> PpllNode {
    if index < per_chunk {
        return ppll_nodes_0[index];
    }
    let i1 = index - per_chunk;
    if i1 < per_chunk {
        return ppll_nodes_1[i1];
    }
    let i2 = i1 - per_chunk;
    if i2 < per_chunk {
        return ppll_nodes_2[i2];
    }
    return ppll_nodes_3[i2 - per_chunk];
}
