//! [`Lighting`], owner of `lighting.wgsl` (Table 1, "lighting").

use super::SatfGeometry;
use super::index_calc::Uniforms;
use super::passes::{Slot, compute_pipelines, group, groups, layout, pipeline_layout};
use crate::{GpuContext, RenderError};

/// Per texel of every layer, equations 8–11 summed over the lights (§6.3).
#[derive(Debug)]
pub struct Lighting {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl Lighting {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let layout = layout(
            ctx,
            "satf/lighting/layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                (0, Slot::Uniform),
                (1, Slot::Uniform),
                (2, Slot::Uniform),
                (3, Slot::Texture),
                (4, Slot::StorageTexture(wgpu::TextureFormat::Rgba16Float)),
                (10, Slot::Storage { read_only: true }),
            ],
        );
        let pl = pipeline_layout(ctx, "satf/lighting/pipeline-layout", &layout);
        let pipeline = compute_pipelines(
            ctx,
            "satf/lighting.wgsl",
            "satf/lighting",
            &pl,
            &["cs_main"],
        )?
        .pop()
        .ok_or_else(|| RenderError::Invalid("pipeline missing".into()))?;
        Ok(Lighting { layout, pipeline })
    }

    /// Record the pass over every texel of every tile.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        u: Uniforms<'_>,
        geometry: &SatfGeometry,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let a = &geometry.atlas;
        let bind = group(
            ctx,
            "satf/lighting/bind-group",
            &self.layout,
            &[
                (0, u.params.as_entire_binding()),
                (1, u.camera.as_entire_binding()),
                (2, u.lights.as_entire_binding()),
                (3, wgpu::BindingResource::TextureView(&a.vis)),
                (4, wgpu::BindingResource::TextureView(&a.l_map)),
                (10, geometry.vertices.as_entire_binding()),
            ],
        );
        let l = &geometry.layout;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("satf/lighting/pass"),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, &bind, &[]);
        pass.set_pipeline(&self.pipeline);
        pass.dispatch_workgroups(groups(l.tile_width, 8), groups(l.tile_height, 8), l.tiles());
    }
}
