//! Builders for what every pass creates the same way: pipeline layouts, compute pipelines, render
//! pipelines (a vertex and an optional fragment stage of one module), the depth test, the
//! premultiplied "over" color target and a render pass that draws over a loaded color target.
//! Each pass keeps only what is specific to it: its shader, bind groups, entry points, vertex
//! buffers, culling, depth and color states.

use crate::GpuContext;
use crate::gpu::DEPTH_FORMAT;

/// A pipeline layout of `groups` (`None` for a group the pipeline does not use).
pub(crate) fn pipeline_layout(
    ctx: &GpuContext,
    label: &str,
    groups: &[Option<&wgpu::BindGroupLayout>],
) -> wgpu::PipelineLayout {
    ctx.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: groups,
            immediate_size: 0,
        })
}

/// The compute pipeline of `module`'s `entry` over `layout`.
pub(crate) fn compute_pipeline(
    ctx: &GpuContext,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layout: &wgpu::PipelineLayout,
) -> wgpu::ComputePipeline {
    ctx.device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
}

/// Depth test `compare` against [`DEPTH_FORMAT`], writing depth or not; no stencil, no bias.
pub(crate) fn depth_test(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// A color target that composites premultiplied color over what it holds
/// (`src + (1 − src.a) · dst`, color and alpha alike).
pub(crate) fn premultiplied_over(format: wgpu::TextureFormat) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

/// A render pipeline of one shader module. [`RasterPipeline::new`] gives `vs_main` and `fs_main`
/// with no vertex buffers, the default primitive state, no depth and no color target; a pass
/// overrides the fields it needs with struct update syntax, then calls
/// [`RasterPipeline::create`].
pub(crate) struct RasterPipeline<'a> {
    pub(crate) label: &'a str,
    pub(crate) layout: &'a wgpu::PipelineLayout,
    pub(crate) module: &'a wgpu::ShaderModule,
    pub(crate) vertex_entry: &'a str,
    pub(crate) buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub(crate) primitive: wgpu::PrimitiveState,
    pub(crate) depth_stencil: Option<wgpu::DepthStencilState>,
    /// The fragment stage's entry point; `None` for a depth-only pipeline.
    pub(crate) fragment_entry: Option<&'a str>,
    pub(crate) targets: &'a [Option<wgpu::ColorTargetState>],
}

impl<'a> RasterPipeline<'a> {
    pub(crate) fn new(
        label: &'a str,
        layout: &'a wgpu::PipelineLayout,
        module: &'a wgpu::ShaderModule,
    ) -> Self {
        RasterPipeline {
            label,
            layout,
            module,
            vertex_entry: "vs_main",
            buffers: &[],
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            fragment_entry: Some("fs_main"),
            targets: &[],
        }
    }

    pub(crate) fn create(&self, ctx: &GpuContext) -> wgpu::RenderPipeline {
        ctx.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(self.label),
                layout: Some(self.layout),
                vertex: wgpu::VertexState {
                    module: self.module,
                    entry_point: Some(self.vertex_entry),
                    compilation_options: Default::default(),
                    buffers: self.buffers,
                },
                primitive: self.primitive,
                depth_stencil: self.depth_stencil.clone(),
                multisample: Default::default(),
                fragment: self.fragment_entry.map(|entry| wgpu::FragmentState {
                    module: self.module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: self.targets,
                }),
                multiview_mask: None,
                cache: None,
            })
    }
}

/// A render pass that loads `color`, draws over it and stores it (no depth attachment).
pub(crate) fn over_color_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    color: &wgpu::TextureView,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
