// Volume resolve pass (Jansson 2019 §3.3, Figure 4): one invocation per voxel turns the counters
// into 8-bit texels of the 3D volume texture — rgb the de-quantized mean tangent, a the count —
// and of the highlight texture (each light's mean quantized highlight, tress_shading::highlights),
// with the reconstruction box filter in the vertices mode (twin of
// tress_shading::voxelize::resolve and encode_texel), and marks the occupancy blocks the voxel's
// trilinear footprint touches. A filter box summing more than 255 counts (vertices mode only: the
// segments mode's counters hold at most 255) is clamped and counted. Owner: `VolumeResolve`.

#include "common/volume.wgsl"

@group(0) @binding(0) var<uniform> volume: VolumeParams;
@group(0) @binding(1) var<storage, read> grid: VolumeGrid;
@group(0) @binding(2) var<storage, read> counts: array<u32>;
@group(0) @binding(3) var<storage, read> tangent_xy: array<u32>;
@group(0) @binding(4) var<storage, read> tangent_z: array<u32>;
@group(0) @binding(5) var volume_out: texture_storage_3d<rgba8unorm, write>;
@group(0) @binding(6) var<storage, read_write> occupancy: array<atomic<u32>>;
@group(0) @binding(7) var<storage, read> region: ResolveArgs;
@group(0) @binding(8) var<storage, read_write> stats: VoxelStats;
// The voxelizer's quantized highlight sums (two words a voxel) and the highlight texture they
// resolve into, one channel a light (tress_shading::highlights).
@group(0) @binding(9) var<storage, read> highlight_sums: array<u32>;
@group(0) @binding(10) var highlights_out: texture_storage_3d<rgba8unorm, write>;

// Dispatched indirectly over `region` (this frame's box and the last frame's): texels outside
// this frame's box are zeroed, so every texel outside it holds zero.
@compute @workgroup_size(4, 4, 4)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let res = volume.resolution;
    let v = id + region.origin;
    if any(v >= min(region.end, vec3<u32>(res))) {
        return;
    }
    if any(v < grid.box_min) || any(v >= grid.box_max) {
        textureStore(volume_out, v, vec4<f32>(0.0));
        textureStore(highlights_out, v, vec4<f32>(0.0));
        return;
    }
    let vertices = volume.voxelize == VOXELIZE_VERTICES;
    let r = i32(select(0u, volume.reconstruction_radius, vertices));
    // Most voxels are empty: without a filter their texel is zero and they mark nothing.
    if r == 0 && counts[voxel_index(res, v)] == 0u {
        textureStore(volume_out, v, vec4<f32>(0.0));
        textureStore(highlights_out, v, vec4<f32>(0.0));
        return;
    }
    var c = 0u;
    var sum = vec3<u32>(0u);
    var lit = vec4<u32>(0u);
    var fades = 0u;
    for (var dz = -r; dz <= r; dz = dz + 1) {
        for (var dy = -r; dy <= r; dy = dy + 1) {
            for (var dx = -r; dx <= r; dx = dx + 1) {
                let n = vec3<i32>(v) + vec3<i32>(dx, dy, dz);
                if any(n < vec3<i32>(0)) || any(n >= vec3<i32>(i32(res))) {
                    continue;
                }
                let i = voxel_index(res, vec3<u32>(n));
                c = c + min(counts[i], volume.capacity);
                let xy = tangent_xy[i];
                let z = tangent_z[i];
                sum = sum + vec3<u32>(xy & 0xffffu, xy >> 16u, z & 0xffffu);
                fades = fades + (z >> 16u);
                let h01 = highlight_sums[2u * i];
                let h23 = highlight_sums[2u * i + 1u];
                lit = lit + vec4<u32>(h01 & 0xffffu, h01 >> 16u, h23 & 0xffffu, h23 >> 16u);
            }
        }
    }
    if c > TEXEL_MAX_COUNT {
        atomicAdd(&stats.saturated, 1u);
    }
    let tangent = dequantize_tangent(vec3<f32>(sum), f32(c));
    textureStore(volume_out, v, encode_texel(tangent, c));
    let h = vec4<u32>(
        highlight_texel(lit.x, fades), highlight_texel(lit.y, fades),
        highlight_texel(lit.z, fades), highlight_texel(lit.w, fades));
    textureStore(highlights_out, v, vec4<f32>(h) / 255.0);
    if c > 0u {
        let last = vec3<i32>(i32(volume.occupancy_res) - 1);
        let b0 = clamp((vec3<i32>(v) - vec3<i32>(1)) / i32(OCCUPANCY_BLOCK), vec3<i32>(0), last);
        let b1 = clamp((vec3<i32>(v) + vec3<i32>(1)) / i32(OCCUPANCY_BLOCK), vec3<i32>(0), last);
        for (var z = b0.z; z <= b1.z; z = z + 1) {
            for (var y = b0.y; y <= b1.y; y = y + 1) {
                for (var x = b0.x; x <= b1.x; x = x + 1) {
                    atomicStore(&occupancy[voxel_index(volume.occupancy_res, vec3<u32>(vec3<i32>(x, y, z)))], 1u);
                }
            }
        }
    }
}
