//! [`SMaps`], owner of `s_maps.wgsl` (Table 1, "shadowing", with [`super::ClusterShadow`]).

use super::SatfGeometry;
use super::cluster_shadow::ShadowTargets;
use super::index_calc::Uniforms;
use super::passes::{Slot, TilePass};
use crate::{GpuContext, RenderError};

/// Per texel of every layer, the s-map of equation 12 and each light's visibility through the
/// other clusters (§6.4).
#[derive(Debug)]
pub struct SMaps(TilePass);

impl SMaps {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        TilePass::new(
            ctx,
            "s_maps",
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
        )
        .map(SMaps)
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
        self.0.encode(
            ctx,
            encoder,
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
            &geometry.layout,
            timestamps,
        );
    }
}
