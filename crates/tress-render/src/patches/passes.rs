//! The render schemes of the slides as data: each pass's alpha test, culling, depth compare and
//! writes ([`PatchPass`]), and the pipeline descriptor parts built from them
//! ([`PatchPipelineParts`]), which the pass owners ([`ZPrime`](super::ZPrime),
//! [`PatchShade`](super::PatchShade)) hand to wgpu unchanged. Tests check these parts against
//! the slides.

use std::fmt;
use std::str::FromStr;

use crate::RenderError;
use crate::gpu::DEPTH_FORMAT;
use crate::gpu::pipeline::RasterPipeline;

/// Which of the slides' two schemes draws the patches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RenderScheme {
    /// "Optimized Rendering Scheme": Z prime, opaque (`Equal`), transparent back faces,
    /// transparent front faces; `"4-pass"`.
    #[default]
    FourPass,
    /// "Sorted Hair Rendering Scheme": alpha-tested opaque, transparent back faces, transparent
    /// front faces; `"3-pass"`.
    ThreePass,
}

impl RenderScheme {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            RenderScheme::FourPass => "4-pass",
            RenderScheme::ThreePass => "3-pass",
        }
    }

    /// The passes exactly as the slides give them, in draw order (after the head).
    pub fn passes(self) -> &'static [PatchPass] {
        match self {
            RenderScheme::FourPass => &FOUR_PASS,
            RenderScheme::ThreePass => &THREE_PASS,
        }
    }

    /// The passes with the `min_alpha` option (`drop_empty`): the last pass, the only
    /// transparent one that writes depth, also discards fragments with `alpha < min_alpha`, so
    /// the empty parts of a patch (between strands, past the tips) do not hide the patches drawn
    /// after it. Without the option these are [`RenderScheme::passes`].
    pub fn passes_with(self, drop_empty: bool) -> Vec<PatchPass> {
        self.passes()
            .iter()
            .map(|p| {
                let transparent_z = p.shader == PassShader::Full && p.depth_write;
                let alpha_test = match (drop_empty && transparent_z, p.alpha_test) {
                    (true, AlphaTest::Off) => AlphaTest::PassNonEmpty,
                    (true, AlphaTest::PassTransparent) => AlphaTest::PassTransparentNonEmpty,
                    (_, a) => a,
                };
                PatchPass { alpha_test, ..*p }
            })
            .collect()
    }
}

impl fmt::Display for RenderScheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for RenderScheme {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "4-pass" => Ok(RenderScheme::FourPass),
            "3-pass" => Ok(RenderScheme::ThreePass),
            _ => Err(RenderError::Invalid(format!(
                "unknown patches.scheme `{s}` (expected 4-pass or 3-pass)"
            ))),
        }
    }
}

/// The alpha test of a pass (`discard` in the fragment shader; wgpu has no fixed-function alpha
/// test).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AlphaTest {
    /// No alpha test: every fragment that passes the depth test is shaded and blended.
    Off,
    /// Only opaque pixels pass: `alpha >= alpha_ref`.
    PassOpaque,
    /// Only non-opaque pixels pass: `alpha < alpha_ref`.
    PassTransparent,
    /// Only pixels that are not (nearly) empty pass: `alpha >= min_alpha` (the `min_alpha`
    /// option's depth-writing pass of the 4-pass scheme).
    PassNonEmpty,
    /// Only non-opaque pixels that are not (nearly) empty pass: `min_alpha <= alpha <
    /// alpha_ref` (the `min_alpha` option's depth-writing pass of the 3-pass scheme).
    PassTransparentNonEmpty,
}

/// Which fragment shader a pass runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PassShader {
    /// `z_prime.wgsl`: returns only the alpha (the optimized scheme's pass 1).
    AlphaOnly,
    /// `patch_shade.wgsl`: the full `HairLighting` shader.
    Full,
}

/// One pass of a scheme: its render state, exactly as the slides list it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PatchPass {
    /// Timer and label name (`patches/z_prime`, `patches/opaque`, `patches/back`,
    /// `patches/front`).
    pub name: &'static str,
    /// The fragment shader.
    pub shader: PassShader,
    /// The alpha test.
    pub alpha_test: AlphaTest,
    /// Faces culled (`None`: back-face culling disabled).
    pub cull_mode: Option<wgpu::Face>,
    /// Z test.
    pub depth_compare: wgpu::CompareFunction,
    /// Z writes.
    pub depth_write: bool,
    /// Color buffer writes.
    pub color_write: bool,
}

/// The slides' "Optimized Rendering Scheme" (and the sketch's four passes).
pub const FOUR_PASS: [PatchPass; 4] = [
    // Pass 1 - prime Z buffer: alpha test passes opaque pixels, no back-face culling, Z writes,
    // Z test Less, color writes off, a pixel shader that only returns alpha.
    PatchPass {
        name: "patches/z_prime",
        shader: PassShader::AlphaOnly,
        alpha_test: AlphaTest::PassOpaque,
        cull_mode: None,
        depth_compare: wgpu::CompareFunction::Less,
        depth_write: true,
        color_write: false,
    },
    // Pass 2 - opaque parts: no back-face culling, no Z writes, Z test Equal.
    PatchPass {
        name: "patches/opaque",
        shader: PassShader::Full,
        alpha_test: AlphaTest::Off,
        cull_mode: None,
        depth_compare: wgpu::CompareFunction::Equal,
        depth_write: false,
        color_write: true,
    },
    // Pass 3 - transparent back-facing parts: cull front faces, no Z writes, Z test Less.
    PatchPass {
        name: "patches/back",
        shader: PassShader::Full,
        alpha_test: AlphaTest::Off,
        cull_mode: Some(wgpu::Face::Front),
        depth_compare: wgpu::CompareFunction::Less,
        depth_write: false,
        color_write: true,
    },
    // Pass 4 - transparent front-facing parts: cull back faces, Z writes, Z test Less.
    PatchPass {
        name: "patches/front",
        shader: PassShader::Full,
        alpha_test: AlphaTest::Off,
        cull_mode: Some(wgpu::Face::Back),
        depth_compare: wgpu::CompareFunction::Less,
        depth_write: true,
        color_write: true,
    },
];

/// The slides' "Sorted Hair Rendering Scheme" (unoptimized).
pub const THREE_PASS: [PatchPass; 3] = [
    // Pass 1 - opaque parts: alpha test passes opaque pixels, no back-face culling, Z writes,
    // Z test Less.
    PatchPass {
        name: "patches/opaque",
        shader: PassShader::Full,
        alpha_test: AlphaTest::PassOpaque,
        cull_mode: None,
        depth_compare: wgpu::CompareFunction::Less,
        depth_write: true,
        color_write: true,
    },
    // Pass 2 - transparent back-facing parts: alpha test passes non-opaque pixels, cull front
    // faces, no Z writes, Z test Less.
    PatchPass {
        name: "patches/back",
        shader: PassShader::Full,
        alpha_test: AlphaTest::PassTransparent,
        cull_mode: Some(wgpu::Face::Front),
        depth_compare: wgpu::CompareFunction::Less,
        depth_write: false,
        color_write: true,
    },
    // Pass 3 - transparent front-facing parts: alpha test passes non-opaque pixels, cull back
    // faces, Z writes, Z test Less.
    PatchPass {
        name: "patches/front",
        shader: PassShader::Full,
        alpha_test: AlphaTest::PassTransparent,
        cull_mode: Some(wgpu::Face::Back),
        depth_compare: wgpu::CompareFunction::Less,
        depth_write: true,
        color_write: true,
    },
];

/// Straight-alpha "over" into a premultiplied target: color `src·a + dst·(1 − a)`, alpha
/// `a + dst·(1 − a)`.
pub const BLEND: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::SrcAlpha,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The parts of a pass's `wgpu::RenderPipelineDescriptor` that carry its render state; the pass
/// owners build their pipelines from exactly these.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchPipelineParts {
    /// Pipeline label (`<pass name>/pipeline`).
    pub label: String,
    /// WGSL module (path under `src/`).
    pub module: &'static str,
    /// Fragment entry point (the alpha test).
    pub fragment_entry: &'static str,
    /// Culling and winding (counter-clockwise front faces: seen from the normal's side).
    pub primitive: wgpu::PrimitiveState,
    /// Depth compare and writes.
    pub depth_stencil: wgpu::DepthStencilState,
    /// Blending and color writes.
    pub color_target: wgpu::ColorTargetState,
}

impl PatchPass {
    /// The fragment entry point that implements this pass's shader and alpha test.
    pub fn fragment_entry(&self) -> &'static str {
        match (self.shader, self.alpha_test) {
            (PassShader::AlphaOnly, _) => "fs_main",
            (PassShader::Full, AlphaTest::Off) => "fs_main",
            (PassShader::Full, AlphaTest::PassOpaque) => "fs_opaque",
            (PassShader::Full, AlphaTest::PassTransparent) => "fs_transparent",
            (PassShader::Full, AlphaTest::PassNonEmpty) => "fs_non_empty",
            (PassShader::Full, AlphaTest::PassTransparentNonEmpty) => "fs_transparent_non_empty",
        }
    }

    /// The WGSL module of the pass.
    pub fn module(&self) -> &'static str {
        match self.shader {
            PassShader::AlphaOnly => "patches/z_prime.wgsl",
            PassShader::Full => "patches/patch_shade.wgsl",
        }
    }

    /// The pipeline descriptor parts for a color target of `format`.
    pub fn pipeline_parts(&self, format: wgpu::TextureFormat) -> PatchPipelineParts {
        PatchPipelineParts {
            label: format!("{}/pipeline", self.name),
            module: self.module(),
            fragment_entry: self.fragment_entry(),
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: self.cull_mode,
                ..Default::default()
            },
            depth_stencil: wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(self.depth_write),
                depth_compare: Some(self.depth_compare),
                stencil: Default::default(),
                bias: Default::default(),
            },
            color_target: wgpu::ColorTargetState {
                format,
                blend: self.color_write.then_some(BLEND),
                write_mask: if self.color_write {
                    wgpu::ColorWrites::ALL
                } else {
                    wgpu::ColorWrites::empty()
                },
            },
        }
    }
}

/// Create a pass's pipeline from its parts (`shader` compiled from `parts.module`).
pub(crate) fn create_pipeline(
    ctx: &crate::GpuContext,
    layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    parts: &PatchPipelineParts,
) -> wgpu::RenderPipeline {
    RasterPipeline {
        buffers: &[Some(super::geometry::PATCH_VERTEX_LAYOUT)],
        primitive: parts.primitive,
        depth_stencil: Some(parts.depth_stencil.clone()),
        fragment_entry: Some(parts.fragment_entry),
        targets: &[Some(parts.color_target.clone())],
        ..RasterPipeline::new(&parts.label, layout, shader)
    }
    .create(ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scheme_names_round_trip() {
        for s in [RenderScheme::FourPass, RenderScheme::ThreePass] {
            assert_eq!(s.name().parse::<RenderScheme>().unwrap(), s);
        }
        assert!("2-pass".parse::<RenderScheme>().is_err());
    }

    #[test]
    fn min_alpha_only_changes_the_depth_writing_transparent_pass() {
        for s in [RenderScheme::FourPass, RenderScheme::ThreePass] {
            assert_eq!(s.passes_with(false), s.passes());
            let with = s.passes_with(true);
            let last = s.passes().len() - 1;
            for (i, (a, b)) in with.iter().zip(s.passes()).enumerate() {
                if i == last {
                    assert_ne!(a.alpha_test, b.alpha_test, "{}", a.name);
                    assert_eq!(
                        PatchPass {
                            alpha_test: b.alpha_test,
                            ..*a
                        },
                        *b
                    );
                } else {
                    assert_eq!(a, b);
                }
            }
        }
        let four = RenderScheme::FourPass.passes_with(true);
        assert_eq!(four[3].alpha_test, AlphaTest::PassNonEmpty);
        assert_eq!(four[3].fragment_entry(), "fs_non_empty");
        let three = RenderScheme::ThreePass.passes_with(true);
        assert_eq!(three[2].alpha_test, AlphaTest::PassTransparentNonEmpty);
        assert_eq!(three[2].fragment_entry(), "fs_transparent_non_empty");
    }

    #[test]
    fn every_pass_name_is_timed() {
        for s in [RenderScheme::FourPass, RenderScheme::ThreePass] {
            for p in s.passes() {
                assert!(super::super::PASS_NAMES.contains(&p.name), "{}", p.name);
            }
        }
    }
}
