//! Procedural hair: a head and hair styles grown from its scalp.
//!
//! Units are centimetre-like world units; y is up and the face looks toward +z. Every style
//! grows from an ellipsoid ([`head_for`] gives it, so renderers can draw it):
//!
//! - `straight`, `wavy`, `curly`: roots spread uniformly over the scalp ([`Head::sample_scalp`]);
//!   each strand rises from the scalp, is combed over the upper head away from the face and falls
//!   under gravity, sliding over the head where it meets it. Wavy adds a planar sinusoid of
//!   amplitude `curl_radius`, curly a helix of radius `curl_radius`, both with `curl_frequency`
//!   periods per unit of length, around that shape.
//! - `ponytail`: strands run over the scalp to a tie at the back of the head, keeping their
//!   layout (crown hair in the middle of the bundle, hairline hair outside), then a tail of
//!   `length` turns down and spreads. The defaults match the ponytail of Jansson et al. 2019,
//!   Table 1: 136,320 strands, 1,772,160 vertices (13 per strand).
//! - `fur`: a short coat over a whole body ellipsoid, along the surface normal and leaning toward
//!   the back and down.
//!
//! ## Implementation
//!
//! Each strand is built independently, from its own random stream
//! [`Rng::stream`]`(seed, strand index)`, so the result does not depend on how rayon schedules the
//! work: the same parameters give the same asset. The steps, per strand:
//!
//! 1. the style's base shape (module `styles`), `vertices` vertices;
//! 2. clumping: the scalp (or body) coordinate is split into a grid of clumps, each with a centre
//!    strand grown the same way from the middle of its cell; a strand's vertex at fraction `t`
//!    of its length moves toward the same vertex of its clump's centre by
//!    `clumping * (1 - (1 - t)^2)`, so roots stay and tips meet when `clumping` is 1;
//! 3. noise: each vertex moves by a random vector of length up to `noise * t`;
//! 4. collision: every vertex but the root is pushed out of the ellipsoid.
//!
//! Thickness tapers linearly from `thickness` at the root to a tenth of it at the tip. Each
//! strand's UV is its scalp coordinate ([`Head::scalp_point`]) or, for fur, its body coordinate
//! ([`Head::body_point`]).

mod face;
mod head;
mod styles;
#[cfg(test)]
mod tests;

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use rayon::prelude::*;

pub use face::{HeadShape, face_mesh};
pub use head::{Head, ScalpPoint, TriMesh};

use crate::ops::MAX_VERTICES;
use crate::rng::Rng;
use crate::{HairAsset, HairError};
use styles::Grower;

/// The tip's thickness as a fraction of the root's.
const TIP_THICKNESS: f32 = 0.1;
/// Largest accepted length-like parameter (world units): beyond it positions would lose all
/// precision or overflow.
const MAX_LENGTH: f32 = 1e6;
/// Clump centres use random streams from here on, apart from the strands' streams.
const CLUMP_STREAMS: u64 = 1 << 63;

/// A procedural hair style.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Style {
    /// Long straight hair falling around the head.
    Straight,
    /// Long hair with planar waves.
    Wavy,
    /// Helical curls.
    Curly,
    /// Hair gathered at the back of the head into a tail.
    Ponytail,
    /// A short dense coat on a body.
    Fur,
}

impl Style {
    /// Every style, in the order the CLI lists them.
    pub const ALL: [Style; 5] = [
        Style::Straight,
        Style::Wavy,
        Style::Curly,
        Style::Ponytail,
        Style::Fur,
    ];

    /// The style's lowercase name (what [`FromStr`] accepts).
    pub fn name(self) -> &'static str {
        match self {
            Style::Straight => "straight",
            Style::Wavy => "wavy",
            Style::Curly => "curly",
            Style::Ponytail => "ponytail",
            Style::Fur => "fur",
        }
    }

    /// The parameters the style is designed for.
    ///
    /// | style | strands | vertices | length | curl radius, frequency | clumping | noise |
    /// | --- | --- | --- | --- | --- | --- | --- |
    /// | straight | 50,000 | 32 | 30 | 0, 0 | 0.25 | 0.1 |
    /// | wavy | 50,000 | 48 | 30 | 1.0, 0.12 | 0.35 | 0.1 |
    /// | curly | 40,000 | 96 | 22 | 0.8, 0.4 | 0.5 | 0.05 |
    /// | ponytail | 136,320 | 13 | 35 (tail) | 0, 0 | 0.2 | 0.15 |
    /// | fur | 200,000 | 6 | 1.5 | 0, 0 | 0.15 | 0.03 |
    ///
    /// Thickness is 0.007 (70 µm) for head hair and 0.004 for fur; the seed is 0.
    pub fn default_params(self) -> StyleParams {
        let base = StyleParams {
            strands: 50_000,
            vertices: 32,
            length: 30.0,
            curl_radius: 0.0,
            curl_frequency: 0.0,
            clumping: 0.25,
            noise: 0.1,
            seed: 0,
            thickness: 0.007,
        };
        match self {
            Style::Straight => base,
            Style::Wavy => StyleParams {
                vertices: 48,
                curl_radius: 1.0,
                curl_frequency: 0.12,
                clumping: 0.35,
                ..base
            },
            Style::Curly => StyleParams {
                strands: 40_000,
                vertices: 96,
                length: 22.0,
                curl_radius: 0.8,
                curl_frequency: 0.4,
                clumping: 0.5,
                noise: 0.05,
                ..base
            },
            Style::Ponytail => StyleParams {
                strands: 136_320,
                vertices: 13,
                length: 35.0,
                clumping: 0.2,
                noise: 0.15,
                ..base
            },
            Style::Fur => StyleParams {
                strands: 200_000,
                vertices: 6,
                length: 1.5,
                clumping: 0.15,
                noise: 0.03,
                thickness: 0.004,
                ..base
            },
        }
    }
}

impl fmt::Display for Style {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Style {
    type Err = HairError;

    /// A style from its lowercase name (`straight`, `wavy`, `curly`, `ponytail`, `fur`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Style::ALL
            .into_iter()
            .find(|style| style.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Style::ALL.iter().map(|s| s.name()).collect();
                HairError::Parameter(format!(
                    "unknown hair style '{s}' (expected one of: {})",
                    names.join(", ")
                ))
            })
    }
}

/// Parameters of a generated style (world units are centimetre-like).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StyleParams {
    /// Number of strands (at least 1).
    pub strands: u32,
    /// Vertices per strand (at least 2).
    pub vertices: u32,
    /// Strand length; for wavy and curly hair, the length of the axis the curl winds around;
    /// for the ponytail, the length of the tail below the tie.
    pub length: f32,
    /// Wavy: wave amplitude; curly (and a ponytail's tail): helix radius. Straight hair and fur
    /// ignore it.
    pub curl_radius: f32,
    /// Waves or turns per unit of length.
    pub curl_frequency: f32,
    /// How far strands are pulled toward their clump's centre, from 0 (not at all) to 1 (tips
    /// meet).
    pub clumping: f32,
    /// Largest random displacement of a vertex, reached at the tip (0 at the root).
    pub noise: f32,
    /// Random seed: the same parameters and seed give the same asset.
    pub seed: u64,
    /// Strand diameter at the root; it tapers to a tenth of it at the tip.
    pub thickness: f32,
}

impl StyleParams {
    /// Check the parameters: at least one strand of at least two vertices, at most 2^31 vertices
    /// in all, lengths finite, non-negative and at most 10^6, clumping in `[0, 1]`.
    pub fn validate(&self) -> Result<(), HairError> {
        if self.strands == 0 {
            return Err(HairError::Parameter(
                "a style needs at least one strand".into(),
            ));
        }
        if self.vertices < 2 {
            return Err(HairError::Parameter(format!(
                "strands need at least 2 vertices, got {}",
                self.vertices
            )));
        }
        let total = u64::from(self.strands) * u64::from(self.vertices);
        if total > MAX_VERTICES {
            return Err(HairError::Parameter(format!(
                "{} strands of {} vertices is {total} vertices, more than 2^31",
                self.strands, self.vertices
            )));
        }
        for (name, value) in [
            ("length", self.length),
            ("curl radius", self.curl_radius),
            ("curl frequency", self.curl_frequency),
            ("noise", self.noise),
            ("thickness", self.thickness),
        ] {
            if !(value.is_finite() && (0.0..=MAX_LENGTH).contains(&value)) {
                return Err(HairError::Parameter(format!(
                    "{name} must be finite, non-negative and at most {MAX_LENGTH}, got {value}"
                )));
            }
        }
        if !(0.0..=1.0).contains(&self.clumping) {
            return Err(HairError::Parameter(format!(
                "clumping must lie in [0, 1], got {}",
                self.clumping
            )));
        }
        Ok(())
    }
}

/// The ellipsoid a style grows from: the default [`Head`] for head hair, a body (radii 12, 10
/// and 20, long along z) for fur.
pub fn head_for(style: Style) -> Head {
    match style {
        Style::Fur => Head {
            center: Vec3::ZERO,
            radii: Vec3::new(12.0, 10.0, 20.0),
        },
        _ => Head::default(),
    }
}

/// What a style's head is drawn as: the bare ellipsoid for fur, a face and a neck on it for
/// head hair.
pub fn shape_for(style: Style) -> HeadShape {
    match style {
        Style::Fur => HeadShape::Ellipsoid,
        _ => HeadShape::Face,
    }
}

/// Generate a hair asset of `style` (see the module docs for the shapes). The parameters are
/// validated before anything is allocated.
pub fn generate(style: Style, params: &StyleParams) -> Result<HairAsset, HairError> {
    params.validate()?;
    let n = params.vertices as usize;
    let strands = params.strands as usize;
    let total = strands * n;
    let grower = Grower::new(style, params);

    let clumps = if params.clumping > 0.0 {
        let mut clumps = vec![Vec3::ZERO; grower.clump_count() * n];
        clumps
            .par_chunks_mut(n)
            .enumerate()
            .for_each(|(cell, out)| {
                let mut rng = Rng::stream(params.seed, CLUMP_STREAMS | cell as u64);
                let root = grower.clump_root(cell, &mut rng);
                grower.grow(&root, out);
            });
        clumps
    } else {
        Vec::new()
    };

    let mut positions = zeroed(total)?;
    let mut uvs = zeroed(strands)?;
    positions
        .par_chunks_mut(n)
        .zip(uvs.par_iter_mut())
        .enumerate()
        .for_each(|(i, (out, uv))| {
            let mut rng = Rng::stream(params.seed, i as u64);
            let root = grower.sample_root(&mut rng);
            grower.grow(&root, out);
            if !clumps.is_empty() {
                let cell = grower.clump_of(root.scalp.uv);
                clump(out, &clumps[cell * n..(cell + 1) * n], params.clumping);
            }
            if params.noise > 0.0 {
                jitter(out, params.noise, &mut rng);
            }
            grower.collide(out);
            *uv = root.scalp.uv;
        });

    let taper: Vec<f32> = (0..n)
        .map(|i| params.thickness * (1.0 - (1.0 - TIP_THICKNESS) * i as f32 / (n - 1) as f32))
        .collect();
    let mut thickness = zeroed(total)?;
    thickness
        .par_chunks_mut(n)
        .for_each(|c| c.copy_from_slice(&taper));

    let offsets: Vec<u32> = (0..=strands).map(|i| (i * n) as u32).collect();
    HairAsset::from_offsets(positions, offsets)?
        .with_thickness(thickness)?
        .with_strand_uv(uvs)
}

/// A vector of `len` default values, or an error if the memory cannot be had.
fn zeroed<T: Clone + Default>(len: usize) -> Result<Vec<T>, HairError> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|e| HairError::Parameter(format!("cannot allocate {len} elements: {e}")))?;
    v.resize(len, T::default());
    Ok(v)
}

/// Pull `strand` toward `centre` (same vertex count), more toward the tip.
fn clump(strand: &mut [Vec3], centre: &[Vec3], clumping: f32) {
    let last = (strand.len() - 1) as f32;
    for (i, (p, c)) in strand.iter_mut().zip(centre).enumerate() {
        let t = 1.0 - i as f32 / last;
        *p = p.lerp(*c, clumping * (1.0 - t * t));
    }
}

/// Move each vertex by a random vector of length up to `noise * t` (`t` the fraction of the
/// strand from the root).
fn jitter(strand: &mut [Vec3], noise: f32, rng: &mut Rng) {
    let last = (strand.len() - 1) as f32;
    for (i, p) in strand.iter_mut().enumerate().skip(1) {
        *p += rng.on_sphere() * (rng.f32() * noise * i as f32 / last);
    }
}
