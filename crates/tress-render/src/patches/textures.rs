//! The four patch textures on the GPU ([`PatchTextures`]) and their PNG import and export.
//!
//! Upload: the base texture is stored as `Rgba8UnormSrgb` (the GPU decodes to linear when
//! sampling; sRGB keeps dark hair free of banding at 8 bits), the alpha, specular shift and
//! specular noise textures as `R8Unorm` holding their linear values. With `mipmaps` a full chain
//! is built on the CPU by 2×2 box filtering (in linear space), so distant patches do not
//! shimmer. The sampler filters linearly, repeats across `u` (the procedural textures tile
//! across a patch) and clamps along `v` (root and tip must not bleed into each other).
//!
//! PNG files: the base texture is written as 8-bit sRGB RGB, the three others as 8-bit
//! grayscale of their linear values; reading reverses this (an alpha texture read from a PNG
//! with an alpha channel takes that channel, otherwise the gray level).

use std::path::{Path, PathBuf};

use tress_hair::patches::{HairTextures, Texture};
use wgpu::util::DeviceExt;

use crate::gpu::{linear_to_srgb, srgb_to_linear};
use crate::{GpuContext, RenderError};

/// Largest texture edge read from a PNG file.
pub const MAX_TEXTURE_EDGE: u32 = 8192;

/// One of the four textures of the technique.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureSlot {
    /// Base color (RGB, sRGB in PNG files).
    Base,
    /// Opacity.
    Alpha,
    /// Specular shift (0.5: none).
    SpecShift,
    /// Specular noise (the secondary highlight's sparkle mask).
    SpecNoise,
}

impl TextureSlot {
    /// All four, in binding order.
    pub const ALL: [TextureSlot; 4] = [
        TextureSlot::Base,
        TextureSlot::Alpha,
        TextureSlot::SpecShift,
        TextureSlot::SpecNoise,
    ];

    /// Name used in labels and file names (`base`, `alpha`, `spec_shift`, `spec_noise`).
    pub fn name(self) -> &'static str {
        match self {
            TextureSlot::Base => "base",
            TextureSlot::Alpha => "alpha",
            TextureSlot::SpecShift => "spec_shift",
            TextureSlot::SpecNoise => "spec_noise",
        }
    }

    /// Channels the slot holds (3 for the base, 1 otherwise).
    pub fn channels(self) -> u32 {
        if self == TextureSlot::Base { 3 } else { 1 }
    }

    /// The slot's texture of a set.
    pub fn of(self, t: &HairTextures) -> &Texture {
        match self {
            TextureSlot::Base => &t.base,
            TextureSlot::Alpha => &t.alpha,
            TextureSlot::SpecShift => &t.spec_shift,
            TextureSlot::SpecNoise => &t.spec_noise,
        }
    }

    /// The slot's texture of a set, mutably.
    pub fn of_mut(self, t: &mut HairTextures) -> &mut Texture {
        match self {
            TextureSlot::Base => &mut t.base,
            TextureSlot::Alpha => &mut t.alpha,
            TextureSlot::SpecShift => &mut t.spec_shift,
            TextureSlot::SpecNoise => &mut t.spec_noise,
        }
    }
}

/// Check a texture's size, channel count and values against its slot.
pub fn validate_texture(tex: &Texture, slot: TextureSlot) -> Result<(), RenderError> {
    let name = slot.name();
    if tex.channels != slot.channels() {
        return Err(RenderError::Invalid(format!(
            "{name} texture has {} channels, expected {}",
            tex.channels,
            slot.channels()
        )));
    }
    if !(1..=MAX_TEXTURE_EDGE).contains(&tex.width) || !(1..=MAX_TEXTURE_EDGE).contains(&tex.height)
    {
        return Err(RenderError::Invalid(format!(
            "{name} texture is {}x{}, edges must lie in 1..={MAX_TEXTURE_EDGE}",
            tex.width, tex.height
        )));
    }
    let expect = tex.width as usize * tex.height as usize * tex.channels as usize;
    if tex.data.len() != expect {
        return Err(RenderError::Invalid(format!(
            "{name} texture has {} values, expected {expect}",
            tex.data.len()
        )));
    }
    if tex.data.iter().any(|v| !v.is_finite()) {
        return Err(RenderError::Invalid(format!(
            "{name} texture has non-finite values"
        )));
    }
    Ok(())
}

/// The 2×2 box-filtered half-size level of a texture (edges of 1 stay 1).
pub fn downsample(tex: &Texture) -> Texture {
    let (w, h, c) = (tex.width, tex.height, tex.channels);
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut data = Vec::with_capacity((nw * nh * c) as usize);
    for y in 0..nh {
        for x in 0..nw {
            let xs = [(2 * x).min(w - 1), (2 * x + 1).min(w - 1)];
            let ys = [(2 * y).min(h - 1), (2 * y + 1).min(h - 1)];
            for ch in 0..c {
                let sum: f32 = ys
                    .iter()
                    .flat_map(|&yy| xs.iter().map(move |&xx| (xx, yy)))
                    .map(|(xx, yy)| tex.data[((yy * w + xx) * c + ch) as usize])
                    .sum();
                data.push(sum * 0.25);
            }
        }
    }
    Texture {
        width: nw,
        height: nh,
        channels: c,
        data,
    }
}

/// The texture's levels, full size first; one level without `mipmaps`.
pub fn mip_chain(tex: &Texture, mipmaps: bool) -> Vec<Texture> {
    let mut levels = vec![tex.clone()];
    if !mipmaps {
        return levels;
    }
    loop {
        let last = &levels[levels.len() - 1];
        if last.width == 1 && last.height == 1 {
            return levels;
        }
        levels.push(downsample(last));
    }
}

/// 8-bit texels as uploaded: sRGB RGBA for the base, linear gray otherwise.
fn encode_texels(tex: &Texture, slot: TextureSlot) -> Vec<u8> {
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    match slot {
        TextureSlot::Base => tex
            .data
            .chunks_exact(3)
            .flat_map(|c| {
                [
                    q(linear_to_srgb(c[0])),
                    q(linear_to_srgb(c[1])),
                    q(linear_to_srgb(c[2])),
                    255,
                ]
            })
            .collect(),
        _ => tex.data.iter().map(|&v| q(v)).collect(),
    }
}

/// The four textures on the GPU with their sampler.
#[derive(Debug)]
pub struct PatchTextures {
    views: Vec<wgpu::TextureView>,
    pub(crate) sampler: wgpu::Sampler,
    sizes: [[u32; 2]; 4],
    bytes: u64,
}

impl PatchTextures {
    /// Validate and upload a texture set, with a mip chain when `mipmaps` is set.
    pub fn new(
        ctx: &GpuContext,
        textures: &HairTextures,
        mipmaps: bool,
    ) -> Result<Self, RenderError> {
        let max = ctx.caps.max_texture_2d;
        let mut uploads = Vec::with_capacity(4);
        for slot in TextureSlot::ALL {
            let tex = slot.of(textures);
            validate_texture(tex, slot)?;
            if tex.width > max || tex.height > max {
                return Err(RenderError::Invalid(format!(
                    "{} texture is {}x{}, the device allows {max}",
                    slot.name(),
                    tex.width,
                    tex.height
                )));
            }
            let levels = mip_chain(tex, mipmaps);
            let data: Vec<u8> = levels.iter().flat_map(|l| encode_texels(l, slot)).collect();
            uploads.push((slot, tex.width, tex.height, levels.len() as u32, data));
        }
        ctx.scoped("uploading the patch textures", || {
            let mut views = Vec::with_capacity(4);
            let mut sizes = [[0; 2]; 4];
            for (i, (slot, width, height, mips, data)) in uploads.iter().enumerate() {
                let format = match slot {
                    TextureSlot::Base => wgpu::TextureFormat::Rgba8UnormSrgb,
                    _ => wgpu::TextureFormat::R8Unorm,
                };
                let texture = ctx.device.create_texture_with_data(
                    &ctx.queue,
                    &wgpu::TextureDescriptor {
                        label: Some(&format!("patches/textures/{}", slot.name())),
                        size: wgpu::Extent3d {
                            width: *width,
                            height: *height,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: *mips,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    data,
                );
                views.push(texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(&format!("patches/textures/{}-view", slot.name())),
                    ..Default::default()
                }));
                sizes[i] = [*width, *height];
            }
            let sampler = ctx.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("patches/textures/sampler"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                address_mode_w: wgpu::AddressMode::ClampToEdge,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            });
            PatchTextures {
                views,
                sampler,
                sizes,
                bytes: uploads.iter().map(|u| u.4.len() as u64).sum(),
            }
        })
    }

    /// The view of a slot's texture.
    pub(crate) fn view(&self, slot: TextureSlot) -> &wgpu::TextureView {
        &self.views[slot as usize]
    }

    /// Size in texels of a slot's full-resolution level.
    pub fn size(&self, slot: TextureSlot) -> [u32; 2] {
        self.sizes[slot as usize]
    }

    /// Bytes of texels on the GPU (all four textures, every mip level).
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

fn image_error(path: &Path, source: image::ImageError) -> RenderError {
    RenderError::Image {
        path: path.display().to_string(),
        source,
    }
}

/// A texture as an 8-bit PNG image (see the module docs).
pub fn texture_image(tex: &Texture, slot: TextureSlot) -> Result<image::DynamicImage, RenderError> {
    validate_texture(tex, slot)?;
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let bad = || RenderError::Invalid(format!("{} texture size mismatch", slot.name()));
    Ok(match slot {
        TextureSlot::Base => {
            let data = tex.data.iter().map(|&v| q(linear_to_srgb(v))).collect();
            image::DynamicImage::ImageRgb8(
                image::RgbImage::from_raw(tex.width, tex.height, data).ok_or_else(bad)?,
            )
        }
        _ => image::DynamicImage::ImageLuma8(
            image::GrayImage::from_raw(tex.width, tex.height, tex.to_u8()).ok_or_else(bad)?,
        ),
    })
}

/// Write a texture as a PNG file (see the module docs).
pub fn save_texture_png(
    tex: &Texture,
    slot: TextureSlot,
    path: impl AsRef<Path>,
) -> Result<(), RenderError> {
    let path = path.as_ref();
    texture_image(tex, slot)?
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| image_error(path, e))
}

/// Write the four textures into `dir` as `base.png`, `alpha.png`, `spec_shift.png` and
/// `spec_noise.png`; returns the paths.
pub fn save_textures_png(
    textures: &HairTextures,
    dir: impl AsRef<Path>,
) -> Result<Vec<PathBuf>, RenderError> {
    let dir = dir.as_ref();
    TextureSlot::ALL
        .iter()
        .map(|&slot| {
            let path = dir.join(format!("{}.png", slot.name()));
            save_texture_png(slot.of(textures), slot, &path)?;
            Ok(path)
        })
        .collect()
}

/// Read a texture for `slot` from an image file (PNG or any format the `image` crate reads
/// here). The size is checked before the pixels are decoded.
pub fn load_texture_png(path: impl AsRef<Path>, slot: TextureSlot) -> Result<Texture, RenderError> {
    let path = path.as_ref();
    let open = || {
        image::ImageReader::open(path)
            .map_err(|e| image_error(path, e.into()))?
            .with_guessed_format()
            .map_err(|e| image_error(path, e.into()))
    };
    let (w, h) = open()?
        .into_dimensions()
        .map_err(|e| image_error(path, e))?;
    if !(1..=MAX_TEXTURE_EDGE).contains(&w) || !(1..=MAX_TEXTURE_EDGE).contains(&h) {
        return Err(RenderError::Invalid(format!(
            "{}: {w}x{h} texture, edges must lie in 1..={MAX_TEXTURE_EDGE}",
            path.display()
        )));
    }
    let img = open()?.decode().map_err(|e| image_error(path, e))?;
    let data: Vec<f32> = match slot {
        TextureSlot::Base => img
            .to_rgb8()
            .into_raw()
            .into_iter()
            .map(|v| srgb_to_linear(f32::from(v) / 255.0))
            .collect(),
        TextureSlot::Alpha if img.color().has_alpha() => img
            .to_rgba8()
            .pixels()
            .map(|p| f32::from(p.0[3]) / 255.0)
            .collect(),
        _ => img
            .to_luma8()
            .into_raw()
            .into_iter()
            .map(|v| f32::from(v) / 255.0)
            .collect(),
    };
    Ok(Texture {
        width: w,
        height: h,
        channels: slot.channels(),
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gray(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Texture {
        let data = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        Texture {
            width: w,
            height: h,
            channels: 1,
            data,
        }
    }

    #[test]
    fn mip_chain_halves_to_one_texel_and_keeps_the_mean() {
        let t = gray(8, 2, |x, y| (x + 8 * y) as f32 / 15.0);
        let chain = mip_chain(&t, true);
        let dims: Vec<[u32; 2]> = chain.iter().map(|l| [l.width, l.height]).collect();
        assert_eq!(dims, vec![[8, 2], [4, 1], [2, 1], [1, 1]]);
        let mean = t.data.iter().sum::<f32>() / 16.0;
        assert!((chain[3].data[0] - mean).abs() < 1e-6);
        assert_eq!(mip_chain(&t, false).len(), 1);
    }

    #[test]
    fn png_round_trip_keeps_8_bit_values() {
        let dir = std::env::temp_dir().join(format!("tress-patch-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let params = tress_hair::patches::TextureParams {
            width: 16,
            height: 32,
            strands: 4,
            ..Default::default()
        };
        let tex = HairTextures::generate(&params).unwrap();
        let paths = save_textures_png(&tex, &dir).unwrap();
        assert_eq!(paths.len(), 4);
        for (slot, path) in TextureSlot::ALL.iter().zip(&paths) {
            let back = load_texture_png(path, *slot).unwrap();
            let orig = slot.of(&tex);
            assert_eq!(
                (back.width, back.height, back.channels),
                (16, 32, orig.channels)
            );
            // 8-bit quantization: linear for gray, sRGB for the base (finer in the darks).
            for (a, b) in orig.data.iter().zip(&back.data) {
                assert!(
                    (a - b).abs() <= 0.5 / 255.0 + 1e-6
                        || *slot == TextureSlot::Base && (a - b).abs() < 0.01,
                    "{slot:?}: {a} vs {b}"
                );
            }
        }
        let bad = dir.join("not.png");
        std::fs::write(&bad, b"not a png").unwrap();
        assert!(load_texture_png(&bad, TextureSlot::Alpha).is_err());
        assert!(load_texture_png(dir.join("missing.png"), TextureSlot::Alpha).is_err());
    }

    #[test]
    fn invalid_textures_are_named() {
        let mut t = gray(4, 4, |_, _| 0.5);
        t.data.pop();
        let e = validate_texture(&t, TextureSlot::Alpha)
            .unwrap_err()
            .to_string();
        assert!(e.contains("alpha"), "{e}");
        let t = gray(4, 4, |_, _| 0.5);
        assert!(validate_texture(&t, TextureSlot::Base).is_err());
        let t = gray(4, 4, |_, _| f32::NAN);
        assert!(validate_texture(&t, TextureSlot::SpecNoise).is_err());
    }
}
