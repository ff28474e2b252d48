//! The opaque head mesh: plain input ([`HeadMesh`]), its GPU upload ([`HeadGeometry`]) and the pass
//! that draws it first with depth writes ([`HeadPass`]; every technique's head shares its pipeline,
//! `HeadPipeline`).

mod head_pass;

use glam::Vec3;
use wgpu::util::DeviceExt;

pub use head_pass::HeadPass;
pub(crate) use head_pass::HeadPipeline;

use crate::gpu::types::HeadVertex;
use crate::{GpuContext, RenderError};

/// A triangle mesh: positions, per-vertex normals and triangle indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HeadMesh {
    /// Vertex positions (world space).
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (need not be unit length; zero is allowed and lit as facing the eye).
    pub normals: Vec<Vec3>,
    /// Triangle list indices into `positions`.
    pub indices: Vec<u32>,
}

impl HeadMesh {
    /// Check sizes, finiteness and index bounds.
    pub fn validate(&self) -> Result<(), RenderError> {
        if self.positions.len() != self.normals.len() {
            return Err(RenderError::Invalid(format!(
                "head mesh has {} positions but {} normals",
                self.positions.len(),
                self.normals.len()
            )));
        }
        if self.indices.is_empty() || !self.indices.len().is_multiple_of(3) {
            return Err(RenderError::Invalid(format!(
                "head mesh index count {} is not a positive multiple of 3",
                self.indices.len()
            )));
        }
        if let Some(i) = self
            .indices
            .iter()
            .position(|&i| i as usize >= self.positions.len())
        {
            return Err(RenderError::Invalid(format!(
                "head mesh index {i} ({}) is out of range",
                self.indices[i]
            )));
        }
        if self
            .positions
            .iter()
            .chain(&self.normals)
            .any(|p| !p.is_finite())
        {
            return Err(RenderError::Invalid(
                "head mesh has non-finite positions or normals".into(),
            ));
        }
        Ok(())
    }

    /// A UV sphere (a stand-in head for tests and examples).
    pub fn uv_sphere(center: Vec3, radius: f32, rings: u32, segments: u32) -> Self {
        let (rings, segments) = (rings.max(2), segments.max(3));
        let mut mesh = HeadMesh::default();
        for r in 0..=rings {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let phi = std::f32::consts::TAU * s as f32 / segments as f32;
                let n = Vec3::new(
                    theta.sin() * phi.sin(),
                    theta.cos(),
                    theta.sin() * phi.cos(),
                );
                mesh.positions.push(center + n * radius);
                mesh.normals.push(n);
            }
        }
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let a = r * row + s;
                let b = a + row;
                mesh.indices
                    .extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        mesh
    }

    /// Centre and radius of a sphere around all vertices.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        bounding_sphere(&self.positions)
    }
}

/// Centre of the bounding box and the radius around it (zero for no points).
pub(crate) fn bounding_sphere(points: &[Vec3]) -> (Vec3, f32) {
    let Some(b) = tress_hair::Aabb::from_points(points) else {
        return (Vec3::ZERO, 0.0);
    };
    (b.center(), b.size().length() * 0.5)
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

    /// Validate and upload a mesh.
    pub fn new(ctx: &GpuContext, mesh: &HeadMesh) -> Result<Self, RenderError> {
        mesh.validate()?;
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
                    usage: wgpu::BufferUsages::VERTEX,
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
        let m = HeadMesh::uv_sphere(Vec3::new(1.0, 0.0, 0.0), 2.0, 8, 12);
        m.validate().expect("valid");
        let (c, r) = m.bounding_sphere();
        assert!((c - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-4);
        assert!(r >= 2.0 && r < 2.0 * 3f32.sqrt() + 1e-3);
    }

    #[test]
    fn bad_meshes_are_rejected() {
        let mut m = HeadMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.indices.push(10_000);
        m.indices.extend_from_slice(&[0, 0]);
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("out of range")
        );
        let mut m = HeadMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.normals.pop();
        assert!(m.validate().is_err());
        let mut m = HeadMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.indices.pop();
        assert!(m.validate().is_err());
        let mut m = HeadMesh::uv_sphere(Vec3::ZERO, 1.0, 4, 4);
        m.positions[0] = Vec3::NAN;
        assert!(m.validate().is_err());
    }
}
