//! [`PatchHead`], owner of `patch_head.wgsl`.

use crate::gpu::Targets;
use crate::gpu::pipeline::pipeline_layout;
use crate::head::{HeadGeometry, HeadPassInfo, HeadPipeline};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head first, with depth writes (`Less`), so the patch passes' depth test
/// rejects the hair behind it. The patch technique has its own head pass because the strand
/// technique's reads that technique's lighting group (shadow maps and more), which patches do
/// not have; the pipeline is the shared `HeadPipeline`.
#[derive(Debug)]
pub struct PatchHead {
    pipeline: HeadPipeline,
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
            let layout = pipeline_layout(
                ctx,
                "patches/head/layout",
                &[Some(view_layout), Some(lights_layout)],
            );
            PatchHead {
                pipeline: HeadPipeline::new(
                    ctx,
                    "patches/head/pipeline",
                    &module,
                    &layout,
                    color_format,
                ),
            }
        })
    }

    /// The frame's head pass (see [`HeadPipeline::encode`]) with the view and lights groups.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets<'_>,
        clear: Option<wgpu::Color>,
        writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        groups: [&wgpu::BindGroup; 2],
        head: Option<&HeadGeometry>,
    ) {
        let pass = HeadPassInfo {
            label: "patches/head/pass",
            clear,
            writes,
        };
        self.pipeline.encode(encoder, targets, pass, &groups, head);
    }
}
