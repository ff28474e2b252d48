// PPLL resolve pass (Jansson 2019 §3.2, "Sorting and Blending"): a fullscreen pass that walks
// each pixel's list, keeps the k nearest fragments sorted (insertion into a small array), blends
// them front to back and merges the rest order-independently under them (shading.wgsl's tail).
// The result is premultiplied and blended over the target (One, OneMinusSrcAlpha). Owner:
// `PpllResolve`.

#include "common/fullscreen.wgsl"
#include "common/camera.wgsl"
#include "common/params.wgsl"
#include "common/shading.wgsl"
#include "common/ppll_pool.wgsl"

// Largest k the resolve supports (the setting is clamped to it).
const MAX_K: u32 = 32u;

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vertex_index);
}

fn node_color(n: PpllNode) -> vec4<f32> {
    return vec4<f32>(unpack_rgb9e5(n.color), n.alpha);
}

fn kept_color(color: u32, alpha: f32) -> vec4<f32> {
    return vec4<f32>(unpack_rgb9e5(color), alpha);
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<u32>(position.xy);
    var node = atomicLoad(&ppll_heads[px.y * params.target_width + px.x]);
    if node == 0u {
        discard;
    }
    let k = clamp(params.k, 1u, MAX_K);
    // The k nearest so far, sorted by depth (nearest first): depth, packed colour and alpha,
    // kept here so that neither an eviction nor the final blend reads a node again (each node
    // is read from the pool once: a random access into hundreds of megabytes).
    var near_depth: array<f32, MAX_K>;
    var near_color: array<u32, MAX_K>;
    var near_alpha: array<f32, MAX_K>;
    var count = 0u;
    var tail = tail_empty();
    // Fragments merged into the tail (counted once per pixel into `ppll_counters.tail`).
    var merged = 0u;
    // A list can never be longer than the pool; the bound also guards against a corrupt list.
    var steps = 0u;
    while node != 0u && node <= params.node_capacity && steps < params.node_capacity {
        let index = node - 1u;
        let n = ppll_load(index, params.nodes_per_chunk);
        node = n.next;
        steps = steps + 1u;
        let depth = n.depth;
        if count == k {
            merged = merged + 1u;
            if depth >= near_depth[k - 1u] {
                let c = node_color(n);
                tail = tail_accumulate(tail, c.rgb, c.a);
                continue;
            }
            // Evict the farthest of the k into the tail.
            let c = kept_color(near_color[k - 1u], near_alpha[k - 1u]);
            tail = tail_accumulate(tail, c.rgb, c.a);
            count = k - 1u;
        }
        // Insertion sort step: shift farther entries back by one.
        var j = count;
        while j > 0u && near_depth[j - 1u] > depth {
            near_depth[j] = near_depth[j - 1u];
            near_color[j] = near_color[j - 1u];
            near_alpha[j] = near_alpha[j - 1u];
            j = j - 1u;
        }
        near_depth[j] = depth;
        near_color[j] = n.color;
        near_alpha[j] = n.alpha;
        count = count + 1u;
    }
    var acc = vec4<f32>(0.0);
    for (var i = 0u; i < count; i = i + 1u) {
        let c = kept_color(near_color[i], near_alpha[i]);
        acc = blend_front_to_back(acc, c.rgb, c.a);
    }
    acc = blend_under(acc, tail_resolve(tail));
    if merged > 0u {
        atomicAdd(&ppll_counters.tail, merged);
    }
    return acc;
}
