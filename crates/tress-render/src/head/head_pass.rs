//! [`HeadPass`], owner of `head_pass.wgsl`, and `HeadPipeline`, the head pipeline every
//! technique draws its head with.

use crate::bind::Layouts;
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head mesh with depth writes, Lambert-lit with ADSM shadows.
#[derive(Debug)]
pub struct HeadPass {
    pipeline: HeadPipeline,
}

impl HeadPass {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "head/head_pass.wgsl", "head/head_pass/shader")?;
        let pipeline = ctx.scoped("creating the head pipeline", || {
            let layout = pipeline_layout(
                ctx,
                "head/head_pass/layout",
                &[Some(&layouts.view), Some(&layouts.lighting)],
            );
            HeadPipeline::new(
                ctx,
                "head/head_pass/pipeline",
                &module,
                &layout,
                color_format,
            )
        })?;
        Ok(HeadPass { pipeline })
    }

    /// Record the head draw into an open render pass (bind groups 0 and 1 already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, head: &HeadGeometry) {
        self.pipeline.draw(pass, head);
    }
}

/// The opaque head of every technique: `vs_main` and `fs_main` of the technique's head shader
/// over [`HEAD_VERTEX_LAYOUT`], depth written with `Less`, one color target without blending. The
/// techniques' heads differ only in their shader's lighting, and so in their bind groups.
#[derive(Debug)]
pub(crate) struct HeadPipeline(wgpu::RenderPipeline);

impl HeadPipeline {
    pub(crate) fn new(
        ctx: &GpuContext,
        label: &str,
        module: &wgpu::ShaderModule,
        layout: &wgpu::PipelineLayout,
        color_format: wgpu::TextureFormat,
    ) -> Self {
        HeadPipeline(
            RasterPipeline {
                buffers: &[Some(HEAD_VERTEX_LAYOUT)],
                depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                targets: &[Some(color_format.into())],
                ..RasterPipeline::new(label, layout, module)
            }
            .create(ctx),
        )
    }

    /// Record the head draw into an open render pass (its bind groups already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, head: &HeadGeometry) {
        pass.set_pipeline(&self.0);
        head.draw(pass);
    }
}
