//! The ShortCut composite (the strand rasterizer's bounded-memory OIT, after TressFX 4.1's
//! "ShortCut"): the CPU reference of `strands/shortcut_{depth,shade,resolve}.wgsl` for one pixel.
//!
//! The depth pass finds the pixel's `k` nearest fragment depths. The k-th nearest is the tail's
//! threshold, as in TressFX: the shade pass shades the `k - 1` nearer fragments into their
//! layers and multiplies every other fragment's `1 - alpha` (the k-th's too) into a
//! transmittance `T`, and the resolve blends the `k - 1` front to back (as the PPLL's sorted
//! front, [`composite_sorted`]) with the tail under them: opacity `1 - T`, exact and independent
//! of order, and as color a weighted mean of the tail's colors. Only the tail's first fragments
//! show through it, so each is weighted by `alpha · exp(-(z - z_k) / (SHORTCUT_TAIL_SPACINGS ·
//! g))`, `z_k` the k-th depth and `g` the mean depth spacing of the `k` nearest: the tail taken
//! as a few of the front's layer spacings deep per unit of optical depth. Shading every tail
//! fragment would make the shade pass slower than the PPLL's, so a hash roulette picks a
//! fragment with probability `p = min(1, SHORTCUT_TAIL_PICK · factor)` and weighs it `1 / p`
//! more ([`shortcut_tail_weight`]): the same mean in expectation from a few fragments a pixel.
//! The roulette's number is a hash of the fragment's strand, so the fragments of one primitive,
//! shaded side by side in one SIMD group, are picked or passed over together (a per-fragment
//! number made the group shade when any one lane was picked: the bear's shade pass took 19.5 s
//! instead of 10.5 s on lavapipe). Where no falloff is known (k = 1, the `k` nearest at one
//! depth) the fragments at the threshold weigh their alpha: the tail takes the k-th's color.
//!
//! Measured against exact sorting (the fragments of a PPLL frame that held every one, sorted on the
//! CPU), mean FLIP over the frame at k = 8, bear fur 320x180 (885 tail fragments a pixel on
//! average): the farthest layer's color 0.0101, the plain α-weighted mean of the tail 0.044 (the
//! deep, self-shadowed fur is invisible), these weights 0.0046; at 1280x720 0.0147 and 0.0082; on
//! the ponytail (320x180) 0.0024 and 0.0027. Fewer spacings (4) suit the ponytail a little better
//! and the bear worse (0.0056 at 320x180, 0.0091 at 1280x720). (Those figures predate the k-th's
//! move into the tail, which made `k` layers the former `k - 1`'s and saved 4 bytes a pixel.) The
//! difference from the PPLL's [`resolve_k_buffer`] (with `k - 1` sorted) is the tail's color and
//! the layers' precision: a layer is one word, its depth key in 23 bits ([`shortcut_key`]: depths
//! closer than 1 / 8,388,606 tie) and, once claimed, its fragment's alpha in the other 9 (steps of
//! 1 / 510, [`shortcut_layer_alpha`]), so the k-th depth and the layers' spacing stay readable
//! while the shade pass claims layers and no per-pixel copy of them is needed.
//!
//! [`resolve_k_buffer`]: crate::resolve_k_buffer

use glam::{Vec3, Vec4};

use crate::blend::{StrandFragment, blend_under, composite_over_background, composite_sorted};
use crate::saturate;

/// Mean layer spacings of the tail per unit of optical depth (`TAIL_SPACINGS` in
/// `common/shortcut_keys.wgsl`).
pub const SHORTCUT_TAIL_SPACINGS: f32 = 5.0;
/// A tail fragment is shaded with probability `min(1, SHORTCUT_TAIL_PICK · factor)`
/// (`TAIL_PICK`).
pub const SHORTCUT_TAIL_PICK: f32 = 1.0;
/// Salts the strand index for the roulette's number (`TAIL_SALT`).
pub const SHORTCUT_TAIL_SALT: u32 = 0x9e37_79b9;

/// Depth steps of a layer key (`DEPTH_LEVELS` in `common/shortcut_keys.wgsl`): 2^23 - 2, so a
/// key is in `[1, 2^23 - 1]` before its 9-bit shift.
pub const SHORTCUT_DEPTH_LEVELS: f32 = 8_388_606.0;
/// Alpha steps of a claimed layer (`ALPHA_LEVELS`): the word's low 9 bits hold 1 + the step.
pub const SHORTCUT_ALPHA_LEVELS: f32 = 510.0;
const DEPTH_LEVELS: f32 = SHORTCUT_DEPTH_LEVELS;
const ALPHA_LEVELS: f32 = SHORTCUT_ALPHA_LEVELS;

/// The layer-sorting key of a depth (clamped to `[0, 1]`), as the depth pass makes it: larger
/// is nearer, never 0, the low 9 bits clear (`shortcut_key` in `common/shortcut_keys.wgsl`).
pub fn shortcut_key(depth: f32) -> u32 {
    let steps = (saturate(depth) * DEPTH_LEVELS) as u32;
    (DEPTH_LEVELS as u32 + 1 - steps) << 9
}

/// The depth a layer key stands for (`shortcut_depth`): the depth to the key's step.
pub fn shortcut_key_depth(key: u32) -> f32 {
    (DEPTH_LEVELS as u32 + 1 - (key >> 9)) as f32 / DEPTH_LEVELS
}

/// The alpha a claimed layer keeps of a fragment's (clamped to `[0, 1]`), in steps of 1 / 510
/// (`shortcut_claimed` and `shortcut_alpha`).
pub fn shortcut_layer_alpha(alpha: f32) -> f32 {
    (saturate(alpha) * ALPHA_LEVELS).round() / ALPHA_LEVELS
}

/// A fragment of the ShortCut composite: the fragment and the index of its strand (the tail
/// roulette's number comes from the strand).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShortcutFragment {
    /// Color, opacity and depth.
    pub fragment: StrandFragment,
    /// Index of the strand the fragment belongs to.
    pub strand: u32,
}

/// `hash_u32` of `common/strand_shading.wgsl` (a PCG-style output permutation).
fn hash_u32(x: u32) -> u32 {
    let h = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let h = ((h >> ((h >> 28) + 4)) ^ h).wrapping_mul(277_803_737);
    (h >> 22) ^ h
}

/// The weight a tail fragment of `strand` adds to the tail's mean color (0: not picked), `far`
/// the k-th's key ([`shortcut_key`]; `z_k` its depth) and `falloff` from
/// [`shortcut_tail_falloff`]: `alpha · factor / p` when the hash of its strand falls below `p =
/// min(1, SHORTCUT_TAIL_PICK · factor)`, `factor = exp(-(z - z_k) · falloff)`. In expectation
/// over the hash, `alpha · factor`. With no falloff only the fragments at the threshold (the
/// k-th and its ties) weigh their alpha. The shade pass's `tail_weight`.
pub fn shortcut_tail_weight(fragment: &StrandFragment, strand: u32, far: u32, falloff: f32) -> f32 {
    let z_k = shortcut_key_depth(far);
    let z = saturate(fragment.depth);
    let alpha = saturate(fragment.alpha);
    let factor = (-(z - z_k).max(0.0) * falloff).exp();
    let pick = (SHORTCUT_TAIL_PICK * factor).min(1.0);
    let u = (hash_u32(strand ^ SHORTCUT_TAIL_SALT) >> 8) as f32 / 16_777_216.0;
    if (falloff > 0.0 || shortcut_key(fragment.depth) == far) && u < pick {
        alpha * factor / pick
    } else {
        0.0
    }
}

/// The tail's depth falloff `1 / (SHORTCUT_TAIL_SPACINGS · g)` from the sorted `front` layers
/// (`g` their mean depth spacing, from the depths their keys hold), or 0 when it is unknown
/// (one layer, or every layer at one depth). The shade pass's `tail_falloff`.
pub fn shortcut_tail_falloff(front: &[StrandFragment]) -> f32 {
    let (Some(near), Some(far)) = (front.first(), front.last()) else {
        return 0.0;
    };
    if front.len() < 2 {
        return 0.0;
    }
    let depth = |f: &StrandFragment| shortcut_key_depth(shortcut_key(f.depth));
    let spacing = (depth(far) - depth(near)) / (front.len() - 1) as f32;
    if spacing > 0.0 {
        1.0 / (SHORTCUT_TAIL_SPACINGS * spacing)
    } else {
        0.0
    }
}

/// The ShortCut resolve of one pixel's fragments (any order) with `k` sorted layers, over
/// `background`. Fragments are sorted by their layer keys ([`shortcut_key`]); ties keep their input
/// order. The layers blend with the alpha they keep ([`shortcut_layer_alpha`]). With `k >=
/// fragments.len()` this is exact sorted compositing; with `k = 0` nothing is stored and the pixel
/// keeps `background`.
pub fn resolve_shortcut(fragments: &[ShortcutFragment], k: usize, background: Vec3) -> Vec3 {
    if k == 0 || fragments.is_empty() {
        return background;
    }
    let mut sorted = fragments.to_vec();
    sorted.sort_by_key(|s| std::cmp::Reverse(shortcut_key(s.fragment.depth)));
    // The k-th nearest is the tail's threshold and its first fragment.
    let layers = k - 1;
    let nearest: Vec<StrandFragment> = sorted.iter().take(k).map(|s| s.fragment).collect();
    let (front, tail): (Vec<_>, Vec<_>) = (
        sorted
            .iter()
            .take(layers)
            .map(|s| StrandFragment {
                alpha: shortcut_layer_alpha(s.fragment.alpha),
                ..s.fragment
            })
            .collect(),
        sorted.iter().skip(layers).copied().collect(),
    );
    let front = front.as_slice();
    let transmittance: f32 = tail
        .iter()
        .map(|s| 1.0 - saturate(s.fragment.alpha))
        .product();
    let tail_alpha = 1.0 - transmittance;
    let falloff = shortcut_tail_falloff(&nearest);
    let far = nearest.last().map_or(0, |f| shortcut_key(f.depth));
    let (mut weighted, mut weights) = (Vec3::ZERO, 0.0f32);
    for s in &tail {
        let w = shortcut_tail_weight(&s.fragment, s.strand, far, falloff);
        weighted += w * s.fragment.color;
        weights += w;
    }
    let color = if weights > 0.0 {
        weighted / weights
    } else {
        front.last().map_or(Vec3::ZERO, |f| f.color)
    };
    let acc = blend_under(
        composite_sorted(front),
        (color * tail_alpha).extend(tail_alpha),
    );
    composite_over_background(acc, background)
}

/// The premultiplied accumulator `resolve_shortcut` puts over the background (for tests that
/// compare opacity): `(rgb, coverage)`.
pub fn shortcut_accumulator(fragments: &[ShortcutFragment], k: usize) -> Vec4 {
    let black = resolve_shortcut(fragments, k, Vec3::ZERO);
    let white = resolve_shortcut(fragments, k, Vec3::ONE);
    black.extend(1.0 - (white - black).x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resolve_k_buffer;

    fn frag(c: [f32; 3], alpha: f32, depth: f32) -> StrandFragment {
        StrandFragment {
            color: Vec3::from(c),
            alpha,
            depth,
        }
    }

    /// The fragments as the ShortCut composite takes them, fragment `i` on strand `i`.
    fn on(f: &[StrandFragment]) -> Vec<ShortcutFragment> {
        (0u32..)
            .zip(f)
            .map(|(strand, &fragment)| ShortcutFragment { fragment, strand })
            .collect()
    }

    fn sample() -> Vec<StrandFragment> {
        vec![
            frag([0.9, 0.1, 0.1], 0.4, 0.3),
            frag([0.1, 0.8, 0.2], 0.3, 0.1),
            frag([0.2, 0.2, 0.9], 0.6, 0.5),
            frag([0.7, 0.6, 0.1], 0.25, 0.2),
            frag([0.3, 0.3, 0.3], 0.5, 0.4),
            frag([1.0, 1.0, 1.0], 0.2, 0.6),
        ]
    }

    fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).abs().max_element() < tol
    }

    #[test]
    fn keys_order_depths_nearest_largest_and_keep_the_alpha_bits_clear() {
        let mut last = u32::MAX;
        for i in 0..=1000 {
            let z = i as f32 / 1000.0;
            let key = shortcut_key(z);
            assert!(key > 0 && key & 0x1ff == 0, "{z}: {key:#x}");
            assert!(key < last, "{z}: nearer must be larger");
            last = key;
            let back = shortcut_key_depth(key);
            assert!((z - back).abs() < 2.0 / DEPTH_LEVELS, "{z} -> {back}");
        }
        assert_eq!(shortcut_key(-1.0), shortcut_key(0.0));
        assert_eq!(shortcut_key(2.0), shortcut_key(1.0));
        // 1 / 510 steps, 0 and 1 exact.
        assert_eq!(shortcut_layer_alpha(0.0), 0.0);
        assert_eq!(shortcut_layer_alpha(1.0), 1.0);
        assert!((shortcut_layer_alpha(0.3) - 0.3).abs() <= 0.5 / ALPHA_LEVELS);
    }

    #[test]
    fn with_every_fragment_stored_it_is_the_exact_composite() {
        let bg = Vec3::new(0.1, 0.2, 0.3);
        let f = sample();
        // With the alpha the layers keep (0.25 is 127.5 steps: it rounds up).
        let kept: Vec<StrandFragment> = f
            .iter()
            .map(|x| StrandFragment {
                alpha: shortcut_layer_alpha(x.alpha),
                ..*x
            })
            .collect();
        assert!(kept.iter().zip(&f).any(|(a, b)| a.alpha != b.alpha));
        for k in [f.len(), f.len() + 3] {
            let exact = resolve_k_buffer(&kept, k, bg);
            assert!(close(resolve_shortcut(&on(&f), k, bg), exact, 1e-6));
            // And within the alpha steps of the exact composite.
            let exact = resolve_k_buffer(&f, k, bg);
            assert!(close(resolve_shortcut(&on(&f), k, bg), exact, 2e-3));
        }
    }

    #[test]
    fn coverage_is_exact_for_every_k() {
        // What the pixel lets through does not depend on k: Π(1 - alpha) of all fragments.
        let f = sample();
        let pass: f32 = f.iter().map(|f| 1.0 - f.alpha).product();
        for k in 1..=f.len() {
            let a = shortcut_accumulator(&on(&f), k);
            // Exact up to the stored layers' alpha steps (1 / 510).
            assert!((a.w - (1.0 - pass)).abs() < 2e-3, "k = {k}: {}", a.w);
        }
    }

    #[test]
    fn without_a_falloff_the_tail_takes_the_threshold_color() {
        let bg = Vec3::ZERO;
        let near = frag([1.0, 0.0, 0.0], 0.5, 0.1);
        let far = frag([0.0, 1.0, 0.0], 0.5, 0.2);
        let tail = frag([0.0, 0.0, 1.0], 0.5, 0.3);
        // k = 1: no layer, the nearest is the threshold; no spacing to take a falloff from.
        let c = resolve_shortcut(&on(&[tail, far, near]), 1, bg);
        // All three in the tail (opacity 0.875), in the color of the nearest.
        let want = Vec3::new(0.875, 0.0, 0.0);
        assert!(close(c, want, 1e-6), "{c}");
        // The two nearest at one depth: no spacing either.
        let twin = frag([0.0, 1.0, 0.0], 0.5, 0.1);
        let c = resolve_shortcut(&on(&[tail, twin, near]), 2, bg);
        // Ties keep their order: twin is the layer, near (the threshold) and the tail the tail
        // (opacity 0.75) in near's color, under twin.
        let want = Vec3::new(0.5 * 0.75, 0.5, 0.0);
        assert!(close(c, want, 1e-6), "{c}");
    }

    #[test]
    fn the_tail_is_the_mean_of_its_fragments_weighted_by_alpha_and_falloff() {
        // k = 3: layers at 0.1 and 0.12 and the threshold `a` at 0.12: spacing 0.01, falloff
        // 1 / (5 · 0.01) = 20 per unit depth.
        let near = frag([0.2, 0.2, 0.2], 0.5, 0.1);
        let far = frag([0.2, 0.2, 0.2], 0.5, 0.12);
        let a = frag([1.0, 0.0, 0.0], 0.4, 0.12); // the k-th: factor 1
        assert!((shortcut_tail_falloff(&[near, far, a]) - 20.0).abs() < 2e-2);
        let b = frag([0.0, 1.0, 0.0], 0.2, 0.2);
        // exp(-0.78 · 20): picked with probability 2e-7, and this one's strand (0) is not.
        let gone = frag([0.0, 0.0, 1.0], 0.9, 0.9);
        assert_eq!(
            shortcut_tail_weight(&gone, 0, shortcut_key(0.12), 20.0),
            0.0
        );
        // Factor 1: picked for sure, weighed alpha. Factor 0.2: picked with p = 0.2, then
        // weighed alpha · factor / p = alpha.
        let wa = shortcut_tail_weight(&a, 3, shortcut_key(0.12), 20.0);
        let wb = shortcut_tail_weight(&b, 1, shortcut_key(0.12), 20.0);
        assert_eq!(wa, 0.4);
        assert!(wb == 0.0 || (wb - 0.2).abs() < 1e-6, "{wb}");
        let tail = (Vec3::new(wa, wb, 0.0)) / (wa + wb);
        let tail_alpha = 1.0 - 0.6 * 0.8 * 0.1;
        let front = composite_sorted(&[near, far]);
        let want = blend_under(front, (tail * tail_alpha).extend(tail_alpha)).truncate();
        let got = resolve_shortcut(&on(&[gone, b, far, a, near]), 3, Vec3::ZERO);
        assert!(close(got, want, 1e-5), "{got} vs {want}");
    }

    #[test]
    fn the_roulette_gives_the_weighted_sum_in_expectation() {
        // 20,000 tail fragments 0..0.2 behind the k-th at falloff 10: factors 1..0.14, picked
        // with p = 1 down to 0.34.
        let (mut got, mut want, mut picked) = (0.0f64, 0.0f64, 0);
        for i in 0..20_000 {
            let f = frag(
                [0.5; 3],
                0.2 + 0.1 * (i % 7) as f32 / 7.0,
                0.5 + 1e-5 * i as f32,
            );
            let w = shortcut_tail_weight(&f, i, shortcut_key(0.5), 10.0);
            got += f64::from(w);
            want += f64::from(f.alpha * (-(f.depth - 0.5) * 10.0).exp());
            picked += usize::from(w > 0.0);
        }
        assert!((got / want - 1.0).abs() < 0.02, "{got} vs {want}");
        assert!((8_000..16_000).contains(&picked), "{picked}");
        // No falloff: only a fragment at the threshold weighs its alpha; a fragment in front
        // of the k-th counts as at it.
        let at = shortcut_key(0.5);
        assert_eq!(
            shortcut_tail_weight(&frag([0.5; 3], 0.3, 0.6), 0, at, 0.0),
            0.0
        );
        assert_eq!(
            shortcut_tail_weight(&frag([0.5; 3], 0.3, 0.5), 0, at, 0.0),
            0.3
        );
        assert_eq!(
            shortcut_tail_weight(&frag([0.5; 3], 0.3, 0.4), 0, at, 10.0),
            0.3
        );
    }

    #[test]
    fn a_deep_dark_tail_behind_a_bright_front_shows_the_bright_fur_just_behind() {
        // Evenly spaced fur, bright in front and right behind it, then a long, dark,
        // self-shadowed depth: the exact composite is nearly the bright fur's; the tail's
        // plain mean would be nearly the dark's. The falloff keeps the tail near the exact.
        let f: Vec<StrandFragment> = (0..200)
            .map(|i| {
                let c = if i < 8 {
                    [0.8, 0.7, 0.6]
                } else {
                    [0.05, 0.04, 0.03]
                };
                frag(c, 0.3, 0.1 + 0.004 * i as f32)
            })
            .collect();
        let exact = resolve_k_buffer(&f, f.len(), Vec3::ZERO);
        // 64 pixels with this fur, each on its own strands: the roulette picks differently in
        // each.
        let errors: Vec<f32> = (0..64u32)
            .map(|pixel| {
                let mut s = on(&f);
                for x in &mut s {
                    x.strand += 1000 * pixel;
                }
                // Four layers and the threshold.
                (resolve_shortcut(&s, 5, Vec3::ZERO) - exact)
                    .abs()
                    .max_element()
            })
            .collect();
        let mut plain = f.clone();
        plain.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        let tail = &plain[4..];
        let mean = tail.iter().map(|f| f.color * f.alpha).sum::<Vec3>()
            / tail.iter().map(|f| f.alpha).sum::<f32>();
        let t: f32 = tail.iter().map(|f| 1.0 - f.alpha).product();
        let front = composite_sorted(&plain[..4]);
        let mean_composite = blend_under(front, (mean * (1.0 - t)).extend(1.0 - t)).truncate();
        let worst = errors.iter().copied().fold(0.0, f32::max);
        let err = errors.iter().sum::<f32>() / errors.len() as f32;
        let mean_err = (mean_composite - exact).abs().max_element();
        // On average (0.044 of 0.13) and even in the unluckiest pixel (0.11).
        assert!(
            err < 0.35 * mean_err,
            "{err} vs the plain mean's {mean_err}"
        );
        assert!(worst < mean_err, "{worst} vs the plain mean's {mean_err}");
    }

    #[test]
    fn order_does_not_matter_and_the_difference_to_the_ppll_is_the_tail_color() {
        let bg = Vec3::splat(0.5);
        let f = sample();
        let mut rev = on(&f);
        rev.reverse();
        for k in 1..=f.len() {
            assert!(close(
                resolve_shortcut(&on(&f), k, bg),
                resolve_shortcut(&rev, k, bg),
                1e-6
            ));
        }
        // Same colors everywhere: the tail's color is the same whoever stands in for it.
        let mut same = f.clone();
        for x in &mut same {
            x.color = Vec3::new(0.4, 0.3, 0.2);
        }
        // (Alphas on the layers' 1 / 510 steps, which the layers keep exactly.)
        for (i, x) in same.iter_mut().enumerate() {
            x.alpha = (100 + 30 * i) as f32 / 510.0;
        }
        for k in 1..=f.len() {
            assert!(close(
                resolve_shortcut(&on(&same), k, bg),
                resolve_k_buffer(&same, k, bg),
                1e-6
            ));
        }
        assert_eq!(resolve_shortcut(&on(&f), 0, bg), bg);
    }
}
