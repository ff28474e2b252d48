// PPLL build pass (Jansson 2019 §3.1-3.2, after TressFX / Yu et al.): every strand fragment that
// lies in front of the head is shaded (Kajiya-Kay or Scheuermann, with ADSM shadows), its alpha
// multiplied by the §3.2 line coverage, and inserted into its pixel's linked list. Owner:
// `PpllBuild`.

#include "common/strand.wgsl"
#include "common/lighting.wgsl"
#include "common/ppll.wgsl"

// Mirrored by `gpu::types::PpllCounters`.
struct PpllCounters {
    requested: atomic<u32>,
    dropped: atomic<u32>,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;
// Per pixel: index + 1 of the first node; 0 is an empty list.
@group(3) @binding(0) var<storage, read_write> ppll_heads: array<atomic<u32>>;
@group(3) @binding(1) var<storage, read_write> ppll_nodes: array<PpllNode>;
@group(3) @binding(2) var<storage, read_write> ppll_counters: PpllCounters;
@group(3) @binding(3) var head_depth: texture_depth_2d;

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> StrandVarying {
    return strand_vertex(
        camera,
        vertex_index,
        params.width_px,
        params.thickness_fade,
        params.thickness_ref,
    );
}

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

// Radiance of a strand fragment from all lights.
fn shade_strand(in: StrandVarying) -> vec3<f32> {
    let t = normalize(in.tangent);
    let v = camera_to_eye(camera, in.world_line);
    let base = select(material.base_color, in.color.rgb, params.vertex_color != 0u);
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
    // Local ambient occlusion from the hair volume (Jansson 2019 §3.4), when enabled.
    if volume_params.raster_ao != 0u {
        color = color * volume_ambient_occlusion(in.world_line);
    }
    return color;
}

@fragment
fn fs_main(in: StrandVarying) {
    let px = vec2<u32>(in.position.xy);
    // Hair is depth-tested against the head here: stores are side effects, so the fixed-function
    // late depth test could not prevent them.
    if in.position.z >= textureLoad(head_depth, px, 0) {
        return;
    }
    var alpha = in.color.a * params.alpha;
    if params.coverage != 0u {
        alpha = alpha * strand_coverage(
            in.position.xy, vec4<f32>(in.world_line, 1.0), camera.clip_from_world, camera.viewport,
            params.width_px);
    }
    if alpha <= 1.0 / 1024.0 {
        return;
    }
    let node = atomicAdd(&ppll_counters.requested, 1u);
    // Design rule 8: check against the capacity, count what is dropped (before shading, so a
    // full pool costs no shading).
    if node >= params.node_capacity {
        atomicAdd(&ppll_counters.dropped, 1u);
        return;
    }
    let color = shade_strand(in);
    let prev = atomicExchange(&ppll_heads[px.y * params.target_width + px.x], node + 1u);
    ppll_nodes[node] = PpllNode(pack_rgb9e5(color), min(alpha, 1.0), in.position.z, prev);
}
