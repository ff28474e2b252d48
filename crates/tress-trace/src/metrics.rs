//! Image-quality metrics between a reference and a test image: mean FLIP, RMSE and SSIM.
//!
//! All three see the same display-encoded images ([`DisplayImage`]: sRGB-encoded values in
//! `[0, 1]`, as a PNG holds them; EXR inputs are clamped and encoded first, without rounding),
//! so a PNG and an EXR of the same render differ only by the PNG's 8-bit rounding (FLIP, which
//! rounds both, sees them as equal).
//!
//! - **FLIP** (Andersson et al. 2020, LDR-FLIP through the `nv-flip` bindings): the per-pixel
//!   perceptual difference in `[0, 1]` at the default 67 pixels per degree (a 0.7 m viewing
//!   distance from a 24" 4K monitor), averaged over the image. The images are rounded to 8 bits,
//!   as FLIP's LDR path expects. The per-pixel map is also available as a magma heat map.
//! - **RMSE**: the root mean square of the differences of all RGB channels, in encoded units
//!   (`[0, 1]`).
//! - **SSIM** (Wang et al. 2004) of the luma `Y' = 0.2126 R' + 0.7152 G' + 0.0722 B'` of the
//!   encoded values, with *uniform 8×8 windows* at every position where a window fits (stride 1),
//!   averaged:
//!
//!   ```text
//!   SSIM(x, y) = (2 μx μy + C1)(2 σxy + C2) / ((μx² + μy² + C1)(σx² + σy² + C2))
//!   C1 = (0.01 L)², C2 = (0.03 L)², L = 1
//!   ```
//!
//!   with the window's means, (population) variances and covariance. Images smaller than 8
//!   pixels in a dimension use one window as large as the image in that dimension. Window sums
//!   come from summed-area tables in `f64`, so the cost does not depend on the window size.

use std::path::Path;

use crate::{DisplayImage, TraceError};

/// SSIM window edge in pixels.
pub const SSIM_WINDOW: usize = 8;
/// SSIM's `C1 = (0.01 L)²` for `L = 1`.
pub const SSIM_C1: f64 = 0.0001;
/// SSIM's `C2 = (0.03 L)²` for `L = 1`.
pub const SSIM_C2: f64 = 0.0009;

/// The three scores of a comparison.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Scores {
    /// Mean FLIP error in `[0, 1]` (0: identical).
    pub flip: f64,
    /// RMSE of the encoded RGB values, in `[0, 1]` (0: identical).
    pub rmse: f64,
    /// Mean SSIM of the luma, in `[-1, 1]` (1: identical).
    pub ssim: f64,
}

/// A comparison: the scores and FLIP's per-pixel error map.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The scores.
    pub scores: Scores,
    /// Width of the error map.
    pub width: u32,
    /// Height of the error map.
    pub height: u32,
    /// FLIP error per pixel, rows top to bottom.
    pub flip_map: Vec<f32>,
}

impl Comparison {
    /// Mean FLIP over the pixels `mask` marks (a mask of the map's size, rows top to bottom; 0
    /// when it marks none): the error over the hair, which the background does not dilute.
    pub fn masked_flip(&self, mask: &[bool]) -> f64 {
        let (sum, n) = self
            .flip_map
            .iter()
            .zip(mask)
            .filter(|(_, m)| **m)
            .fold((0.0, 0u64), |(s, n), (e, _)| (s + f64::from(*e), n + 1));
        if n == 0 { 0.0 } else { sum / n as f64 }
    }

    /// FLIP's error map colored with its magma look-up table, as 8-bit RGB.
    pub fn heatmap_rgb8(&self) -> Vec<u8> {
        let map = nv_flip::FlipImageFloat::with_data(self.width, self.height, &self.flip_map);
        map.apply_color_lut(&nv_flip::magma_lut()).to_vec()
    }

    /// Write the heat map as a PNG. Errors name the file.
    pub fn save_heatmap(&self, path: impl AsRef<Path>) -> Result<(), TraceError> {
        let path = path.as_ref();
        let fail = |reason: String| TraceError::Image {
            path: path.display().to_string(),
            reason,
        };
        let img = image::RgbImage::from_raw(self.width, self.height, self.heatmap_rgb8())
            .ok_or_else(|| fail("heat map size mismatch".into()))?;
        img.save_with_format(path, image::ImageFormat::Png)
            .map_err(|e| fail(e.to_string()))
    }
}

/// Compare `test` with `reference` (same size, else [`TraceError::SizeMismatch`]).
pub fn compare(reference: &DisplayImage, test: &DisplayImage) -> Result<Comparison, TraceError> {
    check_sizes(reference, test)?;
    if reference.pixels.is_empty() {
        return Err(TraceError::Invalid("the images are empty".into()));
    }
    let (w, h) = (reference.width, reference.height);
    let a = nv_flip::FlipImageRgb8::with_data(w, h, &reference.to_rgb8());
    let b = nv_flip::FlipImageRgb8::with_data(w, h, &test.to_rgb8());
    let map = nv_flip::flip(a, b, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let flip_map = map.to_vec();
    let flip = flip_map.iter().map(|&e| f64::from(e)).sum::<f64>() / flip_map.len() as f64;
    Ok(Comparison {
        scores: Scores {
            flip,
            rmse: rmse(reference, test)?,
            ssim: ssim(reference, test)?,
        },
        width: w,
        height: h,
        flip_map,
    })
}

fn check_sizes(a: &DisplayImage, b: &DisplayImage) -> Result<(), TraceError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(TraceError::SizeMismatch {
            a_width: a.width,
            a_height: a.height,
            b_width: b.width,
            b_height: b.height,
        });
    }
    Ok(())
}

/// Root mean square difference over every RGB channel of every pixel.
pub fn rmse(a: &DisplayImage, b: &DisplayImage) -> Result<f64, TraceError> {
    check_sizes(a, b)?;
    if a.pixels.is_empty() {
        return Ok(0.0);
    }
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| f64::from(p[c]) - f64::from(q[c])))
        .map(|d| d * d)
        .sum();
    Ok((sum / (3 * a.pixels.len()) as f64).sqrt())
}

/// Luma `Y'` of an encoded RGB value (Rec. 709 weights).
fn luma(p: [f32; 3]) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

/// SSIM of one window from its sums (see the module docs).
pub fn ssim_window(n: f64, sx: f64, sy: f64, sxx: f64, syy: f64, sxy: f64) -> f64 {
    let (mx, my) = (sx / n, sy / n);
    // Not clamped: identical windows then give exactly 1 (rounding can make a zero variance
    // slightly negative, far below C2).
    let vx = sxx / n - mx * mx;
    let vy = syy / n - my * my;
    let cov = sxy / n - mx * my;
    ((2.0 * mx * my + SSIM_C1) * (2.0 * cov + SSIM_C2))
        / ((mx * mx + my * my + SSIM_C1) * (vx + vy + SSIM_C2))
}

/// Mean SSIM of the luma over every 8×8 window (see the module docs).
pub fn ssim(a: &DisplayImage, b: &DisplayImage) -> Result<f64, TraceError> {
    check_sizes(a, b)?;
    let (w, h) = (a.width as usize, a.height as usize);
    if w == 0 || h == 0 {
        return Ok(1.0);
    }
    let x: Vec<f64> = a.pixels.iter().map(|&p| luma(p)).collect();
    let y: Vec<f64> = b.pixels.iter().map(|&p| luma(p)).collect();
    // Summed-area tables with a zero first row and column: sat[(j) * (w + 1) + i] is the sum
    // over pixels [0, i) × [0, j).
    let table = |f: &dyn Fn(usize) -> f64| -> Vec<f64> {
        let mut sat = vec![0.0f64; (w + 1) * (h + 1)];
        for j in 0..h {
            let mut row = 0.0;
            for i in 0..w {
                row += f(j * w + i);
                sat[(j + 1) * (w + 1) + i + 1] = sat[j * (w + 1) + i + 1] + row;
            }
        }
        sat
    };
    let sx = table(&|k| x[k]);
    let sy = table(&|k| y[k]);
    let sxx = table(&|k| x[k] * x[k]);
    let syy = table(&|k| y[k] * y[k]);
    let sxy = table(&|k| x[k] * y[k]);
    let (ww, wh) = (SSIM_WINDOW.min(w), SSIM_WINDOW.min(h));
    let n = (ww * wh) as f64;
    let rect = |sat: &[f64], i: usize, j: usize| {
        let (i1, j1) = (i + ww, j + wh);
        sat[j1 * (w + 1) + i1] - sat[j * (w + 1) + i1] - sat[j1 * (w + 1) + i]
            + sat[j * (w + 1) + i]
    };
    let mut total = 0.0;
    let mut count = 0usize;
    for j in 0..=h - wh {
        for i in 0..=w - ww {
            total += ssim_window(
                n,
                rect(&sx, i, j),
                rect(&sy, i, j),
                rect(&sxx, i, j),
                rect(&syy, i, j),
                rect(&sxy, i, j),
            );
            count += 1;
        }
    }
    Ok(total / count as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> DisplayImage {
        let mut pixels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                pixels.push([f(x, y); 3]);
            }
        }
        DisplayImage {
            width: w,
            height: h,
            pixels,
        }
    }

    #[test]
    fn masked_flip_is_the_mean_over_the_marked_pixels() {
        let c = Comparison {
            scores: Scores {
                flip: 0.25,
                rmse: 0.0,
                ssim: 1.0,
            },
            width: 2,
            height: 2,
            flip_map: vec![0.1, 0.2, 0.3, 0.4],
        };
        assert!((c.masked_flip(&[true, false, true, false]) - 0.2).abs() < 1e-6);
        assert!((c.masked_flip(&[true; 4]) - 0.25).abs() < 1e-6);
        assert_eq!(c.masked_flip(&[false; 4]), 0.0);
    }

    #[test]
    fn identical_images_score_perfectly() {
        let a = image(40, 30, |x, y| ((x * 7 + y * 3) % 11) as f32 / 10.0);
        let c = compare(&a, &a).unwrap();
        assert_eq!(c.scores.rmse, 0.0);
        assert!((c.scores.ssim - 1.0).abs() < 1e-9, "{}", c.scores.ssim);
        assert!(c.scores.flip < 1e-6, "{}", c.scores.flip);
        assert_eq!(c.flip_map.len(), 1200);
        assert_eq!(c.heatmap_rgb8().len(), 3600);
    }

    #[test]
    fn constant_offset_gives_the_closed_form() {
        // Constant images a and b: every window has zero variance and covariance, so
        // SSIM = (2ab + C1) / (a² + b² + C1) exactly, and RMSE = |a - b|.
        let (va, vb) = (0.25f32, 0.35f32);
        let a = image(20, 12, |_, _| va);
        let b = image(20, 12, |_, _| vb);
        let (fa, fb) = (f64::from(va), f64::from(vb));
        let expected = (2.0 * fa * fb + SSIM_C1) / (fa * fa + fb * fb + SSIM_C1);
        assert!((ssim(&a, &b).unwrap() - expected).abs() < 1e-9);
        assert!((rmse(&a, &b).unwrap() - (fb - fa)).abs() < 1e-7);
        // (0.175 + C1) / (0.185 + C1) = 0.1751 / 0.1851.
        assert!((expected - 0.945_975).abs() < 1e-6, "{expected}");
        let flip = compare(&a, &b).unwrap().scores.flip;
        assert!(flip > 0.0 && flip < 1.0);
    }

    #[test]
    fn one_window_by_hand() {
        // An 8x8 checkerboard of 0.2 / 0.6 against its inverse: equal means (0.4) and variances
        // (0.04), covariance -0.04, so SSIM = 1 · (-0.08 + C2) / (0.08 + C2).
        let a = image(8, 8, |x, y| if (x + y) % 2 == 0 { 0.2 } else { 0.6 });
        let b = image(8, 8, |x, y| if (x + y) % 2 == 0 { 0.6 } else { 0.2 });
        let expected = (-0.08 + SSIM_C2) / (0.08 + SSIM_C2);
        assert!((ssim(&a, &b).unwrap() - expected).abs() < 1e-6);
        // RMSE: every channel differs by 0.4.
        assert!((rmse(&a, &b).unwrap() - 0.4).abs() < 1e-6);
        // Small images use one window of their own size.
        let s = image(3, 2, |x, _| x as f32 * 0.1);
        assert!((ssim(&s, &s).unwrap() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn windows_average_over_positions() {
        // A 9x8 image has two window positions; make the two differ and check the mean.
        let a = image(9, 8, |x, _| if x == 0 { 1.0 } else { 0.5 });
        let b = image(9, 8, |_, _| 0.5);
        let n = 64.0;
        // Window at x = 0: column 0 is 1 (8 pixels) in a, the rest 0.5.
        let sx = 8.0 * 1.0 + 56.0 * 0.5;
        let sxx = 8.0 * 1.0 + 56.0 * 0.25;
        let first = ssim_window(n, sx, 32.0, sxx, 16.0, 0.5 * sx);
        let second = ssim_window(n, 32.0, 32.0, 16.0, 16.0, 16.0);
        assert!((second - 1.0).abs() < 1e-12);
        let got = ssim(&a, &b).unwrap();
        assert!((got - (first + second) / 2.0).abs() < 1e-9, "{got}");
    }

    #[test]
    fn size_mismatch_is_an_error() {
        let a = image(4, 4, |_, _| 0.0);
        let b = image(4, 5, |_, _| 0.0);
        let e = compare(&a, &b).unwrap_err().to_string();
        assert!(e.contains("4x4") && e.contains("4x5"), "{e}");
    }
}
