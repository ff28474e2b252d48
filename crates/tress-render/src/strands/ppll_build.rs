//! [`PpllBuild`], owner of `ppll_build.wgsl`.

use crate::bind::{Layouts, depth_texture, storage};
use crate::gpu::DEPTH_FORMAT;
use crate::strands::{PpllPool, StrandGeometry};
use crate::{GpuContext, RenderError, shaders};

/// The PPLL build pass: strands are shaded and their fragments inserted into per-pixel lists.
#[derive(Debug)]
pub struct PpllBuild {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// What the build pass reads and writes in a frame.
pub(crate) struct PpllBuildInputs<'a> {
    pub(crate) view: &'a wgpu::BindGroup,
    pub(crate) lighting: &'a wgpu::BindGroup,
    pub(crate) geometry: &'a StrandGeometry,
    pub(crate) pool: &'a PpllPool,
    /// The head's depth: read-only attachment (early rejection) and texture (exact test).
    pub(crate) depth: &'a wgpu::TextureView,
}

impl PpllBuild {
    pub(crate) fn new(ctx: &GpuContext, layouts: &Layouts) -> Result<Self, RenderError> {
        let module =
            shaders::create_module(ctx, "strands/ppll_build.wgsl", "strands/ppll_build/shader")?;
        ctx.scoped("creating the PPLL build pipeline", || {
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let layout = ctx
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("strands/ppll_build/layout"),
                    entries: &[
                        storage(0, fragment, false),
                        storage(1, fragment, false),
                        storage(2, fragment, false),
                        depth_texture(3, fragment),
                    ],
                });
            let pipeline_layout =
                ctx.device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("strands/ppll_build/pipeline-layout"),
                        bind_group_layouts: &[
                            Some(&layouts.view),
                            Some(&layouts.lighting),
                            Some(&layouts.strands),
                            Some(&layout),
                        ],
                        immediate_size: 0,
                    });
            let pipeline = ctx
                .device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("strands/ppll_build/pipeline"),
                    layout: Some(&pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_main"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(false),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_main"),
                        compilation_options: Default::default(),
                        targets: &[],
                    }),
                    multiview_mask: None,
                    cache: None,
                });
            PpllBuild { pipeline, layout }
        })
    }

    /// Record the pass: clear the lists, then draw every segment's quad.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &PpllBuildInputs<'_>,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        inputs.pool.clear(encoder);
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("strands/ppll_build/bind-group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: inputs.pool.heads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: inputs.pool.nodes.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: inputs.pool.counters.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(inputs.depth),
                },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("strands/ppll_build/pass"),
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
        pass.set_bind_group(0, inputs.view, &[]);
        pass.set_bind_group(1, inputs.lighting, &[]);
        pass.set_bind_group(2, &inputs.geometry.bind_group, &[]);
        pass.set_bind_group(3, &group, &[]);
        pass.draw(0..inputs.geometry.segment_count() * 6, 0..1);
    }
}
