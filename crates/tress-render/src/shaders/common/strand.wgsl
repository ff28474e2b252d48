// Strand geometry shared by the strand passes: vertex pulling from storage buffers and the
// expansion of each segment into a camera-facing quad of constant screen width (Jansson 2019
// §3.2 draws lines of constant width; wgpu has only 1-pixel lines, so the quad is the line).
//
// Every pass that includes this file binds the asset at @group(2) @binding(0..1).

#include "common/camera.wgsl"
#include "common/shading.wgsl"
#include "common/params.wgsl"

// One strand vertex (mirrored by `gpu::types::StrandVertex`).
struct StrandVertex {
    position: vec3<f32>,
    // Strand diameter in world units (0 when the asset has none).
    thickness: f32,
    // Linear RGB vertex color (1 when the asset has none).
    color: vec3<f32>,
    // 1 - transparency.
    alpha: f32,
}

@group(2) @binding(0) var<storage, read> strand_vertices: array<StrandVertex>;
// Per segment: (index of its first vertex, index of its strand).
@group(2) @binding(1) var<storage, read> strand_segments: array<vec2<u32>>;

struct StrandVarying {
    @builtin(position) position: vec4<f32>,
    // World position on the segment's centre line (for the coverage of §3.2).
    @location(0) world_line: vec3<f32>,
    // Segment tangent (Q - P) / |Q - P| (§3.1).
    @location(1) tangent: vec3<f32>,
    // Vertex color and alpha (strand alpha times thickness fade).
    @location(2) color: vec4<f32>,
    @location(3) @interpolate(flat) strand: u32,
}

// Quad corner `c` in 0..6 (two triangles): x = segment end (0 or 1), y = side (-1 or +1).
fn quad_corner(c: u32) -> vec2<f32> {
    switch c {
        case 0u: { return vec2<f32>(0.0, -1.0); }
        case 1u: { return vec2<f32>(0.0, 1.0); }
        case 2u: { return vec2<f32>(1.0, -1.0); }
        case 3u: { return vec2<f32>(1.0, -1.0); }
        case 4u: { return vec2<f32>(0.0, 1.0); }
        default: { return vec2<f32>(1.0, 1.0); }
    }
}

// Clip position of a quad corner: the segment end's clip position pushed sideways by half of
// `width_px`, perpendicular to the segment's screen direction. A segment with an end behind the
// eye collapses to a point (the whole quad is culled).
fn expand_segment(
    cam: Camera,
    c0: vec4<f32>,
    c1: vec4<f32>,
    end: f32,
    side: f32,
    width_px: f32,
) -> vec4<f32> {
    if c0.w <= 1e-6 || c1.w <= 1e-6 {
        return vec4<f32>(0.0, 0.0, 0.0, 0.0);
    }
    let half_vp = cam.viewport * 0.5;
    let s0 = c0.xy / c0.w * half_vp;
    let s1 = c1.xy / c1.w * half_vp;
    var d = s1 - s0;
    let len = length(d);
    if len < 1e-6 {
        d = vec2<f32>(1.0, 0.0);
    } else {
        d = d / len;
    }
    let n = vec2<f32>(-d.y, d.x);
    var c = select(c0, c1, end > 0.5);
    let offset_px = n * side * (width_px * 0.5);
    c = vec4<f32>(c.xy + offset_px / half_vp * c.w, c.zw);
    return c;
}

// The varying of quad vertex `vertex_index` (6 per segment) for a camera and a screen width.
// Thickness fade (`params.wgsl` THICKNESS_FADE_*): in the tip mode alpha is scaled by the vertex's
// thickness relative to `thickness_ref` (the asset's thickest vertex), so tapered tips fade out; in
// the projected mode by the fraction of the drawn width the projected thickness covers
// (shading.wgsl `tip_fade`), a physical sub-pixel coverage.
fn strand_vertex(
    cam: Camera,
    vertex_index: u32,
    width_px: f32,
    thickness_fade: u32,
    thickness_ref: f32,
) -> StrandVarying {
    let seg = strand_segments[vertex_index / 6u];
    let corner = quad_corner(vertex_index % 6u);
    let v0 = strand_vertices[seg.x];
    let v1 = strand_vertices[seg.x + 1u];
    let c0 = camera_clip(cam, v0.position);
    let c1 = camera_clip(cam, v1.position);
    let at_end = corner.x > 0.5;
    var v = v0;
    if at_end {
        v = v1;
    }
    let w = select(c0.w, c1.w, at_end);
    let d = v1.position - v0.position;
    let len = length(d);
    var out: StrandVarying;
    out.position = expand_segment(cam, c0, c1, corner.x, corner.y, width_px);
    out.world_line = v.position;
    out.tangent = select(vec3<f32>(0.0, 1.0, 0.0), d / len, len > 1e-20);
    var alpha = v.alpha;
    if thickness_fade == THICKNESS_FADE_TIP {
        alpha = alpha * tip_fade(v.thickness, thickness_ref);
    } else if thickness_fade == THICKNESS_FADE_PROJECTED {
        let thickness_px = v.thickness * cam.pixels_per_unit / max(w, 1e-6);
        alpha = alpha * tip_fade(thickness_px, width_px);
    }
    out.color = vec4<f32>(v.color, alpha);
    out.strand = seg.y;
    return out;
}
