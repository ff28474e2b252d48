//! The flat-layer scene of the OIT tests (`oit.rs`, `ppll.rs`): six camera-facing layers of
//! known colour, opacity and depth, drawn out of depth order, and the check of a composited pixel.

use glam::{Vec3, Vec4};

/// The background the layers are composited over.
pub const BACKGROUND: Vec3 = Vec3::new(0.1, 0.2, 0.3);

/// Layers in the order they are drawn (deliberately not depth order): z, color, alpha.
pub const LAYERS: [(f32, [f32; 3], f32); 6] = [
    (0.5, [1.0, 0.0, 0.0], 0.5),
    (2.0, [0.0, 1.0, 0.0], 0.4),
    (-1.0, [0.0, 0.0, 1.0], 0.7),
    (1.0, [1.0, 1.0, 0.0], 0.3),
    (-2.0, [0.2, 0.9, 0.9], 0.6),
    (0.0, [0.9, 0.5, 0.1], 0.8),
];

/// The first `n` layers as (z, color, alpha).
pub fn layers(n: usize) -> Vec<(f32, Vec3, f32)> {
    LAYERS[..n]
        .iter()
        .map(|&(z, c, a)| (z, Vec3::from(c), a))
        .collect()
}

/// A composited pixel is `want` within `tol` and opaque.
pub fn assert_close(got: [f32; 4], want: Vec3, tol: f32, what: &str) {
    let got = Vec4::from(got);
    assert!(
        (got.truncate() - want).abs().max_element() < tol && (got.w - 1.0).abs() < 1e-3,
        "{what}: got {got}, want {want}"
    );
}
