// The per-pixel linked list node shared by the PPLL build and resolve passes, and its color
// packing.

// One stored fragment (mirrored by `gpu::types::PpllNode`).
struct PpllNode {
    // Straight (not premultiplied) linear RGB, RGB9E5-packed (`pack_rgb9e5`).
    color: u32,
    // Opacity times coverage.
    alpha: f32,
    // Fragment depth (0 near, 1 far).
    depth: f32,
    // Index + 1 of the next node of the pixel's list; 0 ends the list.
    next: u32,
}

// RGB9E5 shared-exponent packing (the layout of the `rgb9e5ufloat` texture format): three 9-bit
// mantissas and a 5-bit exponent with bias 15. Non-negative colors up to 65408; each channel keeps
// about 9 bits of precision relative to the largest. Written out instead of `pack2x16float`,
// which needs `SHADER_F16` on some drivers (llvmpipe).
fn pack_rgb9e5(c: vec3<f32>) -> u32 {
    let m = clamp(c, vec3<f32>(0.0), vec3<f32>(65408.0));
    let max_c = max(m.x, max(m.y, m.z));
    var e = max(-16, i32(floor(log2(max(max_c, 1e-30))))) + 16;
    var denom = exp2(f32(e - 24));
    if u32(floor(max_c / denom + 0.5)) >= 512u {
        denom = denom * 2.0;
        e = e + 1;
    }
    let q = min(vec3<u32>(floor(m / denom + 0.5)), vec3<u32>(511u));
    return q.x | (q.y << 9u) | (q.z << 18u) | (u32(e) << 27u);
}

fn unpack_rgb9e5(v: u32) -> vec3<f32> {
    let scale = exp2(f32(i32(v >> 27u) - 24));
    return vec3<f32>(f32(v & 511u), f32((v >> 9u) & 511u), f32((v >> 18u) & 511u)) * scale;
}
