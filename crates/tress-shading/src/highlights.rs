//! Pre-integrated highlights: the mean of the strands' own Kajiya-Kay highlights in each voxel,
//! for this frame's view and lights. CPU reference of the highlight half of
//! `volume/voxelize.wgsl`, `volume/volume_resolve.wgsl` and of `volume_highlight` in
//! `shaders/common/volume.wgsl`.
//!
//! The paper's raymarcher (Jansson et al. 2019 §3.3) shades the voxels' *mean* tangent. Kajiya-Kay's
//! specular lobe is narrow (exponent 80 by default) and strongly non-linear in the tangent, so
//! the lobe of the mean is not the mean of the lobes: where a voxel holds strands of a few slightly
//! different directions (neighbouring strands on different segments of their polylines, layers
//! crossing), a pixel of rasterized strands lights up where *some* of them meet the mirror cone,
//! while the mean tangent meets it somewhere in between. The highlight arcs then sit in other
//! places in the two renderers, and no widening of one lobe (Toksvig's) moves them back.
//!
//! The voxelizer already visits every strand sample once per frame, with the frame's camera and
//! lights known, so it can integrate the lobes themselves: each segment's specular term
//! `kajiya_kay_specular(t, l, v, exponent)` for every light (`v` towards the eye from the segment's
//! midpoint), weighed by the segment's tip fade (a faded tip is nearly transparent in the strands'
//! composite, so its highlight counts for as little), is quantized to 8 bits
//! ([`quantize_highlight`]) and summed per voxel next to the tangent; the fades themselves are
//! summed too, quantized the same way, in the high half of the tangent's z word. Two `u32` words a
//! voxel hold the four lights' sums, 16 bits each: a voxel accepts at most 255 samples of at most
//! 255, so they cannot overflow. The resolve divides each light's sum by the fade sum
//! ([`highlight_texel`], exact integer rounding: the fade-weighted mean of the lobes) and writes an
//! `rgba8unorm` texel, one channel a light. The raymarcher reads it back at a point as the density-weighted trilinear mean of the
//! eight texels around it ([`volume_highlight`]: empty texels have no strands, so they must not
//! pull a surface point's highlight towards zero) and uses it in place of the mean tangent's lobe.

use glam::{UVec3, Vec3};

use crate::kajiya_kay_specular;

/// Lights whose highlights the voxelizer integrates (the renderer's `MAX_LIGHTS`).
pub const HIGHLIGHT_LIGHTS: usize = 4;
/// Quantization levels of one highlight sample.
pub const HIGHLIGHT_LEVELS: f32 = 255.0;

/// The frame's view and lights as the voxelizer integrates highlights for them.
#[derive(Clone, Debug, PartialEq)]
pub struct HighlightView {
    /// Eye position (perspective).
    pub eye: Vec3,
    /// Unit view direction, into the scene.
    pub forward: Vec3,
    /// Orthographic: `v = -forward` everywhere.
    pub orthographic: bool,
    /// Unit directions towards the lights, at most [`HIGHLIGHT_LIGHTS`] (more are ignored).
    pub lights: Vec<Vec3>,
    /// Kajiya-Kay's specular exponent.
    pub exponent: f32,
}

impl HighlightView {
    /// Unit vector from `p` towards the eye (`camera_to_eye` in `common/camera.wgsl`).
    pub fn to_eye(&self, p: Vec3) -> Vec3 {
        if self.orthographic {
            return -self.forward;
        }
        let d = self.eye - p;
        let len = d.length();
        if len < 1e-20 { -self.forward } else { d / len }
    }
}

/// One specular value in `[0, 1]` as `floor(s · 255 + 1/2)`; WGSL twin `quantize_highlight`.
pub fn quantize_highlight(s: f32) -> u32 {
    (s.clamp(0.0, 1.0) * HIGHLIGHT_LEVELS + 0.5).floor() as u32
}

/// The quantized highlights of the segment `p0`–`p1` (unit tangent `t`, tip fade `fade`) for each
/// light of `view`, `quantize_highlight(fade · spec)` (0 for absent lights); WGSL twin
/// `segment_highlights`.
pub fn segment_highlights(
    view: &HighlightView,
    p0: Vec3,
    p1: Vec3,
    t: Vec3,
    fade: f32,
) -> [u32; 4] {
    let v = view.to_eye((p0 + p1) * 0.5);
    let mut q = [0; HIGHLIGHT_LIGHTS];
    for (qi, l) in q.iter_mut().zip(&view.lights) {
        *qi = quantize_highlight(fade * kajiya_kay_specular(t, *l, v, view.exponent));
    }
    q
}

/// The texel byte of a voxel's highlight: the fade-weighted mean of its samples, their quantized
/// `fade · spec` summing to `sum` over quantized fades summing to `fades`, to the nearest level in
/// integers (`(2 · 255 · sum + fades) / (2 · fades)`, at most 255); 0 without fade. With no fade
/// (every sample's 255) it is the plain mean. WGSL twin `highlight_texel`.
pub fn highlight_texel(sum: u32, fades: u32) -> u8 {
    if fades == 0 {
        return 0;
    }
    ((2 * 255 * sum + fades) / (2 * fades)).min(255) as u8
}

/// The two words the GPU accumulates a voxel's four sums in: lights 0 and 1, then 2 and 3, the
/// lower one in the low 16 bits.
pub fn pack_highlights(q: [u32; 4]) -> [u32; 2] {
    [q[0] | (q[1] << 16), q[2] | (q[3] << 16)]
}

/// The inverse of [`pack_highlights`].
pub fn unpack_highlights(w: [u32; 2]) -> [u32; 4] {
    [w[0] & 0xffff, w[0] >> 16, w[1] & 0xffff, w[1] >> 16]
}

/// A read-only `res³` volume of highlight texels (one byte a light) beside the density texels of
/// the same grid: the CPU stand-in for the highlight texture. `highlights[i]` and `density[i]`
/// (the count's density, as [`crate::DensityVolume`]) belong to voxel `x + res · (y + res · z)`.
#[derive(Clone, Copy, Debug)]
pub struct HighlightVolume<'a> {
    res: u32,
    highlights: &'a [[u8; 4]],
    density: &'a [f32],
}

impl<'a> HighlightVolume<'a> {
    /// A view of the two arrays, checked to hold `res³ > 0` values each.
    pub fn new(
        res: u32,
        highlights: &'a [[u8; 4]],
        density: &'a [f32],
    ) -> Result<Self, crate::VolumeSizeError> {
        crate::volume::check_volume_size(res, highlights.len())?;
        crate::volume::check_volume_size(res, density.len())?;
        Ok(HighlightVolume {
            res,
            highlights,
            density,
        })
    }

    fn load(&self, v: UVec3) -> ([u8; 4], f32) {
        let i =
            v.x as usize + self.res as usize * (v.y as usize + self.res as usize * v.z as usize);
        (self.highlights[i], self.density[i])
    }
}

/// The highlight of light `light` at voxel position `x`: the density-weighted trilinear mean of
/// the eight texels around it (texel centres at `i + 1/2`, clamped to the edge), in `[0, 1]`; 0
/// where none holds strands. WGSL twin `volume_highlight`.
pub fn volume_highlight(vol: &HighlightVolume<'_>, x: Vec3, light: usize) -> f32 {
    let p = x - Vec3::splat(0.5);
    let f = p.floor();
    let w = p - f;
    let last = vol.res as i32 - 1;
    let corner = |c: i32, d: i32| (c + d).clamp(0, last) as u32;
    let (mut sum, mut weight) = (0.0, 0.0);
    for k in 0..8 {
        let (dx, dy, dz) = (k & 1, (k >> 1) & 1, (k >> 2) & 1);
        let tw = (if dx == 1 { w.x } else { 1.0 - w.x })
            * (if dy == 1 { w.y } else { 1.0 - w.y })
            * (if dz == 1 { w.z } else { 1.0 - w.z });
        let v = UVec3::new(
            corner(f.x as i32, dx),
            corner(f.y as i32, dy),
            corner(f.z as i32, dz),
        );
        let (h, density) = vol.load(v);
        sum += tw * density * f32::from(h[light.min(HIGHLIGHT_LIGHTS - 1)]);
        weight += tw * density;
    }
    if weight > 0.0 {
        sum / weight / HIGHLIGHT_LEVELS
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(lights: Vec<Vec3>) -> HighlightView {
        HighlightView {
            eye: Vec3::new(0.0, 0.0, 10.0),
            forward: Vec3::NEG_Z,
            orthographic: false,
            lights,
            exponent: 80.0,
        }
    }

    #[test]
    fn a_segment_on_the_mirror_cone_has_the_full_highlight_and_absent_lights_none() {
        // Light and eye both along +z, the strand across them: the cone's cosine is 1.
        let v = view(vec![Vec3::Z, Vec3::X]);
        let q = segment_highlights(&v, Vec3::new(-1.0, 0.0, 0.0), Vec3::X, Vec3::X, 1.0);
        assert_eq!(q[0], 255);
        // The light along the strand: sin(t, l) = 0 and cos(t, l) cos(t, v) = 0, no highlight.
        assert_eq!(q[1], 0);
        assert_eq!(&q[2..], &[0, 0]);
        // A faded segment's highlight is weighed by its fade.
        let faded = segment_highlights(&v, Vec3::new(-1.0, 0.0, 0.0), Vec3::X, Vec3::X, 0.2);
        assert_eq!(faded[0], 51);
    }

    #[test]
    fn texels_round_the_fade_weighted_mean_to_the_nearest_level_in_integers() {
        // Unfaded samples (fade 255 each): the plain mean.
        let n = |count: u32| 255 * count;
        assert_eq!(highlight_texel(0, 0), 0);
        assert_eq!(highlight_texel(255 * 200, n(200)), 255);
        // 1/2 a level rounds up, less rounds down.
        assert_eq!(highlight_texel(3, n(2)), 2);
        assert_eq!(highlight_texel(5, n(4)), 1);
        for (sum, count) in [(1000u32, 7u32), (17, 255), (64_000, 255)] {
            let exact = sum as f64 / count as f64;
            assert!((f64::from(highlight_texel(sum, n(count))) - exact).abs() <= 0.5);
        }
        // Two samples, spec 1 at fade 0.2 and spec 0 at fade 1: weighted mean 0.2 / 1.2.
        let (sum, fades) = (quantize_highlight(0.2), quantize_highlight(0.2) + 255);
        let want = 255.0 * 0.2 / 1.2;
        assert!((f32::from(highlight_texel(sum, fades)) - want).abs() <= 0.5 + 1.0);
        // A voxel of fully faded tips has no highlight.
        assert_eq!(highlight_texel(0, 0), 0);
    }

    #[test]
    fn packing_keeps_four_full_sums() {
        let q = [255 * 255, 0, 12_345, 65_535];
        assert_eq!(unpack_highlights(pack_highlights(q)), q);
    }

    #[test]
    fn empty_texels_do_not_dim_a_surface_highlight() {
        // A 4³ volume whose voxels with x < 2 hold strands with highlight 200, the rest nothing:
        // halfway across the boundary the highlight stays 200 (the density weighs it), where a
        // plain trilinear mean would halve it.
        let res = 4u32;
        let n = (res * res * res) as usize;
        let (mut h, mut d) = (vec![[0u8; 4]; n], vec![0.0f32; n]);
        for i in 0..n {
            if i % 4 < 2 {
                h[i] = [200, 0, 0, 0];
                d[i] = 3.0;
            }
        }
        let vol = HighlightVolume::new(res, &h, &d).unwrap();
        let x = Vec3::new(2.0, 2.0, 2.0);
        assert!((volume_highlight(&vol, x, 0) - 200.0 / 255.0).abs() < 1e-6);
        assert_eq!(volume_highlight(&vol, Vec3::new(3.9, 2.0, 2.0), 0), 0.0);
        assert_eq!(volume_highlight(&vol, x, 1), 0.0);
    }

    #[test]
    fn the_mean_of_the_lobes_differs_from_the_lobe_of_the_mean() {
        // Two strand directions 12° apart around a mean on the mirror cone: the lobe of their
        // mean is at its peak, the mean of their lobes far below it. This is what the voxel's
        // highlights keep and the mean tangent loses.
        let v = view(vec![Vec3::Z]);
        let a = 6f32.to_radians();
        let t1 = Vec3::new(a.cos(), 0.0, a.sin());
        let t2 = Vec3::new(a.cos(), 0.0, -a.sin());
        let mean = (t1 + t2).normalize();
        let lobe = |t: Vec3| kajiya_kay_specular(t, Vec3::Z, Vec3::Z, 80.0);
        assert!(lobe(mean) > 0.99);
        let of_lobes = 0.5 * (lobe(t1) + lobe(t2));
        assert!(of_lobes < 0.5, "{of_lobes}");
        let q1 = segment_highlights(&v, -t1, t1, t1, 1.0)[0];
        let q2 = segment_highlights(&v, -t2, t2, t2, 1.0)[0];
        let texel = highlight_texel(q1 + q2, 2 * 255);
        assert!((f32::from(texel) / 255.0 - of_lobes).abs() < 1.0 / 255.0);
    }
}
