//! Compositing for the per-pixel linked list (PPLL) k-buffer resolve (Jansson et al. 2019 §3.2,
//! "Sorting and Blending", following TressFX \[MET\*14\] and Yu et al. \[YYH\*12\]).
//!
//! The resolve pass sorts a pixel's fragments by depth, blends the `k` nearest in the correct
//! order and merges the remaining ones ("the tail") order-independently.
//!
//! **Colors.** Fragment colors are *straight* (not premultiplied): the shaded color as stored in
//! the PPLL, with `alpha = strand opacity · coverage` beside it. Accumulators are *premultiplied*
//! `Vec4`s: `rgb` is the sum of the colors already weighted by their visible opacity, `a` the
//! opacity accumulated so far. Depth: smaller is nearer.
//!
//! **Front k: front-to-back "under".** Nearest first (Porter-Duff *over*, evaluated front to back):
//!
//! ```text
//! acc.rgb += (1 - acc.a) · alpha · color
//! acc.a   += (1 - acc.a) · alpha
//! ```
//!
//! which gives exactly the back-to-front `dst = alpha · color + (1 - alpha) · dst` result, and once
//! `acc.a` reaches 1 nothing behind can change the pixel.
//!
//! **Tail: weighted average (the choice made here).** TressFX blends the fragments beyond `k` with
//! ordinary *over* in whatever order the linked list holds them, so the tail's result depends on
//! the order in which GPU threads inserted the fragments and can flicker from frame to frame. The
//! twin instead uses the weighted-average operator of Bavoil and Myers (2008): the tail's opacity is
//! the exact product `1 - Π(1 - alpha_i)` and its color the alpha-weighted mean
//! `Σ alpha_i color_i / Σ alpha_i`. Both are sums and products, so the result is independent of
//! order (up to floating-point rounding); it is exact when the tail has one fragment or one color.
//! The tail is composited under the front `k`, since every tail fragment lies behind them.

use glam::{Vec3, Vec4};

use crate::saturate;

/// One PPLL entry: straight color, alpha (opacity × coverage) and depth (smaller is nearer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandFragment {
    /// Shaded color, straight (not premultiplied), linear RGB.
    pub color: Vec3,
    /// Opacity in `[0, 1]` (values outside are clamped).
    pub alpha: f32,
    /// Depth; smaller is nearer to the eye.
    pub depth: f32,
}

/// Front-to-back "under": put the premultiplied `src` behind the premultiplied accumulator `acc`:
/// `acc + (1 - acc.a) · src`.
pub fn blend_under(acc: Vec4, src: Vec4) -> Vec4 {
    acc + (1.0 - acc.w) * src
}

/// Blend one straight-color fragment behind the premultiplied accumulator `acc` (front to back):
/// [`blend_under`]`(acc, (alpha · color, alpha))` with `alpha` clamped to `[0, 1]`.
pub fn blend_front_to_back(acc: Vec4, color: Vec3, alpha: f32) -> Vec4 {
    let alpha = saturate(alpha);
    blend_under(acc, (color * alpha).extend(alpha))
}

/// The order-independent accumulator of the fragments beyond `k` (module docs: weighted average).
/// Field order matches the WGSL `struct TailAccum`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TailAccum {
    /// `Σ alpha_i · color_i`.
    pub weighted_color: Vec3,
    /// `Σ alpha_i`.
    pub alpha_sum: f32,
    /// `Π (1 - alpha_i)`: the light that passes the whole tail.
    pub transmittance: f32,
}

impl TailAccum {
    /// The empty tail (WGSL `tail_empty()`): nothing accumulated, full transmittance.
    pub const EMPTY: TailAccum = TailAccum {
        weighted_color: Vec3::ZERO,
        alpha_sum: 0.0,
        transmittance: 1.0,
    };
}

/// Add one straight-color fragment to the tail (`alpha` clamped to `[0, 1]`). Commutative: the
/// order of calls does not change [`tail_resolve`]'s result (up to rounding).
pub fn tail_accumulate(tail: TailAccum, color: Vec3, alpha: f32) -> TailAccum {
    let alpha = saturate(alpha);
    TailAccum {
        weighted_color: tail.weighted_color + alpha * color,
        alpha_sum: tail.alpha_sum + alpha,
        transmittance: tail.transmittance * (1.0 - alpha),
    }
}

/// The tail as one premultiplied color: opacity `a = 1 - transmittance`, color
/// `weighted_color / alpha_sum`, returned as `(a · color, a)`. An empty (or fully transparent)
/// tail gives 0.
pub fn tail_resolve(tail: TailAccum) -> Vec4 {
    if tail.alpha_sum <= 0.0 {
        return Vec4::ZERO;
    }
    let a = 1.0 - tail.transmittance;
    let color = tail.weighted_color / tail.alpha_sum;
    (color * a).extend(a)
}

/// The premultiplied accumulator over an opaque background: `acc.rgb + (1 - acc.a) · background`.
pub fn composite_over_background(acc: Vec4, background: Vec3) -> Vec3 {
    acc.truncate() + (1.0 - acc.w) * background
}

/// Front-to-back compositing of fragments already sorted nearest first (CPU only): the fold of
/// [`blend_front_to_back`] from a zero accumulator. Returns the premultiplied result.
pub fn composite_sorted(fragments: &[StrandFragment]) -> Vec4 {
    fragments.iter().fold(Vec4::ZERO, |acc, f| {
        blend_front_to_back(acc, f.color, f.alpha)
    })
}

/// The whole k-buffer resolve of one pixel on the CPU: sort `fragments` by depth (nearest first;
/// ties keep their order), composite the nearest `k` front to back, merge the rest with the
/// order-independent tail under them, and put the result over `background`.
///
/// With `k >= fragments.len()` this is exact sorted compositing.
pub fn resolve_k_buffer(fragments: &[StrandFragment], k: usize, background: Vec3) -> Vec3 {
    let mut sorted = fragments.to_vec();
    sorted.sort_by(|a, b| a.depth.total_cmp(&b.depth));
    let (front, rest) = sorted.split_at(k.min(sorted.len()));
    let tail = rest.iter().fold(TailAccum::EMPTY, |t, f| {
        tail_accumulate(t, f.color, f.alpha)
    });
    let acc = blend_under(composite_sorted(front), tail_resolve(tail));
    composite_over_background(acc, background)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frag(r: f32, g: f32, b: f32, alpha: f32, depth: f32) -> StrandFragment {
        StrandFragment {
            color: Vec3::new(r, g, b),
            alpha,
            depth,
        }
    }

    /// Independent reference: classic back-to-front over, farthest first.
    fn back_to_front(fragments: &[StrandFragment], background: Vec3) -> Vec3 {
        let mut sorted = fragments.to_vec();
        sorted.sort_by(|a, b| b.depth.total_cmp(&a.depth));
        sorted.iter().fold(background, |dst, f| {
            f.alpha * f.color + (1.0 - f.alpha) * dst
        })
    }

    fn sample() -> Vec<StrandFragment> {
        vec![
            frag(0.9, 0.1, 0.1, 0.4, 3.0),
            frag(0.1, 0.8, 0.2, 0.3, 1.0),
            frag(0.2, 0.2, 0.9, 0.6, 5.0),
            frag(0.7, 0.6, 0.1, 0.25, 2.0),
            frag(0.3, 0.3, 0.3, 0.5, 4.0),
            frag(1.0, 1.0, 1.0, 0.2, 6.0),
        ]
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn front_to_back_equals_back_to_front() {
        let bg = Vec3::new(0.1, 0.2, 0.3);
        let f = sample();
        for k in [f.len(), f.len() + 10] {
            assert!(close(resolve_k_buffer(&f, k, bg), back_to_front(&f, bg)));
        }
    }

    #[test]
    fn opaque_front_fragment_hides_the_rest() {
        let mut f = sample();
        f.push(frag(0.5, 0.25, 0.125, 1.0, 0.5));
        // Once the opaque fragment is among the sorted k (it is the nearest), nothing else shows.
        for k in [1, 3, 100] {
            let c = resolve_k_buffer(&f, k, Vec3::ONE);
            assert!(close(c, Vec3::new(0.5, 0.25, 0.125)), "k = {k}: {c}");
        }
        let acc = composite_sorted(&[
            frag(0.5, 0.25, 0.125, 1.0, 0.0),
            frag(1.0, 1.0, 1.0, 0.9, 1.0),
        ]);
        assert_eq!(acc, Vec4::new(0.5, 0.25, 0.125, 1.0));
    }

    #[test]
    fn transparent_fragments_change_nothing() {
        let bg = Vec3::new(0.3, 0.6, 0.9);
        let ghosts = [frag(1.0, 0.0, 0.0, 0.0, 1.0), frag(0.0, 1.0, 0.0, 0.0, 2.0)];
        for k in [0, 1, 2] {
            assert_eq!(resolve_k_buffer(&ghosts, k, bg), bg);
        }
        assert_eq!(resolve_k_buffer(&[], 4, bg), bg);
    }

    #[test]
    fn input_order_does_not_matter() {
        let bg = Vec3::splat(0.5);
        let f = sample();
        let mut rev = f.clone();
        rev.reverse();
        for k in 0..=f.len() {
            assert!(close(
                resolve_k_buffer(&f, k, bg),
                resolve_k_buffer(&rev, k, bg)
            ));
        }
    }

    #[test]
    fn tail_is_order_independent() {
        let f = sample();
        let fold = |order: &[usize]| {
            let t = order.iter().fold(TailAccum::EMPTY, |t, &i| {
                tail_accumulate(t, f[i].color, f[i].alpha)
            });
            tail_resolve(t)
        };
        let reference = fold(&[0, 1, 2, 3, 4, 5]);
        for order in [[5, 4, 3, 2, 1, 0], [2, 0, 5, 1, 3, 4], [1, 3, 5, 0, 2, 4]] {
            assert!((fold(&order) - reference).abs().max_element() < 1e-6);
        }
    }

    #[test]
    fn tail_opacity_is_exact() {
        // Whatever the colors, the tail lets through Π(1 - alpha): 0.6·0.7·0.4·0.75·0.5·0.8.
        let f = sample();
        let t = f.iter().fold(TailAccum::EMPTY, |t, f| {
            tail_accumulate(t, f.color, f.alpha)
        });
        let pass = 0.6 * 0.7 * 0.4 * 0.75 * 0.5 * 0.8;
        assert!((tail_resolve(t).w - (1.0 - pass)).abs() < 1e-6);
        // The whole pixel's coverage is exact for every k.
        for k in 0..=f.len() {
            let black = resolve_k_buffer(&f, k, Vec3::ZERO);
            let white = resolve_k_buffer(&f, k, Vec3::ONE);
            assert!(((white - black) - Vec3::splat(pass)).abs().max_element() < 1e-5);
        }
    }

    #[test]
    fn tail_is_exact_for_a_single_color_or_fragment() {
        let bg = Vec3::new(0.0, 0.5, 1.0);
        let mut same = sample();
        for f in &mut same {
            f.color = Vec3::new(0.4, 0.3, 0.2);
        }
        assert!(close(
            resolve_k_buffer(&same, 0, bg),
            back_to_front(&same, bg)
        ));
        let one = [frag(0.9, 0.5, 0.1, 0.35, 1.0)];
        assert!(close(
            resolve_k_buffer(&one, 0, bg),
            back_to_front(&one, bg)
        ));
    }

    #[test]
    fn tail_only_approximates_mixed_colors() {
        // With mixed colors the weighted average is an approximation (k = 0 differs from exact
        // sorting); with every fragment in the sorted front it is exact.
        let bg = Vec3::ZERO;
        let f = sample();
        let exact = back_to_front(&f, bg);
        let err = |k| (resolve_k_buffer(&f, k, bg) - exact).length();
        assert!(err(0) > 1e-3);
        assert!(err(f.len()) < 1e-5);
    }

    #[test]
    fn results_stay_in_range() {
        let f = sample();
        for k in 0..=f.len() {
            let c = resolve_k_buffer(&f, k, Vec3::new(1.0, 0.0, 0.5));
            assert!(c.min_element() >= 0.0 && c.max_element() <= 1.0 + 1e-6);
        }
        assert_eq!(tail_resolve(TailAccum::EMPTY), Vec4::ZERO);
        let clamped = blend_front_to_back(Vec4::ZERO, Vec3::ONE, 2.0);
        assert_eq!(clamped, Vec4::ONE);
    }
}
