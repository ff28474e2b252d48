//! [`PatchHead`], owner of `patch_head.wgsl`.

use crate::gpu::DEPTH_FORMAT;
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head first, with depth writes (`Less`), so the patch passes' depth test
/// rejects the hair behind it. The patch technique has its own head pass because the strand
/// technique's reads that technique's lighting group (shadow maps and more), which patches do
/// not have.
#[derive(Debug)]
pub struct PatchHead {
    pipeline: wgpu::RenderPipeline,
}

impl PatchHead {
    pub(crate) fn new(
        ctx: &GpuContext,
        view_layout: &wgpu::BindGroupLayout,
        lights_layout: &wgpu::BindGroupLayout,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "patches/patch_head.wgsl", "patches/head/shader")?;
        ctx.scoped("creating the patch head pipeline", || {
            let layout = ctx
                .device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("patches/head/layout"),
                    bind_group_layouts: &[Some(view_layout), Some(lights_layout)],
                    immediate_size: 0,
                });
            let pipeline = ctx
                .device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("patches/head/pipeline"),
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
                });
            PatchHead { pipeline }
        })
    }

    /// Record the head draw into an open render pass (bind groups 0 and 1 already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, head: &HeadGeometry) {
        pass.set_pipeline(&self.pipeline);
        pass.set_vertex_buffer(0, head.vertices.slice(..));
        pass.set_index_buffer(head.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..head.index_count, 0, 0..1);
    }
}
