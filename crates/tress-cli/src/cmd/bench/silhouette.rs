//! The hair's silhouette in every technique's image and in the reference's, for `tress bench
//! --quality`: how well each technique's hair covers the pixels the traced hair covers (mask
//! IoU), and how much of it lies where the strand renderer draws no hair (stray geometry).
//!
//! Silhouettes come from frames *without the head*, so a technique's shadows on the head (which
//! each technique casts its own way) do not count as hair: a GPU technique's silhouette is the
//! pixels that change by more than 1/255 in a channel when the hair is hidden (the background
//! alone); the reference's, the pixels whose traced colour differs from the background by as
//! much (a traced ray that misses returns the background exactly). Hair the head would hide is
//! part of every silhouette alike.

use glam::Vec3;
use tress_scene::{HeadSpec, Scene};
use tress_trace::Image;

/// Dilation of the strand renderer's silhouette before the stray-hair test, in pixels.
pub(crate) const DILATION: u32 = 4;

/// A technique's silhouette against the reference's and the strand renderer's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Silhouette {
    /// Intersection over union with the reference's silhouette.
    pub(crate) iou: f64,
    /// Percent of the technique's silhouette outside the strand renderer's dilated by
    /// [`DILATION`] pixels.
    pub(crate) outside_pct: f64,
}

/// `scene` without a head.
pub(crate) fn without_head(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.head = HeadSpec {
        obj: None,
        generated: Some(false),
        ..s.head.clone()
    };
    s
}

/// The traced image's silhouette: pixels whose colour differs from `background` by more than
/// 1/255 in a channel.
pub(crate) fn traced_mask(img: &Image, background: Vec3) -> Vec<bool> {
    img.pixels
        .iter()
        .map(|p| (*p - background).abs().max_element() > 1.0 / 255.0)
        .collect()
}

/// `mask` (`width` pixels a row) dilated by a disk of `radius` pixels.
pub(crate) fn dilate(mask: &[bool], width: u32, radius: u32) -> Vec<bool> {
    let (w, r) = (width as i64, i64::from(radius));
    let h = mask.len() as i64 / w.max(1);
    let mut out = vec![false; mask.len()];
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let (x, y) = (i as i64 % w, i as i64 / w);
        for dy in -r..=r {
            for dx in -r..=r {
                let (nx, ny) = (x + dx, y + dy);
                if dx * dx + dy * dy <= r * r && (0..w).contains(&nx) && (0..h).contains(&ny) {
                    out[(ny * w + nx) as usize] = true;
                }
            }
        }
    }
    out
}

/// `mask`'s IoU with `reference`'s and its share outside `allowed`, percent (both 0 for an
/// empty mask; IoU 1 when both are empty).
pub(crate) fn compare(mask: &[bool], reference: &[bool], allowed: &[bool]) -> Silhouette {
    let (mut inter, mut union, mut count, mut outside) = (0u64, 0u64, 0u64, 0u64);
    for ((&m, &r), &a) in mask.iter().zip(reference).zip(allowed) {
        inter += u64::from(m && r);
        union += u64::from(m || r);
        count += u64::from(m);
        outside += u64::from(m && !a);
    }
    Silhouette {
        iou: if union == 0 {
            1.0
        } else {
            inter as f64 / union as f64
        },
        outside_pct: if count == 0 {
            0.0
        } else {
            100.0 * outside as f64 / count as f64
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dilation_is_a_disk() {
        // One pixel in the middle of 9 × 9, dilated by 2: the 13 pixels within distance 2.
        let mut m = vec![false; 81];
        m[40] = true;
        let d = dilate(&m, 9, 2);
        assert_eq!(d.iter().filter(|x| **x).count(), 13);
        assert!(d[40 - 2] && d[40 + 18] && !d[40 - 20]);
        // At the border nothing wraps to the next row.
        let mut m = vec![false; 81];
        m[9] = true;
        assert!(!dilate(&m, 9, 1)[8]);
    }

    #[test]
    fn iou_and_stray_share() {
        let a = [true, true, false, false];
        let b = [true, false, true, false];
        let allowed = [true, false, false, false];
        let s = compare(&a, &b, &allowed);
        assert!((s.iou - 1.0 / 3.0).abs() < 1e-12);
        assert!((s.outside_pct - 50.0).abs() < 1e-12);
        assert_eq!(compare(&[false; 2], &[false; 2], &[false; 2]).iou, 1.0);
    }
}
