//! Linear RGB images: what the tracer produces, written as 8-bit sRGB PNG or linear float EXR
//! (the same encodings as `tress render`), and read back for comparisons.

use std::path::Path;

use glam::Vec3;

use crate::TraceError;

/// A linear RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear RGB pixels.
    pub pixels: Vec<Vec3>,
}

pub use tress_shading::linear_to_srgb;

/// The output file kinds, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// `.png`: 8-bit sRGB.
    Png,
    /// `.exr`: linear 32-bit float RGBA (alpha 1).
    Exr,
}

impl ImageKind {
    /// The kind for a path's extension (case-insensitive), or an error naming the path.
    pub fn from_path(path: &Path) -> Result<ImageKind, TraceError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(ImageKind::Png),
            Some("exr") => Ok(ImageKind::Exr),
            _ => Err(TraceError::Image {
                path: path.display().to_string(),
                reason: "the image must end in .png or .exr".into(),
            }),
        }
    }
}

impl Image {
    /// A `width × height` image filled with `color`.
    pub fn filled(width: u32, height: u32, color: Vec3) -> Image {
        Image {
            width,
            height,
            pixels: vec![color; width as usize * height as usize],
        }
    }

    /// The pixel at `(x, y)`; panics outside the image.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// 8-bit sRGB, RGB interleaved.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)
            .collect()
    }

    /// Write by extension: `.png` (8-bit sRGB) or `.exr` (linear float). Errors name the file.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), TraceError> {
        let path = path.as_ref();
        let fail = |e: image::ImageError| TraceError::Image {
            path: path.display().to_string(),
            reason: e.to_string(),
        };
        let size_error = || TraceError::Image {
            path: path.display().to_string(),
            reason: "pixel count does not match the image size".into(),
        };
        match ImageKind::from_path(path)? {
            ImageKind::Png => {
                let img = image::RgbImage::from_raw(self.width, self.height, self.to_srgb8())
                    .ok_or_else(size_error)?;
                img.save_with_format(path, image::ImageFormat::Png)
                    .map_err(fail)
            }
            ImageKind::Exr => {
                let flat: Vec<f32> = self
                    .pixels
                    .iter()
                    .flat_map(|p| [p.x, p.y, p.z, 1.0])
                    .collect();
                let img = image::Rgba32FImage::from_raw(self.width, self.height, flat)
                    .ok_or_else(size_error)?;
                image::DynamicImage::ImageRgba32F(img)
                    .save_with_format(path, image::ImageFormat::OpenExr)
                    .map_err(fail)
            }
        }
    }
}

/// A display-encoded RGB image with values in `[0, 1]` (what a PNG holds, or an EXR's linear
/// values clamped and sRGB-encoded): what the comparison metrics see.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplayImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` encoded RGB pixels in `[0, 1]`.
    pub pixels: Vec<[f32; 3]>,
}

impl DisplayImage {
    /// Read a PNG (or any 8/16-bit image the `image` crate reads: values are taken as already
    /// sRGB-encoded) or an EXR (linear: clamped to `[0, 1]` and sRGB-encoded). Alpha is
    /// ignored. Errors name the file.
    pub fn read(path: impl AsRef<Path>) -> Result<DisplayImage, TraceError> {
        let path = path.as_ref();
        let img = image::ImageReader::open(path)
            .map_err(|e| TraceError::Image {
                path: path.display().to_string(),
                reason: e.to_string(),
            })?
            .with_guessed_format()
            .map_err(|e| TraceError::Image {
                path: path.display().to_string(),
                reason: e.to_string(),
            })?
            .decode()
            .map_err(|e| TraceError::Image {
                path: path.display().to_string(),
                reason: e.to_string(),
            })?;
        let linear = matches!(
            img,
            image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
        );
        let rgb = img.to_rgb32f();
        let (width, height) = rgb.dimensions();
        let pixels = rgb
            .pixels()
            .map(|p| {
                p.0.map(|c| {
                    if linear {
                        linear_to_srgb(c)
                    } else {
                        c.clamp(0.0, 1.0)
                    }
                })
            })
            .collect();
        Ok(DisplayImage {
            width,
            height,
            pixels,
        })
    }

    /// The display encoding of a linear image (as its PNG would hold it, before 8-bit rounding).
    pub fn from_linear(image: &Image) -> DisplayImage {
        DisplayImage {
            width: image.width,
            height: image.height,
            pixels: image
                .pixels
                .iter()
                .map(|p| p.to_array().map(linear_to_srgb))
                .collect(),
        }
    }

    /// 8-bit RGB, interleaved (rounded).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("tress-trace-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn png_and_exr_round_trip_to_the_same_display_values() {
        let mut img = Image::filled(3, 2, Vec3::new(0.0, 0.5, 1.0));
        img.pixels[4] = Vec3::new(0.2, 2.0, -1.0);
        let png = tmp("a.png");
        let exr = tmp("a.exr");
        img.save(&png).unwrap();
        img.save(&exr).unwrap();
        let a = DisplayImage::read(&png).unwrap();
        let b = DisplayImage::read(&exr).unwrap();
        assert_eq!((a.width, a.height), (3, 2));
        assert_eq!(a.to_rgb8(), img.to_srgb8());
        assert_eq!(b.to_rgb8(), img.to_srgb8());
        // 0.5 linear is 0.7354 encoded.
        assert!((b.pixels[0][1] - 0.735_36).abs() < 1e-4);
        assert!(matches!(
            img.save(tmp("a.jpg")),
            Err(TraceError::Image { .. })
        ));
        let missing = DisplayImage::read(tmp("missing.png"))
            .unwrap_err()
            .to_string();
        assert!(missing.contains("missing.png"), "{missing}");
    }
}
