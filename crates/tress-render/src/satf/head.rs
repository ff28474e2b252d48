//! [`SatfHead`], owner of `head.wgsl`.

use super::cluster_shadow::ShadowTargets;
use super::passes::{Slot, layout};
use crate::bind::bind_group;
use crate::gpu::Targets;
use crate::gpu::pipeline::pipeline_layout;
use crate::head::{HeadGeometry, HeadPassInfo, HeadPipeline};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head first with depth writes, lit by Lambert with the clusters' shadows. The
/// SATF technique has its own head pass because the strand technique's reads that technique's
/// lighting group; the pipeline is the shared `HeadPipeline`.
#[derive(Debug)]
pub struct SatfHead {
    layout: wgpu::BindGroupLayout,
    pipeline: HeadPipeline,
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
            let pl = pipeline_layout(ctx, "satf/head/pipeline-layout", &[Some(&layout)]);
            let pipeline = HeadPipeline::new(ctx, "satf/head/pipeline", &module, &pl, color_format);
            SatfHead { layout, pipeline }
        })
    }

    /// The frame's head pass (see [`HeadPipeline::encode`]), lit through the clusters' shadow
    /// maps.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets<'_>,
        info: HeadPassInfo<'_>,
        uniforms: [&wgpu::Buffer; 3],
        shadow: &ShadowTargets,
        head: Option<&HeadGeometry>,
    ) {
        let [camera, lights, params] = uniforms;
        let bind = head.map(|_| {
            bind_group(
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
            )
        });
        let groups: Vec<&wgpu::BindGroup> = bind.iter().collect();
        self.pipeline.encode(encoder, targets, info, &groups, head);
    }
}
