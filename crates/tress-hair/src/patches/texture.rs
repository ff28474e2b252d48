//! Procedural patch textures (Scheuermann 2004, slide "Hair Model - Textures": "Base texture:
//! stretched noise; Alpha texture: should have fully opaque regions; Specular shift texture;
//! Specular noise texture").
//!
//! The paper shows the textures but gives no recipe; these are the choices, all deterministic
//! for a seed and tileable across `u` (a patch's sides may meet the next patch's):
//!
//! - **Stretched noise** is periodic value noise (smoothstep-interpolated lattice values from a
//!   hash of the lattice point and the seed) whose lattice is `strands` cells across and only a
//!   few cells along `v`, summed over three octaves: thin streaks along the hair.
//! - **Base** (RGB): `base_color × lerp(1 − contrast, 1, noise)`.
//! - **Alpha** (1 channel): the patch is `strands` strands wide. Each strand ends at its own
//!   length `v_end ∈ [tip_start, 1]` and fades over `tip_fade` before it (combed, uneven tips);
//!   across the patch, strands in the outer `edge` fraction on either side are dropped at random,
//!   more often toward the border, and the rest fade linearly to the border. The middle of the
//!   patch (`u ∈ [edge, 1 − edge]`, `v ≤ tip_start − tip_fade`) is exactly 1: the "fully opaque
//!   regions" the 4-pass render's alpha test keeps.
//! - **Specular shift** (1 channel): `0.5 + shift_amplitude × (noise − 0.5) × 2`, a per-strand
//!   offset that breaks the highlight up (the shader subtracts 0.5).
//! - **Specular noise** (1 channel): the sparkle mask, `smoothstep(threshold, 1, noise)` of a
//!   finer stretched noise: mostly dark with sparse bright glints.
//!
//! Texels sit at `uv = ((x + 0.5) / width, (y + 0.5) / height)`; row 0 is `v = 0` (the root),
//! as wgpu addresses textures. Data are row-major, channels interleaved.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::HairError;

/// Largest accepted texture edge (texels).
const MAX_SIZE: u32 = 8192;

/// A texture: `width × height` texels of `channels` interleaved `f32` values in `[0, 1]`,
/// row-major, row 0 at `v = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Texels across (`u`).
    pub width: u32,
    /// Texels along (`v`).
    pub height: u32,
    /// Values per texel (1 or 3).
    pub channels: u32,
    /// `width × height × channels` values.
    pub data: Vec<f32>,
}

impl Texture {
    /// Channel `c` of texel `(x, y)`. Panics if out of range.
    pub fn get(&self, x: u32, y: u32, c: u32) -> f32 {
        assert!(x < self.width && y < self.height && c < self.channels);
        self.data[((y * self.width + x) * self.channels + c) as usize]
    }

    /// The values quantized to 8 bits (`round(255 × value)`), e.g. for a PNG.
    pub fn to_u8(&self) -> Vec<u8> {
        self.data
            .iter()
            .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect()
    }
}

/// Settings of the procedural textures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureParams {
    /// Texels across a patch (`u`). Default 256.
    pub width: u32,
    /// Texels along a patch (`v`). Default 512.
    pub height: u32,
    /// Seed of all four textures. Default 0.
    pub seed: u64,
    /// Strands across a patch (streaks of the noise, strands of the alpha). Default 48.
    pub strands: u32,
    /// Base color (linear RGB; the shader's diffuse color is white by default, so this carries
    /// the hue). Default a mid brown `(0.32, 0.2, 0.11)`.
    pub base_color: Vec3,
    /// How dark the base's darkest streaks get, in `[0, 1]`. Default 0.5.
    pub contrast: f32,
    /// Fraction of the patch width on either side where strands thin out, in `[0, 0.5]`.
    /// Default 0.2.
    pub edge: f32,
    /// Shortest strand, as a fraction of the patch length, in `[0, 1]`. Default 0.7.
    pub tip_start: f32,
    /// Length of a strand tip's fade, as a fraction of the patch length, in `[0, 1]`.
    /// Default 0.1.
    pub tip_fade: f32,
    /// Amplitude of the specular shift around 0.5, in `[0, 0.5]`. Default 0.15.
    pub shift_amplitude: f32,
    /// Noise level under which the sparkle mask is 0, in `[0, 1)`. Default 0.55.
    pub sparkle_threshold: f32,
}

impl Default for TextureParams {
    fn default() -> Self {
        TextureParams {
            width: 256,
            height: 512,
            seed: 0,
            strands: 48,
            base_color: Vec3::new(0.32, 0.2, 0.11),
            contrast: 0.5,
            edge: 0.2,
            tip_start: 0.7,
            tip_fade: 0.1,
            shift_amplitude: 0.15,
            sparkle_threshold: 0.55,
        }
    }
}

impl TextureParams {
    /// Check the parameters against the ranges documented on each field (sizes `1..=8192`,
    /// strands `1..=width`).
    pub fn validate(&self) -> Result<(), HairError> {
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if !(1..=MAX_SIZE).contains(&v) {
                return Err(HairError::Parameter(format!(
                    "texture {name} must lie in 1..={MAX_SIZE}, got {v}"
                )));
            }
        }
        if !(1..=self.width.max(1)).contains(&self.strands) {
            return Err(HairError::Parameter(format!(
                "texture strands must lie in 1..=width ({}), got {}",
                self.width, self.strands
            )));
        }
        if !(self.base_color.is_finite() && self.base_color.min_element() >= 0.0) {
            return Err(HairError::Parameter(format!(
                "base color {} must be finite and non-negative",
                self.base_color
            )));
        }
        for (name, v, hi) in [
            ("contrast", self.contrast, 1.0),
            ("edge", self.edge, 0.5),
            ("tip start", self.tip_start, 1.0),
            ("tip fade", self.tip_fade, 1.0),
            ("shift amplitude", self.shift_amplitude, 0.5),
        ] {
            if !(0.0..=hi).contains(&v) {
                return Err(HairError::Parameter(format!(
                    "texture {name} must lie in [0, {hi}], got {v}"
                )));
            }
        }
        if !(0.0..1.0).contains(&self.sparkle_threshold) {
            return Err(HairError::Parameter(format!(
                "sparkle threshold must lie in [0, 1), got {}",
                self.sparkle_threshold
            )));
        }
        Ok(())
    }
}

/// The four textures of the patch technique.
#[derive(Clone, Debug, PartialEq)]
pub struct HairTextures {
    /// Base color (RGB).
    pub base: Texture,
    /// Opacity (1 channel).
    pub alpha: Texture,
    /// Specular shift, 0.5 = none (1 channel).
    pub spec_shift: Texture,
    /// Sparkle mask of the secondary highlight (1 channel).
    pub spec_noise: Texture,
}

impl HairTextures {
    /// All four textures (see the module docs).
    pub fn generate(params: &TextureParams) -> Result<Self, HairError> {
        Ok(HairTextures {
            base: base_texture(params)?,
            alpha: alpha_texture(params)?,
            spec_shift: spec_shift_texture(params)?,
            spec_noise: spec_noise_texture(params)?,
        })
    }
}

/// Sub-streams of the seed, one per texture, so that they are independent.
const BASE: u64 = 1;
const ALPHA: u64 = 2;
const SHIFT: u64 = 3;
const SPARKLE: u64 = 4;

/// The base texture: stretched noise times the base color (RGB).
pub fn base_texture(p: &TextureParams) -> Result<Texture, HairError> {
    let noise = Stretched::new(p, BASE, 4);
    fill(p, 3, |uv, out| {
        let n = noise.at(uv);
        let shade = 1.0 - p.contrast + p.contrast * n;
        out.copy_from_slice(&(p.base_color * shade).min(Vec3::ONE).to_array());
    })
}

/// The alpha texture (1 channel; see the module docs).
pub fn alpha_texture(p: &TextureParams) -> Result<Texture, HairError> {
    let strands = p.strands;
    fill(p, 1, |uv, out| {
        let s = ((uv.x * strands as f32) as u32).min(strands - 1);
        let centre = (s as f32 + 0.5) / strands as f32;
        let end = p.tip_start + (1.0 - p.tip_start) * hash01(p.seed, ALPHA, s, 0);
        let tip = if p.tip_fade > 0.0 {
            ((end - uv.y) / p.tip_fade).clamp(0.0, 1.0)
        } else if uv.y <= end {
            1.0
        } else {
            0.0
        };
        // 0 in the middle, 1 at the border.
        let border = if p.edge > 0.0 {
            ((p.edge - centre.min(1.0 - centre)) / p.edge).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let kept = hash01(p.seed, ALPHA, s, 1) >= border;
        let across = if p.edge > 0.0 {
            (uv.x.min(1.0 - uv.x) / p.edge).clamp(0.0, 1.0)
        } else {
            1.0
        };
        out[0] = if kept { tip * across } else { 0.0 };
    })
}

/// The specular shift texture (1 channel, 0.5 = no shift).
pub fn spec_shift_texture(p: &TextureParams) -> Result<Texture, HairError> {
    let noise = Stretched::new(p, SHIFT, 2);
    fill(p, 1, |uv, out| {
        out[0] = (0.5 + p.shift_amplitude * 2.0 * (noise.at(uv) - 0.5)).clamp(0.0, 1.0);
    })
}

/// The specular noise (sparkle mask) texture (1 channel).
pub fn spec_noise_texture(p: &TextureParams) -> Result<Texture, HairError> {
    let noise = Stretched {
        cells: [p.strands.saturating_mul(2), 16],
        ..Stretched::new(p, SPARKLE, 16)
    };
    let t = p.sparkle_threshold;
    fill(p, 1, |uv, out| {
        out[0] = smoothstep(t, 1.0, noise.at(uv));
    })
}

/// A texture of `channels` channels with each texel set by `f(uv, texel)`.
fn fill(
    p: &TextureParams,
    channels: u32,
    f: impl Fn(Vec2, &mut [f32]) + Sync,
) -> Result<Texture, HairError> {
    p.validate()?;
    let (w, h) = (p.width, p.height);
    let mut data = vec![0.0f32; (w * h * channels) as usize];
    data.par_chunks_mut((w * channels) as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, texel) in row.chunks_exact_mut(channels as usize).enumerate() {
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                f(uv, texel);
            }
        });
    Ok(Texture {
        width: w,
        height: h,
        channels,
        data,
    })
}

/// Three octaves of value noise on a lattice `cells` wide and tall (the finest octave's size is
/// `cells`, each coarser octave halves it), periodic in `u`, in `[0, 1]`.
#[derive(Clone, Copy, Debug)]
struct Stretched {
    seed: u64,
    stream: u64,
    cells: [u32; 2],
}

impl Stretched {
    fn new(p: &TextureParams, stream: u64, along: u32) -> Self {
        Stretched {
            seed: p.seed,
            stream,
            cells: [p.strands, along],
        }
    }

    fn at(&self, uv: Vec2) -> f32 {
        let mut sum = 0.0;
        let mut weight = 0.0;
        for octave in 0..3u32 {
            let cells = self.cells.map(|c| (c >> (2 - octave)).max(1));
            let w = 1.0 / (1 << octave) as f32;
            sum += w * self.value(uv, cells, octave);
            weight += w;
        }
        // Averaging octaves narrows the distribution around 0.5; stretch it back.
        (0.5 + (sum / weight - 0.5) * 1.6).clamp(0.0, 1.0)
    }

    fn value(&self, uv: Vec2, cells: [u32; 2], octave: u32) -> f32 {
        let x = uv.x * cells[0] as f32;
        let y = uv.y * cells[1] as f32;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (smooth(x - x0), smooth(y - y0));
        let stream = self.stream * 8 + u64::from(octave);
        let at = |i: f32, j: f32| {
            // Periodic across u; along v the lattice just continues.
            let i = (i as i64).rem_euclid(i64::from(cells[0])) as u32;
            hash01(self.seed, stream, i, j as i64 as u32)
        };
        let top = at(x0, y0) + (at(x0 + 1.0, y0) - at(x0, y0)) * fx;
        let bottom = at(x0, y0 + 1.0) + (at(x0 + 1.0, y0 + 1.0) - at(x0, y0 + 1.0)) * fx;
        top + (bottom - top) * fy
    }
}

fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

fn smoothstep(lo: f32, hi: f32, x: f32) -> f32 {
    smooth(((x - lo) / (hi - lo)).clamp(0.0, 1.0))
}

/// A uniform value in `[0, 1)` for lattice point `(i, j)` of `stream` under `seed`.
fn hash01(seed: u64, stream: u64, i: u32, j: u32) -> f32 {
    let key = (u64::from(i) << 32 | u64::from(j)) ^ stream.wrapping_mul(0xd6e8_feb8_6659_fd93);
    let mut rng = crate::rng::Rng::stream(seed, key);
    rng.f32()
}
