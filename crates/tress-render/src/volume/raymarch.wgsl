// Raymarch pass (Jansson 2019 §3.3, "Surface" and "Shading"; §3.4 for the volume shadows and
// ambient occlusion): the hair's AABB is rasterized (back faces, so the eye may be inside it) and
// every fragment marches its eye ray through the density volume with constant steps to the
// isosurface, stopping at the head's depth, then shades it like a strand fragment with the volume's
// mean tangent. Output: premultiplied color blended over the target. Owner: `Raymarch`.

#include "common/camera.wgsl"
#include "common/lighting.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;
@group(2) @binding(0) var head_depth: texture_depth_2d;
// Per 8³ block of voxels: 1 when the trilinear footprint of a non-empty voxel reaches it.
@group(2) @binding(1) var<storage, read> occupancy: array<u32>;
// Per voxel, each light's mean Kajiya-Kay highlight of the strands in it, for this frame's view
// (`volume.highlights = "strands"`; tress_shading::highlights).
@group(2) @binding(2) var volume_highlights: texture_3d<f32>;

// Corners (x + 2y + 4z) of the box's 12 triangles, counter-clockwise seen from outside.
const BOX_CORNERS = array<u32, 36>(
    0u, 4u, 6u, 0u, 6u, 2u,  1u, 3u, 7u, 1u, 7u, 5u,
    0u, 1u, 5u, 0u, 5u, 4u,  2u, 6u, 7u, 2u, 7u, 3u,
    0u, 2u, 3u, 0u, 3u, 1u,  4u, 5u, 7u, 4u, 7u, 6u,
);

// The march box: the hair's AABB grown by one voxel (the trilinear footprint of its voxels).
fn march_box_min() -> vec3<f32> {
    return volume_grid.bounds_min - vec3<f32>(volume_grid.voxel_size);
}

fn march_box_max() -> vec3<f32> {
    return volume_grid.bounds_max + vec3<f32>(volume_grid.voxel_size);
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4<f32> {
    if volume_grid.occupied == 0u {
        return vec4<f32>(0.0, 0.0, 0.0, 0.0);
    }
    let c = BOX_CORNERS[vertex_index % 36u];
    let corner = vec3<f32>(f32(c & 1u), f32((c >> 1u) & 1u), f32((c >> 2u) & 1u));
    return camera_clip(camera, mix(march_box_min(), march_box_max(), corner));
}

fn world_at(ndc: vec2<f32>, depth: f32) -> vec3<f32> {
    let h = volume_params.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    return h.xyz / h.w;
}

// Radiance of the isosurface point at voxel position `x` seen along `dir`.
fn shade_volume(x: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    let vt = volume_texels(volume_grid);
    let p = x / volume_grid.scale + volume_grid.origin;
    let mean = volume_sample(volume_texture, volume_sampler, vt, x).rgb;
    let t = select(vec3<f32>(0.0, 1.0, 0.0), normalize(mean), length(mean) > 1e-6);
    let v = -dir;
    let n = density_normal(density_gradient(volume_texture, volume_sampler, vt, x), v);
    let base = material.base_color;
    // Kajiya-Kay: the strands' own highlights, integrated per voxel by the voxelizer; or (the
    // paper's mean tangent) its lobe widened by how spread the strands around the point run, as
    // a pixel of strands averages the highlights of every direction it covers (Toksvig on the
    // cone lobe).
    let integrated = volume_params.highlights != 0u;
    var kk = KajiyaKay(base, material.lighting.primary_color, material.lighting.primary_exponent);
    if volume_params.shading == SHADING_KAJIYA_KAY && !integrated {
        kk = spread_kajiya_kay(kk, volume_tangent_coherence(volume_texture, volume_sampler, vt, x));
    }
    var color = lights.ambient * base;
    for (var i = 0u; i < min(lights.count, MAX_LIGHTS); i = i + 1u) {
        let light = lights.lights[i];
        let l = light.to_light;
        if volume_params.shading == SHADING_MARSCHNER {
            // Dual scattering from the strands the volume counts towards the light, with the
            // voxelized mean tangent.
            var direct = 1.0;
            if volume_params.march_shadows != 0u {
                direct = volume_light_visibility(i, p);
            }
            let n = strands_from_visibility(direct, volume_params.shadow_alpha);
            color = color + material_dual_scattering(t, l, light_radiance(light), v, n, direct);
            continue;
        }
        var c: vec3<f32>;
        if volume_params.shading == SHADING_SCHEUERMANN {
            // The per-strand shift and mask textures average out in a voxel: their means.
            let s = HairSample(t, 0.5, n, 0.5, base, 1.0);
            c = hair_lighting(material.lighting, s, l, light_radiance(light), v);
        } else if integrated {
            let specular = volume_highlight(volume_highlights, volume_texture, vt, x, i);
            c = (kk.diffuse * kajiya_kay_diffuse(t, l) + kk.specular * specular)
                * light_radiance(light);
        } else {
            c = kajiya_kay(kk, t, l, v) * light_radiance(light);
        }
        var visibility = 1.0;
        if volume_params.march_shadows != 0u {
            visibility = volume_light_visibility(i, p);
        }
        color = color + c * visibility;
    }
    if volume_params.march_ao != 0u {
        color = color * volume_ambient_occlusion(p);
    }
    return color;
}

// The transmittance at which a ray has reached the solid surface (1/256, `iso` strands in the
// paper's count).
const SOLID_TRANSMITTANCE: f32 = 1.0 / 256.0;

// Voxels one pixel spans at voxel position `x` (its view depth over the camera's pixels per unit).
fn pixel_voxels(x: vec3<f32>) -> f32 {
    let p = x / volume_grid.scale + volume_grid.origin;
    let depth = select(dot(p - camera.eye, camera.forward), 1.0, camera.orthographic != 0u);
    return max(depth, 0.0) / camera.pixels_per_unit * volume_grid.scale;
}

fn block_occupied(x: vec3<f32>) -> bool {
    let last = vec3<i32>(i32(volume_params.occupancy_res) - 1);
    let b = clamp(vec3<i32>(floor(x / f32(OCCUPANCY_BLOCK))), vec3<i32>(0), last);
    return occupancy[voxel_index(volume_params.occupancy_res, vec3<u32>(b))] != 0u;
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<u32>(position.xy);
    // A dithered hybrid's strand pixel: its strands draw there instead.
    if params.lod_dither != 0u && !(params.lod_factor > dither_threshold(px)) {
        discard;
    }
    let ndc = vec2<f32>(
        position.x / camera.viewport.x * 2.0 - 1.0,
        1.0 - position.y / camera.viewport.y * 2.0,
    );
    let a = world_at(ndc, 0.0);
    let dir = normalize(world_at(ndc, 1.0) - a);
    // Everything below is in voxel units (cubic voxels: directions are unchanged).
    let xo = voxel_from_world(volume_grid, a);
    let span = ray_box(
        xo, dir, voxel_from_world(volume_grid, march_box_min()),
        voxel_from_world(volume_grid, march_box_max()));
    let t0 = max(span.x, 0.0);
    var t1 = span.y;
    // Stop at the scene depth (the head).
    let depth = textureLoad(head_depth, px, 0);
    if depth < 1.0 {
        t1 = min(t1, dot(voxel_from_world(volume_grid, world_at(ndc, depth)) - xo, dir));
    }
    if t0 >= t1 {
        discard;
    }
    let vt = volume_texels(volume_grid);
    let lo = voxel_from_world(volume_grid, volume_grid.bounds_min);
    let hi = voxel_from_world(volume_grid, volume_grid.bounds_max);
    let step = length(hi - lo + vec3<f32>(2.0)) / f32(max(volume_params.steps, 1u));
    // Strands met, each weighed by its opacity fade (the length of the voxel's mean tangent).
    var strands = 0.0;
    // Their optical depth as the strands' lines (`volume.opacity = "strands"`).
    var optical = 0.0;
    // Transmittance after the last sample (1 - alpha of a ray short of the surface: the
    // paper's fake transparency).
    var tr_end = 1.0;
    var hit = false;
    var solid = false;
    var first = vec3<f32>(0.0);
    // The shading points: where the transmittance falls through each of `shade_samples` equal
    // shares of the composite's weight.
    var points: array<vec3<f32>, MAX_SHADE_SAMPLES>;
    let samples = clamp(volume_params.shade_samples, 1u, MAX_SHADE_SAMPLES);
    var m = 0u;
    var k = 0u;
    loop {
        if k >= volume_params.steps {
            break;
        }
        let t = t0 + (f32(k) + 0.5) * step;
        if t >= t1 {
            break;
        }
        let x = xo + dir * t;
        if volume_params.skip_empty != 0u && !block_occupied(x) {
            // Jump to the last lattice sample before the block's exit: samples stay on the
            // same lattice, and every sample skipped lies in the empty block.
            let b = floor(x / f32(OCCUPANCY_BLOCK)) * f32(OCCUPANCY_BLOCK);
            let exit = ray_box(xo, dir, b, b + vec3<f32>(f32(OCCUPANCY_BLOCK))).y;
            let last = floor((exit - t0) / step - 0.5);
            k = max(k + 1u, u32(clamp(last, 0.0, f32(volume_params.steps))));
            continue;
        }
        let v = volume_sample(volume_texture, volume_sampler, vt, x);
        if v.a > 0.0 && !hit {
            hit = true;
            first = x;
        }
        let met = v.a * length(v.rgb) * step;
        strands = strands + met;
        var tr: f32;
        if volume_params.optical_width > 0.0 {
            optical = optical + strand_optical_depth(
                met, v.rgb, dir, pixel_voxels(x), volume_params.optical_width);
            tr = exp(-optical);
        } else {
            tr = composite_transmittance(strands, volume_params.iso);
        }
        tr_end = tr;
        loop {
            if m >= samples || !composite_point_reached(tr, m, samples) {
                break;
            }
            points[m] = x;
            m = m + 1u;
        }
        if tr <= SOLID_TRANSMITTANCE {
            solid = true;
            break;
        }
        k = k + 1u;
    }
    if !hit {
        discard;
    }
    // Fake transparency (§3.3) where the ray never reaches the surface.
    let alpha = select(1.0 - tr_end, 1.0, solid);
    if alpha <= 1.0 / 1024.0 {
        discard;
    }
    // The composite's weight split equally between the points reached (the first non-empty
    // sample when the ray holds less than one share).
    var color = vec3<f32>(0.0);
    if m == 0u {
        color = shade_volume(first, dir);
    } else {
        for (var j = 0u; j < m; j = j + 1u) {
            color = color + shade_volume(points[j], dir);
        }
        color = color / f32(m);
    }
    return vec4<f32>(color * alpha, alpha);
}
