//! [`IndexCalc`], owner of `index_calc.wgsl` (Table 1, "index calculation").

use super::passes::{Slot, compute_pipelines, groups, layout};
use super::{SatfDatabase, SatfGeometry};
use crate::bind::bind_group;
use crate::gpu::pipeline::pipeline_layout;
use crate::{GpuContext, RenderError};

/// Per boundary sector `Params(b)` and its nearest database sample; per HSV equation 6 and the
/// records its maps are built from (§6.2.1).
#[derive(Debug)]
pub struct IndexCalc {
    layout: wgpu::BindGroupLayout,
    sectors: wgpu::ComputePipeline,
    hsvs: wgpu::ComputePipeline,
}

/// The uniforms an online compute pass reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Uniforms<'a> {
    pub(crate) camera: &'a wgpu::Buffer,
    pub(crate) lights: &'a wgpu::Buffer,
    pub(crate) params: &'a wgpu::Buffer,
}

impl IndexCalc {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let storage = |read_only| Slot::Storage { read_only };
        let layout = layout(
            ctx,
            "satf/index_calc/layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                (0, Slot::Uniform),
                (1, Slot::Uniform),
                (2, Slot::Uniform),
                (3, storage(true)),
                (4, storage(true)),
                (5, storage(false)),
                (6, storage(false)),
                (7, storage(false)),
            ],
        );
        let pl = pipeline_layout(ctx, "satf/index_calc/pipeline-layout", &[Some(&layout)]);
        let [sectors, hsvs] = compute_pipelines(
            ctx,
            "satf/index_calc.wgsl",
            "satf/index_calc",
            &pl,
            ["cs_sectors", "cs_hsvs"],
        )?;
        Ok(IndexCalc {
            layout,
            sectors,
            hsvs,
        })
    }

    /// Record the pass: clear the counters, then the sector and the HSV dispatches.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        u: Uniforms<'_>,
        geometry: &SatfGeometry,
        database: &SatfDatabase,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let bind = bind_group(
            ctx,
            "satf/index_calc/bind-group",
            &self.layout,
            &[
                (0, u.camera.as_entire_binding()),
                (1, u.lights.as_entire_binding()),
                (2, u.params.as_entire_binding()),
                (3, geometry.sectors.as_entire_binding()),
                (4, database.features.as_entire_binding()),
                (5, geometry.sector_params.as_entire_binding()),
                (6, geometry.hsvs.as_entire_binding()),
                (7, geometry.counters.as_entire_binding()),
            ],
        );
        encoder.clear_buffer(&geometry.counters, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("satf/index_calc/pass"),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, &bind, &[]);
        pass.set_pipeline(&self.sectors);
        pass.dispatch_workgroups(groups(geometry.layout.sectors(), 64), 1, 1);
        pass.set_pipeline(&self.hsvs);
        pass.dispatch_workgroups(groups(geometry.layout.hsvs(), 64), 1, 1);
    }
}
