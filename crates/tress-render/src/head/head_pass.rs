//! [`HeadPass`], owner of `head_pass.wgsl`.

use crate::bind::Layouts;
use crate::gpu::DEPTH_FORMAT;
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head mesh with depth writes, Lambert-lit with ADSM shadows.
#[derive(Debug)]
pub struct HeadPass {
    pipeline: wgpu::RenderPipeline,
}

impl HeadPass {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "head/head_pass.wgsl", "head/head_pass/shader")?;
        let pipeline = ctx.scoped("creating the head pipeline", || {
            let layout = ctx
                .device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("head/head_pass/layout"),
                    bind_group_layouts: &[Some(&layouts.view), Some(&layouts.lighting)],
                    immediate_size: 0,
                });
            ctx.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("head/head_pass/pipeline"),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_main"),
                        compilation_options: Default::default(),
                        buffers: &[Some(HEAD_VERTEX_LAYOUT)],
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_main"),
                        compilation_options: Default::default(),
                        targets: &[Some(color_format.into())],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
        })?;
        Ok(HeadPass { pipeline })
    }

    /// Record the head draw into an open render pass (bind groups 0 and 1 already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, head: &HeadGeometry) {
        pass.set_pipeline(&self.pipeline);
        pass.set_vertex_buffer(0, head.vertices.slice(..));
        pass.set_index_buffer(head.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..head.index_count, 0, 0..1);
    }
}
