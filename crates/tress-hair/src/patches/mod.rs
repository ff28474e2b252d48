//! Polygon-patch hair (Scheuermann 2004): the CPU side. A [`PatchMesh`] of layered 2D strips,
//! its three sources, its procedural textures, the per-vertex ambient occlusion bake and the
//! static inside-to-outside index buffer. The renderer (`tress-render`, `patches/`) draws it.
//!
//! # Sources
//!
//! - [`generate_patches`]: layered strips grown from the scalp of the generated [`Head`]
//!   ([`generate`](mod@generate));
//! - [`PatchMesh::from_obj`] / [`PatchMesh::read_obj`]: hair cards from a Wavefront OBJ file
//!   ([`obj`]);
//! - [`PatchMesh::from_strands`]: ribbons that follow groups of neighbouring strands of a
//!   [`HairAsset`](crate::HairAsset) ([`cards`]); [`PatchMesh::to_obj`] writes any mesh back
//!   out, e.g. for `tress cards`.
//!
//! # Implementation
//!
//! Paper: T. Scheuermann, "Practical Real-Time Hair Rendering and Shading", SIGGRAPH 2004 sketch
//! (`papers/scheuermann-2004-sketch.txt`) and the slides "Hair Rendering and Shading"
//! (`papers/scheuermann-2004-slides.md`).
//!
//! - *Hair model* (sketch, "Hair model"; slide "Hair Model Authoring"): "layered 2D polygon
//!   patches which provides a simple approximation of the volumetric qualities of hair". The
//!   generator grows `layers` shells of strips; inner layers sit closer to the scalp and are
//!   shorter, so the outer layers hide them except where the hair parts.
//! - *Textures* (slide "Hair Model - Textures"): base (stretched noise), alpha ("should have
//!   fully opaque regions"), specular shift and specular noise. The paper gives no recipe; the
//!   choices are documented in [`texture`].
//! - *Ambient occlusion* (sketch, "Ambient occlusion"; slide "Hair Model Authoring": "per
//!   vertex"): "computed in a pre-processing step". [`bake_ao`] casts rays against the patches
//!   and the head; the two-sided treatment of a patch is documented in [`ao`].
//! - *Approximate depth sorting* (sketch, "Rendering with approximate depth sorting"; slide
//!   "Approximate Depth Sorting"): "sort connected components (hair strand patches) instead of
//!   individual triangles" into a static index buffer, inside to outside. [`sorted_indices`]
//!   orders the components by the mean distance of their vertices from the head centre (see
//!   [`sort`]).
//!
//! # Conventions
//!
//! Tangents point from root to tip and are perpendicular to the normals (the shader shifts them
//! along the normal, `T' = normalize(T + s·N)`, sketch "Specular lighting"). UVs: `u` runs across
//! a patch from 0 to 1, `v` from 0 at the root to 1 at the tip; a texture's row 0 is `v = 0`, as
//! wgpu addresses textures. A component (patch) is a set of triangles connected through shared
//! vertices, where vertices at bit-identical positions count as shared (so UV seams and per-face
//! normals in an OBJ file do not split a card). Triangles are counter-clockwise seen from the side
//! the normal points to; patches are drawn two-sided all the same.

pub mod ao;
pub mod cards;
pub mod generate;
pub mod obj;
mod occluders;
pub mod sort;
pub mod texture;

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use crate::{Aabb, HairError};

pub use ao::{AoParams, AoSides, bake_ao};
pub use cards::CardParams;
pub use generate::{PatchParams, generate_patches};
pub use sort::{component_distances, sorted_indices};
pub use texture::{HairTextures, Texture, TextureParams};

#[cfg(doc)]
use crate::generate::Head;

/// A polygon-patch hair mesh: indexed triangles with per-vertex normals, tangents, UVs and
/// ambient occlusion, and the connected component (patch) of each triangle.
///
/// Invariants (checked by [`PatchMesh::new`]): all per-vertex arrays have one entry per
/// position; positions and UVs are finite; normals and tangents are finite, non-zero and stored
/// normalized; the index count is a multiple of 3 and every index is in range; AO lies in
/// `[0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchMesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    tangents: Vec<Vec3>,
    uvs: Vec<Vec2>,
    ao: Vec<f32>,
    indices: Vec<u32>,
    components: Vec<u32>,
    component_count: u32,
}

impl PatchMesh {
    /// A mesh from its arrays, with AO 1 (unoccluded) everywhere. Normals and tangents are
    /// normalized; components are found from connectivity (see the module docs).
    pub fn new(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        tangents: Vec<Vec3>,
        uvs: Vec<Vec2>,
        indices: Vec<u32>,
    ) -> Result<Self, HairError> {
        let n = positions.len();
        if u32::try_from(n).is_err() {
            return Err(invalid(format!("{n} vertices do not fit 32-bit indices")));
        }
        for (name, len) in [
            ("normal", normals.len()),
            ("tangent", tangents.len()),
            ("UV", uvs.len()),
        ] {
            if len != n {
                return Err(invalid(format!(
                    "{name} array has {len} entries for {n} vertices"
                )));
            }
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(invalid(format!("vertex {i} has a non-finite position")));
        }
        if let Some(i) = uvs.iter().position(|p| !p.is_finite()) {
            return Err(invalid(format!("vertex {i} has a non-finite UV")));
        }
        let normals = unit_vectors("normal", normals)?;
        let tangents = unit_vectors("tangent", tangents)?;
        if !indices.len().is_multiple_of(3) {
            return Err(invalid(format!(
                "{} indices do not make whole triangles",
                indices.len()
            )));
        }
        if let Some(i) = indices.iter().position(|&i| i as usize >= n) {
            return Err(invalid(format!(
                "index {i} is {} but there are {n} vertices",
                indices[i]
            )));
        }
        let (components, component_count) = connected_components(&positions, &indices);
        Ok(PatchMesh {
            ao: vec![1.0; n],
            positions,
            normals,
            tangents,
            uvs,
            indices,
            components,
            component_count,
        })
    }

    /// The mesh with per-vertex ambient occlusion `ao` (one entry per vertex, each in `[0, 1]`,
    /// 1 = unoccluded).
    pub fn with_ao(mut self, ao: Vec<f32>) -> Result<Self, HairError> {
        self.set_ao(ao)?;
        Ok(self)
    }

    /// Replace the per-vertex ambient occlusion (see [`PatchMesh::with_ao`]); on error nothing
    /// changes.
    pub fn set_ao(&mut self, ao: Vec<f32>) -> Result<(), HairError> {
        if ao.len() != self.vertex_count() {
            return Err(invalid(format!(
                "AO array has {} entries for {} vertices",
                ao.len(),
                self.vertex_count()
            )));
        }
        if let Some(i) = ao.iter().position(|a| !(0.0..=1.0).contains(a)) {
            return Err(invalid(format!(
                "AO of vertex {i} is {}, not in [0, 1]",
                ao[i]
            )));
        }
        self.ao = ao;
        Ok(())
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Number of connected components (patches).
    pub fn component_count(&self) -> usize {
        self.component_count as usize
    }

    /// Move the mesh by `affine`, a similarity (rotation, uniform scale, translation, as scene
    /// transforms are): positions mapped, normals and tangents turned and renormalized; AO,
    /// texture coordinates and components are unchanged.
    pub fn transform(&mut self, affine: glam::Affine3A) {
        for p in &mut self.positions {
            *p = affine.transform_point3(*p);
        }
        for v in self.normals.iter_mut().chain(&mut self.tangents) {
            *v = affine.transform_vector3(*v).normalize_or(*v);
        }
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Unit vertex normals.
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// Unit vertex tangents, root to tip.
    pub fn tangents(&self) -> &[Vec3] {
        &self.tangents
    }

    /// Vertex UVs: `u` across the patch, `v` from root (0) to tip (1).
    pub fn uvs(&self) -> &[Vec2] {
        &self.uvs
    }

    /// Per-vertex ambient occlusion in `[0, 1]` (1 = unoccluded).
    pub fn ao(&self) -> &[f32] {
        &self.ao
    }

    /// Triangle vertex indices, three per triangle.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// The component (patch) of each triangle, numbered `0..component_count()` in the order of
    /// each component's first triangle.
    pub fn components(&self) -> &[u32] {
        &self.components
    }

    /// Bounding box of the vertices; `None` for a mesh without vertices.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(&self.positions)
    }

    /// The three corner positions of triangle `t`. Panics if `t >= triangle_count()`.
    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        let i = &self.indices[3 * t..3 * t + 3];
        [0, 1, 2].map(|k| self.positions[i[k] as usize])
    }
}

fn invalid(reason: String) -> HairError {
    HairError::Invalid(format!("patch mesh: {reason}"))
}

/// Normalize every vector, refusing non-finite or zero ones.
fn unit_vectors(name: &str, mut v: Vec<Vec3>) -> Result<Vec<Vec3>, HairError> {
    for (i, x) in v.iter_mut().enumerate() {
        match x.try_normalize() {
            Some(u) if x.is_finite() => *x = u,
            _ => {
                return Err(invalid(format!(
                    "{name} of vertex {i} is {x}: not finite or zero"
                )));
            }
        }
    }
    Ok(v)
}

/// Union-find with path halving and union by size.
pub(crate) struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    pub(crate) fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    pub(crate) fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    pub(crate) fn union(&mut self, a: u32, b: u32) {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] += self.size[b as usize];
    }
}

/// The component of each triangle (numbered by first appearance) and the component count.
/// Triangles sharing a vertex index, or vertices at bit-identical positions, are connected.
fn connected_components(positions: &[Vec3], indices: &[u32]) -> (Vec<u32>, u32) {
    let mut uf = UnionFind::new(positions.len());
    let mut first_at: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    for (i, p) in positions.iter().enumerate() {
        // +0.0 and -0.0 are the same point.
        let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
        let first = *first_at.entry(key).or_insert(i as u32);
        uf.union(first, i as u32);
    }
    for t in indices.chunks_exact(3) {
        uf.union(t[0], t[1]);
        uf.union(t[0], t[2]);
    }
    let mut label = vec![u32::MAX; positions.len()];
    let mut count = 0u32;
    let components = indices
        .chunks_exact(3)
        .map(|t| {
            let root = uf.find(t[0]) as usize;
            if label[root] == u32::MAX {
                label[root] = count;
                count += 1;
            }
            label[root]
        })
        .collect();
    (components, count)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(offset: Vec3) -> (Vec<Vec3>, Vec<u32>) {
        let p = [Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y].map(|p| p + offset);
        (p.to_vec(), vec![0, 1, 2, 0, 2, 3])
    }

    fn mesh(positions: Vec<Vec3>, indices: Vec<u32>) -> Result<PatchMesh, HairError> {
        let n = positions.len();
        PatchMesh::new(
            positions,
            vec![Vec3::Z; n],
            vec![Vec3::Y; n],
            vec![Vec2::ZERO; n],
            indices,
        )
    }

    #[test]
    fn components_follow_shared_vertices_and_positions() {
        let (mut p, mut i) = quad(Vec3::ZERO);
        let (p2, i2) = quad(Vec3::new(5.0, 0.0, 0.0));
        i.extend(i2.iter().map(|k| k + 4));
        p.extend(p2);
        let m = mesh(p.clone(), i.clone()).unwrap();
        assert_eq!(m.component_count(), 2);
        assert_eq!(m.components(), &[0, 0, 1, 1]);
        // A third quad whose corner sits exactly on a corner of the second one (a duplicated
        // vertex, as an OBJ UV seam gives) joins it.
        let (p3, i3) = quad(Vec3::new(6.0, 0.0, 0.0));
        i.extend(i3.iter().map(|k| k + 8));
        p.extend(p3);
        let m = mesh(p, i).unwrap();
        assert_eq!(m.component_count(), 2);
        assert_eq!(m.components(), &[0, 0, 1, 1, 1, 1]);
    }

    #[test]
    fn constructor_validates_and_normalizes() {
        let (p, i) = quad(Vec3::ZERO);
        assert!(mesh(p.clone(), vec![0, 1]).is_err());
        assert!(mesh(p.clone(), vec![0, 1, 4]).is_err());
        let mut bad = p.clone();
        bad[2].x = f32::NAN;
        assert!(mesh(bad, i.clone()).is_err());
        let n = p.len();
        let zero_normal = PatchMesh::new(
            p.clone(),
            vec![Vec3::ZERO; n],
            vec![Vec3::Y; n],
            vec![Vec2::ZERO; n],
            i.clone(),
        );
        assert!(zero_normal.unwrap_err().to_string().contains("normal"));
        let short_uv = PatchMesh::new(
            p.clone(),
            vec![Vec3::Z; n],
            vec![Vec3::Y; n],
            vec![Vec2::ZERO; n - 1],
            i.clone(),
        );
        assert!(short_uv.is_err());
        let m = PatchMesh::new(
            p,
            vec![Vec3::Z * 3.0; n],
            vec![Vec3::Y * 0.5; n],
            vec![Vec2::ZERO; n],
            i,
        )
        .unwrap();
        assert_eq!(m.normals()[0], Vec3::Z);
        assert_eq!(m.tangents()[0], Vec3::Y);
        assert_eq!(m.ao(), &[1.0; 4]);
        assert!(m.clone().with_ao(vec![0.5; 3]).is_err());
        assert!(m.clone().with_ao(vec![1.5; 4]).is_err());
        assert!(m.clone().with_ao(vec![f32::NAN; 4]).is_err());
        assert_eq!(m.with_ao(vec![0.25; 4]).unwrap().ao(), &[0.25; 4]);
    }
}
