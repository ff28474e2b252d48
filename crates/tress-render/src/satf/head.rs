//! [`SatfHead`], owner of `head.wgsl`.

use super::cluster_shadow::ShadowTargets;
use super::passes::{Slot, group, layout, pipeline_layout};
use crate::gpu::DEPTH_FORMAT;
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head first with depth writes, lit by Lambert with the clusters' shadows. The
/// SATF technique has its own head pass because the strand technique's reads that technique's
/// lighting group.
#[derive(Debug)]
pub struct SatfHead {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl SatfHead {
    pub(crate) fn new(
        ctx: &GpuContext,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "satf/head.wgsl", "satf/head/shader")?;
        ctx.scoped("creating the SATF head pipeline", || {
            let layout = layout(
                ctx,
                "satf/head/layout",
                wgpu::ShaderStages::VERTEX_FRAGMENT,
                &[
                    (0, Slot::Uniform),
                    (1, Slot::Uniform),
                    (2, Slot::Uniform),
                    (11, Slot::DepthArray),
                    (12, Slot::UintArray),
                ],
            );
            let pl = pipeline_layout(ctx, "satf/head/pipeline-layout", &layout);
            let pipeline = ctx
                .device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("satf/head/pipeline"),
                    layout: Some(&pl),
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
            SatfHead { layout, pipeline }
        })
    }

    /// Record the head draw into an open render pass.
    pub(crate) fn draw(
        &self,
        ctx: &GpuContext,
        pass: &mut wgpu::RenderPass<'_>,
        uniforms: [&wgpu::Buffer; 3],
        shadow: &ShadowTargets,
        head: &HeadGeometry,
    ) {
        let [camera, lights, params] = uniforms;
        let bind = group(
            ctx,
            "satf/head/bind-group",
            &self.layout,
            &[
                (0, camera.as_entire_binding()),
                (1, lights.as_entire_binding()),
                (2, params.as_entire_binding()),
                (11, wgpu::BindingResource::TextureView(&shadow.depth_array)),
                (12, wgpu::BindingResource::TextureView(&shadow.ids_array)),
            ],
        );
        pass.set_bind_group(0, &bind, &[]);
        pass.set_pipeline(&self.pipeline);
        pass.set_vertex_buffer(0, head.vertices.slice(..));
        pass.set_index_buffer(head.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..head.index_count, 0, 0..1);
    }
}
