// The lighting bind group (@group(1)) shared by the head pass and the strand passes: lights,
// material, one ADSM shadow map per light and the hair volume for volume shadows and local
// ambient occlusion (Jansson 2019 §3.4).

#include "common/lights.wgsl"
#include "common/shading.wgsl"
#include "common/params.wgsl"
#include "common/volume.wgsl"
#include "common/marschner.wgsl"

// Mirrored by `gpu::types::MaterialUniform`.
struct Material {
    // Scheuermann's constants; Kajiya-Kay uses the primary color and exponent.
    lighting: HairLighting,
    base_color: vec3<f32>,
    _pad0: f32,
    head_color: vec3<f32>,
    _pad1: f32,
    // The physically based fibre of `strands.shading = "marschner"` (zero otherwise).
    fiber: Marschner,
    dual: DualScattering,
}

@group(1) @binding(0) var<uniform> lights: Lights;
@group(1) @binding(1) var<uniform> material: Material;
@group(1) @binding(2) var shadow_map_0: texture_depth_2d;
@group(1) @binding(3) var shadow_map_1: texture_depth_2d;
@group(1) @binding(4) var shadow_map_2: texture_depth_2d;
@group(1) @binding(5) var shadow_map_3: texture_depth_2d;
// The hair volume (rgb mean tangent, a density), its linear clamp-to-edge sampler, the grid the
// voxelizer fitted this frame and the volume settings (a 1³ empty volume when none is needed).
@group(1) @binding(6) var volume_texture: texture_3d<f32>;
@group(1) @binding(7) var volume_sampler: sampler;
@group(1) @binding(8) var<uniform> volume_grid: VolumeGrid;
@group(1) @binding(9) var<uniform> volume_params: VolumeParams;
// Local ambient occlusion baked after the voxelization (`volume.ao_texel`): r the visibility at
// each texel's centre, `ao_texel` voxels a texel; 1 where no strand is near (the empty volume's
// texture when the object has none: then `ao_texel` is 0 or the grid unoccupied, and it is never
// read).
@group(1) @binding(10) var volume_ao_texture: texture_3d<f32>;

// The most strands `strands_from_visibility` reports (fully shadowed; mirrored by
// `tress_shading::MAX_SHADOW_STRANDS`).
const MAX_SHADOW_STRANDS: f32 = 64.0;

// The strands of opacity `alpha` that let through `visibility` of the light: the inverse of
// `(1 - alpha)^n` (CPU twin: `tress_shading::strands_from_visibility`).
fn strands_from_visibility(visibility: f32, alpha: f32) -> f32 {
    let transmittance = 1.0 - clamp(alpha, 0.0, 1.0);
    if visibility >= 1.0 || transmittance >= 1.0 {
        return 0.0;
    }
    if visibility <= 0.0 || transmittance <= 0.0 {
        return MAX_SHADOW_STRANDS;
    }
    return min(log(visibility) / log(transmittance), MAX_SHADOW_STRANDS);
}

// Volume shadow (§3.4): the visibility (1 - alpha)^n of world point `p` from light `i`, n the
// strands counted through the volume towards the light times the hit fraction.
fn volume_light_visibility(i: u32, p: vec3<f32>) -> f32 {
    if volume_grid.occupied == 0u {
        return 1.0;
    }
    let x = voxel_from_world(volume_grid, p);
    let l = lights.lights[i].to_light;
    if volume_params.occlusion == OCCLUSION_ADSM {
        let s = volume_grid.scale;
        return volume_adsm_visibility(
            volume_texture, volume_sampler, volume_texels(volume_grid), x, l, volume_params.shadow_step,
            volume_params.shadow_offset, volume_params.occlusion_width * s,
            volume_params.occlusion_r * log(1.0 - min(volume_params.shadow_alpha, 0.999999)) / s,
            volume_params.occlusion_bias * s);
    }
    let n = volume_shadow_strands(
        volume_texture, volume_sampler, volume_texels(volume_grid), x, l, volume_params.shadow_step,
        volume_params.shadow_offset, volume_occlusion_cap());
    return strand_visibility(n * volume_hit_fraction(), volume_params.shadow_alpha);
}

// The most a voxel counts in shadows and AO (`occlusion_cap` of this object's settings).
fn volume_occlusion_cap() -> f32 {
    return occlusion_cap(volume_params);
}

// What turns the march's count into strands in the way (`occlusion_hit_fraction` on this
// object's grid).
fn volume_hit_fraction() -> f32 {
    return occlusion_hit_fraction(volume_params, volume_grid.scale);
}

// Local ambient occlusion (§3.4) of world point `p` from the density around it: one filtered
// lookup of the texture baked after the voxelization (`volume.ao_texel` voxels a texel, the
// default: its texels hold `local_ao` at their centres), or `local_ao` at `p` itself (0).
fn volume_ambient_occlusion(p: vec3<f32>) -> f32 {
    if volume_grid.occupied == 0u {
        return 1.0;
    }
    let x = voxel_from_world(volume_grid, p);
    if volume_params.ao_texel != 0u {
        let span = vec3<f32>(textureDimensions(volume_ao_texture)) * f32(volume_params.ao_texel);
        return textureSampleLevel(volume_ao_texture, volume_sampler, x / span, 0.0).r;
    }
    return local_ao(volume_texture, volume_sampler, volume_grid, volume_params, x);
}

// Shadow visibility of world point `p` from light `i` (1: lit): the volume shadow when
// `volume_params.raster_shadow_mode` says so, else ADSM. ADSM: points outside the light's map are
// lit. `r` is given per world unit and scaled to the map's normalized depth; the bias (world
// units) is subtracted from the fragment's depth before `d = max(0, f - s)`.
fn shadow_visibility(i: u32, p: vec3<f32>, params: StrandParams) -> f32 {
    if params.shadows == 0u {
        return 1.0;
    }
    if volume_params.raster_shadow_mode == SHADOW_MODE_VOLUME {
        return volume_light_visibility(i, p);
    }
    return adsm_map_visibility(i, p, params);
}

// ADSM (§3.4): the visibility of world point `p` from light `i` through its shadow map, PCF
// filtered; 1 outside the map.
fn adsm_map_visibility(i: u32, p: vec3<f32>, params: StrandParams) -> f32 {
    let light = lights.lights[i];
    let t = light_texel(light, p, params.shadow_map_size);
    if t.x < 0.0 || t.y < 0.0 || t.x >= params.shadow_map_size || t.y >= params.shadow_map_size
        || t.z < 0.0 || t.z > 1.0 {
        return 1.0;
    }
    let range = max(light.depth_range, 1e-6);
    let r = params.shadow_r * range;
    let f = t.z - params.shadow_bias / range;
    let texel = vec2<i32>(t.xy);
    switch i {
        case 0u: { return adsm_pcf(shadow_map_0, texel, params.pcf_radius, f, r, params.shadow_alpha); }
        case 1u: { return adsm_pcf(shadow_map_1, texel, params.pcf_radius, f, r, params.shadow_alpha); }
        case 2u: { return adsm_pcf(shadow_map_2, texel, params.pcf_radius, f, r, params.shadow_alpha); }
        default: { return adsm_pcf(shadow_map_3, texel, params.pcf_radius, f, r, params.shadow_alpha); }
    }
}

// `dual_scattering_lighting` with the material's fibre and table, the table read row by row
// from the uniform (never loaded whole: see `ds_lighting_at`).
fn material_dual_scattering(
    t: vec3<f32>, l: vec3<f32>, light_color: vec3<f32>, v: vec3<f32>, strands: f32,
    direct: f32) -> vec3<f32> {
    let r = ds_rows(hair_angles(t, l, v).sin_theta_i);
    let at = ds_table_mix(
        material.dual.a_f[r.i], material.dual.a_f[r.j], material.dual.a_b[r.i],
        material.dual.a_b[r.j], material.dual.delta_b[r.i], material.dual.delta_b[r.j],
        material.dual.sigma_b2[r.i], material.dual.sigma_b2[r.j], r.f);
    return ds_lighting_at(
        material.fiber, material.dual.params, material.dual.tt_avg, material.dual.trt_avg, at,
        t, l, light_color, v, strands, direct);
}
