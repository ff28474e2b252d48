// The simulated hair into the renderers' vertex buffer, once a frame (twin of
// tress_sim::Simulation::positions and tress_sim::follow). Entry points, in order:
//
//   write_frames     (a guide vertex)     each guide segment's frame: the head's rotation, then the
//                                   smallest rotation from the head-turned rest direction to the
//                                   current one
//   write_guides     (a guide vertex)     the guides' positions as simulated
//   write_followers  (a follower vertex)  each follower rebuilt from its guides' blend at the same
//                                   fraction of their length, plus its rest offset turned by the
//                                   blend of their frames there (at the root, by the head's
//                                   rotation alone)
//   fix_follower_lengths (a follower)     each follower keeps its segments' directions and takes
//                                   back their rest lengths from the root out
//                                   (tress_sim::follow::keep_lengths)
//
// Only `position` of the renderers' `StrandVertex` is written; thickness, colour and alpha stay
// as uploaded.

#include "common/sim.wgsl"

// Mirrored by `gpu::types::SimOutputParams`.
struct SimOutputParams {
    // The head's rotation now.
    head_rotation: vec4<f32>,
    // x: guide vertices, y: follower vertices, z: followers, w: unused.
    counts: vec4<u32>,
}

// Mirrored by `gpu::types::StrandVertex` (the renderers' vertex; only `position` is written).
struct SimOutVertex {
    position: vec3<f32>,
    thickness: f32,
    color: vec3<f32>,
    alpha: f32,
}

// Mirrored by `gpu::types::SimFollower`.
struct SimFollower {
    // xyz: its guides (simulated strands); w: its vertex count.
    guides: vec4<u32>,
    // xyz: the guides' weights (summing to 1).
    weights: vec4<f32>,
    // Its first vertex in `follower_vertices`.
    first: u32,
    // Its first vertex in the renderers' buffer.
    asset_first: u32,
    _pad0: u32,
    _pad1: u32,
}

// Mirrored by `gpu::types::SimFollowerVertex`.
struct SimFollowerVertex {
    // The rest offset from the guides' blend, head space.
    offset: vec3<f32>,
    // Its follower.
    follower: u32,
}

@group(0) @binding(0) var<uniform> out_params: SimOutputParams;
@group(0) @binding(1) var<storage, read> cur: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> offsets: array<u32>;
@group(0) @binding(3) var<storage, read_write> seg_frames: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> out_vertices: array<SimOutVertex>;

// Group 1 of `write_frames` and `write_guides`.
@group(1) @binding(0) var<storage, read> rest: array<SimRest>;
@group(1) @binding(1) var<storage, read> guide_first: array<u32>;

// Group 1 of `write_followers`.
@group(1) @binding(2) var<storage, read> followers: array<SimFollower>;
@group(1) @binding(3) var<storage, read> follower_vertices: array<SimFollowerVertex>;
// Rest length of the segment ending at each follower vertex (0 at a root).
@group(1) @binding(4) var<storage, read> follower_len: array<f32>;

fn thread_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

@compute @workgroup_size(64)
fn write_frames(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= out_params.counts.x {
        return;
    }
    let head = out_params.head_rotation;
    let s = rest[i].strand;
    if i + 1u >= offsets[s + 1u] {
        // The tip: no segment starts here.
        seg_frames[i] = head;
        return;
    }
    let r = normalize_or_zero(quat_rotate(head, rest[i + 1u].position - rest[i].position));
    let c = normalize_or_zero(cur[i + 1u].xyz - cur[i].xyz);
    var turn = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if any(r != vec3<f32>(0.0)) && any(c != vec3<f32>(0.0)) {
        turn = quat_arc(r, c);
    }
    seg_frames[i] = normalize(quat_mul(turn, head));
}

@compute @workgroup_size(64)
fn write_guides(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= out_params.counts.x {
        return;
    }
    let s = rest[i].strand;
    out_vertices[guide_first[s] + (i - offsets[s])].position = cur[i].xyz;
}

@compute @workgroup_size(64)
fn write_followers(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = thread_index(id, groups);
    if v >= out_params.counts.y {
        return;
    }
    let fv = follower_vertices[v];
    let f = followers[fv.follower];
    let j = v - f.first;
    let m = f.guides.w;
    let frac = select(0.0, f32(j) / f32(m - 1u), m >= 2u);
    var blend = vec3<f32>(0.0);
    var q_sum = vec4<f32>(0.0);
    var reference = vec4<f32>(0.0);
    var have_reference = false;
    for (var k = 0u; k < 3u; k = k + 1u) {
        let w = f.weights[k];
        if w == 0.0 {
            continue;
        }
        let g = f.guides[k];
        let first = offsets[g];
        let n = offsets[g + 1u] - first;
        // tress_sim::follow::sample_at.
        var seg = 0u;
        var t = 0.0;
        if n >= 2u {
            let x = clamp(frac, 0.0, 1.0) * f32(n - 1u);
            seg = min(u32(floor(x)), n - 2u);
            t = x - f32(seg);
        }
        let a = cur[first + seg].xyz;
        let b = select(a, cur[first + seg + 1u].xyz, n > 1u);
        blend += mix(a, b, t) * w;
        var q = seg_frames[first + seg];
        if have_reference && dot(reference, q) < 0.0 {
            q = -q;
        }
        if !have_reference {
            reference = q;
            have_reference = true;
        }
        q_sum += q * w;
    }
    let len = length(q_sum);
    var q = select(vec4<f32>(0.0, 0.0, 0.0, 1.0), q_sum / len, len > 0.0);
    if j == 0u {
        // A root turns with the head alone, so it sits exactly where the head carries it.
        q = out_params.head_rotation;
    }
    out_vertices[f.asset_first + j].position = blend + quat_rotate(q, fv.offset);
}

@compute @workgroup_size(64)
fn fix_follower_lengths(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= out_params.counts.z {
        return;
    }
    let f = followers[i];
    let m = f.guides.w;
    if m < 2u {
        return;
    }
    var before = out_vertices[f.asset_first].position;
    var fixed = before;
    for (var j = 1u; j < m; j = j + 1u) {
        let x = out_vertices[f.asset_first + j].position;
        let d = x - before;
        let l = length(d);
        before = x;
        fixed += select(d, d * (follower_len[f.first + j] / l), l > 0.0);
        out_vertices[f.asset_first + j].position = fixed;
    }
}
