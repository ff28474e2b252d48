//! The static inside-to-outside index buffer (Scheuermann 2004, sketch "Rendering with
//! approximate depth sorting": "During pre-processing, we sort the hair patches by their distance
//! from the head and store the draw order in a static index buffer"; slide "Approximate Depth
//! Sorting": "sort connected components (hair strand patches) instead of individual triangles").
//!
//! The paper does not say how a patch's distance is measured. Here it is the **mean distance of
//! the component's vertices from the head centre** (each vertex counted once, however many
//! triangles share it). A mean over the whole patch, rather than its root or nearest point,
//! ranks a long outer strip behind (drawn after) the short inner strips it covers, which is what
//! the layered model needs; it costs one pass over the vertices.
//!
//! Components are drawn in order of increasing distance (ties broken by component number, so the
//! order is deterministic); each component's triangles stay together, in their original order.

use super::PatchMesh;
use glam::Vec3;

/// The mean distance of each component's vertices from `head_center`, indexed by component.
pub fn component_distances(mesh: &PatchMesh, head_center: Vec3) -> Vec<f32> {
    let k = mesh.component_count();
    let mut sum = vec![0.0f64; k];
    let mut count = vec![0u32; k];
    // Each vertex belongs to one component; mark it the first time a triangle names it.
    let mut seen = vec![false; mesh.vertex_count()];
    for (tri, &c) in mesh.indices().chunks_exact(3).zip(mesh.components()) {
        for &v in tri {
            if !std::mem::replace(&mut seen[v as usize], true) {
                sum[c as usize] += f64::from(mesh.positions()[v as usize].distance(head_center));
                count[c as usize] += 1;
            }
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(s, &n)| (s / f64::from(n.max(1))) as f32)
        .collect()
}

/// The mesh's index buffer reordered inside to outside: whole components in order of increasing
/// [`component_distances`] from `head_center` (see the module docs). Every triangle appears
/// exactly once, with its corners in their original order.
pub fn sorted_indices(mesh: &PatchMesh, head_center: Vec3) -> Vec<u32> {
    let distance = component_distances(mesh, head_center);
    let mut order: Vec<u32> = (0..distance.len() as u32).collect();
    order.sort_by(|&a, &b| {
        distance[a as usize]
            .total_cmp(&distance[b as usize])
            .then(a.cmp(&b))
    });
    let mut rank = vec![0u32; order.len()];
    for (r, &c) in order.iter().enumerate() {
        rank[c as usize] = r as u32;
    }
    // A stable counting sort of the triangles by their component's rank.
    let mut start = vec![0usize; order.len() + 1];
    for &c in mesh.components() {
        start[rank[c as usize] as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut out = vec![0u32; mesh.indices().len()];
    for (tri, &c) in mesh.indices().chunks_exact(3).zip(mesh.components()) {
        let slot = &mut start[rank[c as usize] as usize];
        out[3 * *slot..3 * *slot + 3].copy_from_slice(tri);
        *slot += 1;
    }
    out
}
