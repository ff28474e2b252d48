//! [`ShortcutResolve`], owner of `shortcut_resolve.wgsl`.

use crate::bind::bind_group_layout;
use crate::gpu::pipeline::{RasterPipeline, over_color_pass, pipeline_layout, premultiplied_over};
use crate::strands::shortcut::{ShortcutBuffers, resolve_layout_entries};
use crate::{GpuContext, RenderError, shaders};

/// ShortCut's resolve pass: a fullscreen pass that blends each pixel's stored layers front to
/// back with the tail under them and composites the result (premultiplied) over the color
/// target.
#[derive(Debug)]
pub struct ShortcutResolve {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl ShortcutResolve {
    pub(crate) fn new(
        ctx: &GpuContext,
        view_layout: &wgpu::BindGroupLayout,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "strands/shortcut_resolve.wgsl",
            "strands/shortcut_resolve/shader",
        )?;
        ctx.scoped("creating the ShortCut resolve pipeline", || {
            let layout = bind_group_layout(
                ctx,
                "strands/shortcut_resolve/layout",
                &resolve_layout_entries(),
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "strands/shortcut_resolve/pipeline-layout",
                &[Some(view_layout), None, None, Some(&layout)],
            );
            let pipeline = RasterPipeline {
                targets: &[Some(premultiplied_over(color_format))],
                ..RasterPipeline::new(
                    "strands/shortcut_resolve/pipeline",
                    &pipeline_layout,
                    &module,
                )
            }
            .create(ctx);
            ShortcutResolve { pipeline, layout }
        })
    }

    /// Record the pass over `color` (loaded, blended into).
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::BindGroup,
        buffers: &ShortcutBuffers,
        color: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let group = buffers.resolve_group(ctx, &self.layout);
        let mut pass = over_color_pass(encoder, "strands/shortcut_resolve/pass", color, timestamps);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, view, &[]);
        pass.set_bind_group(3, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
