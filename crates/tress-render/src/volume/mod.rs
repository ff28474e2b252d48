//! The volume approximation of Jansson et al. 2019 (`volume`): strands voxelized every frame into
//! a density and a tangent volume, raymarched to an isosurface shaded with the strands'
//! Kajiya-Kay, with volume shadows and local ambient occlusion that the strand rasterizer can use
//! too.
//!
//! # Implementation
//!
//! Passes, in frame order (see `hybrid/renderer.rs`), all recorded by the [`Voxelizer`] except the last:
//! [`VolumeBounds`] (`volume_bounds.wgsl`), [`Voxelize`] (`voxelize.wgsl`), [`VolumeResolve`]
//! (`volume_resolve.wgsl`), then [`Raymarch`] (`raymarch.wgsl`). The CPU reference of the
//! voxelizer is `tress_shading::voxelize`, the shading twins are `tress_shading::volume` (their
//! docs hold the formulas); `shaders/common/volume.wgsl` has the WGSL twins.
//!
//! - **Proxy geometry (§3.3 "Surface").** The AABB of the hair is built on the GPU from every
//!   vertex (`atomicMin`/`atomicMax` on order-preserving integer keys of the floats, so it is the
//!   exact box), then one invocation fits the grid: `resolution³` cubic voxels, the box's longest
//!   side spanning `resolution - 4` of them, centred (two empty voxels on every side). Nothing is
//!   precomputed, so animated hair works: the grid follows the hair every frame.
//! - **Strand voxelization (§3.3).** Atomic counters in storage buffers: one `u32` count per
//!   voxel and the quantized tangents (`[-1, 1]` to `[0, 255]` per channel) summed into two more
//!   `u32` words (x and y in 16 bits each, z). `voxelize = "vertices"` is the paper's
//!   one-count-per-vertex scheme, whose gaps (§4.2) the resolve covers with a box reconstruction
//!   filter (`reconstruction_radius`, weighted by the mean segment length in voxels so the unit
//!   stays "strand length per voxel"). `voxelize = "segments"` (the default) samples every
//!   segment at voxel frequency, the remedy §4.2 suggests; it is the default because it leaves no
//!   gaps whatever the segment length or resolution, needs no filter (so it keeps the detail the
//!   filter blurs away), and counts a strand crossing a voxel about once, which is the density the
//!   paper means. Positions go to fixed point once and the rest is integer arithmetic, so the GPU
//!   matches the CPU reference exactly. Counters are capacity-checked (`max_strands_per_voxel`,
//!   default 255: the paper's 8-bit counter): a sample finding the counter full is dropped and
//!   counted (design rule 8), see [`VolumeStats`].
//! - **Resolve.** One invocation per voxel divides the tangent sums by the count, de-quantizes
//!   (§3.3, Figure 4) and writes `rgba8unorm` texels — rgb the mean tangent, a the count — into
//!   a 3D texture that everything downstream filters trilinearly (`volume_sample`: the eight
//!   texels decoded, then blended). It also marks an occupancy volume
//!   of `8³`-voxel blocks (each non-empty voxel marks the blocks within one voxel of it, the
//!   trilinear footprint). It runs only over the voxels the hair's box touches (grown by the
//!   filter radius) and last frame's box, which it zeroes: the bounds pass writes that region as
//!   an indirect dispatch, so the cost follows the hair's extent rather than `resolution³`, and
//!   every texel outside the box holds zero (a test moves the hair and compares with a fresh
//!   voxelizer).
//! - **Raymarch (§3.3 "Surface", "Shading").** The AABB's back faces are rasterized (so the camera
//!   may be inside the box); each fragment intersects its eye ray with the box and marches
//!   `steps` constant steps (default 512, the paper's) across the box diagonal, accumulating
//!   `density · step` strands, each weighed by its tip fade (below), until the hair's
//!   transmittance falls to 1/256: the solid surface. Under the default `opacity = "strands"`
//!   ([`Opacity`]) every strand met is one of the rasterizer's lines: the transmittance is
//!   `exp(-Σ strands · |t × dir| · pixel · w)`, `pixel` the voxels a pixel spans at that depth
//!   and `w` the line's optical width in pixels from the strands' `width_px`, `alpha` and
//!   coverage (`tress_shading::line_optical_width`), so the volume is as opaque as the strands'
//!   composite at every distance (a pixel farther away covers more strands). Under the paper's
//!   `opacity = "iso"` it falls as `256^(-strands / iso)`, the same at every distance. The
//!   colour is the mean of the shading at `shade_samples` points
//!   (default 4), where the transmittance falls through the middles of equal shares of the
//!   composite's weight: the depth the rasterizer's composite of the same strands reaches, not
//!   the paper's one point at the surface (`shade_samples = 1` shades where half the weight is
//!   reached). A ray that never gets to the surface but met hair has the opacity
//!   `1 - transmittance` (fake transparency) and is shaded at the points it reached (its first
//!   non-empty sample when none). The march stops at the scene depth (the head).
//! - **Tip fade.** Under `strands.thickness_fade = "tip"` the rasterizer fades a strand's alpha
//!   with its thickness, so the tips of tapered hair are nearly transparent and the composite
//!   reaches deep into fur. The voxelizer weighs each sample's tangent by its segment's thickness
//!   over the asset's thickest (`tress_shading::segment_fade`), so the mean tangent's length is
//!   the voxel's mean fade (times the strands' coherence), and the raymarcher weighs the density
//!   with that length. Measured on the generated bear (`tress compare scenes/bear.toml --width
//!   640 --height 360`): without the fade the volume's surface sits in the faded tips and is far
//!   lighter than the strands.
//!   Shading is the strands' model from `shading.wgsl` (Kajiya-Kay; Scheuermann with the normal)
//!   with the mean tangent of the volume, normal `-∇density`, base color from the material (the
//!   volume carries no vertex colors).
//! - **Integrated highlights** (beyond the paper; `highlights = "strands"`, the default, under
//!   Kajiya-Kay: [`Highlights`]). The lobe of the mean tangent is not the mean of the strands'
//!   lobes: Kajiya-Kay's specular is narrow (exponent 80) and a voxel's strands run in slightly
//!   different directions, so the paper's raymarcher put the ponytail's highlight arcs beside the
//!   strands' (measured: hair FLIP 0.113 at the scene's distance). The voxelizer knows the frame's
//!   view and lights, so it sums every sample's specular term per light next to its tangent
//!   (quantized to 8 bits, two lights to a `u32`, zero adds skipped); the resolve writes each
//!   light's mean into a second `rgba8unorm` texture, and the raymarcher shades the specular
//!   with their density-weighted trilinear mean (`volume_highlight`) and the diffuse with the
//!   mean tangent. The ponytail's hair FLIP falls to 0.083 (`tress_shading::highlights`). `skip_empty = true` jumps over empty occupancy blocks to the
//!   next sample on the same lattice, so the image is the same as without skipping (a test checks
//!   it); off is the paper.
//! - **Volume shadows (§3.4).** A march from the point towards the light (`shadow_step` voxels,
//!   starting `shadow_offset` voxels out) sums `density · step`, the strands the ray passes; a
//!   strand passing through a voxel is *in the way* of a ray through it with probability
//!   `strand_width / voxel_size`, so `n = Σ density · step · strand_width / voxel_size` (which no
//!   longer depends on the resolution) and `(1 - shadow_alpha)^n` replaces ADSM's
//!   `(1 - alpha)^(d·r)`. The paper plugs the count in directly; without the width factor a dense
//!   voxel of a few hundred strands would black out everything behind it. The default width,
//!   0.002 world units (20 µm in the centimetre-like units of the generators), makes the demo
//!   ponytail's volume shadows about as deep as ADSM's default `r = 4` per unit. The rasterizer uses it with
//!   `strands.shadow_mode = "volume"` (then no shadow maps are rendered), the head too. That is
//!   `occlusion = "strands"`. The default, `occlusion = "adsm"` ([`Occlusion`]), gives shadows
//!   ADSM's model with the strands' `shadow_r`, `shadow_alpha` and `shadow_bias`: ADSM darkens a
//!   point by `(1 - alpha)^(r · (d - bias))`, `d` its distance behind the first strand the light's
//!   depth map holds, and the volume takes the expectation of that over where the first strand
//!   lies (`volume_adsm_visibility` in `common/volume.wgsl`): marching out towards the light, a
//!   step holds a strand of a shadow-map line (`strands.shadow_width_px` texels of the light's
//!   map, in world units) with probability `1 - exp(-density · step · width)`, a farther one
//!   replacing a nearer. So sparse fuzz casts little, gaps between strands count as ADSM counts
//!   them, and the shadow no longer depends on where the surface point sits in a voxel (the
//!   earlier `min(density, 1)` path length gave blotchy shadows on fur and too dark ones on the
//!   ponytail).
//! - **Local ambient occlusion (§3.4).** The mean density at `ao_samples` points spread through a
//!   ball of `ao_radius` (world units) around the point, times the radius, is the number of
//!   strands an average ray passes; with the same width factor and `ao_intensity`,
//!   `(1 - shadow_alpha)^n` multiplies the hair's shaded color (with `occlusion = "adsm"`, ADSM's
//!   `r` per unit of the ball inside the hair). The raymarcher uses it with `ao = true`, the
//!   rasterizer with `strands.ao = true`; both are off by default and agree only when both are on.
//!   By default (`ao_texel = 1`) it is baked after each voxelization at every voxel a point on a
//!   strand can read (`ao_bake.wgsl`) and read with one filtered lookup; `ao_texel = 0` evaluates
//!   the samples at every shaded point, as the paper does.
//!
//! Memory: `5 · 4` bytes of counters (the voxelization's scratch: the count, two tangent words,
//! two highlight words) and `2 · 4` bytes of texture per voxel (the resident volume the frame
//! samples: 128 MiB at the default `256³`, the paper's reference keeps 5 bytes; 448 MiB in all);
//! each counter buffer must fit the device's storage-binding limit (the highlight sums, 8 bytes a
//! voxel, set it: 128 MiB on lavapipe, at most `256³`). The tangent texture is `rgba8unorm`
//! (`tress_shading::voxelize::encode_texel`): the mean tangent in 127 levels a unit, exact zero,
//! and the count as it is (the segments mode's counters hold at most 255, the paper's 8-bit
//! counter), so the density the raymarcher reads is the count the resolve wrote. In the vertices
//! mode the texel holds the filter box's summed count, at most 255 (a mean of 9.4 per voxel of a
//! `3³` box): a box summing more is clamped and counted ([`VolumeStats::saturated`]).

/// `name()`, `FromStr` and `Display` of a `volume.*` setting's enum from its spellings: an
/// unknown spelling is an error naming the key, the value and the choices.
macro_rules! named_setting {
    ($ty:ident, $key:literal, { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// The setting's spelling.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }

        impl std::str::FromStr for $ty {
            type Err = crate::RenderError;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                match s {
                    $($name => Ok($ty::$variant),)+
                    _ => Err(crate::RenderError::Invalid(format!(
                        "unknown {} `{s}` (expected {})",
                        $key,
                        [$($name),+].join(" or ")
                    ))),
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

mod ao_bake;
mod highlights;
mod occlusion;
mod opacity;
pub(crate) mod raymarch;
mod volume_bounds;
mod volume_resolve;
mod voxelize;
mod voxelizer;

use std::fmt;
use std::str::FromStr;

pub use ao_bake::{AO_FORMAT, AoBake, ao_resolution};
pub use highlights::Highlights;
pub use occlusion::Occlusion;
pub use opacity::Opacity;
pub use raymarch::Raymarch;
pub use tress_shading::VoxelizeMode;
pub use volume_bounds::VolumeBounds;
pub(crate) use volume_bounds::dispatch_2d;
pub use volume_resolve::{VOLUME_FORMAT, VolumeResolve};
pub use voxelize::Voxelize;
pub use voxelizer::{VolumeReadback, Voxelizer};

use crate::gpu::types::{VolumeGrid, VolumeParams};
use crate::{GpuContext, RenderError};

/// The largest `volume.ao_texel`.
pub const MAX_AO_TEXEL: u32 = 8;

/// Edge of an occupancy block in voxels (`OCCUPANCY_BLOCK` in `common/volume.wgsl`).
pub const OCCUPANCY_BLOCK: u32 = 8;

/// Most points the raymarcher shades per pixel (`MAX_SHADE_SAMPLES` in `common/volume.wgsl`).
pub const MAX_SHADE_SAMPLES: u32 = 8;

/// Where the strand rasterizer (and the head) gets its self-shadowing from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowMode {
    /// Approximated deep shadow maps, `(1 - alpha)^(d·r)` (§3.4), `"adsm"`.
    #[default]
    Adsm,
    /// Strands counted through the density volume towards the light (§3.4), `"volume"`.
    Volume,
}

impl ShadowMode {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            ShadowMode::Adsm => "adsm",
            ShadowMode::Volume => "volume",
        }
    }
}

impl FromStr for ShadowMode {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "adsm" => Ok(ShadowMode::Adsm),
            "volume" => Ok(ShadowMode::Volume),
            _ => Err(RenderError::Invalid(format!(
                "unknown shadow_mode `{s}` (expected adsm or volume)"
            ))),
        }
    }
}

impl fmt::Display for ShadowMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Parse a voxelization mode setting (`"vertices"` or `"segments"`).
pub fn parse_voxelize_mode(s: &str) -> Result<VoxelizeMode, RenderError> {
    match s {
        "vertices" => Ok(VoxelizeMode::Vertices),
        "segments" => Ok(VoxelizeMode::Segments),
        _ => Err(RenderError::Invalid(format!(
            "unknown voxelize mode `{s}` (expected vertices or segments)"
        ))),
    }
}

/// The setting's spelling of a voxelization mode.
pub fn voxelize_mode_name(mode: VoxelizeMode) -> &'static str {
    match mode {
        VoxelizeMode::Vertices => "vertices",
        VoxelizeMode::Segments => "segments",
    }
}

/// The grid resolutions a character gets under `volume.screen_resolution`, about √2 apart and
/// whole 8-voxel occupancy blocks ([`VolumeSettings::object_resolution`]).
pub const RESOLUTION_STEPS: [u32; 11] = [32, 48, 64, 96, 128, 192, 256, 384, 512, 768, 1024];

/// Settings of the volume technique (`[volume]`). Every parameter the paper names is here.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeSettings {
    /// Voxels per axis of the grid (the paper: 256); with `screen_resolution`, the most a
    /// character gets.
    pub resolution: u32,
    /// Size each voxelized character's grid by its size on screen: `voxels_per_px` voxels a
    /// pixel across its bounding sphere, up to the next of [`RESOLUTION_STEPS`] and clamped to
    /// `min_resolution..=resolution` ([`VolumeSettings::object_resolution`]), so a far
    /// character costs kilobytes, not a full `resolution³` (default on; off: every character
    /// at `resolution`, the paper's fixed grid). A character whose volume gives ambient
    /// occlusion (`ao`, or the strands' `ao`) keeps `resolution` (the renderer decides).
    pub screen_resolution: bool,
    /// The fewest voxels per axis a character's grid gets under `screen_resolution` (at most
    /// `resolution` is used).
    pub min_resolution: u32,
    /// Under `screen_resolution`: voxels across a character per pixel of its size on screen
    /// (default 2: at one a pixel the fur scene's volume at 3× its distance scores FLIP 0.112
    /// against the strands over the hair, at two 0.058, as the fixed 128³ grid's 0.058).
    pub voxels_per_px: f32,
    /// How strands are deposited (default segments; see the module docs).
    pub voxelize: VoxelizeMode,
    /// Radius in voxels of the vertices mode's reconstruction box filter, `0..=3`.
    pub reconstruction_radius: u32,
    /// Capacity of a voxel's counter, `1..=255` (the paper's 8-bit counter: 255).
    pub max_strands_per_voxel: u32,
    /// Raymarching steps across the box diagonal (the paper: 512).
    pub steps: u32,
    /// How the strands along an eye ray make the hair opaque ([`Opacity`]): as the strand
    /// rasterizer's lines (default), or the paper's `iso` count.
    pub opacity: Opacity,
    /// Under `opacity = "iso"`: strands along a ray to a solid isosurface, each weighed by its
    /// tip fade: the hair's transmittance falls as `256^(-strands / iso)`, to 1/256 there
    /// (default 48: where the rasterizer's composite of the same strands is as deep at the fur
    /// and ponytail scenes' own distance; measured by `tress compare`).
    pub iso: f32,
    /// Where the Kajiya-Kay highlights come from ([`Highlights`]): the strands' own, integrated
    /// per voxel (default), or the paper's mean tangent.
    pub highlights: Highlights,
    /// Points shaded per pixel, `1..=8`: each at the middle of an equal share of the composite's
    /// weight along the ray (default 4; 1 shades where half the weight is reached).
    pub shade_samples: u32,
    /// Jump over empty blocks of the occupancy volume (off: the paper).
    pub skip_empty: bool,
    /// Volume shadows in the raymarcher.
    pub shadows: bool,
    /// How shadows and ambient occlusion count the strands in the way (default ADSM's model,
    /// with the strands' `shadow_r` and `shadow_alpha`).
    pub occlusion: Occlusion,
    /// Opacity of one occluding strand in volume shadows and ambient occlusion
    /// (`occlusion = "strands"`; ADSM's model uses `strands.shadow_alpha`).
    pub shadow_alpha: f32,
    /// Step of the shadow march in voxels.
    pub shadow_step: f32,
    /// Start of the shadow march in voxels from the point (skips its own strands).
    pub shadow_offset: f32,
    /// Effective strand width in world units (`occlusion = "strands"`): a strand crossing a voxel blocks a ray through it
    /// with probability `strand_width / voxel_size`, which turns the strands a shadow or AO ray
    /// passes into the strands in its way (and makes both independent of the resolution).
    pub strand_width: f32,
    /// Local ambient occlusion in the raymarcher (off by default, as the strands' `ao`: the two
    /// techniques agree only with both on or both off).
    pub ao: bool,
    /// Radius of the ambient-occlusion ball in world units.
    pub ao_radius: f32,
    /// Ambient-occlusion samples, `1..=64`.
    pub ao_samples: u32,
    /// Multiplier of the occluding strand count (the paper's tweak towards a ray tracer).
    pub ao_intensity: f32,
    /// Voxels per axis of a texel of the ambient-occlusion texture baked after each
    /// voxelization while something reads AO (`ao` or `strands.ao`): every shaded point then
    /// reads local AO with one filtered lookup instead of `ao_samples` trilinear density
    /// samples. 1 (the default) bakes every voxel, 2 every other one (an eighth of the bake and
    /// its memory, coarser AO), 0 evaluates the samples at every shaded point (the paper's).
    pub ao_texel: u32,
    /// GPU memory the volumes of one frame may take, MiB: the shared voxel counters and every
    /// head of hair's own volume (textures and occupancy, about 8 bytes a voxel). A head of hair
    /// whose volume would not fit is drawn as strands instead, with a warning (default 4096:
    /// the counters and 29 volumes at 256³, as many as 2048 held before the highlight texture).
    pub budget_mib: u32,
}

impl Default for VolumeSettings {
    fn default() -> Self {
        VolumeSettings {
            resolution: 256,
            screen_resolution: true,
            min_resolution: 32,
            voxels_per_px: 2.0,
            voxelize: VoxelizeMode::Segments,
            reconstruction_radius: 1,
            max_strands_per_voxel: 255,
            steps: 512,
            opacity: Opacity::Strands,
            iso: 48.0,
            shade_samples: 4,
            highlights: Highlights::Strands,
            skip_empty: false,
            shadows: true,
            occlusion: Occlusion::Adsm,
            shadow_alpha: 0.25,
            shadow_step: 1.0,
            shadow_offset: 1.0,
            strand_width: 0.002,
            ao: false,
            ao_radius: 1.0,
            ao_samples: 16,
            ao_intensity: 1.0,
            ao_texel: 1,
            budget_mib: 4096,
        }
    }
}

impl VolumeSettings {
    /// Check every setting's range; the error names the setting.
    pub fn validate(&self) -> Result<(), RenderError> {
        let bad = |name: &str, why: &str| Err(RenderError::Invalid(format!("volume.{name} {why}")));
        let (lo, hi) = (
            tress_shading::voxelize::MIN_RESOLUTION,
            tress_shading::voxelize::MAX_RESOLUTION,
        );
        if !(lo..=hi).contains(&self.resolution) {
            return bad("resolution", &format!("must be in {lo}..={hi}"));
        }
        if !(lo..=hi).contains(&self.min_resolution) {
            return bad("min_resolution", &format!("must be in {lo}..={hi}"));
        }
        if !(self.voxels_per_px > 0.0 && self.voxels_per_px <= 16.0) {
            return bad("voxels_per_px", "must be in (0, 16]");
        }
        if self.reconstruction_radius > 3 {
            return bad("reconstruction_radius", "must be in 0..=3");
        }
        let cap = tress_shading::voxelize::MAX_CAPACITY;
        if !(1..=cap).contains(&self.max_strands_per_voxel) {
            return bad("max_strands_per_voxel", &format!("must be in 1..={cap}"));
        }
        if !(1..=8192).contains(&self.steps) {
            return bad("steps", "must be in 1..=8192");
        }
        if !(self.iso > 0.0 && self.iso.is_finite()) {
            return bad("iso", "must be positive and finite");
        }
        if !(1..=MAX_SHADE_SAMPLES).contains(&self.shade_samples) {
            return bad(
                "shade_samples",
                &format!("must be in 1..={MAX_SHADE_SAMPLES}"),
            );
        }
        if !(0.0..=1.0).contains(&self.shadow_alpha) {
            return bad("shadow_alpha", "must be in [0, 1]");
        }
        if !(self.shadow_step >= 0.25 && self.shadow_step <= 64.0) {
            return bad("shadow_step", "must be in [0.25, 64] voxels");
        }
        if !(self.shadow_offset >= 0.0 && self.shadow_offset <= 64.0) {
            return bad("shadow_offset", "must be in [0, 64] voxels");
        }
        if !(self.strand_width >= 0.0 && self.strand_width.is_finite()) {
            return bad("strand_width", "must be finite and non-negative");
        }
        if !(self.ao_radius > 0.0 && self.ao_radius.is_finite()) {
            return bad("ao_radius", "must be positive and finite");
        }
        if !(1..=tress_shading::volume::MAX_AO_SAMPLES).contains(&self.ao_samples) {
            return bad("ao_samples", "must be in 1..=64");
        }
        if !(self.ao_intensity >= 0.0 && self.ao_intensity.is_finite()) {
            return bad("ao_intensity", "must be finite and non-negative");
        }
        if self.ao_texel > MAX_AO_TEXEL {
            return bad("ao_texel", "must be in 0..=8");
        }
        if self.budget_mib == 0 {
            return bad("budget_mib", "must be positive");
        }
        Ok(())
    }

    /// The voxels per axis of a character `size_px` pixels across on screen (its bounding
    /// sphere's diameter): `resolution` without `screen_resolution`, else the smallest of
    /// [`RESOLUTION_STEPS`] at least `voxels_per_px × size_px`, clamped to
    /// `min_resolution..=resolution` (the minimum lowered to `resolution` when above it).
    ///
    /// The steps are about √2 apart: any change of a grid's resolution re-aligns its voxels
    /// with the strands and changes the raymarched image's pixel texture (its mean colour stays),
    /// so a character moving from far to near changes resolution a few times, not every 8
    /// pixels.
    pub fn object_resolution(&self, size_px: f32) -> u32 {
        if !self.screen_resolution {
            return self.resolution;
        }
        let px = if size_px.is_finite() {
            (size_px * self.voxels_per_px).clamp(0.0, self.resolution as f32)
        } else {
            self.resolution as f32
        };
        let step = RESOLUTION_STEPS
            .iter()
            .copied()
            .find(|&r| r as f32 >= px)
            .unwrap_or(self.resolution);
        step.clamp(self.min_resolution.min(self.resolution), self.resolution)
    }

    /// Bytes of counters, texture and occupancy a grid of this resolution takes.
    pub fn bytes(&self) -> u64 {
        self.counter_bytes() + self.resident_bytes()
    }

    /// Bytes of what the frame keeps after the voxelization: the two textures (tangent and
    /// density, highlights: 8 bytes a voxel) and the occupancy blocks; [`VolumeSettings::ao_bytes`]
    /// more while something reads the baked AO.
    pub fn resident_bytes(&self) -> u64 {
        let voxels = u64::from(self.resolution).pow(3);
        let blocks = u64::from(self.resolution.div_ceil(OCCUPANCY_BLOCK)).pow(3);
        voxels * 8 + blocks * 4
    }

    /// Bytes of the baked ambient-occlusion texture (4 a texel of `ao_texel³` voxels) of a
    /// volume whose AO is read (`reads_ao`); 0 when nothing reads it or `ao_texel` is 0.
    pub fn ao_bytes(&self, reads_ao: bool) -> u64 {
        match (reads_ao, self.ao_texel) {
            (false, _) | (_, 0) => 0,
            (true, t) => u64::from(ao_resolution(self.resolution, t)).pow(3) * 4,
        }
    }

    /// Bytes of the voxelization's scratch: the count, the two tangent-sum words and the two
    /// highlight-sum words a voxel.
    pub fn counter_bytes(&self) -> u64 {
        u64::from(self.resolution).pow(3) * 5 * 4
    }
}

/// The volume resources bound in the lighting group (`common/lighting.wgsl` bindings 6 to 10).
#[derive(Clone, Copy, Debug)]
pub(crate) struct VolumeBinding<'a> {
    pub(crate) view: &'a wgpu::TextureView,
    /// The baked ambient occlusion (`volume.ao_baked`).
    pub(crate) ao_view: &'a wgpu::TextureView,
    pub(crate) sampler: &'a wgpu::Sampler,
    pub(crate) grid: &'a wgpu::Buffer,
    pub(crate) params: &'a wgpu::Buffer,
}

/// The renderer's volume resources that exist without a voxelizer: the [`VolumeParams`] uniform,
/// the linear clamp-to-edge sampler, and an empty `1³` volume with its (unoccupied) grid.
pub(crate) fn volume_resources(
    ctx: &GpuContext,
) -> Result<
    (
        wgpu::Buffer,
        wgpu::Sampler,
        (wgpu::TextureView, wgpu::Buffer),
    ),
    RenderError,
> {
    use wgpu::util::DeviceExt;
    ctx.scoped("creating the volume bindings", || {
        let params = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("volume/params"),
                contents: bytemuck::bytes_of(&VolumeParams::default()),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
        let sampler = ctx.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("volume/sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("volume/empty/texture"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: volume_resolve::VOLUME_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let grid = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("volume/empty/grid"),
                contents: bytemuck::bytes_of(&VolumeGrid {
                    res: 1,
                    scale: 1.0,
                    voxel_size: 1.0,
                    ..Default::default()
                }),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        (
            params,
            sampler,
            (texture.create_view(&Default::default()), grid),
        )
    })
}

/// What the voxelizer reported about one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VolumeStats {
    /// Samples deposited into the counters (accepted and dropped).
    pub deposits: u32,
    /// Samples dropped because their voxel's counter was at the capacity.
    pub dropped: u32,
    /// Voxels whose reconstruction filter summed more counts than a texel holds (255; vertices
    /// mode only), clamped.
    pub saturated: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_characters_resolution_follows_its_size_on_screen() {
        // The default: two voxels a pixel across the character.
        let two = VolumeSettings::default();
        assert_eq!(two.object_resolution(40.0), 96);
        assert_eq!(two.object_resolution(48.0), 96);
        assert_eq!(two.object_resolution(48.5), 128);
        let s = VolumeSettings {
            voxels_per_px: 1.0,
            ..VolumeSettings::default()
        };
        // A voxel a pixel: the next step up, steps about √2 apart in whole 8-voxel blocks.
        assert_eq!(s.object_resolution(100.0), 128);
        assert_eq!(s.object_resolution(96.0), 96);
        assert_eq!(s.object_resolution(96.5), 128);
        assert_eq!(s.object_resolution(40.0), 48);
        for pair in RESOLUTION_STEPS.windows(2) {
            let ratio = pair[1] as f32 / pair[0] as f32;
            assert!(
                (1.3..=1.55).contains(&ratio) && pair[0] % 8 == 0,
                "{pair:?}"
            );
        }
        // Clamped to the minimum (a far character) and to `resolution` (a near one).
        assert_eq!(s.object_resolution(3.0), 32);
        assert_eq!(s.object_resolution(0.0), 32);
        assert_eq!(s.object_resolution(900.0), 256);
        assert_eq!(s.object_resolution(f32::INFINITY), 256);
        assert_eq!(s.object_resolution(f32::NAN), 256);
        // A 32-voxel character keeps about 256 KiB (8 bytes a voxel and its blocks), a
        // full-resolution one 128 MiB.
        let far = VolumeSettings {
            resolution: s.object_resolution(20.0),
            ..s.clone()
        };
        assert_eq!(far.resident_bytes(), 32 * 32 * 32 * 8 + 4 * 4 * 4 * 4);
        // Off: the paper's fixed grid; a minimum above `resolution` gives way to it.
        let fixed = VolumeSettings {
            screen_resolution: false,
            ..s.clone()
        };
        assert_eq!(fixed.object_resolution(3.0), 256);
        let small = VolumeSettings {
            resolution: 24,
            ..s.clone()
        };
        assert_eq!(small.object_resolution(3.0), 24);
        assert!(small.validate().is_ok());
        let bad = VolumeSettings {
            min_resolution: 4,
            ..s.clone()
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("volume.min_resolution")
        );
        let bad = VolumeSettings {
            voxels_per_px: 0.0,
            ..s
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("volume.voxels_per_px")
        );
    }

    #[test]
    fn defaults_are_the_papers_and_valid() {
        let s = VolumeSettings::default();
        s.validate().expect("valid");
        assert_eq!(
            (s.resolution, s.steps, s.max_strands_per_voxel),
            (256, 512, 255)
        );
        assert_eq!(s.voxelize, VoxelizeMode::Segments);
        assert!(!s.skip_empty);
        // 256³: 3 counter buffers of 64 MiB and the highlight sums' 128 MiB (each inside
        // lavapipe's 128 MiB binding) + two textures of 4 bytes a voxel (64 MiB each) + the
        // occupancy blocks.
        assert_eq!(s.counter_bytes(), 5 << 26);
        assert_eq!(s.resident_bytes(), (2 << 26) + 32u64.pow(3) * 4);
        assert_eq!(s.highlights, Highlights::Strands);
        assert_eq!(s.bytes(), s.counter_bytes() + s.resident_bytes());
    }

    #[test]
    fn out_of_range_settings_name_themselves() {
        let cases = [
            (
                VolumeSettings {
                    resolution: 4,
                    ..Default::default()
                },
                "volume.resolution",
            ),
            (
                VolumeSettings {
                    steps: 0,
                    ..Default::default()
                },
                "volume.steps",
            ),
            (
                VolumeSettings {
                    iso: 0.0,
                    ..Default::default()
                },
                "volume.iso",
            ),
            (
                VolumeSettings {
                    max_strands_per_voxel: 256,
                    ..Default::default()
                },
                "volume.max_strands_per_voxel",
            ),
            (
                VolumeSettings {
                    ao_samples: 0,
                    ..Default::default()
                },
                "volume.ao_samples",
            ),
            (
                VolumeSettings {
                    shadow_step: 0.0,
                    ..Default::default()
                },
                "volume.shadow_step",
            ),
        ];
        for (s, name) in cases {
            let e = s.validate().expect_err(name).to_string();
            assert!(e.contains(name), "{e}");
        }
    }

    #[test]
    fn names_round_trip() {
        for m in [ShadowMode::Adsm, ShadowMode::Volume] {
            assert_eq!(m.name().parse::<ShadowMode>().unwrap(), m);
        }
        for m in [VoxelizeMode::Vertices, VoxelizeMode::Segments] {
            assert_eq!(parse_voxelize_mode(voxelize_mode_name(m)).unwrap(), m);
        }
        assert!("dsm".parse::<ShadowMode>().is_err());
        assert!(parse_voxelize_mode("voxels").is_err());
    }
}
