//! Wavefront OBJ import and export of patch meshes (hair cards).
//!
//! **Import** ([`PatchMesh::from_obj`]) parses with `tobj` (polygons triangulated as fans, one
//! index per distinct `v/vt/vn` corner, every object and group of the file merged into one mesh)
//! and then:
//!
//! - requires texture coordinates on every face corner (a card's `v` direction is its hair
//!   direction), and reads them as the file has them: `v` must grow from root to tip;
//! - takes the file's normals when every corner has one, and otherwise the area-weighted mean of
//!   the adjacent faces' normals;
//! - derives each vertex's tangent from the UV layout: per triangle the direction `∂P/∂v` of
//!   growing `v` (solving `P1 − P0 = ∂P/∂u Δu1 + ∂P/∂v Δv1`, same for `P2`), weighted by the
//!   triangle's area, summed over the vertex's triangles and made perpendicular to its normal.
//!   Vertices whose triangles all have degenerate UVs get any direction perpendicular to the
//!   normal;
//! - finds components from connectivity ([`PatchMesh::new`]);
//! - reads per-vertex ambient occlusion from the vertex colors (`v x y z r g b`, the red channel)
//!   only in files that [`PatchMesh::to_obj`] wrote (recognised by its first line); anywhere
//!   else colors mean something else, and AO starts at 1.
//!
//! **Export** ([`PatchMesh::to_obj`]) writes a header comment, then `v x y z ao ao ao` (AO as a
//! gray vertex color, an extension Blender and MeshLab read), `vt u v`, `vn x y z` and one
//! `f a/a/a b/b/b c/c/c` line per triangle. Vertices are written in the order the triangles first
//! use them, which is the order import numbers them in, so a mesh read from a file writes back
//! with the same numbering; vertices no triangle uses are left out. Floats are written in Rust's
//! shortest round-trip form, so positions and UVs come back bit for bit.

use std::fmt::Write as _;
use std::io::BufReader;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::PatchMesh;
use crate::HairError;
use crate::generate::TriMesh;

const FORMAT: &str = "OBJ";
/// First line of the files [`PatchMesh::to_obj`] writes.
const HEADER: &str = "# tress patch mesh";

impl PatchMesh {
    /// A patch mesh from the bytes of an OBJ file (see the [module docs](self)). Material
    /// libraries are ignored.
    ///
    /// Errors: not an OBJ file `tobj` can parse, face indices out of range, faces without
    /// texture coordinates, no faces, or values that are not finite.
    pub fn from_obj(bytes: &[u8]) -> Result<Self, HairError> {
        let models = load_models(bytes)?;
        let ours = bytes.starts_with(HEADER.as_bytes());

        let mut positions = Vec::new();
        let mut uvs = Vec::new();
        let mut normals = Vec::new();
        let mut ao = Vec::new();
        let mut indices = Vec::new();
        let mut all_normals = true;
        for model in &models {
            let m = &model.mesh;
            let n = m.positions.len() / 3;
            if m.texcoords.len() != 2 * n {
                return Err(HairError::format(
                    FORMAT,
                    format!(
                        "object '{}': faces without texture coordinates (vt); hair cards need UVs \
                         whose v runs from root to tip",
                        model.name
                    ),
                ));
            }
            let base = u32::try_from(positions.len())
                .map_err(|_| HairError::format(FORMAT, "more than 2^32 vertices"))?;
            positions.extend(m.positions.chunks_exact(3).map(Vec3::from_slice));
            uvs.extend(m.texcoords.chunks_exact(2).map(Vec2::from_slice));
            if m.normals.len() == 3 * n {
                normals.extend(m.normals.chunks_exact(3).map(Vec3::from_slice));
            } else {
                all_normals = false;
            }
            if ours && m.vertex_color.len() == 3 * n {
                ao.extend(m.vertex_color.chunks_exact(3).map(|c| c[0]));
            }
            indices.extend(m.indices.iter().map(|&i| i + base));
        }
        if indices.is_empty() {
            return Err(HairError::format(FORMAT, "the file has no faces"));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(HairError::format(
                FORMAT,
                format!("vertex {i} has a non-finite position"),
            ));
        }
        if let Some(i) = uvs.iter().position(|p| !p.is_finite()) {
            return Err(HairError::format(
                FORMAT,
                format!("vertex {i} has a non-finite texture coordinate"),
            ));
        }
        let face_normals = face_normals(&positions, &indices);
        let normals = if all_normals {
            normals
                .iter()
                .zip(&face_normals)
                .map(|(n, f)| {
                    if n.is_finite() {
                        n.try_normalize().unwrap_or(*f)
                    } else {
                        *f
                    }
                })
                .collect()
        } else {
            face_normals
        };
        let tangents = uv_tangents(&positions, &uvs, &normals, &indices);
        let mesh = PatchMesh::new(positions, normals, tangents, uvs, indices)
            .map_err(|e| HairError::format(FORMAT, e.to_string()))?;
        if ao.len() == mesh.vertex_count() && ao.iter().all(|a| (0.0..=1.0).contains(a)) {
            mesh.with_ao(ao)
        } else {
            Ok(mesh)
        }
    }

    /// [`PatchMesh::from_obj`] of a file; errors name the file.
    pub fn read_obj(path: impl AsRef<Path>) -> Result<Self, HairError> {
        let path = path.as_ref();
        std::fs::read(path)
            .map_err(HairError::from)
            .and_then(|bytes| Self::from_obj(&bytes))
            .map_err(|e| e.in_file(path))
    }

    /// The mesh as OBJ text (see the [module docs](self)).
    pub fn to_obj(&self) -> String {
        // Number vertices in order of first use.
        let mut new_of = vec![u32::MAX; self.vertex_count()];
        let mut order = Vec::with_capacity(self.vertex_count());
        for &i in self.indices() {
            if new_of[i as usize] == u32::MAX {
                new_of[i as usize] = order.len() as u32;
                order.push(i as usize);
            }
        }
        let mut out = String::with_capacity(100 * order.len() + 40 * self.indices().len());
        // Writing into a String cannot fail.
        let _ = writeln!(
            out,
            "{HEADER}: {} vertices, {} triangles, {} patches; vertex colors hold ambient occlusion",
            order.len(),
            self.triangle_count(),
            self.component_count()
        );
        for &i in &order {
            let (p, a) = (self.positions()[i], self.ao()[i]);
            let _ = writeln!(out, "v {} {} {} {a} {a} {a}", p.x, p.y, p.z);
        }
        for &i in &order {
            let t = self.uvs()[i];
            let _ = writeln!(out, "vt {} {}", t.x, t.y);
        }
        for &i in &order {
            let n = self.normals()[i];
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
        for t in self.indices().chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| new_of[t[k] as usize] + 1);
            let _ = writeln!(out, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
        }
        out
    }

    /// Write [`PatchMesh::to_obj`] to a file; errors name the file.
    pub fn write_obj(&self, path: impl AsRef<Path>) -> Result<(), HairError> {
        let path = path.as_ref();
        std::fs::write(path, self.to_obj()).map_err(|e| HairError::from(e).in_file(path))
    }
}

impl TriMesh {
    /// A triangle mesh (e.g. a head) from the bytes of an OBJ file: every object merged,
    /// polygons fan-triangulated, the file's normals when every corner has one, otherwise
    /// area-weighted face normals. Texture coordinates are not needed. Face indices are checked
    /// before `tobj` parses the file, so a hostile file gives an error, never a panic.
    pub fn from_obj(bytes: &[u8]) -> Result<TriMesh, HairError> {
        let models = load_models(bytes)?;
        let mut mesh = TriMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            indices: Vec::new(),
        };
        let mut file_normals = Vec::new();
        let mut all_normals = true;
        for model in &models {
            let m = &model.mesh;
            let base = u32::try_from(mesh.positions.len())
                .map_err(|_| HairError::format(FORMAT, "more than 2^32 vertices"))?;
            mesh.positions
                .extend(m.positions.chunks_exact(3).map(Vec3::from_slice));
            if m.normals.len() == m.positions.len() {
                file_normals.extend(m.normals.chunks_exact(3).map(Vec3::from_slice));
            } else {
                all_normals = false;
            }
            mesh.indices.extend(m.indices.iter().map(|&i| i + base));
        }
        if mesh.indices.is_empty() {
            return Err(HairError::format(FORMAT, "the file has no faces"));
        }
        if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(HairError::format(
                FORMAT,
                format!("vertex {i} has a non-finite position"),
            ));
        }
        let faces = face_normals(&mesh.positions, &mesh.indices);
        mesh.normals = if all_normals {
            file_normals
                .iter()
                .zip(&faces)
                .map(|(n, f)| {
                    if n.is_finite() {
                        n.try_normalize().unwrap_or(*f)
                    } else {
                        *f
                    }
                })
                .collect()
        } else {
            faces
        };
        Ok(mesh)
    }

    /// A triangle mesh from positions and three vertex indices per triangle, with
    /// area-weighted vertex normals (as an OBJ without normals gets). Errors when an index is
    /// out of range, the index count is not a multiple of three, there is no triangle or a
    /// position is not finite.
    pub fn from_triangles(positions: Vec<Vec3>, indices: Vec<u32>) -> Result<TriMesh, HairError> {
        if indices.is_empty() || !indices.len().is_multiple_of(3) {
            return Err(HairError::Invalid(format!(
                "a mesh needs three indices per triangle and at least one triangle, got {} indices",
                indices.len()
            )));
        }
        if let Some(&i) = indices.iter().find(|&&i| i as usize >= positions.len()) {
            return Err(HairError::Invalid(format!(
                "face index {i} is past the {} vertices",
                positions.len()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(HairError::Invalid(format!(
                "vertex {i} has a non-finite position"
            )));
        }
        let normals = face_normals(&positions, &indices);
        Ok(TriMesh {
            positions,
            normals,
            indices,
        })
    }

    /// [`TriMesh::from_obj`] of a file; errors name the file.
    pub fn read_obj(path: impl AsRef<Path>) -> Result<TriMesh, HairError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| HairError::from(e).in_file(path))?;
        TriMesh::from_obj(&bytes).map_err(|e| e.in_file(path))
    }
}

/// Parse OBJ bytes with `tobj` after checking the text and every face index.
fn load_models(bytes: &[u8]) -> Result<Vec<tobj::Model>, HairError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| HairError::format(FORMAT, format!("not UTF-8 text: {e}")))?;
    check_face_indices(text)?;
    let options = load_options();
    let mut reader = BufReader::new(bytes);
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| HairError::format(FORMAT, obj_error(e)))?;
    Ok(models)
}

/// Check every face (and line, which `tobj` reads as faces) index against the elements defined
/// above it, as OBJ counts them (1-based, or negative: relative to the last one), before `tobj`
/// sees the file: `tobj` trusts relative indices and can overflow on them.
fn check_face_indices(text: &str) -> Result<(), HairError> {
    const KINDS: [&str; 3] = ["vertex (v)", "texture coordinate (vt)", "normal (vn)"];
    let mut count = [0i64; 3];
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => count[0] += 1,
            Some("vt") => count[1] += 1,
            Some("vn") => count[2] += 1,
            Some("f" | "l") => {
                for corner in words {
                    let parts: Vec<&str> = corner.split('/').collect();
                    if parts.len() > 3 {
                        return Err(line_error(number, "a face corner has more than 3 indices"));
                    }
                    for (kind, part) in parts.iter().enumerate() {
                        if part.is_empty() {
                            continue;
                        }
                        let i: i64 = part.parse().map_err(|_| {
                            line_error(number, &format!("'{part}' is not a face index"))
                        })?;
                        if i == 0 || i > count[kind] || i < -count[kind] {
                            return Err(line_error(
                                number,
                                &format!(
                                    "a face names a {} that does not exist (index {i} of {})",
                                    KINDS[kind], count[kind]
                                ),
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

fn line_error(number: usize, reason: &str) -> HairError {
    HairError::format(FORMAT, format!("line {}: {reason}", number + 1))
}

/// One index per distinct corner, fan-triangulated polygons, no points or lines. Set field by
/// field: the struct has more fields when another crate enables tobj features, and a struct
/// literal would then not compile.
#[allow(clippy::field_reassign_with_default)]
fn load_options() -> tobj::LoadOptions {
    let mut options = tobj::LoadOptions::default();
    options.single_index = true;
    options.triangulate = true;
    options.ignore_points = true;
    options.ignore_lines = true;
    options
}

fn obj_error(e: tobj::LoadError) -> String {
    match e {
        tobj::LoadError::FaceVertexOutOfBounds => "a face names a vertex (v) that does not exist",
        tobj::LoadError::FaceTexCoordOutOfBounds => {
            "a face names a texture coordinate (vt) that does not exist"
        }
        tobj::LoadError::FaceNormalOutOfBounds => "a face names a normal (vn) that does not exist",
        tobj::LoadError::FaceColorOutOfBounds => "some vertices have colors and others do not",
        tobj::LoadError::FaceParseError => "a face line (f) cannot be parsed",
        tobj::LoadError::PositionParseError => "a vertex line (v) cannot be parsed",
        tobj::LoadError::TexcoordParseError => "a texture coordinate line (vt) cannot be parsed",
        tobj::LoadError::NormalParseError => "a normal line (vn) cannot be parsed",
        other => return other.to_string(),
    }
    .to_string()
}

/// Area-weighted vertex normals from the faces; vertices without a usable face get +Y.
pub(crate) fn face_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        // The cross product's length is twice the area: area weighting for free.
        let n = (b - a).cross(c - a);
        if n.is_finite() {
            for &i in t {
                sum[i as usize] += n;
            }
        }
    }
    sum.iter().map(|n| n.normalize_or(Vec3::Y)).collect()
}

/// Per-vertex tangents along growing `v`, perpendicular to the normals (see the module docs).
pub(super) fn uv_tangents(
    positions: &[Vec3],
    uvs: &[Vec2],
    normals: &[Vec3],
    indices: &[u32],
) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| t[k] as usize);
        let (e1, e2) = (positions[b] - positions[a], positions[c] - positions[a]);
        let (d1, d2) = (uvs[b] - uvs[a], uvs[c] - uvs[a]);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det.abs() < 1e-12 {
            continue;
        }
        // ∂P/∂v = (Δu1 e2 − Δu2 e1) / det.
        let dp_dv = (e2 * d1.x - e1 * d2.x) / det;
        let area = 0.5 * e1.cross(e2).length();
        if let Some(dir) = dp_dv.try_normalize() {
            let w = dir * area;
            if w.is_finite() {
                for i in [a, b, c] {
                    sum[i] += w;
                }
            }
        }
    }
    sum.iter()
        .zip(normals)
        .map(|(t, n)| {
            (*t - *n * t.dot(*n))
                .try_normalize()
                .unwrap_or_else(|| n.any_orthonormal_vector())
        })
        .collect()
}
