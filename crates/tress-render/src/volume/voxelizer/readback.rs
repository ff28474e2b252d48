//! [`Voxelizer::read_back`]: everything a voxelization left on the GPU, read back (tests and
//! tools; slow).

use super::{GRID_BYTES, Voxelizer, buffer};
use crate::gpu::read_buffer;
use crate::gpu::types::{BoundsKeys, VolumeGrid, VoxelStats};
use crate::volume::OCCUPANCY_BLOCK;
use crate::{GpuContext, RenderError};
use tress_shading::voxelize::decode_texel;

/// Everything the voxelizer holds after a frame, read back (tests and tools; slow).
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeReadback {
    /// The grid the GPU fitted.
    pub grid: VolumeGrid,
    /// The box as order-preserving keys.
    pub keys: BoundsKeys,
    /// Per voxel: samples that reached it (dropped ones included).
    pub counts: Vec<u32>,
    /// Per voxel: quantized tangent sums of the accepted samples (x, y, z).
    pub tangent_sums: Vec<[u32; 3]>,
    /// Per voxel: quantized highlight sums of the accepted samples, a light each.
    pub highlight_sums: Vec<[u32; 4]>,
    /// Per voxel: quantized tip fades of the accepted samples, summed (the high half of the
    /// tangent's z word).
    pub fade_sums: Vec<u32>,
    /// Per voxel: the highlight texel's bytes, a light each.
    pub highlight_texels: Vec<[u8; 4]>,
    /// Per voxel: the texel read as the mean tangent and the density.
    pub texels: Vec<[f32; 4]>,
    /// Per voxel: the texel's bytes (`tress_shading::voxelize::encode_texel`).
    pub texel_bytes: Vec<[u8; 4]>,
    /// Per texel of the baked ambient-occlusion texture (`ao_resolution(res, ao_texel)³`, x
    /// fastest): the visibility's byte (255: unoccluded); empty without one.
    pub ao_texels: Vec<u8>,
    /// Per occupancy block: 1 when occupied.
    pub occupancy: Vec<u32>,
    /// Deposits and drops.
    pub stats: VoxelStats,
}

impl Voxelizer {
    /// Read object 0's volume and the counters back (slow: for tests and tools).
    pub fn read_back(&self, ctx: &GpuContext) -> Result<VolumeReadback, RenderError> {
        let g = self.grid0()?;
        let res = g.res;
        let n = u64::from(res).pow(3);
        let words = |b: &wgpu::Buffer| -> Result<Vec<u32>, RenderError> {
            Ok(bytemuck::cast_slice(&self.read(ctx, b, n * 4)?).to_vec())
        };
        let counts = words(&self.scratch.counts)?;
        let xy = words(&self.scratch.tangent_xy)?;
        let z = words(&self.scratch.tangent_z)?;
        let blocks = u64::from(res.div_ceil(OCCUPANCY_BLOCK)).pow(3);
        let occupancy = bytemuck::cast_slice(&self.read(ctx, &g.occupancy, blocks * 4)?).to_vec();
        let grid: VolumeGrid = bytemuck::pod_read_unaligned(&self.read(ctx, &g.grid, GRID_BYTES)?);
        let keys = bytemuck::pod_read_unaligned(&self.read(ctx, &g.keys, 24)?);
        let stats = bytemuck::pod_read_unaligned(&self.read(ctx, &g.stats, 16)?);
        let bytes = self.read_texture(ctx, &g.texture, res)?;
        let highlight_texels: Vec<[u8; 4]> = self
            .read_texture(ctx, &g.highlight_texture, res)?
            .chunks_exact(4)
            .map(|t| [t[0], t[1], t[2], t[3]])
            .collect();
        let ao_texels: Vec<u8> = match &g.ao {
            Some(ao) => self
                .read_texture(ctx, &ao.texture, ao.res)?
                .chunks_exact(4)
                .map(|t| t[0])
                .collect(),
            None => Vec::new(),
        };
        let highlight_words: Vec<u32> =
            bytemuck::cast_slice(&self.read(ctx, &self.scratch.highlights, n * 8)?).to_vec();
        let mut texels = Vec::with_capacity(n as usize);
        let mut texel_bytes = Vec::with_capacity(n as usize);
        for t in bytes.chunks_exact(4) {
            let b = [t[0], t[1], t[2], t[3]];
            texel_bytes.push(b);
            let (tangent, density) = decode_texel(b, grid.density_unit);
            texels.push([tangent.x, tangent.y, tangent.z, density]);
        }
        Ok(VolumeReadback {
            grid,
            keys,
            counts,
            tangent_sums: xy
                .iter()
                .zip(&z)
                .map(|(&xy, &z)| [xy & 0xffff, xy >> 16, z & 0xffff])
                .collect(),
            fade_sums: z.iter().map(|&z| z >> 16).collect(),
            highlight_sums: highlight_words
                .chunks_exact(2)
                .map(|w| tress_shading::highlights::unpack_highlights([w[0], w[1]]))
                .collect(),
            highlight_texels,
            texels,
            texel_bytes,
            ao_texels,
            occupancy,
            stats,
        })
    }

    /// A `res³` `rgba8unorm` texture's bytes, x fastest, without the copy's row padding.
    fn read_texture(
        &self,
        ctx: &GpuContext,
        texture: &wgpu::Texture,
        res: u32,
    ) -> Result<Vec<u8>, RenderError> {
        let row = res * 4;
        let padded =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let size = u64::from(padded) * u64::from(res) * u64::from(res);
        let staging = ctx.scoped("volume texture readback", || {
            let staging = buffer(
                ctx,
                "volume/readback/texture",
                size,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            );
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("volume/readback/texture-encoder"),
                });
            encoder.copy_texture_to_buffer(
                texture.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded),
                        rows_per_image: Some(res),
                    },
                },
                texture.size(),
            );
            ctx.queue.submit([encoder.finish()]);
            staging
        })?;
        let bytes = read_buffer(ctx, &staging, 0..size)?;
        Ok((0..(res * res) as usize)
            .flat_map(|r| &bytes[r * padded as usize..r * padded as usize + row as usize])
            .copied()
            .collect())
    }
}
