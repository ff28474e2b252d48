//! [`PatchGeometry`]: a [`PatchMesh`] uploaded once, with its static inside-to-outside index
//! buffer; owner of the vertex layout in `geometry.wgsl`.

use glam::Vec3;
use tress_hair::patches::{PatchMesh, sorted_indices};
use wgpu::util::DeviceExt;

use crate::gpu::types::PatchVertex;
use crate::{GpuContext, RenderError};

/// A patch mesh on the GPU: one interleaved [`PatchVertex`] per vertex and the triangle indices
/// sorted inside to outside by patch (Scheuermann 2004, slide "Approximate Depth Sorting": "use
/// static index buffer with inside to outside draw order, computed at preprocess time"). The
/// order is computed once, here, and never changes.
#[derive(Debug)]
pub struct PatchGeometry {
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) indices: wgpu::Buffer,
    index_count: u32,
    components: u32,
    /// Bounding sphere (centre, radius) of the vertices.
    pub bounds: (Vec3, f32),
    /// The point the patches were sorted around (the head centre).
    pub sort_center: Vec3,
}

/// The interleaved vertices uploaded for a mesh.
pub fn patch_vertices(mesh: &PatchMesh) -> Vec<PatchVertex> {
    (0..mesh.vertex_count())
        .map(|i| {
            let uv = mesh.uvs()[i];
            PatchVertex {
                position: mesh.positions()[i].to_array(),
                ao: mesh.ao()[i],
                normal: mesh.normals()[i].to_array(),
                u: uv.x,
                tangent: mesh.tangents()[i].to_array(),
                v: uv.y,
            }
        })
        .collect()
}

impl PatchGeometry {
    /// Upload `mesh` with its patches sorted inside to outside around `sort_center` (the head
    /// centre; [`tress_hair::patches::sorted_indices`]).
    pub fn new(ctx: &GpuContext, mesh: &PatchMesh, sort_center: Vec3) -> Result<Self, RenderError> {
        if !sort_center.is_finite() {
            return Err(RenderError::Invalid(
                "patch sort centre is not finite".into(),
            ));
        }
        let vertices = patch_vertices(mesh);
        let indices = sorted_indices(mesh, sort_center);
        let bytes = std::mem::size_of_val(vertices.as_slice()) as u64;
        let index_bytes = std::mem::size_of_val(indices.as_slice()) as u64;
        for (what, needed) in [
            ("patch vertex buffer", bytes),
            ("patch index buffer", index_bytes),
        ] {
            if needed > ctx.caps.max_buffer_size {
                return Err(RenderError::Limit {
                    what: what.into(),
                    needed,
                    limit: ctx.caps.max_buffer_size,
                });
            }
        }
        let index_count = u32::try_from(indices.len()).map_err(|_| {
            RenderError::Invalid(format!("{} patch indices do not fit u32", indices.len()))
        })?;
        // Zero-sized buffers cannot be bound; an empty mesh gets one unused element.
        let vertex_bytes: Vec<u8> = if vertices.is_empty() {
            vec![0; std::mem::size_of::<PatchVertex>()]
        } else {
            bytemuck::cast_slice(&vertices).to_vec()
        };
        let index_data: Vec<u32> = if indices.is_empty() {
            vec![0; 3]
        } else {
            indices
        };
        let bounds = mesh
            .bounds()
            .map_or((Vec3::ZERO, 0.0), |b| (b.center(), b.size().length() * 0.5));
        ctx.scoped("uploading the patch mesh", || PatchGeometry {
            vertices: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("patches/geometry/vertices"),
                    contents: &vertex_bytes,
                    usage: wgpu::BufferUsages::VERTEX,
                }),
            indices: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("patches/geometry/sorted-indices"),
                    contents: bytemuck::cast_slice(&index_data),
                    usage: wgpu::BufferUsages::INDEX,
                }),
            index_count,
            components: mesh.component_count() as u32,
            bounds,
            sort_center,
        })
    }

    /// Number of triangles drawn.
    pub fn triangle_count(&self) -> u32 {
        self.index_count / 3
    }

    /// Bytes of GPU buffers (vertices and sorted indices).
    pub fn bytes(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }

    /// Number of patches (connected components).
    pub fn component_count(&self) -> u32 {
        self.components
    }

    /// Record the draw of the whole sorted index buffer into an open pass (pipeline and bind
    /// groups already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.index_count == 0 {
            return;
        }
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}

/// Vertex buffer layout of [`PatchVertex`] (locations 0 to 5 of `geometry.wgsl`).
pub(crate) const PATCH_VERTEX_LAYOUT: wgpu::VertexBufferLayout<'static> =
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<PatchVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Float32, 4 => Float32x3,
            5 => Float32
        ],
    };

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::offset_of;

    #[test]
    fn vertex_attributes_sit_at_the_struct_offsets() {
        let offsets: Vec<u64> = PATCH_VERTEX_LAYOUT
            .attributes
            .iter()
            .map(|a| a.offset)
            .collect();
        let expect = [
            offset_of!(PatchVertex, position),
            offset_of!(PatchVertex, ao),
            offset_of!(PatchVertex, normal),
            offset_of!(PatchVertex, u),
            offset_of!(PatchVertex, tangent),
            offset_of!(PatchVertex, v),
        ]
        .map(|o| o as u64);
        assert_eq!(offsets, expect);
        assert_eq!(
            PATCH_VERTEX_LAYOUT.array_stride as usize,
            std::mem::size_of::<PatchVertex>()
        );
    }
}
