// The radiance of a strand fragment from all lights (Jansson 2019 §3.1 Kajiya-Kay, or
// Scheuermann's dual shifted highlights), with ADSM or volume shadows and the volume's local
// ambient occlusion (§3.4). Shared by the OIT passes that shade fragments (PPLL build, ShortCut
// shade). The lighting group is @group(1).

#include "common/strand.wgsl"
#include "common/lighting.wgsl"

// A well-mixed 32-bit hash (PCG-style output permutation).
fn hash_u32(x: u32) -> u32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    return (h >> 22u) ^ h;
}

// A per-strand random number in [0, 1): stands in for Scheuermann's shift and noise textures.
fn strand_random(strand: u32, salt: u32) -> f32 {
    return f32(hash_u32(strand * 2u + salt) >> 8u) / 16777216.0;
}

// Radiance of a strand fragment from all lights under Marschner's lobes with dual scattering:
// the unscattered light is the shadow's visibility, the strands in the way those the
// visibility stands for.
fn shade_strand_marschner(
    in: StrandVarying, t: vec3<f32>, v: vec3<f32>, base: vec3<f32>, params: StrandParams,
) -> vec3<f32> {
    var color = lights.ambient * base;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let light = lights.lights[i];
        let direct = shadow_visibility(i, in.world_line, params);
        let n = strands_from_visibility(direct, params.shadow_alpha);
        color = color + material_dual_scattering(
            t, light.to_light, light_radiance(light), v, n, direct);
    }
    return color;
}

// Radiance of a strand fragment from all lights.
fn shade_strand(in: StrandVarying, camera: Camera, params: StrandParams) -> vec3<f32> {
    let t = normalize(in.tangent);
    let v = camera_to_eye(camera, in.world_line);
    let base = select(material.base_color, in.color.rgb, params.vertex_color != 0u);
    var color: vec3<f32>;
    if params.shading == SHADING_MARSCHNER {
        color = shade_strand_marschner(in, t, v, base, params);
    } else {
        color = shade_strand_kajiya_kay(in, t, v, base, params);
    }
    // Local ambient occlusion from the hair volume (Jansson 2019 §3.4), when enabled.
    if volume_params.raster_ao != 0u {
        color = color * volume_ambient_occlusion(in.world_line);
    }
    return color;
}

// Radiance of a strand fragment from all lights under Kajiya-Kay or Scheuermann's lobes.
fn shade_strand_kajiya_kay(
    in: StrandVarying, t: vec3<f32>, v: vec3<f32>, base: vec3<f32>, params: StrandParams,
) -> vec3<f32> {
    // Scheuermann needs a normal: the direction away from the hair's centre, made perpendicular
    // to the tangent (the view direction when that is degenerate).
    var n = in.world_line - params.hair_center;
    n = n - dot(n, t) * t;
    if length(n) < 1e-6 {
        n = v - dot(v, t) * t;
    }
    n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(n), length(n) > 1e-12);
    var color = lights.ambient * base;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let light = lights.lights[i];
        let l = light.to_light;
        var c: vec3<f32>;
        if params.shading == SHADING_SCHEUERMANN {
            let s = HairSample(t, strand_random(in.strand, 0u), n, strand_random(in.strand, 1u), base, 1.0);
            c = hair_lighting(material.lighting, s, l, light_radiance(light), v);
        } else {
            let kk = KajiyaKay(base, material.lighting.primary_color, material.lighting.primary_exponent);
            c = kajiya_kay(kk, t, l, v) * light_radiance(light);
        }
        color = color + c * shadow_visibility(i, in.world_line, params);
    }
    return color;
}
