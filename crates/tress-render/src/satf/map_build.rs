//! [`MapBuild`], owner of `map_build.wgsl` (Table 1, "map construction").

use super::index_calc::Uniforms;
use super::passes::{Slot, compute_pipelines, group, groups, layout, pipeline_layout};
use super::{SatfDatabase, SatfGeometry};
use crate::{GpuContext, RenderError};

/// Every texel of every layer's re-map and α-map from its HSV's records (§6.2.2, equation 7).
#[derive(Debug)]
pub struct MapBuild {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl MapBuild {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let layout = layout(
            ctx,
            "satf/map_build/layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                (0, Slot::Uniform),
                (1, Slot::Storage { read_only: true }),
                (2, Slot::Storage { read_only: true }),
                (3, Slot::Storage { read_only: true }),
                (4, Slot::StorageTexture(wgpu::TextureFormat::Rgba16Float)),
            ],
        );
        let pl = pipeline_layout(ctx, "satf/map_build/pipeline-layout", &layout);
        let pipeline = compute_pipelines(
            ctx,
            "satf/map_build.wgsl",
            "satf/map_build",
            &pl,
            &["cs_main"],
        )?
        .pop()
        .ok_or_else(|| RenderError::Invalid("pipeline missing".into()))?;
        Ok(MapBuild { layout, pipeline })
    }

    /// Record the pass over every texel of every tile.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        u: Uniforms<'_>,
        geometry: &SatfGeometry,
        database: &SatfDatabase,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let bind = group(
            ctx,
            "satf/map_build/bind-group",
            &self.layout,
            &[
                (0, u.params.as_entire_binding()),
                (1, geometry.hsvs.as_entire_binding()),
                (2, database.alpha.as_entire_binding()),
                (3, database.re.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&geometry.atlas.maps)),
            ],
        );
        let l = &geometry.layout;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("satf/map_build/pass"),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, &bind, &[]);
        pass.set_pipeline(&self.pipeline);
        pass.dispatch_workgroups(groups(l.tile_width, 8), groups(l.tile_height, 8), l.tiles());
    }
}
