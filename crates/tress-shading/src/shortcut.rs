//! The ShortCut composite (the strand rasterizer's bounded-memory OIT, after TressFX 4.1's
//! "ShortCut"): the CPU reference of `strands/shortcut_{depth,shade,resolve}.wgsl` for one pixel.
//!
//! The depth pass finds the pixel's `k` nearest fragments, the shade pass shades only those
//! and multiplies every other fragment's `1 - alpha` into a transmittance `T`, and the resolve
//! blends the `k` front to back (as the PPLL's sorted front, [`composite_sorted`]) with the tail
//! under them: opacity `1 - T`, exact and independent of order, and as color the color of the
//! farthest of the `k` (the tail is never shaded; the fragment nearest to it in depth, hence in
//! self-shadowing, stands in for it). The difference from the PPLL's [`resolve_k_buffer`] is
//! then only the tail's color, weighted by how much light reaches the tail at all.
//!
//! [`resolve_k_buffer`]: crate::resolve_k_buffer

use glam::{Vec3, Vec4};

use crate::blend::{StrandFragment, blend_under, composite_over_background, composite_sorted};
use crate::saturate;

/// The ShortCut resolve of one pixel's fragments (any order) with `k` sorted layers, over
/// `background`. Ties in depth keep their input order. With `k >= fragments.len()` this is
/// exact sorted compositing; with `k = 0` nothing is stored and the pixel keeps `background`.
pub fn resolve_shortcut(fragments: &[StrandFragment], k: usize, background: Vec3) -> Vec3 {
    let mut sorted = fragments.to_vec();
    sorted.sort_by(|a, b| a.depth.total_cmp(&b.depth));
    let (front, tail) = sorted.split_at(k.min(sorted.len()));
    let Some(farthest) = front.last() else {
        return background;
    };
    let transmittance: f32 = tail.iter().map(|f| 1.0 - saturate(f.alpha)).product();
    let tail_alpha = 1.0 - transmittance;
    let acc = blend_under(
        composite_sorted(front),
        (farthest.color * tail_alpha).extend(tail_alpha),
    );
    composite_over_background(acc, background)
}

/// The premultiplied accumulator `resolve_shortcut` puts over the background (for tests that
/// compare opacity): `(rgb, coverage)`.
pub fn shortcut_accumulator(fragments: &[StrandFragment], k: usize) -> Vec4 {
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

    fn sample() -> Vec<StrandFragment> {
        vec![
            frag([0.9, 0.1, 0.1], 0.4, 3.0),
            frag([0.1, 0.8, 0.2], 0.3, 1.0),
            frag([0.2, 0.2, 0.9], 0.6, 5.0),
            frag([0.7, 0.6, 0.1], 0.25, 2.0),
            frag([0.3, 0.3, 0.3], 0.5, 4.0),
            frag([1.0, 1.0, 1.0], 0.2, 6.0),
        ]
    }

    fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).abs().max_element() < tol
    }

    #[test]
    fn with_every_fragment_stored_it_is_the_exact_composite() {
        let bg = Vec3::new(0.1, 0.2, 0.3);
        let f = sample();
        for k in [f.len(), f.len() + 3] {
            let exact = resolve_k_buffer(&f, k, bg);
            assert!(close(resolve_shortcut(&f, k, bg), exact, 1e-6));
        }
    }

    #[test]
    fn coverage_is_exact_for_every_k() {
        // What the pixel lets through does not depend on k: Π(1 - alpha) of all fragments.
        let f = sample();
        let pass: f32 = f.iter().map(|f| 1.0 - f.alpha).product();
        for k in 1..=f.len() {
            let a = shortcut_accumulator(&f, k);
            assert!((a.w - (1.0 - pass)).abs() < 1e-5, "k = {k}: {}", a.w);
        }
    }

    #[test]
    fn the_tail_takes_the_farthest_stored_color() {
        let bg = Vec3::ZERO;
        let near = frag([1.0, 0.0, 0.0], 0.5, 1.0);
        let far = frag([0.0, 1.0, 0.0], 0.5, 2.0);
        let tail = frag([0.0, 0.0, 1.0], 0.5, 3.0);
        let c = resolve_shortcut(&[tail, far, near], 2, bg);
        // near over far over (far's color at the tail's opacity).
        let want = Vec3::new(0.5, 0.25 + 0.25 * 0.5, 0.0);
        assert!(close(c, want, 1e-6), "{c}");
    }

    #[test]
    fn order_does_not_matter_and_the_difference_to_the_ppll_is_the_tail_color() {
        let bg = Vec3::splat(0.5);
        let f = sample();
        let mut rev = f.clone();
        rev.reverse();
        for k in 1..=f.len() {
            assert!(close(
                resolve_shortcut(&f, k, bg),
                resolve_shortcut(&rev, k, bg),
                1e-6
            ));
        }
        // Same colors everywhere: the tail's color is the same whoever stands in for it.
        let mut same = f.clone();
        for x in &mut same {
            x.color = Vec3::new(0.4, 0.3, 0.2);
        }
        for k in 1..=f.len() {
            assert!(close(
                resolve_shortcut(&same, k, bg),
                resolve_k_buffer(&same, k, bg),
                1e-6
            ));
        }
        assert_eq!(resolve_shortcut(&f, 0, bg), bg);
    }
}
