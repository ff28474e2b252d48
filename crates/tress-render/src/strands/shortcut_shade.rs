//! [`ShortcutShade`], owner of `shortcut_shade.wgsl`.

use crate::bind::Layouts;
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::strands::oit::OitInputs;
use crate::strands::shortcut::{ShortcutBuffers, TAIL_FORMAT, TRANSMITTANCE_FORMAT};
use crate::{GpuContext, RenderError, shaders};

/// ShortCut's shade pass: the `k` nearest fragments of each pixel are shaded into their layers,
/// every other fragment multiplies its opacity into the tail's transmittance, and those near the
/// k-th add their weighted color into the tail's color.
#[derive(Debug)]
pub struct ShortcutShade {
    pipeline: wgpu::RenderPipeline,
}

/// `dst * (1 - src)`: the transmittance target's blend (the product of `1 - alpha`).
const MULTIPLY_TRANSMITTANCE: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::Zero,
    dst_factor: wgpu::BlendFactor::OneMinusSrc,
    operation: wgpu::BlendOperation::Add,
};

/// `dst + src`: the tail color's blend (sums of weighted colors and weights).
const ADD: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::One,
    operation: wgpu::BlendOperation::Add,
};

impl ShortcutShade {
    /// `raster_layout`: the group 3 layout the depth pass created (the two passes share it).
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        raster_layout: &wgpu::BindGroupLayout,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "strands/shortcut_shade.wgsl",
            "strands/shortcut_shade/shader",
        )?;
        ctx.scoped("creating the ShortCut shade pipeline", || {
            let pipeline_layout = pipeline_layout(
                ctx,
                "strands/shortcut_shade/pipeline-layout",
                &[
                    Some(&layouts.view),
                    Some(&layouts.lighting),
                    Some(&layouts.strands),
                    Some(raster_layout),
                ],
            );
            let target = wgpu::ColorTargetState {
                format: TRANSMITTANCE_FORMAT,
                blend: Some(wgpu::BlendState {
                    color: MULTIPLY_TRANSMITTANCE,
                    alpha: MULTIPLY_TRANSMITTANCE,
                }),
                write_mask: wgpu::ColorWrites::RED,
            };
            let tail = wgpu::ColorTargetState {
                format: TAIL_FORMAT,
                blend: Some(wgpu::BlendState {
                    color: ADD,
                    alpha: ADD,
                }),
                write_mask: wgpu::ColorWrites::ALL,
            };
            let pipeline = RasterPipeline {
                depth_stencil: Some(depth_test(false, wgpu::CompareFunction::Less)),
                targets: &[Some(target), Some(tail)],
                ..RasterPipeline::new("strands/shortcut_shade/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
            ShortcutShade { pipeline }
        })
    }

    /// Record the pass: clear the transmittance to 1 and the tail color to 0, then draw every
    /// segment's quad.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &OitInputs<'_>,
        buffers: &ShortcutBuffers,
        group: &wgpu::BindGroup,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let cleared = |view, color| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(color),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("strands/shortcut_shade/pass"),
            color_attachments: &[
                cleared(&buffers.transmittance, wgpu::Color::WHITE),
                cleared(&buffers.tail, wgpu::Color::TRANSPARENT),
            ],
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
            pass.set_bind_group(1, part.lighting, &[]);
            pass.set_bind_group(2, &part.geometry.bind_group, &[]);
            pass.draw(0..part.geometry.segment_count() * 6, 0..1);
        }
    }
}
