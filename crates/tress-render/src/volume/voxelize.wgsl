// Voxelize pass (Jansson 2019 §3.3, "Strand Voxelization"; §4.2 for the segments mode): one
// invocation per segment deposits samples into the per-voxel atomic counters and sums their
// quantized tangents and, with `volume.highlights`, their quantized Kajiya-Kay highlights for
// this frame's view and lights (twin of tress_shading::voxelize::voxelize_lit). A sample finding
// its counter at the capacity is dropped and counted. Owner: `Voxelize`.

#include "common/strand.wgsl"
#include "common/volume.wgsl"
#include "common/shading.wgsl"

@group(0) @binding(0) var<uniform> volume: VolumeParams;
@group(0) @binding(1) var<storage, read> grid: VolumeGrid;
@group(0) @binding(2) var<storage, read_write> counts: array<atomic<u32>>;
// Quantized tangent sums: x in the low 16 bits, y in the high 16 bits; z in the low 16 bits and
// the quantized tip fades (the highlights' weights) in the high 16 bits.
@group(0) @binding(3) var<storage, read_write> tangent_xy: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> tangent_z: array<atomic<u32>>;
@group(0) @binding(5) var<storage, read_write> stats: VoxelStats;
// Quantized highlight sums, two words a voxel: lights 0 and 1, then 2 and 3 (16 bits each).
@group(0) @binding(6) var<storage, read_write> highlight_sums: array<atomic<u32>>;

var<workgroup> wg_deposits: atomic<u32>;
var<workgroup> wg_dropped: atomic<u32>;

// The quantized highlights of a segment of tip fade `fade` for each light, quantize(fade * spec)
// (tress_shading::highlights::segment_highlights), packed two to a word; zero when the volume
// integrates none.
fn segment_highlights(p0: vec3<f32>, p1: vec3<f32>, t: vec3<f32>, fade: f32) -> vec2<u32> {
    if volume.highlights == 0u {
        return vec2<u32>(0u);
    }
    var v = -volume.view_forward;
    if volume.view_orthographic == 0u {
        let d = volume.view_eye - (p0 + p1) * 0.5;
        let len = length(d);
        if len >= 1e-20 {
            v = d / len;
        }
    }
    var q = vec4<u32>(0u);
    for (var i = 0u; i < min(volume.light_count, 4u); i = i + 1u) {
        let l = volume.light_dirs[i].xyz;
        q[i] = quantize_highlight(fade * kajiya_kay_specular(t, l, v, volume.highlight_exponent));
    }
    return vec2<u32>(q.x | (q.y << 16u), q.z | (q.w << 16u));
}

// Add one sample at fixed-point position `q` (quantized tangent `tq`, highlights `hq`, fade
// `fq`); returns 1 when it was dropped.
fn deposit(q: vec3<u32>, tq: vec3<u32>, hq: vec2<u32>, fq: u32) -> u32 {
    let i = voxel_index(grid.res, q >> vec3<u32>(SUBVOXEL_BITS));
    let old = atomicAdd(&counts[i], 1u);
    // Design rule 8: check against the capacity, count what is dropped.
    if old >= volume.capacity {
        return 1u;
    }
    atomicAdd(&tangent_xy[i], tq.x | (tq.y << 16u));
    atomicAdd(&tangent_z[i], tq.z | (fq << 16u));
    // Most samples are far from every light's mirror cone: their zero adds are skipped.
    if hq.x != 0u {
        atomicAdd(&highlight_sums[2u * i], hq.x);
    }
    if hq.y != 0u {
        atomicAdd(&highlight_sums[2u * i + 1u], hq.y);
    }
    return 0u;
}

@compute @workgroup_size(64)
fn voxelize(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    if li == 0u {
        atomicStore(&wg_deposits, 0u);
        atomicStore(&wg_dropped, 0u);
    }
    workgroupBarrier();
    let s = id.x + id.y * groups.x * 64u;
    if s < volume.segment_count && grid.occupied != 0u {
        let seg = strand_segments[s];
        let p0 = strand_vertices[seg.x].position;
        let p1 = strand_vertices[seg.x + 1u].position;
        // The strands' tip fade weighs the tangent: the mean tangent's length carries the
        // opacity the raymarcher gives the voxel's strands.
        var fade = 1.0;
        if volume.fade_ref > 0.0 {
            let th = strand_vertices[seg.x].thickness + strand_vertices[seg.x + 1u].thickness;
            fade = saturate(0.5 * th / volume.fade_ref);
        }
        let t = segment_tangent(p0, p1);
        let tq = quantize_tangent(t * fade);
        let hq = segment_highlights(p0, p1, t, fade);
        let fq = quantize_highlight(fade);
        let q0 = fixed_point(grid, p0);
        let q1 = fixed_point(grid, p1);
        var deposits = 0u;
        var dropped = 0u;
        if volume.voxelize == VOXELIZE_SEGMENTS {
            let n = segment_sample_count(q0, q1, s);
            let a = vec3<i32>(q0);
            let d = vec3<i32>(q1) - a;
            for (var k = 0u; k < n; k = k + 1u) {
                dropped = dropped + deposit(segment_sample(a, d, k, n), tq, hq, fq);
            }
            deposits = n;
        } else {
            dropped = deposit(q0, tq, hq, fq);
            deposits = 1u;
            // The last segment of a strand also deposits the strand's last vertex.
            var last = s + 1u >= volume.segment_count;
            if !last {
                let next = strand_segments[s + 1u];
                last = next.y != seg.y || next.x != seg.x + 1u;
            }
            if last {
                dropped = dropped + deposit(q1, tq, hq, fq);
                deposits = 2u;
            }
        }
        atomicAdd(&wg_deposits, deposits);
        atomicAdd(&wg_dropped, dropped);
    }
    workgroupBarrier();
    if li == 0u {
        atomicAdd(&stats.deposits, atomicLoad(&wg_deposits));
        atomicAdd(&stats.dropped, atomicLoad(&wg_dropped));
    }
}
