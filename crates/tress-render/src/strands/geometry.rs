//! [`StrandGeometry`]: a [`HairAsset`] uploaded for vertex pulling.

use glam::Vec3;
use tress_hair::HairAsset;
use wgpu::util::DeviceExt;

use crate::bind::Layouts;
use crate::gpu::types::StrandVertex;
use crate::{GpuContext, RenderError};

/// A hair asset on the GPU: one [`StrandVertex`] per vertex and one `(first vertex, strand)` pair
/// per segment, bound at group 2 of the strand passes.
#[derive(Debug)]
pub struct StrandGeometry {
    pub(crate) bind_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    bytes: u64,
    mean_segment_length: f32,
    segments: u32,
    strands: u32,
    has_thickness: bool,
    max_thickness: f32,
    has_color: bool,
    /// Bounding sphere (centre, radius) of the vertices.
    pub bounds: (Vec3, f32),
}

/// The CPU arrays uploaded for an asset (exposed for tests of the layout).
pub(crate) fn build_arrays(asset: &HairAsset) -> (Vec<StrandVertex>, Vec<[u32; 2]>) {
    let thickness = asset.thickness();
    let transparency = asset.transparency();
    let color = asset.color();
    let vertices = asset
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| StrandVertex {
            position: p.to_array(),
            thickness: thickness.map_or(0.0, |t| t[i]),
            color: color.map_or([1.0; 3], |c| c[i].to_array()),
            alpha: transparency.map_or(1.0, |t| (1.0 - t[i]).clamp(0.0, 1.0)),
        })
        .collect();
    let mut segments = Vec::with_capacity(asset.segment_count());
    for s in 0..asset.strand_count() {
        let r = asset.strand_range(s);
        segments.extend((r.start..r.end.saturating_sub(1)).map(|v| [v as u32, s as u32]));
    }
    (vertices, segments)
}

/// Mean length of the asset's segments (0 without segments).
fn mean_segment_length(asset: &HairAsset) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0u64);
    for strand in asset.strands() {
        for w in strand.windows(2) {
            sum += f64::from(w[0].distance(w[1]));
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { (sum / n as f64) as f32 }
}

impl StrandGeometry {
    /// Upload an asset. Fails with [`RenderError::Limit`] when an array exceeds the device's
    /// storage-binding or buffer limits.
    pub fn new(ctx: &GpuContext, asset: &HairAsset) -> Result<Self, RenderError> {
        let layouts = Layouts::new(&ctx.device);
        Self::with_layout(ctx, &layouts.strands, asset)
    }

    pub(crate) fn with_layout(
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        asset: &HairAsset,
    ) -> Result<Self, RenderError> {
        let (vertices, segments) = build_arrays(asset);
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        let check = |what: &str, bytes: u64| {
            if bytes > limit {
                Err(RenderError::Limit {
                    what: what.into(),
                    needed: bytes,
                    limit,
                })
            } else {
                Ok(())
            }
        };
        check(
            "strand vertex buffer",
            std::mem::size_of_val(vertices.as_slice()) as u64,
        )?;
        check(
            "strand segment buffer",
            std::mem::size_of_val(segments.as_slice()) as u64,
        )?;
        let segment_count = u32::try_from(segments.len())
            .ok()
            .filter(|s| s.checked_mul(6).is_some())
            .ok_or_else(|| RenderError::Invalid("too many segments for one draw".into()))?;
        // Storage bindings cannot be empty: pad with one unused element.
        let seg_bytes: Vec<u8> = if segments.is_empty() {
            vec![0; 8]
        } else {
            bytemuck::cast_slice(&segments).to_vec()
        };
        let (bind_group, vertex_buffer, segment_bytes) = ctx.scoped("uploading strands", || {
            let v = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("strands/geometry/vertices"),
                    contents: bytemuck::cast_slice(&vertices),
                    // COPY_SRC: a simulation's cache reads the simulated positions back.
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                });
            let s = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("strands/geometry/segments"),
                    contents: &seg_bytes,
                    usage: wgpu::BufferUsages::STORAGE,
                });
            let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("strands/geometry/bind-group"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: v.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: s.as_entire_binding(),
                    },
                ],
            });
            (group, v, s.size())
        })?;
        let b = asset.bounds();
        let bytes = vertex_buffer.size() + segment_bytes;
        Ok(StrandGeometry {
            bind_group,
            vertices: vertex_buffer,
            vertex_count: vertices.len() as u32,
            bytes,
            mean_segment_length: mean_segment_length(asset),
            segments: segment_count,
            strands: asset.strand_count() as u32,
            has_thickness: asset.thickness().is_some(),
            max_thickness: asset
                .thickness()
                .map_or(0.0, |t| t.iter().fold(0.0, |m: f32, &x| m.max(x))),
            has_color: asset.color().is_some(),
            bounds: (b.center(), b.size().length() * 0.5),
        })
    }

    /// Replace the vertex positions with those of `asset`, which must have the same strands and
    /// vertex counts (animated hair: the volume is voxelized again every frame). The other vertex
    /// attributes, the segments and the statistics fixed at upload are kept; the bounds follow.
    pub fn update_positions(
        &mut self,
        ctx: &GpuContext,
        asset: &HairAsset,
    ) -> Result<(), RenderError> {
        if asset.vertex_count() != self.vertex_count as usize
            || asset.strand_count() != self.strands as usize
        {
            return Err(RenderError::Invalid(format!(
                "update_positions: the asset has {} strands and {} vertices, the geometry {} and {}",
                asset.strand_count(),
                asset.vertex_count(),
                self.strands,
                self.vertex_count
            )));
        }
        let (vertices, _) = build_arrays(asset);
        ctx.queue
            .write_buffer(&self.vertices, 0, bytemuck::cast_slice(&vertices));
        let b = asset.bounds();
        self.bounds = (b.center(), b.size().length() * 0.5);
        Ok(())
    }

    /// The vertex buffer: one [`crate::gpu::types::StrandVertex`] a vertex, storage usage (a
    /// simulation writes positions into it, [`crate::sim::GpuSimulation::write_positions`]).
    pub fn vertex_buffer(&self) -> &wgpu::Buffer {
        &self.vertices
    }

    /// Bytes of GPU buffers (vertices and segments).
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Vertices uploaded.
    pub fn vertex_count(&self) -> u32 {
        self.vertex_count
    }

    /// Mean segment length in world units at upload (0 without segments).
    pub fn mean_segment_length(&self) -> f32 {
        self.mean_segment_length
    }

    /// Number of segments drawn.
    pub fn segment_count(&self) -> u32 {
        self.segments
    }

    /// Number of strands.
    pub fn strand_count(&self) -> u32 {
        self.strands
    }

    /// The thickest vertex of the asset (0 without thickness); the tip fade's reference.
    pub fn max_thickness(&self) -> f32 {
        self.max_thickness
    }

    /// Whether the asset has per-vertex thickness (enables the tip fade).
    pub fn has_thickness(&self) -> bool {
        self.has_thickness
    }

    /// Whether the asset has per-vertex colors (they replace the material's base color).
    pub fn has_color(&self) -> bool {
        self.has_color
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_never_cross_strands() {
        let p = vec![
            Vec3::ZERO,
            Vec3::Y,
            Vec3::X,
            Vec3::ONE,
            Vec3::Z,
            Vec3::NEG_Y,
        ];
        let asset = HairAsset::from_counts(p, &[2, 1, 3])
            .unwrap()
            .with_transparency(vec![0.0, 0.5, 0.0, 0.0, 0.0, 2.0])
            .unwrap();
        let (v, s) = build_arrays(&asset);
        assert_eq!(s, vec![[0, 0], [3, 2], [4, 2]]);
        assert_eq!(v.len(), 6);
        assert_eq!(v[1].alpha, 0.5);
        assert_eq!(v[5].alpha, 0.0);
        assert_eq!(v[0].color, [1.0; 3]);
        assert_eq!(v[0].thickness, 0.0);
    }
}
