// ShortCut's layer words and tail constants, shared by its passes (`common/shortcut.wgsl`).
//
// A layer word is a depth key in its top 23 bits and, once the shade pass claims the layer, the
// claimed fragment's alpha in its low 9 bits: `key | (round(alpha * ALPHA_LEVELS) + 1)`. A key
// is `(DEPTH_LEVELS + 1 - floor(depth * DEPTH_LEVELS)) << ALPHA_BITS`: larger is nearer, so
// atomicMax inserts, 0 (what a cleared buffer holds) is an empty layer, and an unclaimed layer
// has its low bits clear. A claimed word keeps its depth, so the k-th depth and the layers'
// spacing are read from the layers themselves while they are claimed (mirrored by
// `tress_shading::shortcut_key` and `shortcut_alpha`).

const ALPHA_BITS: u32 = 9u;
const ALPHA_MASK: u32 = 0x1ffu;
const KEY_MASK: u32 = 0xfffffe00u;
// Alpha steps a claimed word holds (its low bits hold 1 + the step: 0 is unclaimed).
const ALPHA_LEVELS: f32 = 510.0;
// Depth steps a key holds: 2^23 - 2, so a key is in [1, 2^23 - 1] before the shift.
const DEPTH_LEVELS: f32 = 8388606.0;

// The tail is shaded as the average of its fragments weighted by `alpha * exp(-(z - z_k) *
// falloff)`: an estimate of how much of each shows through the tail in front of it, the tail
// taken as `TAIL_SPACINGS` of the k layers' mean spacings deep per unit of optical depth
// (mirrored by `tress_shading::SHORTCUT_TAIL_SPACINGS`). Shading every tail fragment would cost
// more than the PPLL, so a tail fragment is shaded with probability `p = min(1, TAIL_PICK *
// factor)` (a hash of its strand decides) and then weighs `alpha * factor / p`: the same
// weighted mean in expectation, from a few fragments a pixel (mirrored by
// `tress_shading::SHORTCUT_TAIL_PICK`).
const TAIL_SPACINGS: f32 = 5.0;
const TAIL_PICK: f32 = 1.0;
// Salts the strand index for the roulette's number (mirrored by `tress_shading::SHORTCUT_TAIL_SALT`).
const TAIL_SALT: u32 = 0x9e3779b9u;

// The layer-sorting key of a depth (clamped to [0, 1]): larger is nearer, never 0, low bits clear.
fn shortcut_key(depth: f32) -> u32 {
    let steps = u32(clamp(depth, 0.0, 1.0) * DEPTH_LEVELS);
    return (u32(DEPTH_LEVELS) + 1u - steps) << ALPHA_BITS;
}

// The depth a layer word's key stands for (`shortcut_key`'s inverse, to the key's step).
fn shortcut_depth(word: u32) -> f32 {
    return f32(u32(DEPTH_LEVELS) + 1u - (word >> ALPHA_BITS)) / DEPTH_LEVELS;
}

// A claimed layer word: the key with the fragment's alpha.
fn shortcut_claimed(key: u32, alpha: f32) -> u32 {
    return key | (u32(round(clamp(alpha, 0.0, 1.0) * ALPHA_LEVELS)) + 1u);
}

// The alpha a claimed layer word holds.
fn shortcut_alpha(word: u32) -> f32 {
    return f32((word & ALPHA_MASK) - 1u) / ALPHA_LEVELS;
}
