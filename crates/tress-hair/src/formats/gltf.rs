//! glTF 2.0 head and body meshes (`.gltf` with its `.bin` buffers or `data:` URIs, and `.glb`),
//! read with the `gltf` crate.
//!
//! Every triangle primitive (`mode` 4) of every mesh instanced by the default scene's nodes (or,
//! without scenes, of every mesh) is merged in world space: node transforms composed, positions
//! (`POSITION`), indices (or none: consecutive triangles) and normals (`NORMAL`, else
//! area-weighted face normals). Materials, textures, skins, morph targets and other primitive
//! modes are ignored.
//!
//! # Validation
//!
//! `gltf` validates the JSON (indices of accessors, views and buffers). Before any accessor is
//! read, every buffer's data is checked to be as long as its declared `byteLength` and every
//! accessor to lie inside its view and its view inside its buffer, so a lying file gives an
//! error, never an out-of-range read; every index is checked against its primitive's positions.

use std::path::Path;

use base64::Engine;
use glam::{Mat4, Vec3};

use crate::HairError;
use crate::generate::TriMesh;

const FORMAT: &str = "glTF";

fn err(reason: impl std::fmt::Display) -> HairError {
    HairError::format(FORMAT, reason.to_string())
}

/// Read a glTF or GLB mesh from memory. `base_dir` is where external buffers (`uri` paths)
/// are looked up; `None` refuses them.
pub fn read_gltf(bytes: &[u8], base_dir: Option<&Path>) -> Result<TriMesh, HairError> {
    let gltf = parse(bytes)?;
    let mut buffers = Vec::new();
    for b in gltf.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| err("a buffer refers to the GLB binary chunk, which is missing"))?,
            gltf::buffer::Source::Uri(uri) => load_uri(uri, base_dir)?,
        };
        if data.len() < b.length() {
            return Err(err(format!(
                "buffer {} declares {} bytes but holds {}",
                b.index(),
                b.length(),
                data.len()
            )));
        }
        buffers.push(data);
    }
    for v in gltf.views() {
        let end = v.offset().checked_add(v.length());
        if end.is_none_or(|e| e > buffers[v.buffer().index()].len()) {
            return Err(err(format!(
                "buffer view {} lies outside its buffer",
                v.index()
            )));
        }
    }
    for a in gltf.accessors() {
        let Some(view) = a.view() else { continue };
        let stride = view.stride().unwrap_or(a.size());
        let need = a
            .count()
            .checked_sub(1)
            .map_or(Some(0), |n| n.checked_mul(stride)?.checked_add(a.size()))
            .and_then(|n| n.checked_add(a.offset()));
        if need.is_none_or(|n| n > view.length()) {
            return Err(err(format!(
                "accessor {} reads past its buffer view",
                a.index()
            )));
        }
    }
    let mut mesh = TriMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
    };
    let scene = gltf.default_scene().or_else(|| gltf.scenes().next());
    match scene {
        Some(scene) => {
            let mut stack: Vec<(gltf::Node<'_>, Mat4, usize)> =
                scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
            while let Some((node, parent, depth)) = stack.pop() {
                if depth > 256 {
                    return Err(err("nodes nest deeper than 256 levels"));
                }
                let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
                if let Some(m) = node.mesh() {
                    add_mesh(&mut mesh, &m, &buffers, world)?;
                }
                stack.extend(node.children().map(|c| (c, world, depth + 1)));
            }
        }
        None => {
            for m in gltf.meshes() {
                add_mesh(&mut mesh, &m, &buffers, Mat4::IDENTITY)?;
            }
        }
    }
    if mesh.indices.is_empty() {
        return Err(err("the file has no triangles"));
    }
    Ok(mesh)
}

/// Parse and validate the document. gltf-json 1.4's validation indexes `accessors` with each
/// primitive's `POSITION` unchecked (`primitive_validate_hook`, found by fuzzing), so those
/// indices are checked first; the `catch_unwind` stays as the last line of defence.
fn parse(bytes: &[u8]) -> Result<gltf::Gltf, HairError> {
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(err)?;
    let json = document.into_json();
    let accessors = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= accessors {
                    return Err(err(format!(
                        "mesh {m} primitive {p}: {} names accessor {}, but the file has {accessors}",
                        semantic.to_string(),
                        index.value()
                    )));
                }
            }
        }
    }
    let validated = crate::panic_guard::quietly(|| gltf::Document::from_json(json));
    let document = validated
        .ok_or_else(|| err("the file's references are out of range (the gltf crate panicked)"))?
        .map_err(err)?;
    Ok(gltf::Gltf { document, blob })
}

/// Read a `.gltf` or `.glb` file; errors name the file.
pub fn read_gltf_path(path: &Path) -> Result<TriMesh, HairError> {
    let bytes = std::fs::read(path).map_err(|e| HairError::from(e).in_file(path))?;
    read_gltf(&bytes, Some(path.parent().unwrap_or(Path::new(".")))).map_err(|e| e.in_file(path))
}

fn load_uri(uri: &str, base_dir: Option<&Path>) -> Result<Vec<u8>, HairError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or_else(|| err("a data URI buffer is not base64"))?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| err(format!("a data URI buffer: {e}")));
    }
    let dir = base_dir.ok_or_else(|| err(format!("buffer `{uri}` is an external file")))?;
    if uri.contains("://") {
        return Err(err(format!("buffer `{uri}` is not a local file")));
    }
    let path = dir.join(uri.replace("%20", " "));
    std::fs::read(&path).map_err(|e| err(format!("buffer {}: {e}", path.display())))
}

fn add_mesh(
    out: &mut TriMesh,
    mesh: &gltf::Mesh<'_>,
    buffers: &[Vec<u8>],
    world: Mat4,
) -> Result<(), HairError> {
    let normal_matrix = world.inverse().transpose();
    let flip = world.determinant() < 0.0;
    for prim in mesh.primitives() {
        if prim.mode() != gltf::mesh::Mode::Triangles {
            continue;
        }
        // gltf's reader assumes the component types the specification requires and reaches
        // `unreachable!` otherwise: check them first.
        use gltf::accessor::{DataType, Dimensions};
        let position = prim.get(&gltf::Semantic::Positions);
        if position
            .as_ref()
            .is_some_and(|a| a.data_type() != DataType::F32 || a.dimensions() != Dimensions::Vec3)
        {
            return Err(err("POSITION is not float VEC3"));
        }
        if let Some(n) = prim.get(&gltf::Semantic::Normals)
            && (n.data_type() != DataType::F32 || n.dimensions() != Dimensions::Vec3)
        {
            return Err(err("NORMAL is not float VEC3"));
        }
        if let Some(i) = prim.indices()
            && (!matches!(i.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
                || i.dimensions() != Dimensions::Scalar)
        {
            return Err(err("the indices are not unsigned integer scalars"));
        }
        let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let Some(positions) = reader.read_positions() else {
            continue;
        };
        let positions: Vec<Vec3> = positions
            .map(|p| world.transform_point3(Vec3::from(p)))
            .collect();
        let n = positions.len();
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..n as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(err(format!(
                "index {bad} is past its primitive's {n} positions"
            )));
        }
        let mut tris: Vec<u32> = indices
            .chunks_exact(3)
            .flat_map(|t| {
                if flip {
                    [t[0], t[2], t[1]]
                } else {
                    [t[0], t[1], t[2]]
                }
            })
            .collect();
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(err("a position is not finite"));
        }
        let faces = crate::patches::obj::face_normals(&positions, &tris);
        let normals: Vec<Vec3> = match reader.read_normals() {
            Some(ns) => {
                let ns: Vec<Vec3> = ns.map(Vec3::from).collect();
                if ns.len() == n {
                    ns.iter()
                        .zip(&faces)
                        .map(|(v, f)| {
                            normal_matrix
                                .transform_vector3(*v)
                                .try_normalize()
                                .unwrap_or(*f)
                        })
                        .collect()
                } else {
                    faces
                }
            }
            None => faces,
        };
        let base =
            u32::try_from(out.positions.len()).map_err(|_| err("more than 2^32 vertices"))?;
        for t in &mut tris {
            *t += base;
        }
        out.positions.extend(positions);
        out.normals.extend(normals);
        out.indices.extend(tris);
    }
    Ok(())
}
