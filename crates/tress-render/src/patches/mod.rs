//! Polygon-patch hair (Scheuermann 2004, `patches`): layered, alpha-textured 2D patches shaded
//! with two shifted strand highlights and baked ambient occlusion, drawn in a static
//! inside-to-outside order with the slides' 4-pass (or 3-pass) scheme.
//!
//! The CPU side (the [`PatchMesh`](tress_hair::patches::PatchMesh), its generator, OBJ import,
//! strand-to-card conversion, procedural textures, AO bake and sort) lives in
//! `tress_hair::patches`; this module uploads it ([`PatchGeometry`], [`PatchTextures`]) and draws
//! it ([`PatchRenderer`]). [`scene`] turns a scene's `[patches]` table and hair into both.
//!
//! # Implementation
//!
//! Papers: T. Scheuermann, "Practical Real-Time Hair Rendering and Shading", SIGGRAPH 2004
//! sketch (`papers/scheuermann-2004-sketch.txt`), and the slides "Hair Rendering and Shading"
//! (`papers/scheuermann-2004-slides.md`), which carry the shader functions and both render
//! schemes.
//!
//! A frame (`renderer.rs`, top to bottom): uniforms; the head, first (slide "Performance
//! Tuning": "usually half the hair is hidden behind the head – draw head first"); then the
//! scheme's passes over the one static index buffer.
//!
//! - **Geometry** ([`PatchGeometry`], `geometry.wgsl`). One interleaved vertex per mesh vertex:
//!   position, normal, tangent (root to tip), UV and the baked AO (slide "Shader Breakdown":
//!   the vertex shader "just passes down tangent, normal, view vector, light vector, ambient
//!   occlusion term"; the view and light vectors are formed per pixel from the world position).
//!   The index buffer is sorted once at upload, whole patches inside to outside around the head
//!   centre (slide "Approximate Depth Sorting"; `tress_hair::patches::sorted_indices`), and never
//!   re-sorted.
//! - **Textures** ([`PatchTextures`], slide "Hair Model - Textures"): base, alpha, specular
//!   shift and specular noise, procedural (`tress_hair::patches::texture`; size, seed and look
//!   are settings) or read from PNG files. Mip-mapped (`mipmaps`, default on), repeating across
//!   `u`, clamped along `v`.
//! - **Shading** (`patch_shade.wgsl`, slide "Putting it All Together"). Per light, exactly the
//!   slide's `HairLighting` through the shared `shading.wgsl` functions (twins of
//!   `tress_shading::scheuermann`): `shiftTex = tex2D(tSpecShift, uv) − 0.5`; tangents shifted
//!   along the normal by `primary_shift + shiftTex` and `secondary_shift + shiftTex`
//!   (`ShiftTangent`); diffuse `saturate(lerp(0.25, 1, N·L)) · diffuse_color`; two
//!   `StrandSpecular` terms with their colors and exponents (half vector, `sin(T, H)^exp`,
//!   `smoothstep(−1, 0, T·H)`), the second times the specular noise texture; the sum times the
//!   base texture, the light's color × intensity and the AO; alpha from the alpha texture. Choices
//!   the slides leave open: several lights add up (the slide shows one); the frame's ambient light
//!   adds `ambient · base · ao` (zero ambient gives the slide's formula exactly); the interpolated
//!   tangent is made perpendicular to the interpolated normal again (`ShiftTangent` assumes
//!   `T ⟂ N`); the normal is **not** flipped on back faces, because it stands for the outward
//!   direction of the hair volume the patch approximates (the generator's and the card
//!   converter's normals point away from the head): the side of the hair away from the light
//!   stays dark whichever face is seen, and the highlight shifts keep their direction along
//!   the hair. Every constant is a setting ([`PatchSettings`]).
//! - **Render schemes** ([`RenderScheme`], [`FOUR_PASS`], [`THREE_PASS`]). wgpu has no
//!   fixed-function alpha test; it is a `discard` against `alpha_ref` (default 0.99: "opaque"
//!   with room for filtering round-off) in the passes the slides give one. The default
//!   `"4-pass"` is the slides' "Optimized Rendering Scheme" and the sketch's four passes:
//!   (1) `patches/z_prime`: `z_prime.wgsl` returns only alpha, alpha test passes opaque pixels,
//!   no culling, Z writes, `Less`, color writes masked off; (2) `patches/opaque`: full shader,
//!   no culling, no Z writes, `Equal`, so "the same opaque pixels as in the first pass get
//!   shaded"; (3) `patches/back`: cull front faces, no Z writes, `Less`; (4) `patches/front`:
//!   cull back faces, Z writes, `Less`. Passes 2 to 4 have no `discard`, so early Z can skip
//!   the shading of hidden pixels, which is the point of the extra pass (sketch, "Early-Z
//!   Culling"); an opaque texel fails `Less` against its own primed depth, so passes 3 and 4
//!   blend only the transparent parts in front of the nearest opaque hair. The vertex position
//!   is `@invariant`, so pass 2 reproduces pass 1's depth bit for bit. `"3-pass"` is the slides'
//!   unoptimized "Sorted Hair Rendering Scheme": (1) alpha test passes opaque pixels, no
//!   culling, Z writes, `Less`; (2) alpha test passes non-opaque pixels, cull front faces, no Z
//!   writes, `Less`; (3) the same with back faces culled and Z writes. Each pass is one render
//!   pass with its own GPU timestamps ([`PASS_NAMES`]).
//! - **Empty fragments (an option beside the paper).** In both schemes the last pass writes
//!   depth for every transparent fragment it draws, alpha 0 included, so the empty parts of a
//!   patch (between its strands, past its tips) hide every patch drawn after it and behind it:
//!   wherever the static inside-to-outside order disagrees with the view (hair hanging below the
//!   head, strips crossing), later strips are cut off along the edges of earlier quads.
//!   `min_alpha > 0` makes that pass alone discard fragments with alpha below it
//!   ([`RenderScheme::passes_with`]); the other passes, and early Z in them, are unchanged.
//!   The default 0 is the slides' schemes exactly; about 0.05 suits textures with large empty
//!   areas such as the procedural alpha texture.
//! - **Blending.** Every color pass blends the shader's straight color "over" the target
//!   (`SrcAlpha, OneMinusSrcAlpha`; alpha `One, OneMinusSrcAlpha`), leaving the premultiplied
//!   target the rest of the renderer uses.
//! - **Front faces** are counter-clockwise, i.e. seen from the side the normal points to
//!   (the `PatchMesh` convention).

mod geometry;
mod passes;
mod patch_head;
mod patch_shade;
mod renderer;
pub mod scene;
pub(crate) mod scene_doc;
mod technique;
mod textures;
mod z_prime;

pub use geometry::{PatchGeometry, patch_vertices};
pub use passes::{
    AlphaTest, BLEND, FOUR_PASS, PassShader, PatchPass, PatchPipelineParts, RenderScheme,
    THREE_PASS,
};
pub(crate) use patch_head::patch_head;
pub use patch_shade::PatchShade;
pub use renderer::{PatchFrameInputs, PatchFrameStats, PatchRenderer};
pub(crate) use technique::PatchTechnique;
pub use textures::{
    MAX_TEXTURE_EDGE, PatchTextures, TextureSlot, downsample, load_texture_png, mip_chain,
    save_texture_png, save_textures_png, texture_image, validate_texture,
};
pub use z_prime::ZPrime;

use glam::Vec3;
use tress_hair::patches::TextureParams;
use tress_shading::HairLighting;
use tress_shading::fiber::HairFiber;

use crate::bind::{filterable_texture_2d, filtering_sampler, uniform};
use crate::gpu::types::{DualScatteringGpu, FiberUniform, HairLightingGpu, PatchParamsGpu};
use crate::{RenderError, Shading};

/// Names of the timed passes, in frame order (a 3-pass frame has no `patches/z_prime`).
pub const PASS_NAMES: &[&str] = &[
    "head",
    "patches/z_prime",
    "patches/opaque",
    "patches/back",
    "patches/front",
];

/// Settings of the patch technique: every constant of the slides' shader, the scheme, and the
/// procedural textures.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchSettings {
    /// The render scheme (default [`RenderScheme::FourPass`]).
    pub scheme: RenderScheme,
    /// The slide's external constants of `HairLighting` (default
    /// `tress_shading::HairLighting::default()`).
    pub lighting: HairLighting,
    /// Alpha test reference in `(0, 1]`: alpha at or above it is opaque. Default 0.99.
    pub alpha_ref: f32,
    /// An option beside the slides' schemes, in `[0, alpha_ref)`: when positive, the last pass
    /// (the only transparent pass that writes depth) discards fragments with alpha below it, so
    /// the empty parts of a patch do not hide patches drawn after it. Default 0: the slides'
    /// schemes exactly.
    pub min_alpha: f32,
    /// Multiply by the mesh's baked ambient occlusion. Default true.
    pub ambient_occlusion: bool,
    /// Build mip chains for the textures. Default true.
    pub mipmaps: bool,
    /// The procedural textures (used unless textures are given explicitly).
    pub textures: TextureParams,
    /// The pixel shader's model: [`Shading::Scheuermann`] (default, the slides' `HairLighting`)
    /// or [`Shading::Marschner`] (Marschner's lobes of [`PatchSettings::fiber`] with dual
    /// scattering's local back-scattering; the base texture only tints the ambient term). Kajiya-Kay
    /// is the strands' model and is refused here.
    pub shading: Shading,
    /// The physically based fibre under [`Shading::Marschner`] (the hair material's melanin,
    /// roughness, tilt and η).
    pub fiber: HairFiber,
}

impl Default for PatchSettings {
    fn default() -> Self {
        PatchSettings {
            scheme: RenderScheme::FourPass,
            lighting: HairLighting::default(),
            alpha_ref: 0.99,
            min_alpha: 0.0,
            ambient_occlusion: true,
            mipmaps: true,
            textures: TextureParams::default(),
            shading: Shading::Scheuermann,
            fiber: HairFiber::default(),
        }
    }
}

impl PatchSettings {
    /// Check every setting's range; the error names the setting (`patches.<key>`).
    pub fn validate(&self) -> Result<(), RenderError> {
        let bad =
            |name: &str, why: &str| Err(RenderError::Invalid(format!("patches.{name} {why}")));
        let l = &self.lighting;
        for (name, c) in [
            ("diffuse_color", l.diffuse_color),
            ("primary_color", l.primary_color),
            ("secondary_color", l.secondary_color),
        ] {
            if !(c.is_finite() && c.min_element() >= 0.0) {
                return bad(name, "must be finite and non-negative");
            }
        }
        for (name, e) in [
            ("primary_exponent", l.primary_exponent),
            ("secondary_exponent", l.secondary_exponent),
        ] {
            if !(e.is_finite() && e > 0.0) {
                return bad(name, "must be finite and positive");
            }
        }
        for (name, s) in [
            ("primary_shift", l.primary_shift),
            ("secondary_shift", l.secondary_shift),
        ] {
            if !(s.is_finite() && s.abs() <= 100.0) {
                return bad(name, "must be finite and in [-100, 100]");
            }
        }
        if !(self.alpha_ref > 0.0 && self.alpha_ref <= 1.0) {
            return bad("alpha_ref", "must be in (0, 1]");
        }
        if !(self.min_alpha >= 0.0 && self.min_alpha < self.alpha_ref) {
            return bad("min_alpha", "must be in [0, alpha_ref)");
        }
        if self.shading == Shading::KajiyaKay {
            return bad(
                "shading",
                "must be scheuermann or marschner (kajiya-kay is the strands' model)",
            );
        }
        self.fiber
            .validate()
            .map_err(|e| RenderError::setting("patches.fiber", e))?;
        self.textures
            .validate()
            .map_err(|e| RenderError::setting("patches.textures", e))
    }

    /// The GPU uniform.
    pub fn params(&self) -> PatchParamsGpu {
        let l = &self.lighting;
        PatchParamsGpu {
            lighting: HairLightingGpu {
                diffuse_color: l.diffuse_color.to_array(),
                primary_exponent: l.primary_exponent,
                primary_color: l.primary_color.to_array(),
                primary_shift: l.primary_shift,
                secondary_color: l.secondary_color.to_array(),
                secondary_exponent: l.secondary_exponent,
                secondary_shift: l.secondary_shift,
                _pad: [0.0; 3],
            },
            alpha_ref: self.alpha_ref,
            use_ao: u32::from(self.ambient_occlusion),
            min_alpha: self.min_alpha,
            shading: u32::from(self.shading == Shading::Marschner),
            fiber: [[0.0; 4]; 2],
            dual: DualScatteringGpu::default(),
        }
    }

    /// [`PatchSettings::params`] with the fibre's lobes and dual-scattering table when the
    /// patches shade with Marschner (`fiber` is [`FiberUniform::new`] of
    /// [`PatchSettings::fiber`], computed once: the table takes some 20 ms).
    pub fn params_with(&self, fiber: &FiberUniform) -> PatchParamsGpu {
        let mut p = self.params();
        if self.shading == Shading::Marschner {
            p.fiber = fiber.marschner;
            p.dual = fiber.dual;
        }
        p
    }

    /// The passes these settings draw: the scheme's, with the `min_alpha` option applied
    /// ([`RenderScheme::passes_with`]).
    pub fn passes(&self) -> Vec<PatchPass> {
        self.scheme.passes_with(self.min_alpha > 0.0)
    }
}

/// The bind group layouts of the patch passes: the technique's own, so that it does not depend
/// on the strand technique's lighting group.
///
/// | group | layout | contents |
/// | --- | --- | --- |
/// | 0 | `view` | camera |
/// | 1 | `lights` | lights, head color |
/// | 2 | `material` | patch constants, base, alpha, shift and noise textures, sampler |
#[derive(Debug)]
pub(crate) struct PatchLayouts {
    pub(crate) view: wgpu::BindGroupLayout,
    pub(crate) lights: wgpu::BindGroupLayout,
    pub(crate) material: wgpu::BindGroupLayout,
}

impl PatchLayouts {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let texture = |binding| filterable_texture_2d(binding, fragment);
        let view = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("patches/view/layout"),
            entries: &[uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT)],
        });
        let lights = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("patches/lights/layout"),
            entries: &[uniform(0, fragment), uniform(1, fragment)],
        });
        let material = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("patches/material/layout"),
            entries: &[
                uniform(0, fragment),
                texture(1),
                texture(2),
                texture(3),
                texture(4),
                filtering_sampler(5, fragment),
            ],
        });
        PatchLayouts {
            view,
            lights,
            material,
        }
    }
}

/// The centre patches are sorted around when no head is known: the centre of the mesh bounds.
pub fn default_sort_center(mesh: &tress_hair::patches::PatchMesh) -> Vec3 {
    mesh.bounds().map_or(Vec3::ZERO, |b| b.center())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_follow_the_slides() {
        let s = PatchSettings::default();
        s.validate().expect("valid");
        assert_eq!(s.scheme, RenderScheme::FourPass);
        let p = s.params();
        assert_eq!(
            p.lighting.primary_shift,
            HairLighting::default().primary_shift
        );
        assert_eq!(p.use_ao, 1);
    }

    #[test]
    fn out_of_range_settings_name_themselves() {
        let check = |s: PatchSettings, name: &str| {
            let e = s.validate().expect_err(name).to_string();
            assert!(e.contains(name), "{e}");
        };
        let d = PatchSettings::default;
        check(
            PatchSettings {
                alpha_ref: 0.0,
                ..d()
            },
            "patches.alpha_ref",
        );
        let mut s = d();
        s.lighting.secondary_exponent = -1.0;
        check(s, "patches.secondary_exponent");
        let mut s = d();
        s.lighting.primary_color = Vec3::NAN;
        check(s, "patches.primary_color");
        let mut s = d();
        s.textures.width = 0;
        check(s, "patches.textures");
    }
}
