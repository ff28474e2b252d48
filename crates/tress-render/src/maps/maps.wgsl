// Geometry maps of hair for research data: per pixel the nearest strand's index, its projected
// direction and the view depth, and the head's silhouette. Strands are drawn as 1-pixel lines
// (as moderngl's GL_LINES in MonoHair or Im2Haircut), the head as triangles, nearest wins.
// The CPU twin of the vertex stage is maps::cpu::segment_direction (tests compare them).

struct MapCamera {
    clip_from_world: mat4x4<f32>,
    // The third row of view_from_world: view z = dot(view_z, (p, 1)), negative in front.
    view_z: vec4<f32>,
    viewport: vec2<f32>,
    _pad: vec2<f32>,
}

@group(0) @binding(0) var<uniform> cam: MapCamera;
// Two entries a segment: (a.xyz, strand index as bits), (b.xyz, 0).
@group(0) @binding(1) var<storage, read> segments: array<vec4<f32>>;
// Head vertices (xyz, unused), drawn through an index buffer.
@group(0) @binding(2) var<storage, read> head: array<vec4<f32>>;

struct Varyings {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) id: i32,
    @location(1) @interpolate(flat) dir: vec2<f32>,
    @location(2) depth: f32,
}

struct Maps {
    @location(0) id: i32,
    @location(1) data: vec4<f32>,
    @location(2) head: vec4<f32>,
}

// Pixel coordinates of a clip-space point: x right, y down, the image's top-left corner at 0.
fn to_pixels(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((ndc.x + 1.0) * 0.5 * cam.viewport.x, (1.0 - ndc.y) * 0.5 * cam.viewport.y);
}

@vertex
fn vs_strand(@builtin(vertex_index) vi: u32) -> Varyings {
    let s = vi / 2u;
    let a = segments[2u * s];
    let b = segments[2u * s + 1u];
    let p = select(a.xyz, b.xyz, (vi & 1u) == 1u);
    let ca = cam.clip_from_world * vec4<f32>(a.xyz, 1.0);
    let cb = cam.clip_from_world * vec4<f32>(b.xyz, 1.0);
    var dir = vec2<f32>(0.0, 0.0);
    if (ca.w > 1e-6 && cb.w > 1e-6) {
        let d = to_pixels(cb) - to_pixels(ca);
        let len = length(d);
        if (len > 1e-12) {
            dir = d / len;
        }
    }
    var out: Varyings;
    out.clip = cam.clip_from_world * vec4<f32>(p, 1.0);
    out.id = bitcast<i32>(a.w);
    out.dir = dir;
    out.depth = -dot(cam.view_z, vec4<f32>(p, 1.0));
    return out;
}

@vertex
fn vs_head(@builtin(vertex_index) vi: u32) -> Varyings {
    let p = head[vi].xyz;
    var out: Varyings;
    out.clip = cam.clip_from_world * vec4<f32>(p, 1.0);
    out.id = -2;
    out.dir = vec2<f32>(0.0, 0.0);
    out.depth = -dot(cam.view_z, vec4<f32>(p, 1.0));
    return out;
}

@fragment
fn fs_maps(v: Varyings) -> Maps {
    var out: Maps;
    out.id = v.id;
    out.data = vec4<f32>(v.dir, v.depth, 0.0);
    out.head = vec4<f32>(1.0, 0.0, 0.0, 0.0);
    return out;
}
