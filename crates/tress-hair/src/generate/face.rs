//! The drawn head of the head-hair styles: the [`Head`] ellipsoid (the skull the hair grows
//! from, untouched over the scalp) with a face sculpted onto it below the hairline (brow ridge,
//! eye sockets, nose, cheekbones, lips, a jaw and chin) and a neck. Only what is drawn changes:
//! roots, collisions and the head's occlusion of hair in the ray tracer all use this mesh or the
//! ellipsoid, which agree over the scalp.
//!
//! Features are placed by the direction `d` on the unit sphere the ellipsoid is scaled from
//! (`x` right, `y` up, `z` toward the face) and sized in the head's own scale
//! (`radii.x / 8`, so an asset's head in metres gets the same face).

use std::f32::consts::{PI, TAU};

use std::str::FromStr;

use glam::Vec3;

use super::head::{Head, TriMesh};
use crate::HairError;

/// Polar angle (from the crown) where the neck starts, on the unit sphere: below the nape's
/// hairline (115°), so no root is moved.
const NECK_START: f32 = 125.0 * PI / 180.0;
/// Length of the neck below where it starts, in head units (`radii.x / 8`).
const NECK_LENGTH: f32 = 14.0;
/// The neck's semi-axes (x, z) and how far behind the head's centre its axis lies.
const NECK_RADII: [f32; 2] = [4.6, 5.0];
const NECK_BACK: f32 = 1.5;

/// What the generated head is drawn as (`[head] shape`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HeadShape {
    /// The ellipsoid with a face and a neck ([`face_mesh`]): head-hair styles.
    #[default]
    Face,
    /// The bare ellipsoid ([`Head::mesh`]): the body fur grows on.
    Ellipsoid,
}

impl HeadShape {
    /// The shape's name in scene files: `"face"` or `"ellipsoid"`.
    pub fn name(self) -> &'static str {
        match self {
            HeadShape::Face => "face",
            HeadShape::Ellipsoid => "ellipsoid",
        }
    }

    /// The triangle mesh of `head` in this shape, `subdivisions` latitude bands.
    pub fn mesh(self, head: &Head, subdivisions: u32) -> TriMesh {
        match self {
            HeadShape::Face => face_mesh(head, subdivisions),
            HeadShape::Ellipsoid => head.mesh(subdivisions),
        }
    }
}

impl FromStr for HeadShape {
    type Err = HairError;

    /// A shape from its name ([`HeadShape::name`]).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [HeadShape::Face, HeadShape::Ellipsoid]
            .into_iter()
            .find(|shape| shape.name() == s)
            .ok_or_else(|| {
                HairError::Parameter(format!(
                    "unknown head shape '{s}' (expected one of: face, ellipsoid)"
                ))
            })
    }
}

/// `t` eased from 0 at `a` to 1 at `b` (either order).
fn smoothstep(a: f32, b: f32, t: f32) -> f32 {
    let x = ((t - a) / (b - a)).clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// A Gaussian bump of the direction's `(x, y)` around `(cx, cy)` with widths `(sx, sy)`, on the
/// face side (`z > 0`) only.
fn bump(d: Vec3, cx: f32, cy: f32, sx: f32, sy: f32) -> f32 {
    let (u, v) = ((d.x - cx) / sx, (d.y - cy) / sy);
    (-(u * u + v * v)).exp() * smoothstep(0.3, 0.7, d.z)
}

/// The face's offset from the ellipsoid at unit direction `d`, in head units (`radii.x / 8`
/// world units): along the ellipsoid's normal for the reliefs, down and forward for the jaw.
/// Zero over the scalp.
pub(crate) fn face_offset(d: Vec3, normal: Vec3) -> Vec3 {
    let relief = 2.4 * bump(d, 0.0, -0.2, 0.09, 0.2) // nose, longer toward its tip
        + 0.9 * bump(d, 0.0, -0.36, 0.16, 0.07) // its tip and nostrils
        - 1.1 * bump(d, 0.33, 0.06, 0.13, 0.09) // eye sockets
        - 1.1 * bump(d, -0.33, 0.06, 0.13, 0.09)
        + 0.6 * bump(d, 0.3, 0.2, 0.2, 0.05) // brow ridge
        + 0.6 * bump(d, -0.3, 0.2, 0.2, 0.05)
        + 0.7 * bump(d, 0.5, -0.18, 0.14, 0.12) // cheekbones
        + 0.7 * bump(d, -0.5, -0.18, 0.14, 0.12)
        + 0.5 * bump(d, 0.0, -0.55, 0.18, 0.06); // lips
    // The jaw: the lower front of the skull drawn down and a little forward into a chin.
    let jaw = smoothstep(0.1, 0.75, d.z) * smoothstep(0.0, -0.6, d.y);
    normal * relief + Vec3::new(0.0, -9.0 * (-d.y).max(0.0), 1.5) * jaw
}

/// A point of the neck, `t` from its start (0) to its bottom (1) at azimuth `phi`: an elliptic
/// tube of [`NECK_RADII`] closed by a flat bottom, in world units. Its front (the throat)
/// starts lower, under the chin.
fn neck_point(head: &Head, scale: f32, t: f32, phi: f32) -> Vec3 {
    let (sin, cos) = phi.sin_cos();
    let top = head.center.y + head.radii.y * NECK_START.cos() - 5.0 * scale * cos.max(0.0).powi(2);
    // The last tenth of `t` closes the bottom.
    let (y, shrink) = if t < 0.9 {
        (top - NECK_LENGTH * scale * t / 0.9, 1.0)
    } else {
        (top - NECK_LENGTH * scale, (1.0 - t) / 0.1)
    };
    Vec3::new(
        head.center.x + NECK_RADII[0] * scale * sin * shrink,
        y,
        head.center.z - NECK_BACK * scale + NECK_RADII[1] * scale * cos * shrink,
    )
}

/// The head-hair styles' drawn head (see the module docs): `subdivisions` latitude bands
/// (clamped as [`Head::mesh`] clamps them) and twice as many sectors, laid out like
/// [`Head::mesh`]'s ellipsoid, counter-clockwise triangles seen from outside, area-weighted
/// vertex normals. Over the scalp its vertices lie on the ellipsoid.
pub fn face_mesh(head: &Head, subdivisions: u32) -> TriMesh {
    let mut mesh = head.mesh(subdivisions);
    let scale = head.radii.x / 8.0;
    let bands = mesh_bands(mesh.positions.len());
    let sectors = 2 * bands;
    for (index, p) in mesh.positions.iter_mut().enumerate() {
        // Vertex 0 is the crown, the last the bottom pole, rings of `sectors` between.
        let (i, j) = match index {
            0 => (0, 0),
            _ if index == 1 + (bands as usize - 1) * sectors as usize => (bands, 0),
            _ => (
                1 + (index as u32 - 1) / sectors,
                (index as u32 - 1) % sectors,
            ),
        };
        let theta = PI * i as f32 / bands as f32;
        let phi = TAU * j as f32 / sectors as f32;
        let d = ((*p - head.center) / head.radii).normalize_or(Vec3::Y);
        let (_, normal) = head.surface_point(d);
        let face = *p + face_offset(d, normal) * scale;
        *p = if theta <= NECK_START {
            face
        } else {
            let t = (theta - NECK_START) / (PI - NECK_START);
            let neck = neck_point(head, scale, t, phi);
            face.lerp(neck, smoothstep(0.0, 0.3, t))
        };
    }
    mesh.normals = vertex_normals(&mesh.positions, &mesh.indices);
    mesh
}

/// The latitude bands of a [`Head::mesh`] with `vertices` vertices (`2 + (b - 1) · 2b`).
fn mesh_bands(vertices: usize) -> u32 {
    let mut b = 2u32;
    while 2 + (b as usize - 1) * 2 * b as usize != vertices {
        b += 1;
    }
    b
}

/// Area-weighted vertex normals of a triangle mesh (unit, or +Y where every face around a
/// vertex is degenerate).
fn vertex_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let n = (b - a).cross(c - a);
        for &k in t {
            normals[k as usize] += n;
        }
    }
    normals.iter().map(|n| n.normalize_or(Vec3::Y)).collect()
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::rng::Rng;

    fn head() -> Head {
        Head {
            center: Vec3::new(1.0, 2.0, -3.0),
            ..Head::default()
        }
    }

    #[test]
    fn the_scalp_is_untouched() {
        let h = head();
        let mut rng = Rng::new(3);
        for _ in 0..5000 {
            let s = h.sample_scalp(&mut rng);
            let d = ((s.position - h.center) / h.radii).normalize();
            let off = face_offset(d, s.normal);
            assert!(off.length() < 0.02, "{off} at the root {d}");
            assert!(d.y > NECK_START.cos());
        }
    }

    #[test]
    fn it_is_a_closed_outward_surface_with_a_face_and_a_neck() {
        for (h, subdivisions) in [(head(), 48), (Head::default(), 96)] {
            let m = face_mesh(&h, subdivisions);
            let scale = h.radii.x / 8.0;
            assert_eq!(m.positions.len(), h.mesh(subdivisions).positions.len());
            // Closed: every edge is shared by exactly two triangles, in opposite directions.
            let mut edges = HashMap::new();
            for t in m.indices.chunks_exact(3) {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    *edges.entry((a, b)).or_insert(0) += 1;
                }
            }
            for (&(a, b), &n) in &edges {
                assert_eq!((n, edges.get(&(b, a))), (1, Some(&1)), "edge {a}-{b}");
            }
            // Facing out: the enclosed volume (divergence theorem) is positive and larger than
            // the skull's, since the neck and jaw add to it.
            let volume: f32 = m
                .indices
                .chunks_exact(3)
                .map(|t| {
                    let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize] - h.center);
                    a.dot(b.cross(c)) / 6.0
                })
                .sum();
            let skull = 4.0 / 3.0 * PI * h.radii.x * h.radii.y * h.radii.z;
            assert!(volume > skull, "{volume} vs the skull's {skull}");
            for n in &m.normals {
                assert!((n.length() - 1.0).abs() < 1e-4);
            }
            let rel = |p: &Vec3| *p - h.center;
            // The nose is the most forward point, on the middle of the face below the eyes.
            let nose = m
                .positions
                .iter()
                .map(rel)
                .max_by(|a, b| a.z.total_cmp(&b.z))
                .unwrap();
            assert!(nose.x.abs() < 0.5 * scale, "{nose}");
            assert!((-4.0 * scale..0.0).contains(&nose.y), "{nose}");
            assert!(nose.z > h.radii.z + 1.5 * scale, "{nose}");
            // The eye sockets are hollow: inside the skull ellipsoid.
            let eye = Vec3::new(0.33, 0.06, 0.94).normalize();
            let (on, normal) = h.surface_point(eye);
            let socket = on + face_offset(eye, normal) * scale;
            assert!(h.level(socket) < 0.97, "{}", h.level(socket));
            // The chin reaches below the skull; the neck well below it.
            let front_low = m
                .positions
                .iter()
                .map(rel)
                .filter(|p| p.z > 0.5 * h.radii.z)
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min);
            assert!(front_low < -1.05 * h.radii.y, "{front_low}");
            let low = m.positions.iter().map(|p| rel(p).y).fold(0.0, f32::min);
            assert!(low < -h.radii.y - 8.0 * scale, "{low}");
        }
    }

    #[test]
    fn the_face_scales_with_the_head() {
        let small = Head {
            center: Vec3::ZERO,
            radii: Head::default().radii * 0.01,
        };
        let a = face_mesh(&Head::default(), 24);
        let b = face_mesh(&small, 24);
        for (p, q) in a.positions.iter().zip(&b.positions) {
            assert!((*p * 0.01 - *q).length() < 1e-5, "{p} vs {q}");
        }
        assert_eq!(HeadShape::Ellipsoid.mesh(&small, 24), small.mesh(24));
        assert_eq!(HeadShape::Face.mesh(&small, 24), b);
        for shape in [HeadShape::Face, HeadShape::Ellipsoid] {
            assert_eq!(shape.name().parse::<HeadShape>().ok(), Some(shape));
        }
        assert!("sphere".parse::<HeadShape>().is_err());
    }
}
