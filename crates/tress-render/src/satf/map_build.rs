//! [`MapBuild`], owner of `map_build.wgsl` (Table 1, "map construction").

use super::index_calc::Uniforms;
use super::passes::{Slot, TilePass};
use super::{SatfDatabase, SatfGeometry};
use crate::{GpuContext, RenderError};

/// Every texel of every layer's re-map and α-map from its HSV's records (§6.2.2, equation 7).
#[derive(Debug)]
pub struct MapBuild(TilePass);

impl MapBuild {
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, RenderError> {
        TilePass::new(
            ctx,
            "map_build",
            &[
                (0, Slot::Uniform),
                (1, Slot::Storage { read_only: true }),
                (2, Slot::Storage { read_only: true }),
                (3, Slot::Storage { read_only: true }),
                (4, Slot::StorageTexture(wgpu::TextureFormat::Rgba16Float)),
            ],
        )
        .map(MapBuild)
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
        self.0.encode(
            ctx,
            encoder,
            &[
                (0, u.params.as_entire_binding()),
                (1, geometry.hsvs.as_entire_binding()),
                (2, database.alpha.as_entire_binding()),
                (3, database.re.as_entire_binding()),
                (4, wgpu::BindingResource::TextureView(&geometry.atlas.maps)),
            ],
            &geometry.layout,
            timestamps,
        );
    }
}
