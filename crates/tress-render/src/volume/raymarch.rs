//! [`Raymarch`], owner of `raymarch.wgsl`.

use crate::bind::{Layouts, bind_group, bind_group_layout, depth_texture, storage, texture_3d};
use crate::gpu::pipeline::{RasterPipeline, over_color_pass, pipeline_layout, premultiplied_over};
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
    /// Each light's integrated highlights (`volume.highlights = "strands"`).
    pub(crate) highlights: &'a wgpu::TextureView,
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
            let layout = bind_group_layout(
                ctx,
                "volume/raymarch/layout",
                &[
                    depth_texture(0, fragment),
                    storage(1, fragment, true),
                    texture_3d(2, fragment),
                ],
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "volume/raymarch/pipeline-layout",
                &[Some(&layouts.view), Some(&layouts.lighting), Some(&layout)],
            );
            let pipeline = RasterPipeline {
                // Back faces only: every pixel of the box once, also with the eye inside.
                primitive: wgpu::PrimitiveState {
                    cull_mode: Some(wgpu::Face::Front),
                    ..Default::default()
                },
                targets: &[Some(premultiplied_over(color_format))],
                ..RasterPipeline::new("volume/raymarch/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
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
        let group = bind_group(
            ctx,
            "volume/raymarch/bind-group",
            &self.layout,
            &[
                (0, wgpu::BindingResource::TextureView(inputs.depth)),
                (1, inputs.occupancy.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(inputs.highlights)),
            ],
        );
        let mut pass = over_color_pass(encoder, "volume/raymarch/pass", inputs.color, timestamps);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, inputs.view, &[]);
        pass.set_bind_group(1, inputs.lighting, &[]);
        pass.set_bind_group(2, &group, &[]);
        pass.draw(0..36, 0..1);
    }
}
