// PPLL build pass (Jansson 2019 §3.1-3.2, after TressFX / Yu et al.): every strand fragment that
// lies in front of the head is shaded (Kajiya-Kay or Scheuermann, with ADSM shadows), its alpha
// multiplied by the §3.2 line coverage, and inserted into its pixel's linked list. Owner:
// `PpllBuild`.

#include "common/strand_fragment.wgsl"
#include "common/strand_shading.wgsl"
#include "common/ppll_pool.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;
@group(3) @binding(6) var head_depth: texture_depth_2d;

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
    let alpha = strand_fragment_alpha(in, camera, params, head_depth);
    if alpha <= 0.0 {
        return;
    }
    let node = atomicAdd(&ppll_counters.requested, 1u);
    // Design rule 8: check against the capacity, count what is dropped (before shading, so a
    // full pool costs no shading).
    if node >= params.node_capacity {
        atomicAdd(&ppll_counters.dropped, 1u);
        return;
    }
    let color = shade_strand(in, camera, params);
    let prev = atomicExchange(&ppll_heads[strand_pixel_index(in, params)], node + 1u);
    ppll_store(node, params.nodes_per_chunk, PpllNode(pack_rgb9e5(color), alpha, in.position.z, prev));
}
