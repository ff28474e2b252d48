//! [`Raymarch`], owner of `raymarch.wgsl`.

use crate::bind::{Layouts, depth_texture, storage};
use crate::{GpuContext, RenderError, shaders};

/// The raymarch pass: the hair's box rasterized, each fragment marched to the isosurface and
/// shaded, blended (premultiplied) over the color target (§3.3).
#[derive(Debug)]
pub struct Raymarch {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// What the raymarch pass reads and writes in a frame.
pub(crate) struct RaymarchInputs<'a> {
    pub(crate) view: &'a wgpu::BindGroup,
    pub(crate) lighting: &'a wgpu::BindGroup,
    /// The head's depth (the march stops there).
    pub(crate) depth: &'a wgpu::TextureView,
    pub(crate) occupancy: &'a wgpu::Buffer,
    /// Where the volume is drawn (blended over what it holds).
    pub(crate) color: &'a wgpu::TextureView,
}

impl Raymarch {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "volume/raymarch.wgsl", "volume/raymarch/shader")?;
        ctx.scoped("creating the raymarch pipeline", || {
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let layout = ctx
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("volume/raymarch/layout"),
                    entries: &[depth_texture(0, fragment), storage(1, fragment, true)],
                });
            let pipeline_layout =
                ctx.device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("volume/raymarch/pipeline-layout"),
                        bind_group_layouts: &[
                            Some(&layouts.view),
                            Some(&layouts.lighting),
                            Some(&layout),
                        ],
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
                    label: Some("volume/raymarch/pipeline"),
                    layout: Some(&pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_main"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    // Back faces only: every pixel of the box once, also with the eye inside.
                    primitive: wgpu::PrimitiveState {
                        cull_mode: Some(wgpu::Face::Front),
                        ..Default::default()
                    },
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
            Raymarch { pipeline, layout }
        })
    }

    /// Record the pass (the color target is loaded and blended into).
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &RaymarchInputs<'_>,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("volume/raymarch/bind-group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(inputs.depth),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: inputs.occupancy.as_entire_binding(),
                },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("volume/raymarch/pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: inputs.color,
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
        pass.set_bind_group(0, inputs.view, &[]);
        pass.set_bind_group(1, inputs.lighting, &[]);
        pass.set_bind_group(2, &group, &[]);
        pass.draw(0..36, 0..1);
    }
}
