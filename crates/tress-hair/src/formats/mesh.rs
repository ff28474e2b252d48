//! Head and body meshes, chosen by extension: Wavefront `.obj`
//! ([`TriMesh::read_obj`](crate::generate::TriMesh::read_obj)), glTF 2.0 `.gltf` / `.glb`
//! ([`gltf`](super::gltf)) and the `Mesh` prims of a USD stage (`.usda`, `.usdc`, `.usdz`,
//! `.usd`; [`usd`](super::usd)). Scene files and every front end load heads through here.

use std::path::Path;

use crate::HairError;
use crate::generate::TriMesh;

/// The mesh extensions read, for messages.
pub const MESH_EXTENSIONS: &str = ".obj, .gltf, .glb, .usda, .usdc, .usdz and .usd";

/// Whether `path` has a mesh extension.
pub fn is_mesh_path(path: &Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    matches!(
        ext.as_deref(),
        Some("obj" | "gltf" | "glb" | "usda" | "usdc" | "usdz" | "usd")
    )
}

/// Read a head or body mesh, its format chosen by extension; errors name the file.
pub fn read_mesh(path: &Path) -> Result<TriMesh, HairError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj") => TriMesh::read_obj(path),
        Some("gltf" | "glb") => super::gltf::read_gltf_path(path),
        Some("usda" | "usdc" | "usdz" | "usd") => super::usd::read_usd_mesh(path),
        _ => Err(HairError::format(
            "mesh",
            format!("unknown mesh extension; tress reads {MESH_EXTENSIONS}"),
        )
        .in_file(path)),
    }
}
