// ShortCut's layer keys and tail constants, shared by its passes (`common/shortcut.wgsl`) and
// the threshold pass (which binds the buffers at group 0).

const KEY_MAX: u32 = 0x7fffffffu;

// The tail is shaded as the average of its fragments weighted by `alpha * exp(-(z - z_k) *
// falloff)`: an estimate of how much of each shows through the tail in front of it, the tail
// taken as `TAIL_SPACINGS` of the k layers' mean spacings deep per unit of optical depth
// (mirrored by `tress_shading::SHORTCUT_TAIL_SPACINGS`). Shading every tail fragment would cost
// more than the PPLL, so a tail fragment is shaded with probability `p = min(1, TAIL_PICK *
// factor)` (a hash of its depth and alpha decides) and then weighs `alpha * factor / p`: the same
// weighted mean in expectation, from a few fragments a pixel (mirrored by
// `tress_shading::SHORTCUT_TAIL_PICK`).
const TAIL_SPACINGS: f32 = 5.0;
const TAIL_PICK: f32 = 1.0;
// Salts the strand index for the roulette's number (mirrored by `tress_shading::SHORTCUT_TAIL_SALT`).
const TAIL_SALT: u32 = 0x9e3779b9u;

// The top 16 bits of a non-negative f32, rounded to nearest (a bfloat16: 8 bits of mantissa),
// as the falloffs are kept (mirrored by `tress_shading::shortcut_tail_falloff`).
fn falloff_bits(falloff: f32) -> u32 {
    return min(bitcast<u32>(falloff) + 0x8000u, 0x7f7f0000u) >> 16u;
}

// The depth a layer-sorting key stands for (`shortcut_key`'s inverse).
fn shortcut_depth(key: u32) -> f32 {
    return bitcast<f32>(KEY_MAX - key);
}

// The layer-sorting key of a depth in [0, 1]: larger is nearer, never 0 and never CLAIMED.
fn shortcut_key(depth: f32) -> u32 {
    return KEY_MAX - bitcast<u32>(clamp(depth, 0.0, 1.0));
}

