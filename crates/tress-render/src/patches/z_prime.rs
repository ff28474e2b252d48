//! [`ZPrime`], owner of `z_prime.wgsl`: pass 1 of the optimized scheme.

use super::PatchGeometry;
use super::PatchLayouts;
use super::passes::{FOUR_PASS, PassShader, create_pipeline};
use crate::gpu::pipeline::pipeline_layout;
use crate::{GpuContext, RenderError, shaders};

/// Primes the depth buffer with the opaque parts of the patches (alpha test, no culling, color
/// writes off; slide "Optimized Rendering Scheme", pass 1), so that the shading passes after it
/// can rely on the depth test, and early Z, instead of the alpha test.
#[derive(Debug)]
pub struct ZPrime {
    pipeline: wgpu::RenderPipeline,
}

impl ZPrime {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &PatchLayouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let pass = FOUR_PASS
            .iter()
            .find(|p| p.shader == PassShader::AlphaOnly)
            .ok_or_else(|| RenderError::Invalid("the 4-pass scheme has no Z-prime pass".into()))?;
        let parts = pass.pipeline_parts(color_format);
        let module = shaders::create_module(ctx, parts.module, "patches/z_prime/shader")?;
        ctx.scoped("creating the patch Z-prime pipeline", || {
            let layout = pipeline_layout(
                ctx,
                "patches/z_prime/layout",
                &[Some(&layouts.view), None, Some(&layouts.material)],
            );
            ZPrime {
                pipeline: create_pipeline(ctx, &layout, &module, &parts),
            }
        })
    }

    /// Record the pass's draw into an open render pass (bind groups 0 and 2 already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, geometry: &PatchGeometry) {
        pass.set_pipeline(&self.pipeline);
        geometry.draw(pass);
    }
}
