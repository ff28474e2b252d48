// ShortCut shade pass (after TressFX 4.1's "ShortCut"): a fragment whose depth is one of its
// pixel's k - 1 nearest (found by the depth pass; the k-th nearest is the tail's threshold) claims
// that layer, is shaded (the PPLL's own `shade_strand`) and stores its color (and its alpha, in the
// layer's word) there, to be blended in depth order by the resolve. Every other fragment is the
// pixel's tail: its opacity is multiplied into the transmittance target (blend `dst * (1 - src)`),
// so the tail's opacity `1 - Π(1 - alpha)` is exact and independent of order, and the tail
// fragments near the k-th are shaded and added into the tail target with the weight `alpha *
// exp(-(z - z_k) * falloff)` (`common/shortcut_keys.wgsl`), so the resolve gives the tail their
// weighted mean color. No fragment is dropped. Owner: `ShortcutShade`.

#include "common/strand_fragment.wgsl"
#include "common/strand_shading.wgsl"
#include "common/shortcut.wgsl"

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: StrandParams;
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

// Claim the layer of pixel `p` holding `key` among the k - 1 nearest: its index, or
// MAX_SHORTCUT_K when every such layer with this key is taken (a tie at the threshold) or none
// holds it (a tail fragment).
fn claim_layer(p: u32, key: u32, alpha: f32) -> u32 {
    let pixels = shortcut_pixels(params);
    for (var i = 0u; i + 1u < shortcut_k(params); i = i + 1u) {
        let w = i * pixels + p;
        let v = atomicLoad(&shortcut_keys[w]);
        if v == key {
            loop {
                let claimed = shortcut_claimed(key, alpha);
                let r = atomicCompareExchangeWeak(&shortcut_keys[w], key, claimed);
                if r.exchanged {
                    return i;
                }
                if r.old_value != key {
                    break;
                }
            }
        } else if (v & KEY_MASK) < key {
            // Layers are sorted nearest first (claimed or not, a word keeps its key): this and
            // every later layer lie farther away, or are empty.
            break;
        }
    }
    return MAX_SHORTCUT_K;
}

struct ShadeOut {
    // Multiplied into the transmittance: `dst * (1 - src.r)`.
    @location(0) transmittance: vec4<f32>,
    // Added into the tail's weighted color and weight.
    @location(1) tail: vec4<f32>,
}

// The weight a tail fragment adds to the tail's mean color (0: not picked): its color weighted by
// how much of it the falloff from the k-th depth estimates shows through, over the chance the
// roulette picked it (`common/shortcut_keys.wgsl`). Where the pixel has no falloff only the
// fragments at the threshold (`key == far`: the k-th and its ties) weigh their alpha, so the tail
// takes the k-th's color (weighing every tail fragment there shaded all of them: dense fur has many
// pixels whose k nearest tie, and the bear's shade pass took 10x as long). The roulette's number is
// the strand's, so the fragments of one primitive, shaded side by side, are picked or passed over
// together. CPU twin: `tress_shading::shortcut_tail_weight`.
fn tail_weight(in: StrandVarying, alpha: f32, p: u32, key: u32, far: u32) -> f32 {
    let falloff = tail_falloff(params, p, far);
    let z = clamp(in.position.z, 0.0, 1.0);
    let factor = exp(-max(z - shortcut_depth(far), 0.0) * falloff);
    let pick = min(1.0, TAIL_PICK * factor);
    let u = f32(hash_u32(in.strand ^ TAIL_SALT) >> 8u) / 16777216.0;
    if (falloff > 0.0 || key == far) && u < pick {
        return alpha * factor / pick;
    }
    return 0.0;
}

@fragment
fn fs_main(in: StrandVarying) -> ShadeOut {
    let alpha = strand_fragment_alpha(in, camera, params, head_depth);
    if alpha <= 0.0 {
        discard;
    }
    let p = strand_pixel_index(in, params);
    let key = shortcut_key(in.position.z);
    // The k-th layer's key (0: fewer than k); claiming leaves a word's key as it is.
    let kth = (shortcut_k(params) - 1u) * shortcut_pixels(params) + p;
    let far = atomicLoad(&shortcut_keys[kth]) & KEY_MASK;
    // The pixel's k-th nearest or farther (told by one load), or a tie at it: the tail.
    var layer = MAX_SHORTCUT_K;
    if key > far {
        layer = claim_layer(p, key, alpha);
    }
    var out: ShadeOut;
    out.transmittance = vec4<f32>(0.0);
    out.tail = vec4<f32>(0.0);
    var w = 0.0;
    if layer == MAX_SHORTCUT_K {
        out.transmittance = vec4<f32>(alpha, 0.0, 0.0, 0.0);
        w = tail_weight(in, alpha, p, key, far);
    }
    // One shading call for the claimed and the picked fragments, so a SIMD group holding both
    // shades once.
    if layer < MAX_SHORTCUT_K || w > 0.0 {
        let color = shade_strand(in, camera, params);
        if layer < MAX_SHORTCUT_K {
            // Blended as `dst * (1 - 0)` and `dst + 0`: the near fragments leave the tail alone.
            shortcut_colors[layer * shortcut_pixels(params) + p] = pack_rgb9e5(color);
        } else {
            out.tail = vec4<f32>(color * w, w);
        }
    }
    return out;
}
