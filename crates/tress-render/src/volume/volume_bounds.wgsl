// Volume bounds pass (Jansson 2019 §3.3, "Surface"): the AABB of the hair, "expanding a cuboid
// with each incoming vertex", then the voxel grid fitted to it (twin of
// tress_shading::VoxelGrid::fit). Three entry points dispatched in order: `clear` (one
// invocation), `reduce` (one per vertex), `fit` (one invocation). Owner: `VolumeBounds`.

#include "common/strand.wgsl"
#include "common/volume.wgsl"

// Mirrored by `gpu::types::BoundsKeys`: the box as order-preserving keys of its floats.
struct BoundsKeys {
    lo: array<atomic<u32>, 3>,
    hi: array<atomic<u32>, 3>,
}

@group(0) @binding(0) var<uniform> volume: VolumeParams;
@group(0) @binding(1) var<storage, read_write> keys: BoundsKeys;
@group(0) @binding(2) var<storage, read_write> grid: VolumeGrid;
@group(0) @binding(3) var<storage, read_write> resolve_args: ResolveArgs;

var<workgroup> wg_lo: array<atomic<u32>, 3>;
var<workgroup> wg_hi: array<atomic<u32>, 3>;

// A u32 key whose unsigned order is the float order (negative floats: all bits flipped; others:
// the sign bit set), so atomicMin/atomicMax find the exact extremes.
fn order_key(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn from_key(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k & 0x7fffffffu, (k & 0x80000000u) != 0u));
}

@compute @workgroup_size(1)
fn clear() {
    for (var i = 0u; i < 3u; i = i + 1u) {
        atomicStore(&keys.lo[i], 0xffffffffu);
        atomicStore(&keys.hi[i], 0u);
    }
}

@compute @workgroup_size(64)
fn reduce(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    if li == 0u {
        for (var i = 0u; i < 3u; i = i + 1u) {
            atomicStore(&wg_lo[i], 0xffffffffu);
            atomicStore(&wg_hi[i], 0u);
        }
    }
    workgroupBarrier();
    let v = id.x + id.y * groups.x * 64u;
    if v < volume.vertex_count {
        let p = strand_vertices[v].position;
        for (var i = 0u; i < 3u; i = i + 1u) {
            let k = order_key(p[i]);
            atomicMin(&wg_lo[i], k);
            atomicMax(&wg_hi[i], k);
        }
    }
    workgroupBarrier();
    if li == 0u {
        for (var i = 0u; i < 3u; i = i + 1u) {
            atomicMin(&keys.lo[i], atomicLoad(&wg_lo[i]));
            atomicMax(&keys.hi[i], atomicLoad(&wg_hi[i]));
        }
    }
}

// The resolve's region: this frame's box and last frame's (still in `grid`), so that texels the
// last frame wrote outside this frame's box are zeroed. Then the new grid.
fn set_grid(g: VolumeGrid) {
    let prev_min = select(g.box_min, grid.box_min, any(grid.box_max > grid.box_min));
    let prev_max = select(g.box_max, grid.box_max, any(grid.box_max > grid.box_min));
    let origin = min(prev_min, g.box_min);
    let end = max(prev_max, g.box_max);
    resolve_args.origin = origin;
    resolve_args.end = end;
    resolve_args.groups = (end - origin + vec3<u32>(3u)) / 4u;
    grid = g;
}

@compute @workgroup_size(1)
fn fit() {
    var lo: vec3<f32>;
    var hi: vec3<f32>;
    for (var i = 0u; i < 3u; i = i + 1u) {
        lo[i] = from_key(atomicLoad(&keys.lo[i]));
        hi[i] = from_key(atomicLoad(&keys.hi[i]));
    }
    var g: VolumeGrid;
    g.res = volume.resolution;
    if volume.vertex_count == 0u || !all(lo <= hi) {
        g.occupied = 0u;
        g.scale = 1.0;
        g.voxel_size = 1.0;
        set_grid(g);
        return;
    }
    // tress_shading::VoxelGrid::fit, same operations in the same order.
    let extent = hi - lo;
    let longest = max(max(extent.x, extent.y), max(extent.z, 1e-6));
    let inner = f32(volume.resolution - 2u * GRID_PAD);
    let voxel_size = longest / inner;
    let center = (lo + hi) * 0.5;
    g.origin = center - vec3<f32>(voxel_size * (f32(volume.resolution) * 0.5));
    g.scale = inner / longest;
    g.voxel_size = voxel_size;
    g.bounds_min = lo;
    g.bounds_max = hi;
    g.occupied = 1u;
    // Voxels the hair's box touches, grown by the vertices mode's filter radius.
    let r = vec3<u32>(select(0u, volume.reconstruction_radius, volume.voxelize == VOXELIZE_VERTICES));
    let v0 = fixed_point(g, lo) >> vec3<u32>(SUBVOXEL_BITS);
    let v1 = fixed_point(g, hi) >> vec3<u32>(SUBVOXEL_BITS);
    g.box_min = max(v0, r) - r;
    g.box_max = min(v1 + vec3<u32>(1u) + r, vec3<u32>(g.res));
    // The texels' density unit: a count (segments), the filter's weight over its box (vertices).
    let side = f32(2u * r.x + 1u);
    g.density_unit = select(1.0, volume.mean_segment_length * g.scale / (side * side * side),
        volume.voxelize == VOXELIZE_VERTICES);
    set_grid(g);
}
