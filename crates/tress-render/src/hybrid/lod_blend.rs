//! [`LodBlend`], owner of `lod_blend.wgsl`, and the two scratch layers it mixes.

use crate::bind::{bind_group, bind_group_layout, texture_2d, uniform};
use crate::gpu::pipeline::{RasterPipeline, over_color_pass, pipeline_layout, premultiplied_over};
use crate::gpu::screen_layer;
use crate::gpu::types::LodParams;
use crate::{GpuContext, RenderError, shaders};

use super::Transition;
use super::plan::FramePlan;

/// The blend pass (`lod_blend.wgsl`).
#[derive(Debug)]
pub struct LodBlend {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
}

/// Two premultiplied scratch layers of one target size.
#[derive(Debug)]
pub(crate) struct LodLayers {
    pub(crate) size: [u32; 2],
    pub(crate) strands: wgpu::TextureView,
    pub(crate) volume: wgpu::TextureView,
}

impl LodLayers {
    pub(crate) fn new(
        ctx: &GpuContext,
        size: [u32; 2],
        format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        ctx.scoped("allocating the LOD layers", || {
            let layer = |name: &str| {
                screen_layer(ctx, &format!("lod/lod_blend/{name}-layer"), size, format)
            };
            LodLayers {
                size,
                strands: layer("strands"),
                volume: layer("volume"),
            }
        })
    }

    /// Record clears of both layers to transparent.
    pub(crate) fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        for view in [&self.strands, &self.volume] {
            encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("lod/lod_blend/clear-pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
        }
    }
}

impl LodBlend {
    pub(crate) fn new(
        ctx: &GpuContext,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "hybrid/lod_blend.wgsl", "lod/lod_blend/shader")?;
        ctx.scoped("creating the LOD blend pipeline", || {
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let layout = bind_group_layout(
                ctx,
                "lod/lod_blend/layout",
                &[
                    texture_2d(0, fragment),
                    texture_2d(1, fragment),
                    uniform(2, fragment),
                ],
            );
            let pipeline_layout =
                pipeline_layout(ctx, "lod/lod_blend/pipeline-layout", &[Some(&layout)]);
            let pipeline = RasterPipeline {
                targets: &[Some(premultiplied_over(color_format))],
                ..RasterPipeline::new("lod/lod_blend/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
            let params = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lod/lod_blend/params"),
                size: std::mem::size_of::<LodParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            LodBlend {
                pipeline,
                layout,
                params,
            }
        })
    }

    /// Record the blend of `layers` by the plan's factor and transition over `color`.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        layers: &LodLayers,
        plan: &FramePlan,
        color: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let params = LodParams {
            factor: plan.lod,
            transition: match plan.transition {
                Transition::Alpha => 0,
                Transition::Dither => 1,
            },
            ..Default::default()
        };
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let group = bind_group(
            ctx,
            "lod/lod_blend/bind-group",
            &self.layout,
            &[
                (0, wgpu::BindingResource::TextureView(&layers.strands)),
                (1, wgpu::BindingResource::TextureView(&layers.volume)),
                (2, self.params.as_entire_binding()),
            ],
        );
        let mut pass = over_color_pass(encoder, "lod/lod_blend/pass", color, timestamps);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
