//! Scores at a matched scale: what separates a real difference between a real-time image and a
//! path-traced reference from the reference's sampling noise and from the strands' own pixel
//! texture.
//!
//! FLIP at pixel scale mixes three things: the reference's Monte Carlo noise (speckle and
//! fireflies), the hair's sub-pixel texture (a rasterizer's 1.5-pixel lines against traced
//! strands a fraction of a pixel wide), and the model's real differences (shadows, multiple
//! scattering, colour). Box-filtering both images in *linear light* by a factor `s` (each
//! `s × s` block averaged, an `s`-times smaller image) before scoring removes most of the first
//! two and keeps the third: light is additive, so the block's mean is what a sensor `s` times
//! coarser would see of either image. The reference's own seed-to-seed figure at the same scale
//! is the floor no technique can beat.
//!
//! Beside FLIP, the **mean linear colour over the hair** and its per-channel ratio to the
//! reference's say in which direction a systematic difference goes (darker, lighter, tinted),
//! which FLIP cannot.

use glam::Vec3;

use crate::{DisplayImage, Image, TraceError, metrics};

/// The default scale factor: 3 × 3 blocks.
pub const DEFAULT_SCALE: u32 = 3;

/// sRGB-encoded value in `[0, 1]` to linear (the inverse of [`crate::linear_to_srgb`]).
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The linear image of a display-encoded one (a PNG's values decoded).
pub fn to_linear(image: &DisplayImage) -> Image {
    Image {
        width: image.width,
        height: image.height,
        pixels: image
            .pixels
            .iter()
            .map(|p| Vec3::from_array(p.map(srgb_to_linear)))
            .collect(),
    }
}

/// The image's `factor × factor` blocks averaged in linear light: a `ceil(w / factor) ×
/// ceil(h / factor)` image (a partial block at the right or bottom edge averages the pixels it
/// has). A factor of 1 returns a copy.
pub fn box_downsample(image: &Image, factor: u32) -> Image {
    let f = factor.max(1);
    let (w, h) = (image.width.div_ceil(f), image.height.div_ceil(f));
    let mut sums = vec![(Vec3::ZERO, 0u32); (w * h) as usize];
    for y in 0..image.height {
        for x in 0..image.width {
            let cell = &mut sums[((y / f) * w + x / f) as usize];
            cell.0 += image.pixels[(y * image.width + x) as usize];
            cell.1 += 1;
        }
    }
    Image {
        width: w,
        height: h,
        pixels: sums.into_iter().map(|(s, n)| s / n.max(1) as f32).collect(),
    }
}

/// A mask (rows top to bottom, `width × height`) downsampled like [`box_downsample`]: a block
/// is marked when at least half of its pixels are, so a block is scored only where it is
/// mostly hair.
pub fn downsample_mask(mask: &[bool], width: u32, height: u32, factor: u32) -> Vec<bool> {
    let f = factor.max(1);
    let (w, h) = (width.div_ceil(f), height.div_ceil(f));
    let mut counts = vec![(0u32, 0u32); (w * h) as usize];
    for y in 0..height {
        for x in 0..width {
            let cell = &mut counts[((y / f) * w + x / f) as usize];
            cell.0 += u32::from(mask[(y * width + x) as usize]);
            cell.1 += 1;
        }
    }
    counts.into_iter().map(|(m, n)| 2 * m >= n).collect()
}

/// The mean linear colour over the pixels `mask` marks (all pixels without a mask), or `None`
/// when it marks none.
pub fn mean_color(image: &Image, mask: Option<&[bool]>) -> Option<[f64; 3]> {
    let mut sum = [0.0f64; 3];
    let mut n = 0u64;
    for (i, p) in image.pixels.iter().enumerate() {
        if mask.is_none_or(|m| m[i]) {
            for (s, c) in sum.iter_mut().zip(p.to_array()) {
                *s += f64::from(c);
            }
            n += 1;
        }
    }
    (n > 0).then(|| sum.map(|s| s / n as f64))
}

/// A comparison at a matched scale.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MatchedScore {
    /// The box filter's factor.
    pub scale: u32,
    /// Mean FLIP over the whole downsampled frame.
    pub flip: f64,
    /// Mean FLIP over the downsampled mask's blocks (with a mask).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flip_masked: Option<f64>,
    /// Blocks the downsampled mask marks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mask_blocks: Option<usize>,
    /// The reference's mean linear colour over the mask (the frame without one), full scale.
    pub mean_reference: Option<[f64; 3]>,
    /// The test image's mean linear colour over the same pixels.
    pub mean_test: Option<[f64; 3]>,
    /// `mean_test / mean_reference` per channel (absent where the reference's mean is 0).
    pub color_ratio: Option<[f64; 3]>,
}

/// Score linear `test` against linear `reference` (same size) at `scale`, over the frame and,
/// with a mask of the frame's size, over the mask.
pub fn compare(
    reference: &Image,
    test: &Image,
    mask: Option<&[bool]>,
    scale: u32,
) -> Result<MatchedScore, TraceError> {
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(TraceError::SizeMismatch {
            a_width: reference.width,
            a_height: reference.height,
            b_width: test.width,
            b_height: test.height,
        });
    }
    if let Some(m) = mask
        && m.len() != reference.pixels.len()
    {
        return Err(TraceError::Invalid(format!(
            "the mask has {} pixels, the images {}",
            m.len(),
            reference.pixels.len()
        )));
    }
    let a = box_downsample(reference, scale);
    let b = box_downsample(test, scale);
    let cmp = metrics::compare(
        &DisplayImage::from_linear(&a),
        &DisplayImage::from_linear(&b),
    )?;
    let small_mask =
        mask.map(|m| downsample_mask(m, reference.width, reference.height, scale.max(1)));
    let mean_reference = mean_color(reference, mask);
    let mean_test = mean_color(test, mask);
    let color_ratio = match (mean_reference, mean_test) {
        (Some(r), Some(t)) if r.iter().all(|&c| c > 0.0) => {
            Some([t[0] / r[0], t[1] / r[1], t[2] / r[2]])
        }
        _ => None,
    };
    Ok(MatchedScore {
        scale: scale.max(1),
        flip: cmp.scores.flip,
        flip_masked: small_mask.as_ref().map(|m| cmp.masked_flip(m)),
        mask_blocks: small_mask
            .as_ref()
            .map(|m| m.iter().filter(|&&x| x).count()),
        mean_reference,
        mean_test,
        color_ratio,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test picture: dark strands (thin diagonal lines) over a lighter ground.
    fn picture(w: u32, h: u32) -> Image {
        let mut img = Image::filled(w, h, Vec3::new(0.35, 0.3, 0.27));
        for y in 0..h {
            for x in 0..w {
                if (x + 2 * y) % 5 == 0 {
                    img.pixels[(y * w + x) as usize] = Vec3::new(0.15, 0.12, 0.1);
                }
            }
        }
        img
    }

    /// Noise that averages out over 3 × 3 blocks: an offset per pixel whose block sum is zero
    /// (a noisy render's speckle, which a coarser sensor would not see).
    fn noisy(img: &Image) -> Image {
        let mut out = img.clone();
        for (i, p) in out.pixels.iter_mut().enumerate() {
            let (x, y) = (i as u32 % img.width, i as u32 / img.width);
            let k = (x % 3) * 3 + y % 3; // 0..9 inside each block
            let factor = [1.9, 0.1, 1.6, 0.4, 1.0, 1.3, 0.7, 1.8, 0.2][k as usize];
            *p += Vec3::splat((factor - 1.0) * 0.15);
        }
        out
    }

    #[test]
    fn noise_scores_near_zero_at_scale_three_and_a_darker_copy_does_not() {
        let a = picture(96, 72);
        let speckled = noisy(&a);
        let darker = Image {
            pixels: a.pixels.iter().map(|p| *p * 0.9).collect(),
            ..a.clone()
        };
        let pixel_noise = compare(&a, &speckled, None, 1).unwrap().flip;
        let matched_noise = compare(&a, &speckled, None, 3).unwrap().flip;
        let matched_dark = compare(&a, &darker, None, 3).unwrap();
        assert!(pixel_noise > 0.02, "speckle at pixel scale {pixel_noise}");
        assert!(matched_noise < 0.002, "speckle at scale 3 {matched_noise}");
        assert!(
            matched_dark.flip > 5.0 * matched_noise.max(1e-3),
            "10% darker at scale 3 {} against noise {matched_noise}",
            matched_dark.flip
        );
        let ratio = matched_dark.color_ratio.unwrap();
        for c in ratio {
            assert!((c - 0.9).abs() < 1e-4, "{ratio:?}");
        }
    }

    #[test]
    fn box_downsample_averages_blocks_in_linear_light() {
        let mut img = Image::filled(4, 3, Vec3::ZERO);
        img.pixels[0] = Vec3::splat(0.9); // block (0, 0): 4 pixels of 3 x 3... of 2 x 2
        img.pixels[3] = Vec3::splat(0.5); // the right edge's partial block
        let small = box_downsample(&img, 2);
        assert_eq!((small.width, small.height), (2, 2));
        assert!((small.pixels[0].x - 0.9 / 4.0).abs() < 1e-6);
        assert!((small.pixels[1].x - 0.5 / 4.0).abs() < 1e-6);
        // The bottom row is a partial block of 2 pixels each.
        assert_eq!(small.pixels[2], Vec3::ZERO);
        assert_eq!(box_downsample(&img, 1), img);
    }

    #[test]
    fn masks_keep_blocks_that_are_mostly_marked() {
        // 3 x 3 block with 5 of 9 marked: kept; 4 of 9: dropped.
        let mut m = vec![false; 6 * 3];
        for i in [0, 1, 2, 6, 7] {
            m[i] = true;
        }
        for i in [3, 4, 5, 9] {
            m[i] = true;
        }
        assert_eq!(downsample_mask(&m, 6, 3, 3), vec![true, false]);
    }

    #[test]
    fn mean_color_and_ratio_over_a_mask() {
        let a = picture(30, 30);
        let mask: Vec<bool> = (0..900).map(|i| i % 2 == 0).collect();
        let mut b = a.clone();
        for (i, p) in b.pixels.iter_mut().enumerate() {
            if i % 2 == 0 {
                *p *= Vec3::new(1.0, 0.5, 2.0);
            } else {
                *p = Vec3::ONE; // outside the mask: must not count
            }
        }
        let s = compare(&a, &b, Some(&mask), 3).unwrap();
        let r = s.color_ratio.unwrap();
        assert!(
            (r[0] - 1.0).abs() < 1e-6 && (r[1] - 0.5).abs() < 1e-6 && (r[2] - 2.0).abs() < 1e-6
        );
        assert!(s.flip_masked.is_some() && s.mask_blocks.unwrap() > 0);
        assert!(compare(&a, &b, Some(&mask[..10]), 3).is_err());
        assert_eq!(mean_color(&a, Some(&[false; 900])), None);
    }

    #[test]
    fn srgb_round_trips() {
        for i in 0..=20 {
            let c = i as f32 / 20.0;
            assert!((srgb_to_linear(crate::linear_to_srgb(c)) - c).abs() < 1e-5);
        }
    }
}
