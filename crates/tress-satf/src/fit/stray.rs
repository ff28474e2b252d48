//! How far a fitted cluster's shell strays from its strands, relative to the shell's own size:
//! the test that splits a group in two (see the parent module's docs, step 7).

use glam::Vec3;

use crate::hierarchy::MacroCluster;

/// A shell point nearer a strand than this many minimum half-axes (by default 1% of the hair's
/// diagonal, a pixel or two where the hair fills the frame) does not stray, whatever the
/// cluster's size: splitting further would only multiply clusters (and their layer meshes).
const NEGLIGIBLE_RADII: f32 = 10.0;
/// A shell point farther than this many minimum half-axes from every strand (by default 2% of
/// the hair's diagonal, a few pixels where the hair fills a small frame) strays whatever the
/// cross-section's size: a wide, flat root ring across a curved patch of scalp.
const STRAY_RADII: f32 = 20.0;
/// Shell samples along `t` and around `u`.
const SHELL_T: usize = 16;
const SHELL_U: usize = 16;

/// How far the shell of `m` strays, over its threshold: the larger of [`stray_ratio`] over
/// `split` (only when `relative`: groups of 8 strands or more) and the farthest such point's
/// distance over [`STRAY_RADII`] minimum half-axes (`floor`). Above 1 the group is to be
/// split; 0 for a single strand.
pub(super) fn stray_score(
    m: &MacroCluster,
    strands: &[&[Vec3]],
    floor: f32,
    split: f32,
    relative: bool,
) -> f32 {
    stray_ratio(m, strands, floor).map_or(0.0, |(ratio, farthest)| {
        let absolute = farthest / (STRAY_RADII * floor.max(f32::MIN_POSITIVE));
        if relative {
            (ratio / split).max(absolute)
        } else {
            absolute
        }
    })
}

/// The largest ratio, over the points of the shell `v = 1` on a grid of `(t, u)` (16 around
/// `u`; the root ring `t = 0` and the rings at the middles of 16 intervals of `t`), of the
/// distance to the nearest of `strands` to the cross-section's larger half-axis there (at least
/// `floor`): 0 for a shell on its strands, about 1 for a shell a whole radius from every strand
/// (a rim standing off a curved sheet of hair, a wide tube around a few strands), and the
/// largest of those distances. `None` for a single strand.
///
/// The roots of a group lie on a patch of the scalp, so the root ring measures that patch's
/// curvature like any other ring. The tip ring `t = 1` does not count: where the strands' tips
/// are staggered it closes over the one farthest tip while the cross-section there is sized by
/// the tips near it, however few strands the group holds; splitting cannot shrink that (it is
/// not a sheet's sagitta), the profile's end limits bound it and the module's tests check it.
fn stray_ratio(m: &MacroCluster, strands: &[&[Vec3]], floor: f32) -> Option<(f32, f32)> {
    if strands.len() < 2 {
        return None;
    }
    let (g, c) = (&m.geometry, m.clusters.first()?);
    let mut worst = 0.0f32;
    let mut farthest = 0.0f32;
    let rings = std::iter::once(0.0).chain((0..SHELL_T).map(|i| (i as f32 + 0.5) / SHELL_T as f32));
    for t in rings {
        let (a, b, _) = g.profile(t);
        let size = a.max(b).max(floor).max(f32::MIN_POSITIVE);
        for k in 0..SHELL_U {
            let u = k as f32 / SHELL_U as f32 * std::f32::consts::TAU;
            let p = c.point(g, t, 1.0, u);
            let d = strands
                .iter()
                .map(|s| polyline_distance(p, s))
                .fold(f32::INFINITY, f32::min);
            if d > NEGLIGIBLE_RADII * floor {
                worst = worst.max(d / size);
                farthest = farthest.max(d);
            }
        }
    }
    Some((worst, farthest))
}

/// Distance from `p` to the polyline `s`.
fn polyline_distance(p: Vec3, s: &[Vec3]) -> f32 {
    if s.len() == 1 {
        return p.distance(s[0]);
    }
    s.windows(2)
        .map(|w| {
            let ab = w[1] - w[0];
            let f =
                ((p - w[0]).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
            (w[0] + ab * f).distance_squared(p)
        })
        .fold(f32::INFINITY, f32::min)
        .sqrt()
}
