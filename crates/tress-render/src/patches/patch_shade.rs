//! [`PatchShade`], owner of `patch_shade.wgsl`: the shading passes of both schemes.

use super::PatchGeometry;
use super::PatchLayouts;
use super::passes::{PassShader, PatchPass, create_pipeline};
use crate::gpu::pipeline::pipeline_layout;
use crate::{GpuContext, RenderError, shaders};

/// The full `HairLighting` shader in the render states of a scheme's shading passes: opaque
/// (`Equal`, or alpha-tested in the 3-pass scheme), transparent back faces, transparent front
/// faces. One pipeline per pass; the pass states come from [`PatchPass::pipeline_parts`].
#[derive(Debug)]
pub struct PatchShade {
    passes: Vec<PatchPass>,
    pipelines: Vec<(&'static str, wgpu::RenderPipeline)>,
}

impl PatchShade {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &PatchLayouts,
        color_format: wgpu::TextureFormat,
        passes: Vec<PatchPass>,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "patches/patch_shade.wgsl",
            "patches/patch_shade/shader",
        )?;
        ctx.scoped("creating the patch shading pipelines", || {
            let layout = pipeline_layout(
                ctx,
                "patches/patch_shade/layout",
                &[
                    Some(&layouts.view),
                    Some(&layouts.lights),
                    Some(&layouts.material),
                ],
            );
            let pipelines = passes
                .iter()
                .filter(|p| p.shader == PassShader::Full)
                .map(|p| {
                    let parts = p.pipeline_parts(color_format);
                    (p.name, create_pipeline(ctx, &layout, &module, &parts))
                })
                .collect();
            PatchShade { passes, pipelines }
        })
    }

    /// All passes of the scheme the pipelines were built for (the Z prime included), in draw
    /// order.
    pub fn passes(&self) -> &[PatchPass] {
        &self.passes
    }

    /// Record `pass`'s draw into an open render pass (bind groups 0 to 2 already set). A pass
    /// of another scheme draws nothing.
    pub(crate) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        which: &PatchPass,
        geometry: &PatchGeometry,
    ) {
        if let Some((_, pipeline)) = self.pipelines.iter().find(|(n, _)| *n == which.name) {
            pass.set_pipeline(pipeline);
            geometry.draw(pass);
        }
    }
}
