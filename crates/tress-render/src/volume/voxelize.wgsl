// Voxelize pass (Jansson 2019 §3.3, "Strand Voxelization"; §4.2 for the segments mode): one
// invocation per segment deposits samples into the per-voxel atomic counters and sums their
// quantized tangents (twin of tress_shading::voxelize). A sample finding its counter at the
// capacity is dropped and counted. Owner: `Voxelize`.

#include "common/strand.wgsl"
#include "common/volume.wgsl"

@group(0) @binding(0) var<uniform> volume: VolumeParams;
@group(0) @binding(1) var<storage, read> grid: VolumeGrid;
@group(0) @binding(2) var<storage, read_write> counts: array<atomic<u32>>;
// Quantized tangent sums: x in the low 16 bits, y in the high 16 bits; z.
@group(0) @binding(3) var<storage, read_write> tangent_xy: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> tangent_z: array<atomic<u32>>;
@group(0) @binding(5) var<storage, read_write> stats: VoxelStats;

var<workgroup> wg_deposits: atomic<u32>;
var<workgroup> wg_dropped: atomic<u32>;

// Add one sample at fixed-point position `q`; returns 1 when it was dropped.
fn deposit(q: vec3<u32>, tq: vec3<u32>) -> u32 {
    let i = voxel_index(grid.res, q >> vec3<u32>(SUBVOXEL_BITS));
    let old = atomicAdd(&counts[i], 1u);
    // Design rule 8: check against the capacity, count what is dropped.
    if old >= volume.capacity {
        return 1u;
    }
    atomicAdd(&tangent_xy[i], tq.x | (tq.y << 16u));
    atomicAdd(&tangent_z[i], tq.z);
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
        let tq = quantize_tangent(segment_tangent(p0, p1) * fade);
        let q0 = fixed_point(grid, p0);
        let q1 = fixed_point(grid, p1);
        var deposits = 0u;
        var dropped = 0u;
        if volume.voxelize == VOXELIZE_SEGMENTS {
            let n = segment_sample_count(q0, q1, s);
            let a = vec3<i32>(q0);
            let d = vec3<i32>(q1) - a;
            for (var k = 0u; k < n; k = k + 1u) {
                dropped = dropped + deposit(segment_sample(a, d, k, n), tq);
            }
            deposits = n;
        } else {
            dropped = deposit(q0, tq);
            deposits = 1u;
            // The last segment of a strand also deposits the strand's last vertex.
            var last = s + 1u >= volume.segment_count;
            if !last {
                let next = strand_segments[s + 1u];
                last = next.y != seg.y || next.x != seg.x + 1u;
            }
            if last {
                dropped = dropped + deposit(q1, tq);
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
