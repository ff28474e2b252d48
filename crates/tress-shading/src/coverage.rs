//! Analytic strand coverage for anti-aliasing (Jansson et al. 2019 §3.2, listing
//! `strand_coverage`, after GPAA \[Per12\]).
//!
//! A strand is drawn as a line (on wgpu: a camera-facing ribbon) of constant screen width
//! `line_thickness` pixels. Each fragment's coverage falls linearly from 1 on the line's centre to
//! 0 at its edge, `d` pixels from the centre:
//!
//! ```text
//! coverage = saturate(1 - d / (line_thickness / 2))        (Jansson §3.2, listing line 9)
//! ```
//!
//! The listing returns the unclamped value; the twin clamps it to `[0, 1]` because the value is
//! used as an alpha (a fragment at the ribbon's corner can lie farther than half the width from the
//! centre line).
//!
//! Two conventions differ from the GLSL listing, which was written for OpenGL:
//! - screen `y` points *down* with the origin at the top-left (wgpu's `@builtin(position)`), so
//!   `screen = ((ndc.x + 1) · w / 2, (1 - ndc.y) · h / 2)` instead of `(ndc + 1) · res / 2`;
//! - the listing's `view_projection` is named `clip_from_world` (design rule 5).
//!
//! Thin strands: real strands taper and are often far thinner than one pixel, but lines thinner
//! than a pixel alias. [`tip_fade`] keeps the drawn width and lowers the alpha instead, by the
//! fraction of that width the strand really covers.

use glam::{Mat4, Vec2, Vec4};

use crate::saturate;

/// Coverage of a fragment `d` pixels from the centre of a line `line_thickness` pixels wide:
/// `saturate(1 - d / (line_thickness / 2))` (Jansson §3.2, listing line 9, clamped).
///
/// 1 on the centre line, 0 at and beyond the edge (`d >= line_thickness / 2`). A line of
/// non-positive width covers nothing (0).
pub fn coverage_from_distance(d: f32, line_thickness: f32) -> f32 {
    if line_thickness <= 0.0 {
        return 0.0;
    }
    saturate(1.0 - d / (line_thickness * 0.5))
}

/// Framebuffer position (pixels, origin top-left, `y` down) of a clip-space point (Jansson §3.2,
/// listing lines 5-7 with wgpu's `y` flip): `((ndc.x + 1) · w / 2, (1 - ndc.y) · h / 2)`.
///
/// Precondition: `clip.w ≠ 0` ([`strand_coverage`] checks `w > 0` first).
pub fn screen_from_clip(clip: Vec4, resolution: Vec2) -> Vec2 {
    let ndc = clip.truncate().truncate() / clip.w;
    Vec2::new(
        (ndc.x + 1.0) * 0.5 * resolution.x,
        (1.0 - ndc.y) * 0.5 * resolution.y,
    )
}

/// `strand_coverage` of Jansson §3.2: project the interpolated point on the strand's centre line
/// `world_line` (homogeneous, usually `w = 1`) to the screen, measure its distance `d` to the
/// fragment at `screen_fragment` (pixels, as in `@builtin(position).xy`) and return
/// [`coverage_from_distance`]`(d, line_thickness)`.
///
/// A centre point behind the eye (`clip.w <= 0`) gives 0.
pub fn strand_coverage(
    screen_fragment: Vec2,
    world_line: Vec4,
    clip_from_world: Mat4,
    resolution: Vec2,
    line_thickness: f32,
) -> f32 {
    let clip_line = clip_from_world * world_line;
    if clip_line.w <= 0.0 {
        return 0.0;
    }
    let screen_line = screen_from_clip(clip_line, resolution);
    let d = screen_line.distance(screen_fragment);
    coverage_from_distance(d, line_thickness)
}

/// Alpha factor for a strand `thickness` pixels wide drawn as a line `line_thickness` pixels wide:
/// `saturate(thickness / line_thickness)`, the fraction of the drawn width the strand covers.
///
/// Used towards the tips, where a strand's projected thickness shrinks below the drawn width: the
/// ribbon keeps its (at least one-pixel) width and fades instead of aliasing. 1 for strands at
/// least as wide as the line, 0 for zero thickness or a non-positive line width; monotonic in
/// `thickness`.
pub fn tip_fade(thickness: f32, line_thickness: f32) -> f32 {
    if line_thickness <= 0.0 {
        return 0.0;
    }
    saturate(thickness / line_thickness)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn coverage_is_one_at_centre_zero_at_edge() {
        assert_eq!(coverage_from_distance(0.0, 3.0), 1.0);
        assert_eq!(coverage_from_distance(1.5, 3.0), 0.0);
        assert_eq!(coverage_from_distance(10.0, 3.0), 0.0);
        assert!((coverage_from_distance(0.75, 3.0) - 0.5).abs() < 1e-6);
        assert_eq!(coverage_from_distance(0.0, 0.0), 0.0);
        assert_eq!(coverage_from_distance(0.0, -1.0), 0.0);
    }

    #[test]
    fn coverage_bounded_and_decreasing() {
        let mut last = f32::INFINITY;
        for i in 0..100 {
            let d = i as f32 * 0.05;
            let c = coverage_from_distance(d, 4.0);
            assert!((0.0..=1.0).contains(&c));
            assert!(c <= last);
            last = c;
        }
    }

    #[test]
    fn screen_mapping_uses_top_left_origin() {
        let res = Vec2::new(200.0, 100.0);
        assert_eq!(
            screen_from_clip(Vec4::new(0.0, 0.0, 0.5, 1.0), res),
            Vec2::new(100.0, 50.0)
        );
        // NDC (-1, +1) is the top-left corner; homogeneous w divides.
        assert_eq!(
            screen_from_clip(Vec4::new(-2.0, 2.0, 0.0, 2.0), res),
            Vec2::ZERO
        );
        assert_eq!(screen_from_clip(Vec4::new(1.0, -1.0, 0.0, 1.0), res), res);
    }

    #[test]
    fn strand_coverage_through_a_camera() {
        let res = Vec2::new(64.0, 64.0);
        let proj = Mat4::perspective_rh(60f32.to_radians(), 1.0, 0.1, 100.0);
        let view = Mat4::look_at_rh(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y);
        let clip_from_world = proj * view;
        // The origin projects to the image centre (32, 32).
        let centre = Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!(
            (strand_coverage(Vec2::new(32.0, 32.0), centre, clip_from_world, res, 2.0) - 1.0).abs()
                < 1e-5
        );
        let half = strand_coverage(Vec2::new(32.5, 32.0), centre, clip_from_world, res, 2.0);
        assert!((half - 0.5).abs() < 1e-4, "{half}");
        assert_eq!(
            strand_coverage(Vec2::new(31.0, 32.0), centre, clip_from_world, res, 2.0),
            0.0
        );
        // World +Y is screen up (smaller y): a point above the origin is covered above the centre.
        let above = Vec4::new(0.0, 0.5, 0.0, 1.0);
        let screen_above = screen_from_clip(clip_from_world * above, res);
        assert!(screen_above.y < 32.0);
        assert!(
            (strand_coverage(screen_above, above, clip_from_world, res, 2.0) - 1.0).abs() < 1e-5
        );
        // Behind the camera: nothing.
        let behind = Vec4::new(0.0, 0.0, 10.0, 1.0);
        assert_eq!(
            strand_coverage(Vec2::new(32.0, 32.0), behind, clip_from_world, res, 2.0),
            0.0
        );
    }

    #[test]
    fn tip_fade_bounds() {
        assert_eq!(tip_fade(2.0, 1.0), 1.0);
        assert_eq!(tip_fade(1.0, 1.0), 1.0);
        assert!((tip_fade(0.25, 1.0) - 0.25).abs() < 1e-7);
        assert_eq!(tip_fade(0.0, 1.0), 0.0);
        assert_eq!(tip_fade(0.5, 0.0), 0.0);
        let mut last = 0.0;
        for i in 0..40 {
            let f = tip_fade(i as f32 * 0.05, 1.5);
            assert!((0.0..=1.0).contains(&f) && f >= last);
            last = f;
        }
    }
}
