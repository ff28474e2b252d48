// Ambient-occlusion bake (`volume.ao_texel`): after the resolve, one invocation per texel of the
// AO texture, `volume.ao_texel` voxels a side, stores the local ambient occlusion (§3.4, `local_ao`) at
// the texel's centre, so that every shaded point then reads it with one filtered lookup instead
// of `ao_samples` trilinear density samples (twin: tress_shading::volume::bake_ao). Only texels
// a shaded point can reach are evaluated: those whose filter footprint meets an occupied block
// (points lie on strands, in voxels the resolve counted, whose blocks it marked with a voxel's
// margin); the rest hold 1. Owner: `AoBake`.

#include "common/volume.wgsl"

@group(0) @binding(0) var<uniform> volume: VolumeParams;
@group(0) @binding(1) var<storage, read> grid: VolumeGrid;
@group(0) @binding(2) var<storage, read> occupancy: array<u32>;
@group(0) @binding(3) var density: texture_3d<f32>;
@group(0) @binding(4) var density_sampler: sampler;
@group(0) @binding(5) var ao_out: texture_storage_3d<rgba8unorm, write>;

// Whether a shaded point can read texel `t` through the trilinear filter (twin:
// tress_shading::volume::ao_texel_reached): a point at voxel position `x` reads the texels whose
// centres `T·(t + 1/2)` lie within `T` of it (`T` voxels a texel), so points in voxels
// `T·t - ceil(T/2) ..= T·t + ceil(3T/2) - 1`. Points lie on strands, within a voxel of a voxel the
// resolve counted, and it marked the blocks of each counted voxel's neighbours.
fn texel_reached(t: vec3<u32>, texel: u32) -> bool {
    let last = vec3<i32>(i32(volume.occupancy_res) - 1);
    let first = vec3<i32>(t * texel);
    let before = i32((texel + 1u) / 2u);
    let after = i32((3u * texel + 1u) / 2u) - 1;
    let b0 = clamp((first - vec3<i32>(before)) / i32(OCCUPANCY_BLOCK), vec3<i32>(0), last);
    let b1 = clamp((first + vec3<i32>(after)) / i32(OCCUPANCY_BLOCK), vec3<i32>(0), last);
    for (var z = b0.z; z <= b1.z; z = z + 1) {
        for (var y = b0.y; y <= b1.y; y = y + 1) {
            for (var x = b0.x; x <= b1.x; x = x + 1) {
                if occupancy[voxel_index(volume.occupancy_res, vec3<u32>(vec3<i32>(x, y, z)))] != 0u {
                    return true;
                }
            }
        }
    }
    return false;
}

@compute @workgroup_size(4, 4, 4)
fn bake(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id >= textureDimensions(ao_out)) {
        return;
    }
    var visibility = 1.0;
    let texel = max(volume.ao_texel, 1u);
    if grid.occupied != 0u && texel_reached(id, texel) {
        let x = (vec3<f32>(id) + vec3<f32>(0.5)) * f32(texel);
        visibility = local_ao(density, density_sampler, grid, volume, x);
    }
    textureStore(ao_out, id, vec4<f32>(visibility, 0.0, 0.0, 0.0));
}
