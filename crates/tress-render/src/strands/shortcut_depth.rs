//! [`ShortcutDepth`], owner of `shortcut_depth.wgsl`.

use crate::bind::{Layouts, bind_group_layout};
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::strands::oit::OitInputs;
use crate::strands::shortcut::{ShortcutBuffers, raster_layout_entries};
use crate::{GpuContext, RenderError, shaders};

/// ShortCut's depth pass: every strand fragment inserts its depth into its pixel's `k` nearest.
#[derive(Debug)]
pub struct ShortcutDepth {
    pipeline: wgpu::RenderPipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

impl ShortcutDepth {
    pub(crate) fn new(ctx: &GpuContext, layouts: &Layouts) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "strands/shortcut_depth.wgsl",
            "strands/shortcut_depth/shader",
        )?;
        ctx.scoped("creating the ShortCut depth pipeline", || {
            let layout = bind_group_layout(
                ctx,
                "strands/shortcut/raster-layout",
                &raster_layout_entries(),
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "strands/shortcut_depth/pipeline-layout",
                &[
                    Some(&layouts.view),
                    None,
                    Some(&layouts.strands),
                    Some(&layout),
                ],
            );
            let pipeline = RasterPipeline {
                depth_stencil: Some(depth_test(false, wgpu::CompareFunction::Less)),
                ..RasterPipeline::new("strands/shortcut_depth/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
            ShortcutDepth { pipeline, layout }
        })
    }

    /// Record the pass: empty the layers, then draw every segment's quad.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &OitInputs<'_>,
        buffers: &ShortcutBuffers,
        group: &wgpu::BindGroup,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        buffers.clear(encoder);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("strands/shortcut_depth/pass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: inputs.depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(3, group, &[]);
        for part in inputs.parts {
            pass.set_bind_group(0, part.view, &[]);
            pass.set_bind_group(2, &part.geometry.bind_group, &[]);
            pass.draw(0..part.geometry.segment_count() * 6, 0..1);
        }
    }
}
