//! [`VolumeBounds`], owner of `volume_bounds.wgsl`.

use crate::bind::{Layouts, bind_group_layout, storage, uniform};
use crate::gpu::pipeline::{compute_pipeline, pipeline_layout};
use crate::strands::StrandGeometry;
use crate::{GpuContext, RenderError, shaders};

/// The bounds pass: the hair's AABB from every vertex, then the grid fitted to it (§3.3).
#[derive(Debug)]
pub struct VolumeBounds {
    clear: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
    fit: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

/// Workgroups `(x, y)` covering `threads` invocations of `size` each, `x` within the 65535 limit
/// (the shaders index `id.x + id.y · x · size`).
pub(crate) fn dispatch_2d(threads: u32, size: u32) -> (u32, u32) {
    let groups = threads.div_ceil(size);
    let x = groups.min(65_535);
    (x, if x == 0 { 0 } else { groups.div_ceil(x) })
}

impl VolumeBounds {
    pub(crate) fn new(ctx: &GpuContext, layouts: &Layouts) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "volume/volume_bounds.wgsl",
            "volume/volume_bounds/shader",
        )?;
        ctx.scoped("creating the volume bounds pipelines", || {
            let c = wgpu::ShaderStages::COMPUTE;
            let layout = bind_group_layout(
                ctx,
                "volume/volume_bounds/layout",
                &[
                    uniform(0, c),
                    storage(1, c, false),
                    storage(2, c, false),
                    storage(3, c, false),
                ],
            );
            let pipeline_layout = pipeline_layout(
                ctx,
                "volume/volume_bounds/pipeline-layout",
                &[Some(&layout), None, Some(&layouts.strands)],
            );
            let p = |entry: &str| {
                compute_pipeline(
                    ctx,
                    &format!("volume/volume_bounds/{entry}-pipeline"),
                    &module,
                    entry,
                    &pipeline_layout,
                )
            };
            VolumeBounds {
                clear: p("clear"),
                reduce: p("reduce"),
                fit: p("fit"),
                layout,
            }
        })
    }

    /// Record the three dispatches into an open compute pass.
    pub(crate) fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        geometry: &StrandGeometry,
    ) {
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(2, &geometry.bind_group, &[]);
        pass.set_pipeline(&self.clear);
        pass.dispatch_workgroups(1, 1, 1);
        let (x, y) = dispatch_2d(geometry.vertex_count(), 64);
        if x > 0 {
            pass.set_pipeline(&self.reduce);
            pass.dispatch_workgroups(x, y, 1);
        }
        pass.set_pipeline(&self.fit);
        pass.dispatch_workgroups(1, 1, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatch_covers_every_thread_within_limits() {
        assert_eq!(dispatch_2d(0, 64), (0, 0));
        assert_eq!(dispatch_2d(1, 64), (1, 1));
        assert_eq!(dispatch_2d(65, 64), (2, 1));
        let (x, y) = dispatch_2d(10_000_000, 64);
        assert!(x <= 65_535 && u64::from(x) * u64::from(y) * 64 >= 10_000_000);
    }
}
