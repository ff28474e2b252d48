//! [`Voxelize`], owner of `voxelize.wgsl`.

use crate::bind::{Layouts, bind_group_layout, storage, uniform};
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::strands::StrandGeometry;
use crate::volume::volume_bounds::dispatch_2d;
use crate::{GpuContext, RenderError, shaders};

/// The voxelize pass: strand samples into the per-voxel atomic counters and tangent sums (§3.3).
#[derive(Debug)]
pub struct Voxelize {
    pipeline: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

impl Voxelize {
    pub(crate) fn new(ctx: &GpuContext, layouts: &Layouts) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, "volume/voxelize.wgsl", "volume/voxelize/shader")?;
        ctx.scoped("creating the voxelize pipeline", || {
            let c = wgpu::ShaderStages::COMPUTE;
            let layout = bind_group_layout(
                ctx,
                "volume/voxelize/layout",
                &[
                    uniform(0, c),
                    storage(1, c, true),
                    storage(2, c, false),
                    storage(3, c, false),
                    storage(4, c, false),
                    storage(5, c, false),
                    storage(6, c, false),
                ],
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "volume/voxelize/pipeline-layout",
                &[Some(&layout), None, Some(&layouts.strands)],
            );
            Voxelize {
                pipeline: compute_pipeline(
                    ctx,
                    "volume/voxelize/pipeline",
                    &module,
                    "voxelize",
                    &pipeline_layout,
                ),
                layout,
            }
        })
    }

    /// Record one invocation per segment into an open compute pass.
    pub(crate) fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        geometry: &StrandGeometry,
    ) {
        let (x, y) = dispatch_2d(geometry.segment_count(), 64);
        if x == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(2, &geometry.bind_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}
