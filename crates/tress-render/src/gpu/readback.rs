//! Reading textures and buffers back to the CPU, and writing PNG (8-bit sRGB) and EXR (linear
//! 32-bit float) files.

use std::path::Path;
use std::sync::mpsc;

use crate::{GpuContext, RenderError};

/// A linear RGBA image read back from the GPU, rows top to bottom. Color is as the renderer left
/// it: premultiplied by alpha.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear RGBA pixels.
    pub pixels: Vec<[f32; 4]>,
}

impl LinearImage {
    /// The pixel at `(x, y)`, `None` outside the image.
    pub fn get(&self, x: u32, y: u32) -> Option<[f32; 4]> {
        (x < self.width && y < self.height).then(|| self.pixels[(y * self.width + x) as usize])
    }

    /// 8-bit sRGB RGBA with straight (not premultiplied) alpha, as PNG expects.
    pub fn to_srgb8(&self) -> image::RgbaImage {
        let mut out = image::RgbaImage::new(self.width, self.height);
        for (dst, src) in out.pixels_mut().zip(&self.pixels) {
            let a = src[3].clamp(0.0, 1.0);
            let un = |c: f32| if a > 0.0 && a < 1.0 { c / a } else { c };
            let enc = |c: f32| (linear_to_srgb(un(c)) * 255.0 + 0.5) as u8;
            *dst = image::Rgba([
                enc(src[0]),
                enc(src[1]),
                enc(src[2]),
                (a * 255.0 + 0.5) as u8,
            ]);
        }
        out
    }

    /// Write an 8-bit sRGB PNG.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<(), RenderError> {
        let path = path.as_ref();
        self.to_srgb8()
            .save_with_format(path, image::ImageFormat::Png)
            .map_err(|source| RenderError::Image {
                path: path.display().to_string(),
                source,
            })
    }

    /// Write a linear 32-bit float EXR (premultiplied alpha, the EXR convention).
    pub fn save_exr(&self, path: impl AsRef<Path>) -> Result<(), RenderError> {
        let path = path.as_ref();
        let flat: Vec<f32> = self.pixels.iter().flatten().copied().collect();
        let img =
            image::Rgba32FImage::from_raw(self.width, self.height, flat).ok_or_else(|| {
                RenderError::Readback("pixel count does not match the image size".into())
            })?;
        image::DynamicImage::ImageRgba32F(img)
            .save_with_format(path, image::ImageFormat::OpenExr)
            .map_err(|source| RenderError::Image {
                path: path.display().to_string(),
                source,
            })
    }
}

pub use tress_shading::linear_to_srgb;

/// sRGB transfer function (encoded to linear).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// IEEE half float bits to `f32`.
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = (h >> 10) & 0x1f;
    let frac = f32::from(h & 0x3ff);
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 if frac == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + frac / 1024.0) * 2f32.powi(i32::from(e) - 15),
    }
}

/// Map `buffer` (which must have `MAP_READ` usage and be idle after the last submit), wait, and
/// copy out `range` bytes.
pub fn read_buffer(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    range: std::ops::Range<u64>,
) -> Result<Vec<u8>, RenderError> {
    let (tx, rx) = mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, range.clone(), move |r| {
        // The receiver outlives this callback: it is dropped only after recv below.
        let _ = tx.send(r);
    });
    ctx.device.poll(wgpu::PollType::wait_indefinitely())?;
    rx.recv()
        .map_err(|_| RenderError::Readback("map callback never ran".into()))??;
    let bytes = buffer.get_mapped_range(range)?.to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Copy all of `buffer` (`COPY_SRC` usage) into a mappable buffer and read it back.
pub fn read_whole_buffer(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    label: &str,
) -> Result<Vec<u8>, RenderError> {
    let size = buffer.size();
    let staging = ctx.scoped(label, || {
        let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        ctx.queue.submit([enc.finish()]);
        staging
    })?;
    read_buffer(ctx, &staging, 0..size)
}

/// Bytes per texel of the color formats readback understands.
fn texel_bytes(format: wgpu::TextureFormat) -> Option<u32> {
    use wgpu::TextureFormat as F;
    match format {
        F::Rgba8Unorm | F::Rgba8UnormSrgb | F::Bgra8Unorm | F::Bgra8UnormSrgb => Some(4),
        F::Rgba16Float => Some(8),
        F::Rgba32Float => Some(16),
        _ => None,
    }
}

/// A 2D texture's texels (`bpp` bytes each), rows top to bottom without the copy's row padding:
/// what every readback of a whole texture needs (the texture must have `COPY_SRC`).
pub(crate) fn read_texture_bytes(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    bpp: u32,
) -> Result<Vec<u8>, RenderError> {
    let (width, height) = (texture.width(), texture.height());
    let row = width * bpp;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let size = u64::from(padded) * u64::from(height);
    let buffer = ctx.scoped("texture readback", || {
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame/readback/texture"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame/readback/encoder"),
            });
        enc.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            texture.size(),
        );
        ctx.queue.submit([enc.finish()]);
        buffer
    })?;
    let bytes = read_buffer(ctx, &buffer, 0..size)?;
    let mut out = Vec::with_capacity((row * height) as usize);
    for y in 0..height {
        let start = (y * padded) as usize;
        out.extend_from_slice(&bytes[start..start + row as usize]);
    }
    Ok(out)
}

/// Read a 2D color texture (`COPY_SRC` usage; formats Rgba8/Bgra8 (sRGB or not), Rgba16Float,
/// Rgba32Float) into a linear image. Handles the 256-byte row alignment of copies.
pub fn read_texture(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<LinearImage, RenderError> {
    let format = texture.format();
    let bpp = texel_bytes(format)
        .ok_or_else(|| RenderError::Target(format!("cannot read back {format:?} textures")))?;
    if !texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
        return Err(RenderError::Target("texture lacks COPY_SRC usage".into()));
    }
    let (width, height) = (texture.width(), texture.height());
    let bytes = read_texture_bytes(ctx, texture, bpp)?;
    let pixels = bytes
        .chunks_exact(bpp as usize)
        .map(|t| decode_texel(format, t))
        .collect();
    Ok(LinearImage {
        width,
        height,
        pixels,
    })
}

fn decode_texel(format: wgpu::TextureFormat, t: &[u8]) -> [f32; 4] {
    use wgpu::TextureFormat as F;
    let unorm = |b: u8| f32::from(b) / 255.0;
    let half = |i: usize| f16_to_f32(u16::from_le_bytes([t[2 * i], t[2 * i + 1]]));
    let float = |i: usize| f32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]]);
    match format {
        F::Rgba8Unorm => [unorm(t[0]), unorm(t[1]), unorm(t[2]), unorm(t[3])],
        F::Bgra8Unorm => [unorm(t[2]), unorm(t[1]), unorm(t[0]), unorm(t[3])],
        F::Rgba8UnormSrgb => {
            let s = |b: u8| srgb_to_linear(unorm(b));
            [s(t[0]), s(t[1]), s(t[2]), unorm(t[3])]
        }
        F::Bgra8UnormSrgb => {
            let s = |b: u8| srgb_to_linear(unorm(b));
            [s(t[2]), s(t[1]), s(t[0]), unorm(t[3])]
        }
        F::Rgba16Float => [half(0), half(1), half(2), half(3)],
        _ => [float(0), float(1), float(2), float(3)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_decode() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x3800), 0.5);
        assert_eq!(f16_to_f32(0x0000), 0.0);
        assert_eq!(f16_to_f32(0x7c00), f32::INFINITY);
        assert!(f16_to_f32(0x7e00).is_nan());
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
    }

    #[test]
    fn srgb_round_trips() {
        for i in 0..=255u8 {
            let c = f32::from(i) / 255.0;
            let back = linear_to_srgb(srgb_to_linear(c));
            assert!((back - c).abs() < 1e-5, "{c} -> {back}");
        }
        assert!((linear_to_srgb(2.0) - 1.0).abs() < 1e-6);
        assert_eq!(linear_to_srgb(-1.0), 0.0);
    }

    #[test]
    fn png_conversion_unpremultiplies() {
        let img = LinearImage {
            width: 2,
            height: 1,
            pixels: vec![[0.5, 0.0, 0.0, 0.5], [1.0; 4]],
        };
        let png = img.to_srgb8();
        assert_eq!(png.get_pixel(0, 0).0, [255, 0, 0, 128]);
        assert_eq!(png.get_pixel(1, 0).0, [255, 255, 255, 255]);
        assert_eq!(img.get(1, 0), Some([1.0; 4]));
        assert_eq!(img.get(2, 0), None);
    }
}
