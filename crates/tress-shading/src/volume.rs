//! Volume shading: the formulas of the raymarcher, the volume shadows and the local ambient
//! occlusion, and the level-of-detail blend (Jansson et al. 2019 §3.3, §3.4, §3). WGSL twins in
//! `crates/tress-render/src/shaders/common/volume.wgsl`, same names and arguments.
//!
//! Positions are *voxel coordinates* of a [`crate::VoxelGrid`] (`(p - origin) · scale`, voxel `i`
//! spans `[i, i + 1)`), so marching distances are in voxel edges and "density × step" is a number
//! of strands. The density volume is read through [`DensityVolume`], the CPU stand-in for the
//! trilinearly filtered 3D texture (texel centres at `i + 1/2`, clamp to edge).
//!
//! - **Surface (§3.3).** The raymarcher accumulates `density · step` along the eye ray, each
//!   strand weighed by its opacity fade; the hair's transmittance falls as
//!   [`composite_transmittance`] `= 256^(-strands / iso)`, and the "solid" isosurface is where the
//!   sum first reaches `iso` (1/256 left). The colour is the mean of the shading at the points
//!   where the transmittance falls through equal shares of the composite's weight
//!   ([`composite_point_reached`]), so the whole depth the rasterizer's composite reaches is
//!   shaded, not one point. A ray that never gets to the surface has the opacity
//!   [`fake_transparency_alpha`] `= 1 - transmittance`: the paper's "fake transparency",
//!   continuous with the solid case. The shading normal is [`density_normal`], `-∇density`
//!   normalized.
//! - **Volume shadows (§3.4).** [`volume_shadow_strands`] marches from the point towards the
//!   light and counts the strands passed; times the share in the ray's way
//!   (`strand_width / voxel_size`, applied by the renderer) that count replaces ADSM's `d · r` in
//!   [`crate::strand_visibility`]`(n, alpha) = (1 - alpha)^n`.
//!   With ADSM's model the renderer uses [`volume_adsm_visibility`] instead: the expectation of
//!   ADSM's `(1 - alpha)^(r · (d - bias))` over where the first strand seen from the light lies.
//! - **Local ambient occlusion (§3.4).** [`volume_ao`] averages the density at `samples` points
//!   spread evenly through a ball of radius `radius` around the point ([`ao_offset`]: a Fibonacci
//!   spiral of directions at radii `cbrt(u)`, `u` a golden-ratio sequence, uniform in volume).
//!   The mean density times the radius is the number of strands an average ray of that length
//!   passes; scaled by `intensity` (the paper's tweak to match a ray tracer; the renderer also
//!   folds in the share of passed strands in a ray's way, `strand_width / voxel_size`) it goes
//!   through the same visibility `(1 - alpha)^n` as the shadows.
//! - **Level of detail (§3, §4).** [`lod_factor`] is `smoothstep(near, far, distance)`; the
//!   dithered transition compares it with [`dither_threshold`], a 4 × 4 Bayer matrix.

use glam::{IVec3, UVec2, UVec3, Vec3};

use crate::{smoothstep, strand_visibility};

/// Most marching steps a shadow ray takes (a safety bound; a `1024³` grid needs at most
/// `1024 · √3 / step`).
pub const MAX_MARCH_STEPS: u32 = 4096;
/// Most ambient-occlusion samples honoured.
pub const MAX_AO_SAMPLES: u32 = 64;
/// `(√5 - 1) / 2`.
pub const GOLDEN_RATIO_CONJUGATE: f32 = 0.618_034;
/// The golden angle in radians, `π (3 - √5)`.
pub const GOLDEN_ANGLE: f32 = 2.399_963_3;

/// A density array that does not hold `res³ > 0` values.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("a {res}³ density volume needs {expected} values (at least one), got {got}")]
pub struct VolumeSizeError {
    /// Voxels per axis.
    pub res: u32,
    /// `res³`.
    pub expected: u64,
    /// Length of the array given.
    pub got: usize,
}

/// `Ok` when `len` values fill a `res³ > 0` volume.
pub(crate) fn check_volume_size(res: u32, len: usize) -> Result<(), VolumeSizeError> {
    VolumeSizeError::check(res, len)
}

impl VolumeSizeError {
    /// `Ok` when `len` values fill a `res³ > 0` volume.
    fn check(res: u32, len: usize) -> Result<(), VolumeSizeError> {
        let expected = u64::from(res).pow(3);
        if expected == 0 || len as u64 != expected {
            return Err(VolumeSizeError {
                res,
                expected,
                got: len,
            });
        }
        Ok(())
    }
}

/// A read-only `res³` density volume: the CPU stand-in for the density channel of the 3D texture
/// sampled with a linear, clamp-to-edge sampler. `density[x + res · (y + res · z)]`.
#[derive(Clone, Copy, Debug)]
pub struct DensityVolume<'a> {
    res: u32,
    density: &'a [f32],
}

impl<'a> DensityVolume<'a> {
    /// A view of `density`, checked to hold `res³ > 0` values.
    pub fn new(res: u32, density: &'a [f32]) -> Result<Self, VolumeSizeError> {
        VolumeSizeError::check(res, density.len())?;
        Ok(DensityVolume { res, density })
    }

    /// Voxels per axis.
    pub fn res(&self) -> u32 {
        self.res
    }

    /// The voxel at integer coordinates, clamped to the grid.
    pub fn load(&self, x: i32, y: i32, z: i32) -> f32 {
        let c = |v: i32| v.clamp(0, self.res as i32 - 1) as usize;
        let r = self.res as usize;
        self.density[c(x) + r * (c(y) + r * c(z))]
    }

    /// Trilinear sample at continuous voxel coordinates `x` (texel centres at `i + 1/2`).
    pub fn sample(&self, x: Vec3) -> f32 {
        let p = x - Vec3::splat(0.5);
        let i = p.floor();
        let f = p - i;
        let (x0, y0, z0) = (i.x as i32, i.y as i32, i.z as i32);
        let mut acc = 0.0;
        for dz in 0..2 {
            for dy in 0..2 {
                for dx in 0..2 {
                    let w = (if dx == 1 { f.x } else { 1.0 - f.x })
                        * (if dy == 1 { f.y } else { 1.0 - f.y })
                        * (if dz == 1 { f.z } else { 1.0 - f.z });
                    acc += w * self.load(x0 + dx, y0 + dy, z0 + dz);
                }
            }
        }
        acc
    }
}

/// A read-only `res³` volume of resolved texels (rgba bytes: the mean tangent in the cube-root
/// store, the strand count), the CPU stand-in for the whole 3D texture where a function needs the
/// tangents. `texels[x + res · (y + res · z)]`; `density_unit` as for
/// [`crate::voxelize::decode_texel`].
#[derive(Clone, Copy, Debug)]
pub struct TexelVolume<'a> {
    res: u32,
    texels: &'a [[u8; 4]],
    density_unit: f32,
}

impl<'a> TexelVolume<'a> {
    /// A view of `texels`, checked to hold `res³ > 0` of them.
    pub fn new(
        res: u32,
        texels: &'a [[u8; 4]],
        density_unit: f32,
    ) -> Result<Self, VolumeSizeError> {
        VolumeSizeError::check(res, texels.len())?;
        Ok(TexelVolume {
            res,
            texels,
            density_unit,
        })
    }

    /// The decoded texel (mean tangent, density) at integer coordinates, clamped to the grid.
    pub fn load(&self, x: i32, y: i32, z: i32) -> (Vec3, f32) {
        let c = |v: i32| v.clamp(0, self.res as i32 - 1) as usize;
        let r = self.res as usize;
        crate::voxelize::decode_texel(self.texels[c(x) + r * (c(y) + r * c(z))], self.density_unit)
    }
}

/// How parallel the strands around voxel position `x` run (WGSL `volume_tangent_coherence(tex,
/// samp, vt, x)`): the length of the density-weighted trilinear mean of the eight nearest texels'
/// tangent *directions*, in `[0, 1]`, 1 where they all run along one line (or no texel holds
/// hair). The texels' own lengths carry the tip fade, so they are normalized first; empty texels
/// do not count (interpolating towards their zero tangent would read as spread at the hair's
/// surface). The raymarcher widens Kajiya-Kay's lobe with it
/// ([`crate::spread_kajiya_kay`]): a pixel of strands averages the highlights of all the
/// directions it covers.
pub fn volume_tangent_coherence(vol: &TexelVolume<'_>, x: Vec3) -> f32 {
    let p = x - Vec3::splat(0.5);
    let i = p.floor();
    let f = p - i;
    let (x0, y0, z0) = (i.x as i32, i.y as i32, i.z as i32);
    let mut sum = Vec3::ZERO;
    let mut weight = 0.0;
    for k in 0..8 {
        let (dx, dy, dz) = (k & 1, (k >> 1) & 1, (k >> 2) & 1);
        let w = (if dx == 1 { f.x } else { 1.0 - f.x })
            * (if dy == 1 { f.y } else { 1.0 - f.y })
            * (if dz == 1 { f.z } else { 1.0 - f.z });
        let (t, density) = vol.load(x0 + dx, y0 + dy, z0 + dz);
        let len = t.length();
        if len > 1e-6 {
            sum += w * density * t / len;
            weight += w * density;
        }
    }
    if weight > 0.0 {
        sum.length() / weight
    } else {
        1.0
    }
}

/// Entry and exit distances `(t0, t1)` of the ray `o + t · d` through the box `[lo, hi]` (slab
/// method; `t0 > t1` is a miss). Zero components of `d` are handled by IEEE infinities.
pub fn ray_box(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> (f32, f32) {
    let inv = Vec3::ONE / d;
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let near = a.min(b);
    let far = a.max(b);
    (near.max_element(), far.min_element())
}

/// The `cap` of [`volume_shadow_strands`] and [`volume_ao`] that caps nothing: every strand counts.
pub const NO_CAP: f32 = 1e30;

/// Strands between voxel position `x` and the grid's edge towards unit direction `l` (§3.4):
/// `Σ min(density(x + l t), cap) · step` for `t = max(offset, t_enter), + step, ...` while inside
/// the grid. `offset` (voxels) skips the point's own strands. With `cap` = [`NO_CAP`] this counts
/// the strands passed; with `cap` = 1 it is the length in voxels of the ray's path inside the
/// hair (voxels holding a strand or more), the depth ADSM's `r` multiplies.
pub fn volume_shadow_strands(
    vol: &DensityVolume<'_>,
    x: Vec3,
    l: Vec3,
    step: f32,
    offset: f32,
    cap: f32,
) -> f32 {
    shadow_march(vol, x, l, step, offset)
        .fold(0.0, |n, t| n + vol.sample(x + l * t).min(cap) * step)
}

/// The distances a shadow ray from voxel position `x` towards `l` samples: `max(offset,
/// t_enter)`, then `+ step` at a time (accumulated, as the WGSL does) while inside the grid, at
/// most [`MAX_MARCH_STEPS`] of them.
fn shadow_march(
    vol: &DensityVolume<'_>,
    x: Vec3,
    l: Vec3,
    step: f32,
    offset: f32,
) -> impl Iterator<Item = f32> {
    let res = vol.res() as f32;
    let (t0, t1) = ray_box(x, l, Vec3::ZERO, Vec3::splat(res));
    std::iter::successors(Some(offset.max(t0)), move |t| Some(t + step))
        .take_while(move |t| *t < t1)
        .take(MAX_MARCH_STEPS as usize)
}

/// Offset of ambient-occlusion sample `i` of `n` inside the unit ball: Fibonacci-spiral
/// direction, radius `cbrt(u)` with `u = fract((i + 1/2) · (√5 - 1) / 2)` (a golden-ratio
/// sequence, so the radii are spread evenly and independent of the direction).
pub fn ao_offset(i: u32, n: u32) -> Vec3 {
    let fi = i as f32 + 0.5;
    let nf = n.max(1) as f32;
    let z = 1.0 - 2.0 * fi / nf;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = GOLDEN_ANGLE * i as f32;
    let u = fi * GOLDEN_RATIO_CONJUGATE;
    let radius = (u - u.floor()).powf(1.0 / 3.0);
    Vec3::new(r * phi.cos(), r * phi.sin(), z) * radius
}

/// Local ambient occlusion at voxel position `x` (§3.4): with the mean `m` of
/// `min(density, cap)` at `min(samples, MAX_AO_SAMPLES)` points in the ball of `radius` voxels,
/// `strand_visibility(intensity · m · radius, alpha)`. 1 without samples or radius. `cap` as in
/// [`volume_shadow_strands`].
pub fn volume_ao(
    vol: &DensityVolume<'_>,
    x: Vec3,
    radius: f32,
    samples: u32,
    intensity: f32,
    alpha: f32,
    cap: f32,
) -> f32 {
    let n = samples.min(MAX_AO_SAMPLES);
    if n == 0 || radius <= 0.0 {
        return 1.0;
    }
    let mut sum = 0.0;
    for i in 0..n {
        sum += vol.sample(x + ao_offset(i, n) * radius).min(cap);
    }
    let mean = sum / n as f32;
    strand_visibility(intensity * mean * radius, alpha)
}

/// The voxel position of the centre of texel `t` of the ambient-occlusion texture baked at
/// `texel` voxels a texel (`volume.ao_texel`; the texture spans the grid, texel centres at
/// `texel · (t + 1/2)`): the bake stores [`volume_ao`] there, and a shaded point at voxel
/// position `x` reads the texture trilinearly at `x / texel` texels.
pub fn ao_texel_centre(t: UVec3, texel: u32) -> Vec3 {
    (t.as_vec3() + Vec3::splat(0.5)) * texel as f32
}

/// Whether the bake evaluates AO texel `t` of `texel` voxels (`texel_reached` in
/// `volume/ao_bake.wgsl`): a point at voxel position `x` reads the texels whose centres lie
/// within `texel` of it, so points in voxels from `texel · t - ⌈texel/2⌉` to
/// `texel · t + ⌈3 texel/2⌉ - 1`; it is evaluated when one of those voxels lies in an occupied
/// block (`occupied(block)`, `block` below `occupancy_res` per axis, blocks of `block_edge`
/// voxels). The rest hold 1: no shaded point reads them.
pub fn ao_texel_reached(
    t: UVec3,
    texel: u32,
    occupancy_res: u32,
    block_edge: u32,
    occupied: impl Fn(UVec3) -> bool,
) -> bool {
    let last = IVec3::splat(occupancy_res as i32 - 1);
    let first = (t * texel).as_ivec3();
    let (before, after) = (texel.div_ceil(2) as i32, (3 * texel).div_ceil(2) as i32 - 1);
    let e = block_edge as i32;
    let b0 = ((first - IVec3::splat(before)) / e).clamp(IVec3::ZERO, last);
    let b1 = ((first + IVec3::splat(after)) / e).clamp(IVec3::ZERO, last);
    (b0.z..=b1.z).any(|z| {
        (b0.y..=b1.y).any(|y| (b0.x..=b1.x).any(|x| occupied(IVec3::new(x, y, z).as_uvec3())))
    })
}

/// Central-difference gradient of the density at `x` (one voxel either side).
pub fn density_gradient(vol: &DensityVolume<'_>, x: Vec3) -> Vec3 {
    let d = |o: Vec3| vol.sample(x + o) - vol.sample(x - o);
    Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z)) * 0.5
}

/// The isosurface normal `-∇d / |∇d|` (§3.3); `fallback` where the gradient vanishes.
pub fn density_normal(gradient: Vec3, fallback: Vec3) -> Vec3 {
    let len = gradient.length();
    if len > 1e-12 {
        -gradient / len
    } else {
        fallback
    }
}

/// Transmittance of the hair after `strands` (opacity-weighted) strands along an eye ray:
/// `256^(-strands / iso)`, so 1/256 at the isosurface (`strands = iso`); 0 when `iso <= 0`.
pub fn composite_transmittance(strands: f32, iso: f32) -> f32 {
    if iso <= 0.0 {
        return 0.0;
    }
    (-8.0 * strands.max(0.0) / iso).exp2()
}

/// Opacity of a "non-solid" hit (§3.3, fake transparency): `1 - composite_transmittance`; 1 when
/// `iso <= 0`.
pub fn fake_transparency_alpha(strands: f32, iso: f32) -> f32 {
    1.0 - composite_transmittance(strands, iso)
}

/// The optical width of one strand as the rasterizer draws it, in pixels: a line `width_px` wide
/// of opacity `alpha`, times the §3.2 line coverage when `coverage` is on, lets through
/// `exp(-width)` of the light summed across it: `width_px · ∫₀¹ -ln(1 - alpha · u) du =
/// width_px · (1 + (1 - alpha) ln(1 - alpha) / alpha)` with coverage (it falls linearly from
/// the centre line to the edges), `width_px · -ln(1 - alpha)` without. A ray through a pixel
/// crossing strands of optical width `w` every `n` per pixel of path has the transmittance
/// `exp(-n · w)`: the raymarcher's `volume.opacity = "strands"` uses it so the volume is as
/// opaque as the strands' composite at any distance. 0 for `alpha <= 0` or `width_px <= 0`;
/// `alpha` is clamped below 1 (a fully opaque line would be infinitely thick).
pub fn line_optical_width(alpha: f32, width_px: f32, coverage: bool) -> f32 {
    if alpha <= 0.0 || width_px <= 0.0 {
        return 0.0;
    }
    let a = alpha.min(1.0 - 1.0 / 1024.0);
    let keep = 1.0 - a;
    if coverage {
        width_px * (1.0 + keep * keep.ln() / a)
    } else {
        width_px * -keep.ln()
    }
}

/// Optical depth of `strands` (opacity-weighted strand length, in voxel edges) met along an eye
/// ray of direction `dir`, drawn as lines of optical width `optical_width` pixels where a pixel
/// spans `pixel_voxels` voxels: the strands' projected length `strands · |t × dir|` (`t` the
/// normalized mean `tangent`; a strand seen end-on covers nothing, and no tangent counts as
/// across) times the line's width in voxels.
pub fn strand_optical_depth(
    strands: f32,
    tangent: Vec3,
    dir: Vec3,
    pixel_voxels: f32,
    optical_width: f32,
) -> f32 {
    let len = tangent.length();
    let across = if len > 1e-6 {
        (tangent / len).cross(dir).length()
    } else {
        1.0
    };
    strands * across * pixel_voxels * optical_width
}

/// Whether the transmittance `tr` has fallen to shading point `m` of `k`: the points split the
/// composite's weight `1 - tr` into `k` equal shares and sit at their middles,
/// `tr <= 1 - (m + 1/2) / k`.
pub fn composite_point_reached(tr: f32, m: u32, k: u32) -> bool {
    tr <= 1.0 - (m as f32 + 0.5) / k.max(1) as f32
}

/// ADSM's visibility `(1 - alpha)^(r · (d - bias))` at voxel position `x` towards unit `l`, in
/// expectation over where the first strand seen from the light lies (`d` its distance from the
/// point). Marching out from `max(offset, t_enter)` in `step`s, a step holds a strand of a
/// shadow-map line `width` voxels wide with probability `p = 1 - exp(-density · step · width)`,
/// and a farther one replaces a nearer: `seen ← seen · (1 - p) + p · exp(ln_keep · max(t - bias,
/// 0))`, `none ← none · (1 - p)`; the result is `seen + none`. `ln_keep` is `r · ln(1 - alpha)`
/// per voxel, `bias` in voxels.
#[allow(clippy::too_many_arguments)]
pub fn volume_adsm_visibility(
    vol: &DensityVolume<'_>,
    x: Vec3,
    l: Vec3,
    step: f32,
    offset: f32,
    width: f32,
    ln_keep: f32,
    bias: f32,
) -> f32 {
    let (mut seen, mut none) = (0.0, 1.0);
    for t in shadow_march(vol, x, l, step, offset) {
        let p = 1.0 - (-vol.sample(x + l * t) * step * width).exp();
        seen = seen * (1.0 - p) + p * (ln_keep * (t - bias).max(0.0)).exp();
        none *= 1.0 - p;
    }
    seen + none
}

/// Level-of-detail blend factor (0: strands, 1: volume) from the camera distance:
/// `smoothstep(near, far, distance)`; a step at `near` when `far <= near`.
pub fn lod_factor(distance: f32, near: f32, far: f32) -> f32 {
    if far <= near {
        return if distance >= near { 1.0 } else { 0.0 };
    }
    smoothstep(near, far, distance)
}

/// Threshold of the dithered transition at pixel `px`: `(b + 1/2) / 16` with `b` the 4 × 4 Bayer
/// matrix entry. A pixel shows the volume when the blend factor exceeds it, so factor 0 shows
/// only strands, 1 only volume, and `k/16` about `k` pixels of every 16.
pub fn dither_threshold(px: UVec2) -> f32 {
    const BAYER: [u32; 16] = [0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5];
    let b = BAYER[((px.y & 3) * 4 + (px.x & 3)) as usize];
    (b as f32 + 0.5) / 16.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slab(res: u32, lo: u32, hi: u32, value: f32) -> Vec<f32> {
        // Density `value` in voxels with lo <= x < hi, empty elsewhere.
        let r = res as usize;
        let mut d = vec![0.0; r * r * r];
        for z in 0..r {
            for y in 0..r {
                for x in lo as usize..hi as usize {
                    d[x + r * (y + r * z)] = value;
                }
            }
        }
        d
    }

    #[test]
    fn trilinear_sampling_interpolates_between_centres() {
        let d = slab(8, 4, 8, 2.0);
        let v = DensityVolume::new(8, &d).unwrap();
        assert_eq!(v.sample(Vec3::new(4.5, 3.3, 2.0)), 2.0);
        assert_eq!(v.sample(Vec3::new(3.5, 3.3, 2.0)), 0.0);
        assert!((v.sample(Vec3::new(4.0, 3.3, 2.0)) - 1.0).abs() < 1e-6);
        // Clamp to edge outside the grid.
        assert_eq!(v.sample(Vec3::new(100.0, 3.0, 3.0)), 2.0);
        assert!(DensityVolume::new(8, &d[1..]).is_err());
        assert!(DensityVolume::new(0, &[]).is_err());
    }

    #[test]
    fn shadow_march_counts_the_strands_in_the_way() {
        // A slab 3 voxels thick with 2 strands per voxel: 6 strands between the two sides.
        let d = slab(16, 8, 11, 2.0);
        let v = DensityVolume::new(16, &d).unwrap();
        let n = volume_shadow_strands(&v, Vec3::new(2.0, 8.0, 8.0), Vec3::X, 0.25, 0.5, NO_CAP);
        assert!((n - 6.0).abs() < 0.3, "{n}");
        // Looking away from the slab: nothing.
        let n = volume_shadow_strands(&v, Vec3::new(2.0, 8.0, 8.0), Vec3::NEG_X, 0.25, 0.5, NO_CAP);
        assert_eq!(n, 0.0);
        // A point outside the grid starts where the ray enters it.
        let n = volume_shadow_strands(&v, Vec3::new(-20.0, 8.0, 8.0), Vec3::X, 0.25, 0.5, NO_CAP);
        assert!((n - 6.0).abs() < 0.3, "{n}");
        assert!((strand_visibility(n, 0.25) - 0.75f32.powf(6.0)).abs() < 0.05);
        // Capped at one strand per voxel: the path's length inside the hair, the 3 voxels plus
        // the trilinear ramps at the two faces where the filtered density passes 1 strand
        // (0 -> 2 over a voxel: 3/4 of it counts at each face, where the plain count has 1).
        let depth = volume_shadow_strands(&v, Vec3::new(2.0, 8.0, 8.0), Vec3::X, 0.25, 0.5, 1.0);
        assert!((depth - 3.5).abs() < 0.1, "{depth}");
        // And the same slab twice as dense is no deeper.
        let dense = DensityVolume::new(16, &slab(16, 8, 11, 4.0))
            .map(|v| volume_shadow_strands(&v, Vec3::new(2.0, 8.0, 8.0), Vec3::X, 0.25, 0.5, 1.0));
        assert!((dense.unwrap() - depth).abs() < 0.3);
    }

    #[test]
    fn ao_offsets_fill_the_unit_ball_evenly() {
        let n = 64;
        let pts: Vec<Vec3> = (0..n).map(|i| ao_offset(i, n)).collect();
        assert!(pts.iter().all(|p| p.length() <= 1.0 + 1e-5));
        let mean = pts.iter().copied().sum::<Vec3>() / n as f32;
        assert!(mean.length() < 0.1, "{mean}");
        // Uniform in volume: about 1/8 of the points lie within radius 1/2.
        let inner = pts.iter().filter(|p| p.length() < 0.5).count();
        assert!((6..=10).contains(&inner), "{inner}");
    }

    #[test]
    fn ao_darkens_with_density_and_intensity() {
        let empty = vec![0.0; 512];
        let full = vec![3.0; 512];
        let (e, f) = (
            DensityVolume::new(8, &empty).unwrap(),
            DensityVolume::new(8, &full).unwrap(),
        );
        let x = Vec3::splat(4.0);
        assert_eq!(volume_ao(&e, x, 2.0, 16, 1.0, 0.3, NO_CAP), 1.0);
        let a = volume_ao(&f, x, 2.0, 16, 1.0, 0.3, NO_CAP);
        assert!((a - 0.7f32.powf(6.0)).abs() < 1e-4, "{a}");
        assert!(volume_ao(&f, x, 2.0, 16, 2.0, 0.3, NO_CAP) < a);
        assert_eq!(volume_ao(&f, x, 2.0, 0, 1.0, 0.3, NO_CAP), 1.0);
        assert_eq!(volume_ao(&f, x, 0.0, 16, 1.0, 0.3, NO_CAP), 1.0);
        // Capped at one strand per voxel: the ball counts as full of hair, whatever its density.
        let capped = volume_ao(&f, x, 2.0, 16, 1.0, 0.3, 1.0);
        assert!((capped - 0.7f32.powf(2.0)).abs() < 1e-4, "{capped}");
    }

    #[test]
    fn normal_points_out_of_the_hair() {
        let d = slab(16, 8, 16, 4.0);
        let v = DensityVolume::new(16, &d).unwrap();
        let g = density_gradient(&v, Vec3::new(8.0, 8.0, 8.0));
        assert_eq!(density_normal(g, Vec3::Z), Vec3::NEG_X);
        assert_eq!(density_normal(Vec3::ZERO, Vec3::Z), Vec3::Z);
    }

    #[test]
    fn adsm_visibility_is_the_expectation_over_the_first_strand_from_the_light() {
        // Empty volume: nothing in the way.
        let zero = vec![0.0; 16 * 16 * 16];
        let empty = DensityVolume::new(16, &zero).unwrap();
        let x = Vec3::new(8.0, 8.0, 2.5);
        assert_eq!(
            volume_adsm_visibility(&empty, x, Vec3::Z, 1.0, 1.0, 0.5, -0.3, 0.0),
            1.0
        );
        // Opaque hair everywhere (every step holds a strand): the first strand from the light is
        // at the last step inside the grid, so the visibility is ADSM's at that distance.
        let full = vec![64.0; 16 * 16 * 16];
        let dense = DensityVolume::new(16, &full).unwrap();
        let (step, ln_keep, bias) = (1.0, -0.3, 0.5);
        let v = volume_adsm_visibility(&dense, x, Vec3::Z, step, 1.0, 1.0, ln_keep, bias);
        // From z = 2.5 with offset 1 the march samples t = 1, 2, ..., 13 (z = 15.5, the last
        // texel centre inside the grid).
        let last = 13.0;
        let adsm = (ln_keep * (last - bias)).exp();
        assert!((v - adsm).abs() < 1e-6, "{v} vs {adsm}");
        // One thin sheet of hair at distance D: a share p of rays sees it (ADSM at D), the
        // rest sees nothing.
        let mut sheet = vec![0.0; 16 * 16 * 16];
        for y in 0..16 {
            for xx in 0..16 {
                sheet[xx + 16 * (y + 16 * 10)] = 0.5;
            }
        }
        let s = DensityVolume::new(16, &sheet).unwrap();
        let x = Vec3::new(8.0, 8.0, 4.5);
        let width = 0.8;
        let v = volume_adsm_visibility(&s, x, Vec3::Z, 1.0, 0.0, width, ln_keep, 0.0);
        // The march samples z = 4.5, 5.5, ...: only z = 10.5 (t = 6) holds the sheet's texel.
        let p = 1.0 - (-0.5f32 * width).exp();
        let expected = p * (ln_keep * 6.0).exp() + (1.0 - p);
        assert!((v - expected).abs() < 1e-6, "{v} vs {expected}");
        // More hair between the point and the light only darkens.
        let thicker = volume_adsm_visibility(&s, x, Vec3::Z, 1.0, 0.0, 2.0 * width, ln_keep, 0.0);
        assert!(thicker < v);
    }

    #[test]
    fn composite_transmittance_and_its_shading_points() {
        assert_eq!(composite_transmittance(0.0, 48.0), 1.0);
        assert!((composite_transmittance(48.0, 48.0) - 1.0 / 256.0).abs() < 1e-9);
        assert!((composite_transmittance(24.0, 48.0) - 1.0 / 16.0).abs() < 1e-8);
        assert_eq!(composite_transmittance(5.0, 0.0), 0.0);
        // k points at the middles of k equal shares of the weight: for k = 4 at 7/8, 5/8, 3/8, 1/8.
        let k = 4;
        let at: Vec<f32> = (0..k).map(|m| 1.0 - (m as f32 + 0.5) / k as f32).collect();
        assert_eq!(at, [0.875, 0.625, 0.375, 0.125]);
        for (m, &tr) in at.iter().enumerate() {
            assert!(composite_point_reached(tr, m as u32, k));
            assert!(!composite_point_reached(tr + 1e-3, m as u32, k));
        }
    }

    #[test]
    fn transparency_lod_and_dither() {
        assert_eq!(fake_transparency_alpha(0.0, 4.0), 0.0);
        assert!((fake_transparency_alpha(1.0, 4.0) - (1.0 - 0.25)).abs() < 1e-7);
        assert!(fake_transparency_alpha(9.0, 4.0) > 0.99);
        assert_eq!(fake_transparency_alpha(0.0, 0.0), 1.0);
        assert_eq!(lod_factor(1.0, 2.0, 4.0), 0.0);
        assert_eq!(lod_factor(3.0, 2.0, 4.0), 0.5);
        assert_eq!(lod_factor(5.0, 2.0, 4.0), 1.0);
        assert_eq!(lod_factor(2.0, 2.0, 2.0), 1.0);
        let mut seen = [false; 16];
        for y in 0..4 {
            for x in 0..4 {
                let t = dither_threshold(UVec2::new(x, y));
                seen[(t * 16.0) as usize] = true;
                assert_eq!(t, dither_threshold(UVec2::new(x + 4, y + 8)));
            }
        }
        assert!(seen.iter().all(|s| *s), "every level once per 4x4 tile");
        let (a, b, c) = (
            ray_box(Vec3::new(-1.0, 0.5, 0.5), Vec3::X, Vec3::ZERO, Vec3::ONE),
            ray_box(Vec3::new(0.5, 0.5, 0.5), Vec3::Y, Vec3::ZERO, Vec3::ONE),
            ray_box(Vec3::new(-1.0, 2.0, 0.5), Vec3::X, Vec3::ZERO, Vec3::ONE),
        );
        assert_eq!(a, (1.0, 2.0));
        assert_eq!(b, (-0.5, 0.5));
        assert!(c.0 > c.1);
    }

    #[test]
    fn line_optical_width_is_the_line_profiles_integral() {
        for alpha in [0.05f32, 0.3, 0.6, 0.95] {
            for width in [1.0f32, 1.5, 3.0] {
                // Sum -ln(1 - alpha · coverage) across the line with the coverage twin.
                let n = 20_000;
                let dx = 2.0 * width / n as f32;
                let integral: f32 = (0..n)
                    .map(|i| {
                        let d = (-width + (i as f32 + 0.5) * dx).abs();
                        -(1.0 - alpha * crate::coverage_from_distance(d, width)).ln() * dx
                    })
                    .sum();
                let w = line_optical_width(alpha, width, true);
                assert!(
                    (w - integral).abs() < 1e-3 * integral,
                    "{alpha} {width}: {w} vs {integral}"
                );
                let flat = line_optical_width(alpha, width, false);
                assert!((flat - width * -(1.0 - alpha).ln()).abs() < 1e-5);
                assert!(flat > w, "coverage thins the line");
            }
        }
        assert_eq!(line_optical_width(0.0, 1.5, true), 0.0);
        assert_eq!(line_optical_width(0.6, 0.0, true), 0.0);
        assert!(line_optical_width(1.0, 1.5, false).is_finite());
    }

    #[test]
    fn strands_seen_end_on_cover_nothing_and_across_cover_their_width() {
        let d = Vec3::Z;
        assert!((strand_optical_depth(2.0, Vec3::X * 0.5, d, 0.5, 0.6) - 0.6).abs() < 1e-6);
        assert!(strand_optical_depth(2.0, Vec3::Z, d, 0.5, 0.6).abs() < 1e-6);
        assert!((strand_optical_depth(2.0, Vec3::ZERO, d, 0.5, 0.6) - 0.6).abs() < 1e-6);
        let diagonal = strand_optical_depth(1.0, Vec3::new(1.0, 0.0, 1.0), d, 1.0, 1.0);
        assert!((diagonal - 0.5f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn coherence_is_one_for_parallel_strands_and_falls_with_their_spread() {
        use crate::voxelize::encode_texel;
        let res = 4u32;
        let texels = |f: &dyn Fn(u32) -> (Vec3, u32)| -> Vec<[u8; 4]> {
            (0..res * res * res)
                .map(|i| {
                    let (t, n) = f(i);
                    encode_texel(t, n)
                })
                .collect()
        };
        let x = Vec3::splat(2.0);
        // Parallel, with tip-faded lengths and empty texels between: coherent.
        let parallel = texels(&|i| {
            (
                Vec3::new(1.0, 1.0, 0.0).normalize() * (0.3 + 0.1 * (i % 5) as f32),
                3 * (i % 2),
            )
        });
        let vol = TexelVolume::new(res, &parallel, 1.0).unwrap();
        assert!((volume_tangent_coherence(&vol, x) - 1.0).abs() < 0.01);
        // Alternating between two directions 90° apart: |mean| = cos 45°.
        let crossed = texels(&|i| {
            let (ix, iy, iz) = (i % res, (i / res) % res, i / (res * res));
            let t = if (ix + iy + iz) % 2 == 0 {
                Vec3::X
            } else {
                Vec3::Y
            };
            (t, 2)
        });
        let vol = TexelVolume::new(res, &crossed, 1.0).unwrap();
        let c = volume_tangent_coherence(&vol, x);
        assert!((c - 0.5f32.sqrt()).abs() < 0.02, "{c}");
        // A denser texel pulls the mean towards its direction.
        let weighted = texels(&|i| {
            let (ix, iy, iz) = (i % res, (i / res) % res, i / (res * res));
            if (ix + iy + iz) % 2 == 0 {
                (Vec3::X, 30)
            } else {
                (Vec3::Y, 1)
            }
        });
        let vol = TexelVolume::new(res, &weighted, 1.0).unwrap();
        assert!(volume_tangent_coherence(&vol, x) > 0.95);
        // No hair: coherent by definition.
        let empty = vec![[0u8; 4]; 64];
        let vol = TexelVolume::new(res, &empty, 1.0).unwrap();
        assert_eq!(volume_tangent_coherence(&vol, x), 1.0);
        assert!(TexelVolume::new(res, &empty[..63], 1.0).is_err());
    }
}
