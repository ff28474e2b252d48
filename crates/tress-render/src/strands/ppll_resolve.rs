//! [`PpllResolve`], owner of `ppll_resolve.wgsl`.

use crate::bind::{Layouts, bind_group, bind_group_layout};
use crate::gpu::pipeline::{RasterPipeline, over_color_pass, pipeline_layout, premultiplied_over};
use crate::strands::PpllPool;
use crate::strands::ppll::pool_layout_entries;
use crate::{GpuContext, RenderError, shaders};

/// Largest `k` the resolve shader supports (`MAX_K` in `ppll_resolve.wgsl`).
pub const MAX_K: u32 = 32;

/// The PPLL resolve pass: a fullscreen pass that sorts each pixel's nearest `k` fragments, blends
/// them front to back with the order-independent tail under them, and composites the result
/// (premultiplied) over the color target.
#[derive(Debug)]
pub struct PpllResolve {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl PpllResolve {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "strands/ppll_resolve.wgsl",
            "strands/ppll_resolve/shader",
        )?;
        ctx.scoped("creating the PPLL resolve pipeline", || {
            let layout =
                bind_group_layout(ctx, "strands/ppll_resolve/layout", &pool_layout_entries());
            let pipeline_layout = pipeline_layout(
                ctx,
                "strands/ppll_resolve/pipeline-layout",
                &[Some(&layouts.view), None, None, Some(&layout)],
            );
            let pipeline = RasterPipeline {
                targets: &[Some(premultiplied_over(color_format))],
                ..RasterPipeline::new("strands/ppll_resolve/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
            PpllResolve { pipeline, layout }
        })
    }

    /// Record the pass over `color` (loaded, blended into).
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::BindGroup,
        pool: &PpllPool,
        color: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let group = bind_group(
            ctx,
            "strands/ppll_resolve/bind-group",
            &self.layout,
            &pool.entries(),
        );
        let mut pass = over_color_pass(encoder, "strands/ppll_resolve/pass", color, timestamps);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, view, &[]);
        pass.set_bind_group(3, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
