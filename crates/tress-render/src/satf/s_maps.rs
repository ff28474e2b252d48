//! [`SMaps`], owner of `s_maps.wgsl` (Table 1, "shadowing", with [`super::ClusterShadow`]).

use super::SatfGeometry;
use super::cluster_shadow::ShadowTargets;
use super::index_calc::Uniforms;
use super::passes::{Slot, compute_pipelines, group, groups, layout, pipeline_layout};
use crate::{GpuContext, RenderError};

/// Per texel of every layer, the s-map of equation 12 and each light's visibility through the
/// other clusters (§6.4).
#[derive(Debug)]
pub struct SMaps {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl SMaps {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        let layout = layout(
            ctx,
            "satf/s_maps/layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                (0, Slot::Uniform),
                (1, Slot::Uniform),
                (2, Slot::Texture),
                (3, Slot::StorageTexture(wgpu::TextureFormat::Rgba16Float)),
                (4, Slot::StorageTexture(wgpu::TextureFormat::Rgba16Float)),
                (10, Slot::Storage { read_only: true }),
                (11, Slot::DepthArray),
                (12, Slot::UintArray),
            ],
        );
        let pl = pipeline_layout(ctx, "satf/s_maps/pipeline-layout", &layout);
        let pipeline =
            compute_pipelines(ctx, "satf/s_maps.wgsl", "satf/s_maps", &pl, &["cs_main"])?
                .pop()
                .ok_or_else(|| RenderError::Invalid("pipeline missing".into()))?;
        Ok(SMaps { layout, pipeline })
    }

    /// Record the pass over every texel of every tile.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        u: Uniforms<'_>,
        geometry: &SatfGeometry,
        shadow: &ShadowTargets,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let a = &geometry.atlas;
        let bind = group(
            ctx,
            "satf/s_maps/bind-group",
            &self.layout,
            &[
                (0, u.params.as_entire_binding()),
                (1, u.lights.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(&a.maps)),
                (3, wgpu::BindingResource::TextureView(&a.s_map)),
                (4, wgpu::BindingResource::TextureView(&a.vis)),
                (10, geometry.vertices.as_entire_binding()),
                (11, wgpu::BindingResource::TextureView(&shadow.depth_array)),
                (12, wgpu::BindingResource::TextureView(&shadow.ids_array)),
            ],
        );
        let l = &geometry.layout;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("satf/s_maps/pass"),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, &bind, &[]);
        pass.set_pipeline(&self.pipeline);
        pass.dispatch_workgroups(groups(l.tile_width, 8), groups(l.tile_height, 8), l.tiles());
    }
}
