// The layer surface at a map texel, bilinear between the four layer-mesh vertices around it:
// what the texel-space passes (s-maps, lighting) shade. Declares binding 10 of group 0.

#include "satf/types.wgsl"

@group(0) @binding(10) var<storage, read> vertices: array<SatfVertex>;

struct TexelGeometry {
    position: vec3f,
    tangent: vec3f,
    normal: vec3f,
}

fn satf_texel_geometry(p: SatfParams, tile: u32, x: u32, y: u32) -> TexelGeometry {
    let nu = p.mesh_nu;
    let nt = p.mesh_nt;
    let gx = (f32(x) + 0.5) / f32(p.tile_width) * f32(nu);
    let gy = (f32(y) + 0.5) / f32(p.tile_height) * f32(nt);
    let x0 = min(u32(gx), nu - 1u);
    let y0 = min(u32(gy), nt - 1u);
    let fx = gx - f32(x0);
    let fy = gy - f32(y0);
    let row = nu + 1u;
    let base = tile * (nt + 1u) * row + y0 * row + x0;
    let a = vertices[base];
    let b = vertices[base + 1u];
    let c = vertices[base + row];
    let d = vertices[base + row + 1u];
    let w = vec4f((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy);
    var g: TexelGeometry;
    g.position = w.x * a.position + w.y * b.position + w.z * c.position + w.w * d.position;
    let t = w.x * a.tangent + w.y * b.tangent + w.z * c.tangent + w.w * d.tangent;
    let n = w.x * a.normal + w.y * b.normal + w.z * c.normal + w.w * d.normal;
    g.tangent = select(a.tangent, normalize(t), length(t) > 1e-12);
    g.normal = select(a.normal, normalize(n), length(n) > 1e-12);
    return g;
}
