//! The opaque head mesh: plain input ([`TriMesh`], checked by [`validate`]), its GPU upload
//! ([`HeadGeometry`]) and the pass that draws it first with depth writes ([`HeadPass`]; every
//! technique's head shares its pipeline, `HeadPipeline`).

mod head_pass;

use glam::Vec3;
use wgpu::util::DeviceExt;

pub use head_pass::HeadPass;
pub(crate) use head_pass::{HeadPassInfo, HeadPipeline};

pub use tress_hair::generate::TriMesh;

use crate::gpu::types::HeadVertex;
use crate::{GpuContext, RenderError};

/// Check a head mesh's sizes, finiteness and index bounds (normals need not be unit length;
/// zero is allowed and lit as facing the eye).
pub fn validate(mesh: &TriMesh) -> Result<(), RenderError> {
    if mesh.positions.len() != mesh.normals.len() {
        return Err(RenderError::Invalid(format!(
            "head mesh has {} positions but {} normals",
            mesh.positions.len(),
            mesh.normals.len()
        )));
    }
    if mesh.indices.is_empty() || !mesh.indices.len().is_multiple_of(3) {
        return Err(RenderError::Invalid(format!(
            "head mesh index count {} is not a positive multiple of 3",
            mesh.indices.len()
        )));
    }
    if let Some(i) = mesh
        .indices
        .iter()
        .position(|&i| i as usize >= mesh.positions.len())
    {
        return Err(RenderError::Invalid(format!(
            "head mesh index {i} ({}) is out of range",
            mesh.indices[i]
        )));
    }
    if mesh
        .positions
        .iter()
        .chain(&mesh.normals)
        .any(|p| !p.is_finite())
    {
        return Err(RenderError::Invalid(
            "head mesh has non-finite positions or normals".into(),
        ));
    }
    Ok(())
}

/// A head mesh uploaded to the GPU.
#[derive(Debug)]
pub struct HeadGeometry {
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) indices: wgpu::Buffer,
    pub(crate) index_count: u32,
    /// Bounding sphere (centre, radius).
    pub bounds: (Vec3, f32),
}

impl HeadGeometry {
    /// Bytes of GPU buffers (vertices and indices).
    pub fn bytes(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }

    /// Record the draw of every triangle into an open render pass (pipeline and bind groups
    /// already set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }

    /// Replace the vertices with `mesh`'s, which must have the same vertices and triangles (the
    /// head moved: its positions and normals changed, not its topology).
    pub fn update_mesh(&mut self, ctx: &GpuContext, mesh: &TriMesh) -> Result<(), RenderError> {
        let verts: Vec<HeadVertex> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .map(|(p, n)| HeadVertex {
                position: p.to_array(),
                normal: n.to_array(),
            })
            .collect();
        let bytes = std::mem::size_of_val(verts.as_slice()) as u64;
        if bytes != self.vertices.size() || mesh.indices.len() as u32 != self.index_count {
            return Err(RenderError::Invalid(format!(
                "update_mesh: the mesh has {} vertices and {} indices, the head {} and {}",
                mesh.positions.len(),
                mesh.indices.len(),
                self.vertices.size() / std::mem::size_of::<HeadVertex>() as u64,
                self.index_count
            )));
        }
        ctx.queue
            .write_buffer(&self.vertices, 0, bytemuck::cast_slice(&verts));
        self.bounds = mesh.bounding_sphere();
        Ok(())
    }

    /// Validate and upload a mesh.
    pub fn new(ctx: &GpuContext, mesh: &TriMesh) -> Result<Self, RenderError> {
        validate(mesh)?;
        let verts: Vec<HeadVertex> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .map(|(p, n)| HeadVertex {
                position: p.to_array(),
                normal: n.to_array(),
            })
            .collect();
        let bytes = std::mem::size_of_val(verts.as_slice()) as u64;
        if bytes > ctx.caps.max_buffer_size {
            return Err(RenderError::Limit {
                what: "head vertex buffer".into(),
                needed: bytes,
                limit: ctx.caps.max_buffer_size,
            });
        }
        ctx.scoped("uploading the head mesh", || HeadGeometry {
            vertices: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("head/geometry/vertices"),
                    contents: bytemuck::cast_slice(&verts),
                    // COPY_DST: a moving head is uploaded again (`update_mesh`).
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                }),
            indices: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("head/geometry/indices"),
                    contents: bytemuck::cast_slice(&mesh.indices),
                    usage: wgpu::BufferUsages::INDEX,
                }),
            index_count: mesh.indices.len() as u32,
            bounds: mesh.bounding_sphere(),
        })
    }
}

/// Vertex buffer layout of [`HeadVertex`] (shared by the head pass and the shadow pass).
pub(crate) const HEAD_VERTEX_LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: std::mem::size_of::<HeadVertex>() as u64,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_is_valid_and_bounded() {
        let m = TriMesh::uv_sphere(Vec3::new(1.0, 0.0, 0.0), 2.0, 8, 12);
        validate(&m).expect("valid");
        let (c, r) = m.bounding_sphere();
        assert!((c - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-4);
        assert!(r >= 2.0 && r < 2.0 * 3f32.sqrt() + 1e-3);
    }

    #[test]
    fn bad_meshes_are_rejected() {
        let mut m = TriMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.indices.push(10_000);
        m.indices.extend_from_slice(&[0, 0]);
        assert!(
            validate(&m)
                .unwrap_err()
                .to_string()
                .contains("out of range")
        );
        let mut m = TriMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.normals.pop();
        assert!(validate(&m).is_err());
        let mut m = TriMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.indices.pop();
        assert!(validate(&m).is_err());
        let mut m = TriMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.positions[0] = Vec3::NAN;
        assert!(validate(&m).is_err());
    }
}
