//! Layered patch hair on the generated head (Scheuermann 2004, sketch "Hair model": "layered 2D
//! polygon patches which provides a simple approximation of the volumetric qualities of hair").
//!
//! Each layer is a shell of strips ("patches") laid side by side around the head like the
//! panels of a skirt, so that a layer covers what lies under it about once. Layer `k` of `L`
//! (0 innermost):
//!
//! - floats `layer_spacing × (k + 1)` above the scalp;
//! - is rooted on a ring of the scalp at scalp coordinate `v = lerp(0.95, 0.1, k / (L − 1))`
//!   ([`Head::scalp_point`]: 0 is the crown, 1 the hairline), so the inner layer starts at the
//!   hairline and the outer one near the crown;
//! - has `patches_per_layer` strips evenly around its ring (every other layer offset by half a
//!   strip, so seams do not line up; each root jittered a little);
//! - has strips `length × lerp(inner_length, 1, k / (L − 1))` long (±15% per strip).
//!
//! Inner layers are thus shorter and closer to the head and fill the volume under the outer
//! ones; a single layer is an outer one.
//!
//! A strip's centre line is grown in `segments` steps: it leaves the scalp combed back and away
//! from the face, bends toward its pull (gravity, plus a comb toward the back on the upper head
//! that runs along the head's surface) and is pushed out to its layer's level of the ellipsoid
//! after every step, so it lies on its shell while over the head and falls freely below it. Its
//! cross direction lies in the shell (`normalize(tangent × outward)`) and its normal points away
//! from the head. Its width at each row is what covers the layer's circumference there with
//! `overlap` to spare, `overlap × 2πρ / patches_per_layer` (ρ the distance from the head's
//! vertical axis), at most `width`, narrowing toward the tip to `tip_width` of that. Everything
//! random is drawn from [`Rng::stream`]`(seed, patch)`, so the result is deterministic.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::PatchMesh;
use crate::HairError;
use crate::generate::Head;
use crate::rng::Rng;

/// Largest accepted length-like parameter (world units).
const MAX_LENGTH: f32 = 1e6;
/// Largest accepted number of vertices in a generated mesh.
const MAX_VERTICES: u64 = 1 << 28;
/// Arc length over which the pull turns a strip's direction by about a radian.
const BEND: f32 = 3.0;
/// Strength of the comb toward the back above the face, relative to gravity.
const COMB: f32 = 4.5;
/// How far a root is jittered around its ring, as a fraction of the strip spacing (±).
const ROOT_JITTER: f32 = 0.3;
/// How far a root is jittered across its ring, in scalp `v` (±).
const RING_JITTER: f32 = 0.03;
/// Scalp `v` of the inner layer's ring (near the hairline) and of the outer layer's (near the
/// crown).
const RING_INNER: f32 = 0.95;
const RING_OUTER: f32 = 0.1;
/// Narrowest strip, as a fraction of `width`.
const MIN_WIDTH: f32 = 0.1;
/// How much each strip's length varies (±).
const LENGTH_JITTER: f32 = 0.15;

/// Settings of [`generate_patches`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchParams {
    /// The head the patches grow from. Default [`Head::default`].
    pub head: Head,
    /// Number of layers (at least 1). Default 4.
    pub layers: u32,
    /// Patches around each layer (at least 1). Default 64.
    pub patches_per_layer: u32,
    /// Quads along each strip (at least 1). Default 12.
    pub segments: u32,
    /// Length of the outer layer's strips (world units). Default 25.
    pub length: f32,
    /// The inner layer's length as a fraction of `length`, in `[0, 1]`. Default 0.5.
    pub inner_length: f32,
    /// Widest strip (world units, positive). Default 4.
    pub width: f32,
    /// How much wider strips are than the gaps between their centres (at least 0). Default 1.3.
    pub overlap: f32,
    /// Strip width at the tip as a fraction of its width elsewhere, in `[0, 1]`. Default 0.7.
    pub tip_width: f32,
    /// Distance between layers, and of the inner layer from the scalp (world units). Default 0.3.
    pub layer_spacing: f32,
    /// Largest random turn of a strip's direction per unit of length (radians). Default 0.05.
    pub waviness: f32,
    /// Random seed. Default 0.
    pub seed: u64,
}

impl Default for PatchParams {
    fn default() -> Self {
        PatchParams {
            head: Head::default(),
            layers: 4,
            patches_per_layer: 64,
            segments: 12,
            length: 25.0,
            inner_length: 0.5,
            width: 4.0,
            overlap: 1.3,
            tip_width: 0.7,
            layer_spacing: 0.3,
            waviness: 0.05,
            seed: 0,
        }
    }
}

impl PatchParams {
    /// Check the parameters (ranges as documented on each field, a valid head, and at most
    /// 2^28 vertices in all).
    pub fn validate(&self) -> Result<(), HairError> {
        self.head.validate()?;
        for (name, v) in [
            ("layers", self.layers),
            ("patches per layer", self.patches_per_layer),
            ("segments", self.segments),
        ] {
            if v == 0 {
                return Err(HairError::Parameter(format!("{name} must be at least 1")));
            }
        }
        let vertices = u128::from(self.layers)
            * u128::from(self.patches_per_layer)
            * 2
            * (u128::from(self.segments) + 1);
        if vertices > u128::from(MAX_VERTICES) {
            return Err(HairError::Parameter(format!(
                "{} layers of {} patches with {} segments is more than 2^28 vertices",
                self.layers, self.patches_per_layer, self.segments
            )));
        }
        for (name, v) in [
            ("length", self.length),
            ("width", self.width),
            ("overlap", self.overlap),
            ("layer spacing", self.layer_spacing),
            ("waviness", self.waviness),
        ] {
            if !(v.is_finite() && (0.0..=MAX_LENGTH).contains(&v)) {
                return Err(HairError::Parameter(format!(
                    "{name} must be finite, non-negative and at most {MAX_LENGTH}, got {v}"
                )));
            }
        }
        if self.length <= 0.0 || self.width <= 0.0 {
            return Err(HairError::Parameter(
                "patch length and width must be positive".into(),
            ));
        }
        for (name, v) in [
            ("inner length", self.inner_length),
            ("tip width", self.tip_width),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(HairError::Parameter(format!(
                    "{name} must lie in [0, 1], got {v}"
                )));
            }
        }
        Ok(())
    }
}

/// One strip to grow.
#[derive(Clone, Copy, Debug)]
struct Strip {
    /// Scalp coordinate of the root (before jitter).
    root: Vec2,
    layer: u32,
    stream: u64,
}

/// Generate layered patch hair on `params.head` (see the module docs). Patches are numbered
/// layer by layer from the inside out; each is one component of the mesh.
pub fn generate_patches(params: &PatchParams) -> Result<PatchMesh, HairError> {
    params.validate()?;
    let n = params.patches_per_layer;
    let mut strips = Vec::with_capacity((params.layers * n) as usize);
    for layer in 0..params.layers {
        let ring = RING_INNER + (RING_OUTER - RING_INNER) * depth(params, layer);
        let stagger = if layer % 2 == 1 { 0.5 } else { 0.0 };
        for i in 0..n {
            let stream = strips.len() as u64;
            strips.push(Strip {
                root: Vec2::new((i as f32 + 0.5 + stagger) / n as f32, ring),
                layer,
                stream,
            });
        }
    }

    let rows = params.segments as usize + 1;
    let per_strip = 2 * rows;
    let mut positions = vec![Vec3::ZERO; strips.len() * per_strip];
    let mut normals = vec![Vec3::ZERO; positions.len()];
    let mut tangents = vec![Vec3::ZERO; positions.len()];
    positions
        .par_chunks_mut(per_strip)
        .zip(normals.par_chunks_mut(per_strip))
        .zip(tangents.par_chunks_mut(per_strip))
        .zip(strips.par_iter())
        .for_each(|(((p, n), t), strip)| {
            grow(params, strip, p, n, t);
        });
    let uvs: Vec<Vec2> = (0..strips.len())
        .flat_map(|_| {
            (0..rows).flat_map(move |r| {
                let v = r as f32 / (rows - 1) as f32;
                [Vec2::new(0.0, v), Vec2::new(1.0, v)]
            })
        })
        .collect();
    let mut indices = Vec::with_capacity(strips.len() * 6 * params.segments as usize);
    for s in 0..strips.len() {
        let base = (s * per_strip) as u32;
        for r in 0..params.segments {
            let (l0, r0) = (base + 2 * r, base + 2 * r + 1);
            let (l1, r1) = (l0 + 2, r0 + 2);
            indices.extend_from_slice(&[l0, r0, l1, r0, r1, l1]);
        }
    }
    PatchMesh::new(positions, normals, tangents, uvs, indices)
}

/// Layer `layer`'s place from the inside (0) to the outside (1); a single layer is outside.
fn depth(params: &PatchParams, layer: u32) -> f32 {
    if params.layers < 2 {
        1.0
    } else {
        layer as f32 / (params.layers - 1) as f32
    }
}

/// Grow one strip: positions, normals and tangents of its `rows` pairs of vertices (left, right).
fn grow(
    params: &PatchParams,
    strip: &Strip,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
    tangents: &mut [Vec3],
) {
    let head = &params.head;
    let mut rng = Rng::stream(params.seed, strip.stream);
    let depth = depth(params, strip.layer);
    let margin = params.layer_spacing * (strip.layer + 1) as f32 / head.radii.min_element();
    let length = params.length
        * (params.inner_length + (1.0 - params.inner_length) * depth)
        * (1.0 + LENGTH_JITTER * rng.range(-1.0, 1.0));
    let n = params.patches_per_layer as f32;
    let u = strip.root.x + ROOT_JITTER / n * rng.range(-1.0, 1.0);
    let v = strip.root.y + RING_JITTER * rng.range(-1.0, 1.0);
    let scalp = head.scalp_point(Vec2::new(u.rem_euclid(1.0), v.clamp(0.0, 1.0)));
    let rows = positions.len() / 2;
    let step = length / (rows - 1) as f32;
    let wobble = params.waviness * step;

    let mut p = head.push_out(scalp.position, margin);
    let mut dir = project(pull(head, p), scalp.normal).unwrap_or(Vec3::NEG_Y);
    let mut centre = Vec::with_capacity(rows);
    centre.push(p);
    for _ in 1..rows {
        let bend = (step / BEND).min(1.0);
        dir = (dir + pull(head, p) * bend + rng.on_sphere() * wobble).normalize_or(dir);
        let next = head.push_out(p + dir * step, margin);
        dir = (next - p).normalize_or(dir);
        p = next;
        centre.push(p);
    }

    let mut across_prev = Vec3::X;
    for r in 0..rows {
        let t = if r + 1 < rows {
            centre[r + 1] - centre[r]
        } else {
            centre[r] - centre[r - 1]
        }
        .normalize_or(Vec3::NEG_Y);
        let outward = (centre[r] - head.center).normalize_or(Vec3::Y);
        let across = t
            .cross(outward)
            .try_normalize()
            .unwrap_or_else(|| project(across_prev, t).unwrap_or(t.any_orthonormal_vector()));
        across_prev = across;
        let normal = across.cross(t).normalize_or(outward);
        let axis = centre[r] - head.center;
        let rho = (axis.x * axis.x + axis.z * axis.z).sqrt();
        let cover = (params.overlap * TAU * rho / n).clamp(MIN_WIDTH * params.width, params.width);
        let fraction = r as f32 / (rows - 1) as f32;
        let half = 0.5 * cover * (1.0 - (1.0 - params.tip_width) * fraction);
        positions[2 * r] = centre[r] - across * half;
        positions[2 * r + 1] = centre[r] + across * half;
        normals[2 * r..2 * r + 2].fill(normal);
        tangents[2 * r..2 * r + 2].fill(t);
    }
}

/// `v` without its component along unit `axis`, normalized; `None` if nothing is left.
fn project(v: Vec3, axis: Vec3) -> Option<Vec3> {
    (v - axis * v.dot(axis)).try_normalize()
}

/// The pull on a strip at `p`: gravity (which, once the strip is pushed back onto its shell,
/// runs it down the head's meridians), plus above the face a comb toward the back that must
/// beat gravity to sweep the hair back over the crown instead of over the face. The comb grows
/// toward the front (`q.z`) and the top (`q.y`) of the unit-sphere position `q`, and runs along
/// the head's surface so that it never lifts the hair off the head.
fn pull(head: &Head, p: Vec3) -> Vec3 {
    let q = (p - head.center) / head.radii;
    let upper = q.y.clamp(0.0, 1.0);
    let front = q.z.max(0.0);
    // The ellipsoid's outward normal at the point's level.
    let normal = (q / head.radii).normalize_or(Vec3::Y);
    let comb = project(Vec3::NEG_Z, normal).unwrap_or(Vec3::ZERO);
    Vec3::NEG_Y + comb * (COMB * upper * front)
}
