//! Per-vertex ambient occlusion by ray casting (Scheuermann 2004, sketch "Ambient occlusion":
//! "we store an ambient occlusion term per vertex. This term is computed in a pre-processing
//! step"; slide "Hair Model Authoring": "ambient occlusion to approximate self-shadowing, per
//! vertex").
//!
//! For each vertex, `rays` directions are drawn from a cosine-weighted hemisphere around the
//! vertex normal and cast against every triangle of the patches and of the head (one
//! bounding-volume hierarchy over both). Only triangles closer than `max_distance` count. The
//! hemisphere's visibility is the mean over its rays of the light each lets through; with
//! cosine-weighted directions this estimates the cosine-weighted visibility integral
//! `(1/π)∫ V(ω) cos θ dω`, the usual ambient occlusion.
//!
//! # Opacity of the patches
//!
//! The head is opaque. With `patch_opacity = 1` (the paper's plain ray casting) so is every
//! patch, and a ray is blocked by the first patch it meets. But the patches are alpha-textured
//! and let light through between their strands; treated as opaque sheets, the stacked layers of
//! a generated head with overlapping strips can leave most vertices almost black. So each patch
//! a ray crosses lets `1 − patch_opacity` of the light through, and a ray's visibility is the
//! product over the patches it crosses (its transmittance; a ray left with less than 1/1024 counts
//! as blocked). The default 0.55 is about the mean coverage of the default alpha texture
//! ([`super::texture`], 0.54); on the default generated head it gives the outer layer a mean AO
//! of about 0.8 and the layers under it 0.3 to 0.45.
//!
//! # Two-sided patches
//!
//! A patch is a sheet seen and lit from both sides, and one AO value per vertex serves both
//! faces. Which hemisphere counts is the setting [`AoSides`]:
//!
//! - [`AoSides::Max`] (default): both hemispheres, `rays` rays each, and the vertex keeps the
//!   more open one. A strip lying on the scalp is then judged by its open outer side (its inner
//!   side faces the skull and would make every patch dark), a patch buried between layers is
//!   dark on both sides and stays dark, and imported cards give the same result whichever way
//!   their normals point.
//! - [`AoSides::Mean`]: the mean of both hemispheres: a physically plainer answer for a sheet
//!   lit from all around, but at most about 0.5 for anything lying on the head.
//! - [`AoSides::Front`]: the hemisphere around the normal only (classic one-sided AO); use it
//!   when the normals are known to point outward.
//!
//! Rays leave from the vertex moved `1e-4 ×` (the scene's bounding-box diagonal) along the
//! hemisphere's axis, so that the patch's own triangles at the vertex are not hit.
//!
//! Each vertex draws its directions from its own random stream [`Rng::stream`]`(seed, vertex)`,
//! so the result is the same however rayon schedules the vertices.

use std::f32::consts::TAU;

use glam::Vec3;
use rayon::prelude::*;

use super::PatchMesh;
use super::occluders::Occluders;
use crate::generate::TriMesh;
use crate::rng::Rng;
use crate::{Aabb, HairError};

/// Which hemispheres of a two-sided patch vertex count (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum AoSides {
    /// The more open of the two hemispheres (default).
    #[default]
    Max,
    /// The mean of the two hemispheres.
    Mean,
    /// The hemisphere around the normal only.
    Front,
}

/// Settings of the AO bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoParams {
    /// Rays per hemisphere and vertex (at least 1). Default 64.
    pub rays: u32,
    /// Occluders farther than this (world units) do not count. Default 8, about the generated
    /// head's radius.
    pub max_distance: f32,
    /// Seed of the ray directions. Default 0.
    pub seed: u64,
    /// Which hemispheres count. Default [`AoSides::Max`].
    pub sides: AoSides,
    /// How much of the light a patch stops where a ray crosses it, in `[0, 1]` (1: opaque, as
    /// the head always is). Default 0.55 (see the module docs).
    pub patch_opacity: f32,
}

impl Default for AoParams {
    fn default() -> Self {
        AoParams {
            rays: 64,
            max_distance: 8.0,
            seed: 0,
            sides: AoSides::Max,
            patch_opacity: 0.55,
        }
    }
}

/// Largest accepted ray count per hemisphere.
const MAX_RAYS: u32 = 1 << 20;

impl AoParams {
    /// Check the parameters: `rays` in `1..=2^20`, `max_distance` finite and positive,
    /// `patch_opacity` in `[0, 1]`.
    pub fn validate(&self) -> Result<(), HairError> {
        if !(0.0..=1.0).contains(&self.patch_opacity) {
            return Err(HairError::Parameter(format!(
                "AO patch opacity must lie in [0, 1], got {}",
                self.patch_opacity
            )));
        }
        if !(1..=MAX_RAYS).contains(&self.rays) {
            return Err(HairError::Parameter(format!(
                "AO rays must lie in 1..={MAX_RAYS}, got {}",
                self.rays
            )));
        }
        if !(self.max_distance.is_finite() && self.max_distance > 0.0) {
            return Err(HairError::Parameter(format!(
                "AO max distance must be finite and positive, got {}",
                self.max_distance
            )));
        }
        Ok(())
    }
}

/// Bake per-vertex ambient occlusion into `mesh`, casting rays against the patches themselves
/// and, when given, the `head` mesh (see the module docs). On error the mesh is unchanged.
///
/// Errors: invalid parameters, or a head mesh with an index out of range, an index count that
/// is not a multiple of 3, or a non-finite position.
pub fn bake_ao(
    mesh: &mut PatchMesh,
    head: Option<&TriMesh>,
    params: &AoParams,
) -> Result<(), HairError> {
    params.validate()?;
    let mut triangles: Vec<[Vec3; 3]> = (0..mesh.triangle_count())
        .map(|t| mesh.triangle(t))
        .collect();
    let mut bounds = mesh.bounds();
    if let Some(head) = head {
        check_head(head)?;
        triangles.extend(
            head.indices
                .chunks_exact(3)
                .map(|t| [0, 1, 2].map(|k| head.positions[t[k] as usize])),
        );
        if let Some(b) = Aabb::from_points(&head.positions) {
            bounds = Some(bounds.map_or(b, |m| m.union(&b)));
        }
    }
    let patches = mesh.triangle_count();
    let patch_transmit = 1.0 - params.patch_opacity;
    let bvh = Occluders::new(
        &triangles,
        |i| if i < patches { patch_transmit } else { 0.0 },
    );
    let diagonal = bounds.map_or(1.0, |b| b.size().length());
    let epsilon = (diagonal * 1e-4).max(f32::MIN_POSITIVE);

    let ao: Vec<f32> = mesh
        .positions()
        .par_iter()
        .zip(mesh.normals().par_iter())
        .enumerate()
        .map(|(i, (&p, &n))| {
            let mut rng = Rng::stream(params.seed, i as u64);
            let mut open =
                |axis: Vec3| visibility(&bvh, p + axis * epsilon, axis, params, &mut rng);
            match params.sides {
                AoSides::Front => open(n),
                AoSides::Max => open(n).max(open(-n)),
                AoSides::Mean => 0.5 * (open(n) + open(-n)),
            }
        })
        .collect();
    mesh.set_ao(ao)
}

/// Mean transmittance of `params.rays` cosine-weighted rays around `axis` from `origin` up to
/// `max_distance`.
fn visibility(bvh: &Occluders, origin: Vec3, axis: Vec3, params: &AoParams, rng: &mut Rng) -> f32 {
    let (b1, b2) = axis.any_orthonormal_pair();
    let mut open = 0.0f32;
    for _ in 0..params.rays {
        // Malley's method: a uniform point on the disk lifted to the hemisphere.
        let r = rng.f32().sqrt();
        let phi = rng.f32() * TAU;
        let (s, c) = phi.sin_cos();
        let z = (1.0 - r * r).max(0.0).sqrt();
        let dir = (b1 * (r * c) + b2 * (r * s) + axis * z).normalize_or(axis);
        open += bvh.transmittance(origin, dir, 0.0, params.max_distance);
    }
    (open / params.rays as f32).clamp(0.0, 1.0)
}

fn check_head(head: &TriMesh) -> Result<(), HairError> {
    if !head.indices.len().is_multiple_of(3) {
        return Err(HairError::Invalid(format!(
            "head mesh: {} indices do not make whole triangles",
            head.indices.len()
        )));
    }
    let n = head.positions.len();
    if let Some(&i) = head.indices.iter().find(|&&i| i as usize >= n) {
        return Err(HairError::Invalid(format!(
            "head mesh: index {i} out of range for {n} vertices"
        )));
    }
    if let Some(i) = head.positions.iter().position(|p| !p.is_finite()) {
        return Err(HairError::Invalid(format!(
            "head mesh: vertex {i} has a non-finite position"
        )));
    }
    Ok(())
}
