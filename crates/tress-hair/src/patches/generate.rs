//! Layered patch hair on the generated head (Scheuermann 2004, sketch "Hair model": "layered 2D
//! polygon patches which provides a simple approximation of the volumetric qualities of hair").
//!
//! Each layer is a shell of strips ("patches"). Layer `k` of `L` (0 innermost) floats
//! `layer_spacing × (k + 1)` above the scalp and its strips are
//! `length × lerp(inner_length, 1, k / (L − 1))` long, so inner layers are shorter and closer and
//! fill the volume under the outer ones. Roots are spread evenly over the scalp region of
//! [`Head::scalp_point`] with a spherical Fibonacci lattice (rotated by a random angle per layer
//! so that layers do not line up), then jittered.
//!
//! A strip's centre line is grown in `segments` steps: it leaves the scalp combed back and away
//! from the face, bends toward its pull (gravity, plus a comb toward the back on the upper head)
//! and is pushed out to its layer's level of the ellipsoid after every step, so it lies on its
//! shell while over the head and falls freely below it. Its cross direction lies in the shell
//! (`normalize(tangent × outward)`), its normal points away from the head, and its width tapers
//! from `width` at the root to `tip_width × width` at the tip. Everything random is drawn from
//! [`Rng::stream`]`(seed, patch)`, so the result is deterministic.

use std::f32::consts::{PI, TAU};

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
/// Strength of the comb toward the back on the upper head, relative to gravity.
const COMB: f32 = 1.5;
/// How far a root is jittered, as a fraction of the mean root spacing.
const ROOT_JITTER: f32 = 0.35;
/// How much each strip's length varies (±).
const LENGTH_JITTER: f32 = 0.15;

/// Settings of [`generate_patches`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchParams {
    /// The head the patches grow from. Default [`Head::default`].
    pub head: Head,
    /// Number of layers (at least 1). Default 4.
    pub layers: u32,
    /// Patches per layer, approximately (the lattice is cut by the hairline; at least 1).
    /// Default 160.
    pub patches_per_layer: u32,
    /// Quads along each strip (at least 1). Default 12.
    pub segments: u32,
    /// Length of the outer layer's strips (world units). Default 25.
    pub length: f32,
    /// The inner layer's length as a fraction of `length`, in `[0, 1]`. Default 0.5.
    pub inner_length: f32,
    /// Strip width at the root (world units). Default 3.
    pub width: f32,
    /// Strip width at the tip as a fraction of `width`, in `[0, 1]`. Default 0.6.
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
            patches_per_layer: 160,
            segments: 12,
            length: 25.0,
            inner_length: 0.5,
            width: 3.0,
            tip_width: 0.6,
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
            * u128::from(lattice_size(self.patches_per_layer))
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
    /// Lattice direction of the root on the unit sphere.
    root: Vec3,
    layer: u32,
    stream: u64,
}

/// Generate layered patch hair on `params.head` (see the module docs). Patches are numbered
/// layer by layer from the inside out; each is one component of the mesh.
pub fn generate_patches(params: &PatchParams) -> Result<PatchMesh, HairError> {
    params.validate()?;
    let lattice = lattice_size(params.patches_per_layer);
    let mut strips = Vec::new();
    for layer in 0..params.layers {
        let mut rng = Rng::stream(params.seed, u64::MAX - u64::from(layer));
        let turn = rng.f32();
        for i in 0..lattice {
            // Spherical Fibonacci lattice: equal-area bands in y, golden-angle azimuths.
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / lattice as f32;
            let phi = ((i as f32 * GOLDEN + turn) * TAU).rem_euclid(TAU);
            let theta = y.clamp(-1.0, 1.0).acos();
            if theta <= hairline(phi) {
                let stream = strips.len() as u64;
                strips.push(Strip {
                    root: spherical(theta, phi),
                    layer,
                    stream,
                });
            }
        }
    }
    if strips.is_empty() {
        return Err(HairError::Parameter(
            "no patch root falls on the scalp: raise patches per layer".into(),
        ));
    }

    let rows = params.segments as usize + 1;
    let per_strip = 2 * rows;
    let spacing = (4.0 * PI / lattice as f32).sqrt();
    let mut positions = vec![Vec3::ZERO; strips.len() * per_strip];
    let mut normals = vec![Vec3::ZERO; positions.len()];
    let mut tangents = vec![Vec3::ZERO; positions.len()];
    positions
        .par_chunks_mut(per_strip)
        .zip(normals.par_chunks_mut(per_strip))
        .zip(tangents.par_chunks_mut(per_strip))
        .zip(strips.par_iter())
        .for_each(|(((p, n), t), strip)| {
            grow(params, strip, spacing, p, n, t);
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

/// The golden ratio's fractional part: the Fibonacci lattice's azimuth step in turns.
const GOLDEN: f32 = 0.618_034;

/// Points in the whole-sphere lattice so that about `per_layer` fall on the scalp (which covers
/// about 40% of the unit sphere, see [`scalp_fraction`]).
fn lattice_size(per_layer: u32) -> u64 {
    (f64::from(per_layer) / scalp_fraction()).ceil() as u64
}

/// Fraction of the unit sphere inside the hairline: the mean over azimuth of
/// `(1 − cos hairline(φ)) / 2`.
fn scalp_fraction() -> f64 {
    let n = 360;
    (0..n)
        .map(|i| {
            let phi = (i as f32 + 0.5) / n as f32 * TAU;
            f64::from((1.0 - hairline(phi).cos()) / 2.0)
        })
        .sum::<f64>()
        / f64::from(n)
}

/// Polar angle of the hairline at azimuth `phi`, read back from [`Head::scalp_point`] (whose
/// `v = 1` is the hairline) on the unit sphere.
fn hairline(phi: f32) -> f32 {
    let unit = Head {
        center: Vec3::ZERO,
        radii: Vec3::ONE,
    };
    unit.scalp_point(Vec2::new(phi / TAU, 1.0))
        .position
        .y
        .clamp(-1.0, 1.0)
        .acos()
}

/// The unit vector at polar angle `theta` from +Y and azimuth `phi` from +Z toward +X (the
/// head's convention).
fn spherical(theta: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * sp, ct, st * cp)
}

/// Grow one strip: positions, normals and tangents of its `rows` pairs of vertices (left, right).
fn grow(
    params: &PatchParams,
    strip: &Strip,
    spacing: f32,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
    tangents: &mut [Vec3],
) {
    let head = &params.head;
    let mut rng = Rng::stream(params.seed, strip.stream);
    let layers = params.layers.max(2) - 1;
    let depth = strip.layer as f32 / layers as f32;
    let margin = params.layer_spacing * (strip.layer + 1) as f32 / head.radii.min_element();
    let length = params.length
        * (params.inner_length + (1.0 - params.inner_length) * depth)
        * (1.0 + LENGTH_JITTER * rng.range(-1.0, 1.0));
    let dir = (strip.root + rng.on_sphere() * (ROOT_JITTER * spacing)).normalize_or(strip.root);
    let phi = dir.x.atan2(dir.z).rem_euclid(TAU);
    let theta = dir.y.clamp(-1.0, 1.0).acos().min(hairline(phi));
    let (root, root_normal) = head.surface_point(spherical(theta, phi));
    let rows = positions.len() / 2;
    let step = length / (rows - 1) as f32;
    let wobble = params.waviness * step;

    let mut p = head.push_out(root, margin);
    let mut dir = project(pull(head, p), root_normal).unwrap_or(Vec3::NEG_Y);
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
        let n = across.cross(t).normalize_or(outward);
        let fraction = r as f32 / (rows - 1) as f32;
        let half = 0.5 * params.width * (1.0 - (1.0 - params.tip_width) * fraction);
        positions[2 * r] = centre[r] - across * half;
        positions[2 * r + 1] = centre[r] + across * half;
        normals[2 * r..2 * r + 2].fill(n);
        tangents[2 * r..2 * r + 2].fill(t);
    }
}

/// `v` without its component along unit `axis`, normalized; `None` if nothing is left.
fn project(v: Vec3, axis: Vec3) -> Option<Vec3> {
    (v - axis * v.dot(axis)).try_normalize()
}

/// The pull on a strip at `p`: gravity, plus on the upper head a comb toward the back, strongest
/// above the face (where it must beat gravity to sweep the hair back over the crown) and fading
/// to nothing at the equator.
fn pull(head: &Head, p: Vec3) -> Vec3 {
    let q = (p - head.center) / head.radii;
    let upper = q.y.clamp(0.0, 1.0);
    let front = q.z.max(0.0);
    Vec3::NEG_Y + Vec3::NEG_Z * (COMB * upper * (1.0 + 2.0 * front))
}
