//! [`Lighting`], owner of `lighting.wgsl` (Table 1, "lighting").

use super::SatfGeometry;
use super::index_calc::Uniforms;
use super::passes::{Slot, TilePass};
use crate::{GpuContext, RenderError};

/// Per texel of every layer, equations 8–11 summed over the lights (§6.3).
#[derive(Debug)]
pub struct Lighting(TilePass);

impl Lighting {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        TilePass::new(
            ctx,
            "lighting",
            &[
                (0, Slot::Uniform),
                (1, Slot::Uniform),
                (2, Slot::Uniform),
                (3, Slot::Texture),
                (4, Slot::StorageTexture(wgpu::TextureFormat::Rgba16Float)),
                (10, Slot::Storage { read_only: true }),
            ],
        )
        .map(Lighting)
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
        self.0.encode(
            ctx,
            encoder,
            &[
                (0, u.params.as_entire_binding()),
                (1, u.camera.as_entire_binding()),
                (2, u.lights.as_entire_binding()),
                (3, wgpu::BindingResource::TextureView(&a.vis)),
                (4, wgpu::BindingResource::TextureView(&a.l_map)),
                (10, geometry.vertices.as_entire_binding()),
            ],
            &geometry.layout,
            timestamps,
        );
    }
}
