//! CPU reference ("twin") of every shading and shadowing formula used by the tress shaders.
//!
//! Each function here has a WGSL twin of the same name and the same arguments in
//! `crates/tress-render/src/shaders/common/shading.wgsl`. The twins exist so a GPU test can evaluate
//! the WGSL function on a grid of inputs and compare it with the CPU function (design rule 6), and
//! so the math can be unit-tested for its properties without a GPU. Names follow the papers'
//! symbols (design rule 5); every item cites its paper, section and equation.
//!
//! ```
//! use glam::{Vec3, Vec4};
//! use tress_shading::{KajiyaKay, blend_front_to_back, composite_over_background, kajiya_kay};
//!
//! // A vertical strand lit and seen head-on: both Kajiya-Kay lobes at their peak.
//! let kk = KajiyaKay::default();
//! let (t, l, v) = (Vec3::Y, Vec3::Z, Vec3::Z);
//! let color = kajiya_kay(&kk, t, l, v);
//! assert!(color.abs_diff_eq(kk.diffuse + kk.specular, 1e-5));
//!
//! // Two such fragments of alpha 0.5, front to back, over a white background.
//! let acc = blend_front_to_back(blend_front_to_back(Vec4::ZERO, color, 0.5), color, 0.5);
//! assert_eq!(acc.w, 0.75);
//! let pixel = composite_over_background(acc, Vec3::ONE);
//! assert!(pixel.abs_diff_eq(0.75 * color + Vec3::splat(0.25), 1e-5));
//! ```
//!
//! # Conventions
//!
//! - Every direction points *away* from the shaded point: `l` towards the light, `v` towards the
//!   eye. `t` is the unit strand tangent, pointing from root to tip. All of them are unit vectors
//!   unless a function says otherwise.
//! - Colors are linear RGB. Compositing inputs are *straight* (not premultiplied) colors with a
//!   separate alpha; accumulators are *premultiplied* (see [`blend`]).
//! - Screen coordinates follow wgpu: origin at the top-left corner of the framebuffer, `y` down,
//!   pixel centres at half-integers (what `@builtin(position)` holds in a fragment shader).
//!
//! # CPU ↔ WGSL signatures
//!
//! | CPU (this crate) | WGSL (`shading.wgsl`) |
//! | --- | --- |
//! | [`KajiyaKay`] `{ diffuse: Vec3, specular: Vec3, exponent: f32 }` | `struct KajiyaKay { diffuse: vec3f, specular: vec3f, exponent: f32 }` |
//! | [`kajiya_kay_diffuse`]`(t: Vec3, l: Vec3) -> f32` | `kajiya_kay_diffuse(t: vec3f, l: vec3f) -> f32` |
//! | [`kajiya_kay_specular`]`(t: Vec3, l: Vec3, v: Vec3, exponent: f32) -> f32` | `kajiya_kay_specular(t: vec3f, l: vec3f, v: vec3f, exponent: f32) -> f32` |
//! | [`kajiya_kay()`]`(kk: &KajiyaKay, t: Vec3, l: Vec3, v: Vec3) -> Vec3` | `kajiya_kay(kk: KajiyaKay, t: vec3f, l: vec3f, v: vec3f) -> vec3f` |
//! | [`spread_kajiya_kay`]`(kk: &KajiyaKay, mean_length: f32) -> KajiyaKay` | `spread_kajiya_kay(kk: KajiyaKay, mean_length: f32) -> KajiyaKay` |
//! | [`shift_tangent`]`(t: Vec3, n: Vec3, shift: f32) -> Vec3` | `shift_tangent(t: vec3f, n: vec3f, shift: f32) -> vec3f` |
//! | [`strand_specular`]`(t: Vec3, v: Vec3, l: Vec3, exponent: f32) -> f32` | `strand_specular(t: vec3f, v: vec3f, l: vec3f, exponent: f32) -> f32` |
//! | [`scheuermann_diffuse`]`(n: Vec3, l: Vec3) -> f32` | `scheuermann_diffuse(n: vec3f, l: vec3f) -> f32` |
//! | [`HairLighting`] (7 fields, same order) | `struct HairLighting` |
//! | [`HairSample`] (6 fields, same order) | `struct HairSample` |
//! | [`hair_lighting`]`(p: &HairLighting, s: &HairSample, l: Vec3, light_color: Vec3, v: Vec3) -> Vec3` | `hair_lighting(p: HairLighting, s: HairSample, l: vec3f, light_color: vec3f, v: vec3f) -> vec3f` |
//! | [`coverage_from_distance`]`(d: f32, line_thickness: f32) -> f32` | `coverage_from_distance(d: f32, line_thickness: f32) -> f32` |
//! | [`screen_from_clip`]`(clip: Vec4, resolution: Vec2) -> Vec2` | `screen_from_clip(clip: vec4f, resolution: vec2f) -> vec2f` |
//! | [`strand_coverage`]`(screen_fragment: Vec2, world_line: Vec4, clip_from_world: Mat4, resolution: Vec2, line_thickness: f32) -> f32` | `strand_coverage(screen_fragment: vec2f, world_line: vec4f, clip_from_world: mat4x4f, resolution: vec2f, line_thickness: f32) -> f32` |
//! | [`tip_fade`]`(thickness: f32, line_thickness: f32) -> f32` | `tip_fade(thickness: f32, line_thickness: f32) -> f32` |
//! | [`strand_visibility`]`(n: f32, alpha: f32) -> f32` | `strand_visibility(n: f32, alpha: f32) -> f32` |
//! | [`adsm_visibility`]`(d: f32, r: f32, alpha: f32) -> f32` | `adsm_visibility(d: f32, r: f32, alpha: f32) -> f32` |
//! | [`adsm_depth`]`(fragment_depth: f32, occluder_depth: f32) -> f32` | `adsm_depth(fragment_depth: f32, occluder_depth: f32) -> f32` |
//! | [`adsm_pcf`]`(map: &DepthMap, texel: IVec2, kernel_radius: i32, fragment_depth: f32, r: f32, alpha: f32) -> f32` | `adsm_pcf(map: texture_depth_2d, texel: vec2i, kernel_radius: i32, fragment_depth: f32, r: f32, alpha: f32) -> f32` |
//! | [`blend_under`]`(acc: Vec4, src: Vec4) -> Vec4` | `blend_under(acc: vec4f, src: vec4f) -> vec4f` |
//! | [`blend_front_to_back`]`(acc: Vec4, color: Vec3, alpha: f32) -> Vec4` | `blend_front_to_back(acc: vec4f, color: vec3f, alpha: f32) -> vec4f` |
//! | [`TailAccum`] `{ weighted_color: Vec3, alpha_sum: f32, transmittance: f32 }`, [`TailAccum::EMPTY`] | `struct TailAccum`, `tail_empty() -> TailAccum` |
//! | [`tail_accumulate`]`(tail: TailAccum, color: Vec3, alpha: f32) -> TailAccum` | `tail_accumulate(tail: TailAccum, color: vec3f, alpha: f32) -> TailAccum` |
//! | [`tail_resolve`]`(tail: TailAccum) -> Vec4` | `tail_resolve(tail: TailAccum) -> vec4f` |
//! | [`composite_over_background`]`(acc: Vec4, background: Vec3) -> Vec3` | `composite_over_background(acc: vec4f, background: vec3f) -> vec3f` |
//!
//! Volume twins (Jansson et al. 2019 §3.3–3.4 and the LOD blend), WGSL side in
//! `shaders/common/volume.wgsl`; the WGSL functions that read the volume take the 3D texture, its
//! sampler and how its texels read (`VolumeTexels`: resolution, density unit) where the CPU takes a [`DensityVolume`] (`tests/volume_twins.rs`
//! checks the names and arguments):
//!
//! | CPU (this crate) | WGSL (`volume.wgsl`) |
//! | --- | --- |
//! | [`voxel_hash`]`(x: u32) -> u32`, [`voxelize::isqrt`]`(x: u32) -> u32` | `voxel_hash(x: u32) -> u32`, `isqrt(x: u32) -> u32` |
//! | [`quantize_tangent`]`(t: Vec3) -> UVec3`, [`dequantize_tangent`]`(sum: Vec3, count: f32) -> Vec3` | `quantize_tangent(t: vec3f) -> vec3u`, `dequantize_tangent(sum: vec3f, count: f32) -> vec3f` |
//! | [`voxelize::segment_sample_count`]`(q0, q1: UVec3, segment: u32) -> u32`, [`voxelize::segment_sample`]`(a, d: IVec3, k, n: u32) -> UVec3` | `segment_sample_count(q0, q1: vec3u, segment: u32) -> u32`, `segment_sample(a, d: vec3i, k, n: u32) -> vec3u` |
//! | [`voxelize::encode_texel`]`(tangent: Vec3, count: u32) -> [u8; 4]`, [`voxelize::decode_texel`]`(bytes: [u8; 4], density_unit: f32) -> (Vec3, f32)` | `encode_texel(tangent: vec3f, count: u32) -> vec4f` (normalized), `decode_texel(raw: vec4f, density_unit: f32) -> vec4f` |
//! | [`ray_box`]`(o, d, lo, hi: Vec3) -> (f32, f32)` | `ray_box(o, d, lo, hi: vec3f) -> vec2f` |
//! | [`volume_shadow_strands`]`(vol, x: Vec3, l: Vec3, step: f32, offset: f32) -> f32` | `volume_shadow_strands(tex, samp, vt: VolumeTexels, x, l: vec3f, step, offset: f32) -> f32` |
//! | [`ao_offset`]`(i: u32, n: u32) -> Vec3`, [`volume_ao`]`(vol, x: Vec3, radius: f32, samples: u32, intensity: f32, alpha: f32) -> f32` | `ao_offset(i, n: u32) -> vec3f`, `volume_ao(tex, samp, vt: VolumeTexels, x: vec3f, radius: f32, samples: u32, intensity, alpha: f32) -> f32` |
//! | [`density_gradient`]`(vol, x: Vec3) -> Vec3`, [`density_normal`]`(gradient: Vec3, fallback: Vec3) -> Vec3` | `density_gradient(tex, samp, vt: VolumeTexels, x: vec3f) -> vec3f`, `density_normal(gradient, fallback: vec3f) -> vec3f` |
//! | [`volume_adsm_visibility`]`(vol, x, l: Vec3, step, offset, width, ln_keep, bias: f32) -> f32` | `volume_adsm_visibility(tex, samp, vt: VolumeTexels, x, l: vec3f, step, offset, width, ln_keep, bias: f32) -> f32` |
//! | [`composite_transmittance`]`(strands, iso: f32) -> f32`, [`fake_transparency_alpha`]`(strands: f32, iso: f32) -> f32`, [`composite_point_reached`]`(tr: f32, m, k: u32) -> bool` | `composite_transmittance(strands, iso: f32) -> f32`, `fake_transparency_alpha(strands: f32, iso: f32) -> f32`, `composite_point_reached(tr: f32, m, k: u32) -> bool` |
//! | [`strand_optical_depth`]`(strands: f32, tangent, dir: Vec3, pixel_voxels, optical_width: f32) -> f32` | `strand_optical_depth(strands: f32, tangent, dir: vec3<f32>, pixel_voxels, optical_width: f32) -> f32` |
//! | [`volume_tangent_coherence`]`(vol: &TexelVolume, x: Vec3) -> f32` | `volume_tangent_coherence(tex, samp, vt: VolumeTexels, x: vec3<f32>) -> f32` |
//! | [`lod_factor`]`(distance, near, far: f32) -> f32`, [`dither_threshold`]`(px: UVec2) -> f32` | `lod_factor(distance, near, far: f32) -> f32`, `dither_threshold(px: vec2u) -> f32` |
//! | [`highlights::quantize_highlight`]`(s: f32) -> u32`, [`highlights::highlight_texel`]`(sum, count: u32) -> u8` | `quantize_highlight(s: f32) -> u32`, `highlight_texel(sum, count: u32) -> u32` |
//! | [`highlights::volume_highlight`]`(vol: &HighlightVolume, x: Vec3, light: usize) -> f32` | `volume_highlight(highlights, volume: texture_3d<f32>, vt: VolumeTexels, x: vec3<f32>, light: u32) -> f32` |
//!
//! Physically based hair (`shading = "marschner"`): the real-time lobes of [`marschner`] (Karis
//! 2016) and the multiple scattering of [`dual_scattering`] (Zinke et al. 2008), WGSL side in
//! `shaders/common/marschner.wgsl` (`tests/marschner_wgsl.rs` checks names, arguments and struct
//! sizes). Their material is a [`fiber::HairFiber`]; [`marschner::Marschner::from_fiber`],
//! [`dual_scattering::DualScattering::from_marschner`] and the colour conversions of [`fiber`]
//! are CPU-only (run once per material, their results uploaded):
//!
//! | CPU (this crate) | WGSL (`marschner.wgsl`) |
//! | --- | --- |
//! | [`marschner::Marschner`] `{ sigma_a: Vec3, eta: f32, beta: Vec3, alpha: f32 }` | `struct Marschner` (32 bytes) |
//! | [`marschner::HairAngles`] (6 fields), [`marschner::hair_angles`]`(t, l, v: Vec3)` | `struct HairAngles`, `hair_angles(t, l, v: vec3f) -> HairAngles` |
//! | [`marschner::hair_gaussian`]`(beta, x: f32) -> f32`, [`marschner::fresnel_schlick`]`(eta, cos_theta: f32) -> f32` | `hair_gaussian(beta, x: f32) -> f32`, `fresnel_schlick(eta, cos_theta: f32) -> f32` |
//! | [`marschner::marschner_r`]`(m, a) -> f32`, [`marschner::marschner_tt`]`(m, a) -> Vec3`, [`marschner::marschner_trt`]`(m, a) -> Vec3` | `marschner_r(m: Marschner, a: HairAngles) -> f32`, `marschner_tt(..) -> vec3f`, `marschner_trt(..) -> vec3f` |
//! | [`marschner::marschner()`]`(m, t, l, v) -> Vec3`, [`marschner::marschner_lighting`]`(m, t, l, light_color, v) -> Vec3` | `marschner(m, t, l, v) -> vec3f`, `marschner_lighting(m, t, l, light_color, v) -> vec3f` |
//! | [`dual_scattering::DualScattering`] (16-entry tables), [`dual_scattering::DualScattering::at`]`(sin_theta_i) -> DualScatteringAt` | `struct DualScattering` (1072 bytes), `dual_scattering_at(ds, sin_theta_i: f32) -> DualScatteringAt` |
//! | [`dual_scattering::dual_scattering_lighting`]`(m, ds, t, l, light_color, v, strands: f32, direct: f32) -> Vec3` | `dual_scattering_lighting(m, ds, t, l, light_color, v, strands: f32, direct: f32) -> vec3f` |
//!
//! The CPU voxelizer [`voxelize()`] (and [`voxelize::voxelize_lit`] with the integrated
//! highlights of [`highlights`]) is the reference of the renderer's voxelize and resolve passes as
//! a whole (the GPU test compares every voxel).
//!
//! CPU-only helpers, compositions of the twins above with no WGSL counterpart (their loops live in
//! the technique's resolve shader): [`StrandFragment`], [`composite_sorted`], [`resolve_k_buffer`],
//! [`resolve_shortcut`],
//! and the [`DepthMap`] view that stands in for the shadow-map texture.
//!
//! Where the WGSL result is undefined (WGSL `pow(x, y)` for `x = 0, y <= 0`, `normalize` of a zero
//! vector), the CPU twin documents the precondition; GPU-vs-CPU tests keep their grids inside it.

pub mod blend;
pub mod coverage;
pub mod dual_scattering;
pub mod fiber;
pub mod highlights;
pub mod kajiya_kay;
pub mod marschner;
pub mod scheuermann;
pub mod shadow;
pub mod shortcut;
#[cfg(test)]
mod test_util;
pub mod volume;
pub mod voxelize;

pub use blend::{
    StrandFragment, TailAccum, blend_front_to_back, blend_under, composite_over_background,
    composite_sorted, resolve_k_buffer, tail_accumulate, tail_resolve,
};
pub use coverage::{coverage_from_distance, screen_from_clip, strand_coverage, tip_fade};
pub use kajiya_kay::{
    KajiyaKay, TANGENT_SPREAD_WIDENING, kajiya_kay, kajiya_kay_diffuse, kajiya_kay_specular,
    spread_kajiya_kay,
};
pub use scheuermann::{
    HairLighting, HairSample, hair_lighting, scheuermann_diffuse, shift_tangent, strand_specular,
};
pub use shadow::{
    DepthMap, MAX_PCF_RADIUS, MAX_SHADOW_STRANDS, ShadingError, adsm_depth, adsm_pcf,
    adsm_visibility, strand_visibility, strands_from_visibility,
};
pub use shortcut::{
    SHORTCUT_ALPHA_LEVELS, SHORTCUT_DEPTH_LEVELS, SHORTCUT_TAIL_PICK, SHORTCUT_TAIL_SALT,
    SHORTCUT_TAIL_SPACINGS, ShortcutFragment, resolve_shortcut, shortcut_accumulator, shortcut_key,
    shortcut_key_depth, shortcut_layer_alpha, shortcut_tail_falloff, shortcut_tail_weight,
};
pub use volume::{
    DensityVolume, NO_CAP, TexelVolume, VolumeSizeError, ao_offset, composite_point_reached,
    composite_transmittance, density_gradient, density_normal, dither_threshold,
    fake_transparency_alpha, line_optical_width, lod_factor, ray_box, strand_optical_depth,
    volume_adsm_visibility, volume_ao, volume_shadow_strands, volume_tangent_coherence,
};
pub use voxelize::{
    VoxelCounts, VoxelGrid, VoxelValue, VoxelizeMode, dequantize_tangent, quantize_tangent,
    segment_fade, voxel_hash, voxelize,
};

/// `sqrt(1 - c²)`, the sine of the angle whose cosine is `c`, clamped so a `|c|` rounded slightly
/// above 1 gives 0 instead of NaN. Mirrors the WGSL `sin_from_cos`.
pub(crate) fn sin_from_cos(c: f32) -> f32 {
    (1.0 - c * c).max(0.0).sqrt()
}

/// sRGB transfer function (linear to encoded), input clamped to `[0, 1]`: what the GPU's sRGB
/// targets apply, for the CPU's image writers (`tress-render`'s readback, `tress-trace`).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// WGSL `saturate`: clamp to `[0, 1]`.
pub(crate) fn saturate(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

/// WGSL / HLSL `smoothstep(low, high, x)`: Hermite interpolation `t²(3 - 2t)` of
/// `t = saturate((x - low) / (high - low))`.
pub(crate) fn smoothstep(low: f32, high: f32, x: f32) -> f32 {
    let t = saturate((x - low) / (high - low));
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothstep_matches_its_definition() {
        assert_eq!(smoothstep(-1.0, 0.0, -2.0), 0.0);
        assert_eq!(smoothstep(-1.0, 0.0, 0.5), 1.0);
        assert!((smoothstep(-1.0, 0.0, -0.5) - 0.5).abs() < 1e-6);
        // t = 0.25: 0.0625 * 2.5 = 0.15625
        assert!((smoothstep(-1.0, 0.0, -0.75) - 0.15625).abs() < 1e-6);
    }

    #[test]
    fn sin_from_cos_never_nan() {
        assert_eq!(sin_from_cos(1.000_001), 0.0);
        assert!((sin_from_cos(0.6) - 0.8).abs() < 1e-6);
    }
}
