// The shading passes of the patch technique (Scheuermann 2004, slides "Putting it All Together"
// and "Sorted/Optimized Rendering Scheme"): the slide's `HairLighting` per light through the
// shared `shading.wgsl` functions, summed over the lights, plus the ambient light times base and
// ambient occlusion. With `patches.shading = "marschner"` each light's term is Marschner's R,
// TT and TRT lobes with dual scattering's local back-scattering instead (the fibre axis is the
// patch tangent; patches have no shadows, so no strands lie towards the light). The pass states
// (depth compare, culling, writes) live in the pipelines; the entry point picks the alpha test.
// Owner: `PatchShade`.

#include "patches/geometry.wgsl"
#include "common/lights.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(1) @binding(0) var<uniform> lights: Lights;

@vertex
fn vs_main(in: PatchVertex) -> PatchVarying {
    return patch_vertex(camera, in);
}

// Straight (not premultiplied) color and alpha of a fragment.
fn shade(in: PatchVarying) -> vec4<f32> {
    let base = textureSample(base_texture, patch_sampler, in.uv).rgb;
    let alpha = patch_alpha(in.uv);
    let shift_tex = textureSample(spec_shift_texture, patch_sampler, in.uv).r;
    let spec_mask = textureSample(spec_noise_texture, patch_sampler, in.uv).r;
    // Interpolated frames are renormalized, and the tangent made perpendicular to the normal
    // again (ShiftTangent assumes T ⟂ N).
    let n_len = length(in.normal);
    let n = select(vec3<f32>(0.0, 0.0, 1.0), in.normal / max(n_len, 1e-20), n_len > 1e-20);
    let t_perp = in.tangent - n * dot(n, in.tangent);
    let t_len = length(t_perp);
    let t = select(vec3<f32>(0.0, 1.0, 0.0), t_perp / max(t_len, 1e-20), t_len > 1e-20);
    let amb_occ = select(1.0, saturate(in.ao), patch_params.use_ao != 0u);
    let s = HairSample(t, shift_tex, n, spec_mask, base, amb_occ);
    let v = camera_to_eye(camera, in.world);
    var rgb = lights.ambient * base * amb_occ;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let light = lights.lights[i];
        if patch_params.shading == PATCH_SHADING_MARSCHNER {
            rgb = rgb + patch_marschner(t, light.to_light, light_radiance(light), v);
        } else {
            rgb = rgb + hair_lighting(patch_params.lighting, s, light.to_light, light_radiance(light), v);
        }
    }
    return vec4<f32>(rgb, alpha);
}

// `dual_scattering_lighting` of the patch fibre, unshadowed (no strands towards the light, all
// of it direct), the table read row by row from the uniform as `material_dual_scattering` does
// (CPU twin: `tress_shading::dual_scattering::dual_scattering_lighting(m, ds, t, l, c, v, 0, 1)`).
fn patch_marschner(t: vec3<f32>, l: vec3<f32>, light_color: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let r = ds_rows(hair_angles(t, l, v).sin_theta_i);
    let at = ds_table_mix(
        patch_params.dual.a_f[r.i], patch_params.dual.a_f[r.j], patch_params.dual.a_b[r.i],
        patch_params.dual.a_b[r.j], patch_params.dual.delta_b[r.i],
        patch_params.dual.delta_b[r.j], patch_params.dual.sigma_b2[r.i],
        patch_params.dual.sigma_b2[r.j], r.f);
    return ds_lighting_at(
        patch_params.fiber, patch_params.dual.params, patch_params.dual.tt_avg,
        patch_params.dual.trt_avg, at, t, l, light_color, v, 0.0, 1.0);
}

// No alpha test: the 4-pass scheme's passes 2 to 4 resolve opacity with the primed depth.
@fragment
fn fs_main(in: PatchVarying) -> @location(0) vec4<f32> {
    return shade(in);
}

// Alpha test passing only opaque pixels (the 3-pass scheme's pass 1).
@fragment
fn fs_opaque(in: PatchVarying) -> @location(0) vec4<f32> {
    let c = shade(in);
    if c.a < patch_params.alpha_ref {
        discard;
    }
    return c;
}

// Alpha test passing only non-opaque pixels (the 3-pass scheme's passes 2 and 3).
@fragment
fn fs_transparent(in: PatchVarying) -> @location(0) vec4<f32> {
    let c = shade(in);
    if c.a >= patch_params.alpha_ref {
        discard;
    }
    return c;
}

// The `min_alpha` option's last pass (4-pass): drops (nearly) empty fragments, which would
// otherwise write depth.
@fragment
fn fs_non_empty(in: PatchVarying) -> @location(0) vec4<f32> {
    let c = shade(in);
    if c.a < patch_params.min_alpha {
        discard;
    }
    return c;
}

// The `min_alpha` option's last pass (3-pass): non-opaque and not (nearly) empty.
@fragment
fn fs_transparent_non_empty(in: PatchVarying) -> @location(0) vec4<f32> {
    let c = shade(in);
    if c.a >= patch_params.alpha_ref || c.a < patch_params.min_alpha {
        discard;
    }
    return c;
}
