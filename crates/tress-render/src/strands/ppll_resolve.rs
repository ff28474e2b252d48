//! [`PpllResolve`], owner of `ppll_resolve.wgsl`.

use crate::bind::{Layouts, storage};
use crate::strands::PpllPool;
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
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let layout = ctx
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("strands/ppll_resolve/layout"),
                    entries: &[storage(0, fragment, true), storage(1, fragment, true)],
                });
            let pipeline_layout =
                ctx.device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("strands/ppll_resolve/pipeline-layout"),
                        bind_group_layouts: &[Some(&layouts.view), Some(&layout)],
                        immediate_size: 0,
                    });
            let premultiplied = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            };
            let pipeline = ctx
                .device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("strands/ppll_resolve/pipeline"),
                    layout: Some(&pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_main"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: None,
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_main"),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format: color_format,
                            blend: Some(wgpu::BlendState {
                                color: premultiplied,
                                alpha: premultiplied,
                            }),
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    multiview_mask: None,
                    cache: None,
                });
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
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("strands/ppll_resolve/bind-group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: pool.heads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: pool.nodes.as_entire_binding(),
                },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("strands/ppll_resolve/pass"),
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
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, view, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
