//! The head (or body) that procedural hair grows from: an axis-aligned ellipsoid, its triangle
//! mesh for rendering, and the scalp region on it.

use std::f32::consts::{PI, TAU};
use std::fmt::Write as _;

use glam::{Vec2, Vec3};

use crate::HairError;
use crate::rng::Rng;

/// Polar angle of the hairline (from the crown, +Y) at the sides of the head, in radians.
const HAIRLINE_SIDE: f32 = 85.0 * PI / 180.0;
/// How far the hairline rises at the forehead and drops at the nape from `HAIRLINE_SIDE`: the
/// hairline lies 55° from the crown above the face and 115° (below the equator) at the nape.
const HAIRLINE_SWING: f32 = 30.0 * PI / 180.0;
/// The range [`Head::mesh`] clamps `subdivisions` to.
const MESH_SUBDIVISIONS: std::ops::RangeInclusive<u32> = 2..=1024;

/// An axis-aligned ellipsoid: the head hair styles grow from, or the body fur grows on.
///
/// Units are centimetre-like world units, y is up and the face looks toward +z. The default is
/// an adult head's skull at the origin: 16 cm wide, 21 cm tall and 19 cm deep (radii 8, 10.5 and
/// 9.5), the proportions of an adult cranium without the jaw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Head {
    /// Centre of the ellipsoid.
    pub center: Vec3,
    /// Semi-axes along x, y and z (all positive).
    pub radii: Vec3,
}

impl Default for Head {
    fn default() -> Self {
        Head {
            center: Vec3::ZERO,
            radii: Vec3::new(8.0, 10.5, 9.5),
        }
    }
}

/// A point on the scalp: where a strand is rooted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalpPoint {
    /// Position on the ellipsoid.
    pub position: Vec3,
    /// Outward unit surface normal.
    pub normal: Vec3,
    /// Scalp coordinate (see [`Head::scalp_point`]).
    pub uv: Vec2,
}

impl Head {
    /// Check that the centre is finite and the radii finite and positive.
    pub fn validate(&self) -> Result<(), HairError> {
        if !self.center.is_finite() {
            return Err(HairError::Parameter(format!(
                "head centre {} is not finite",
                self.center
            )));
        }
        if !(self.radii.is_finite() && self.radii.min_element() > 0.0) {
            return Err(HairError::Parameter(format!(
                "head radii {} must be finite and positive",
                self.radii
            )));
        }
        Ok(())
    }

    /// The surface point in unit direction `dir` of the unit sphere the ellipsoid is scaled from,
    /// and the outward unit normal there.
    pub fn surface_point(&self, dir: Vec3) -> (Vec3, Vec3) {
        let normal = (dir / self.radii).normalize_or(dir);
        (self.center + self.radii * dir, normal)
    }

    /// The ellipsoid's level at `p`: `|(p - center) / radii|`, below 1 inside, 1 on the surface.
    pub fn level(&self, p: Vec3) -> f32 {
        ((p - self.center) / self.radii).length()
    }

    /// `p` moved out along its ellipsoid direction to level `1 + margin` if it lies below it.
    pub(crate) fn push_out(&self, p: Vec3, margin: f32) -> Vec3 {
        let q = (p - self.center) / self.radii;
        let level = q.length();
        let target = 1.0 + margin;
        if level >= target {
            p
        } else if level > 1e-6 {
            self.center + self.radii * q * (target / level)
        } else {
            self.center + self.radii * Vec3::Y * target
        }
    }

    /// Polar angle (radians from the crown) of the hairline at azimuth `phi` (radians around +Y,
    /// 0 toward the face at +z, increasing toward +x).
    fn hairline(phi: f32) -> f32 {
        HAIRLINE_SIDE - HAIRLINE_SWING * phi.cos()
    }

    /// The scalp point with scalp coordinate `uv`: `u` in `[0, 1)` runs once around the head
    /// (0 at the face, 0.25 at +x, 0.5 at the back), `v` in `[0, 1]` from the crown (0) to the
    /// hairline (1). The hairline lies 55° from the crown above the forehead, 85° at the sides
    /// (above the ears) and 115° at the nape; angles are measured on the unit sphere the
    /// ellipsoid is scaled from.
    pub fn scalp_point(&self, uv: Vec2) -> ScalpPoint {
        let phi = uv.x * TAU;
        let theta = uv.y.clamp(0.0, 1.0) * Self::hairline(phi);
        let dir = spherical(theta, phi);
        let (position, normal) = self.surface_point(dir);
        ScalpPoint {
            position,
            normal,
            uv,
        }
    }

    /// A random scalp point, uniform over the scalp area of the unit sphere (nearly uniform on
    /// the ellipsoid for head-like proportions).
    pub fn sample_scalp(&self, rng: &mut Rng) -> ScalpPoint {
        // Rejection sampling: the scalp covers about 40% of the sphere. The bound keeps the loop
        // finite; reaching it (odds below 1e-14) gives a point at the crown.
        for _ in 0..64 {
            let dir = rng.on_sphere();
            let theta = dir.y.clamp(-1.0, 1.0).acos();
            let phi = dir.x.atan2(dir.z).rem_euclid(TAU);
            let max = Self::hairline(phi);
            if theta <= max {
                let (position, normal) = self.surface_point(dir);
                let uv = Vec2::new((phi / TAU).min(1.0 - f32::EPSILON), theta / max);
                return ScalpPoint {
                    position,
                    normal,
                    uv,
                };
            }
        }
        self.scalp_point(Vec2::ZERO)
    }

    /// A random point uniform over the whole unit sphere mapped to the ellipsoid, with its body
    /// coordinate (see [`Head::body_point`]).
    pub fn sample_surface(&self, rng: &mut Rng) -> ScalpPoint {
        let dir = rng.on_sphere();
        let theta = dir.y.clamp(-1.0, 1.0).acos();
        let phi = dir.x.atan2(dir.z).rem_euclid(TAU);
        let (position, normal) = self.surface_point(dir);
        ScalpPoint {
            position,
            normal,
            uv: Vec2::new((phi / TAU).min(1.0 - f32::EPSILON), theta / PI),
        }
    }

    /// The surface point with body coordinate `uv = (azimuth / 2π, polar angle / π)` (azimuth
    /// as in [`Head::scalp_point`], polar angle from +Y): the coordinate fur strands carry.
    pub fn body_point(&self, uv: Vec2) -> ScalpPoint {
        let dir = spherical(uv.y.clamp(0.0, 1.0) * PI, uv.x * TAU);
        let (position, normal) = self.surface_point(dir);
        ScalpPoint {
            position,
            normal,
            uv,
        }
    }

    /// A triangle mesh of the ellipsoid: `subdivisions` latitude bands (clamped to 2..=1024) and
    /// twice as many longitude sectors, one vertex at each pole, counter-clockwise triangles seen
    /// from outside, and exact ellipsoid normals. A head that fails [`Head::validate`] gives
    /// non-finite positions or normals: validate heads that come from user input first.
    pub fn mesh(&self, subdivisions: u32) -> TriMesh {
        let subdivisions = subdivisions.clamp(*MESH_SUBDIVISIONS.start(), *MESH_SUBDIVISIONS.end());
        let bands = subdivisions;
        let sectors = 2 * subdivisions;
        let rings = bands - 1;
        let vertex_count = (2 + rings * sectors) as usize;
        let mut positions = Vec::with_capacity(vertex_count);
        let mut normals = Vec::with_capacity(vertex_count);
        let mut push = |dir: Vec3| {
            let (p, n) = self.surface_point(dir);
            positions.push(p);
            normals.push(n);
        };
        push(Vec3::Y);
        for i in 1..bands {
            let theta = PI * i as f32 / bands as f32;
            for j in 0..sectors {
                push(spherical(theta, TAU * j as f32 / sectors as f32));
            }
        }
        push(Vec3::NEG_Y);

        let bottom = (vertex_count - 1) as u32;
        let ring = |i: u32, j: u32| 1 + (i - 1) * sectors + j % sectors;
        let mut indices = Vec::with_capacity(6 * (bands as usize - 1) * sectors as usize);
        for j in 0..sectors {
            indices.extend_from_slice(&[0, ring(1, j), ring(1, j + 1)]);
            for i in 1..rings {
                let (a, b) = (ring(i, j), ring(i, j + 1));
                let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
                indices.extend_from_slice(&[a, c, d, a, d, b]);
            }
            indices.extend_from_slice(&[ring(rings, j), bottom, ring(rings, j + 1)]);
        }
        TriMesh {
            positions,
            normals,
            indices,
        }
    }
}

/// The unit vector at polar angle `theta` from +Y and azimuth `phi` from +Z toward +X.
fn spherical(theta: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * sp, ct, st * cp)
}

/// An indexed triangle mesh with per-vertex normals: the generated head, an OBJ or glTF head,
/// and the renderer's head pass all use this one type.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Three vertex indices per triangle, counter-clockwise seen from the front.
    pub indices: Vec<u32>,
}

impl TriMesh {
    /// A UV sphere (a stand-in head for tests and examples).
    pub fn uv_sphere(center: Vec3, radius: f32, rings: u32, segments: u32) -> Self {
        let (rings, segments) = (rings.max(2), segments.max(3));
        let mut mesh = TriMesh::default();
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

    /// Centre of the bounding box and the radius around it (zero for no points).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let Some(b) = crate::Aabb::from_points(&self.positions) else {
            return (Vec3::ZERO, 0.0);
        };
        (b.center(), b.size().length() * 0.5)
    }

    /// Add `other`'s triangles to this mesh (its indices moved past this mesh's vertices).
    pub fn append(&mut self, other: &TriMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// The meshes with triangles, in order, as one mesh (`None` when none has any).
    pub fn merge(meshes: &[TriMesh]) -> Option<TriMesh> {
        let mut iter = meshes.iter().filter(|m| !m.indices.is_empty());
        let mut out = iter.next()?.clone();
        for m in iter {
            out.append(m);
        }
        Some(out)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Move the mesh by `affine`, a similarity (rotation, uniform scale, translation, as scene
    /// transforms are): positions mapped, normals turned and renormalized.
    pub fn transform(&mut self, affine: glam::Affine3A) {
        for p in &mut self.positions {
            *p = affine.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = affine.transform_vector3(*n).normalize_or(*n);
        }
    }

    /// The mesh as Wavefront OBJ text: `v` and `vn` lines, then one `f v//vn` line per triangle
    /// (indices 1-based, as OBJ counts them).
    pub fn to_obj(&self) -> String {
        let mut out = String::with_capacity(64 * self.positions.len() + 32 * self.indices.len());
        // Writing into a String cannot fail.
        let _ = writeln!(
            out,
            "# tress mesh: {} vertices, {} triangles",
            self.positions.len(),
            self.triangle_count()
        );
        for p in &self.positions {
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        }
        for n in &self.normals {
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
        for t in self.indices.chunks_exact(3) {
            let (a, b, c) = (t[0] + 1, t[1] + 1, t[2] + 1);
            let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head() -> Head {
        Head {
            center: Vec3::new(1.0, 2.0, -3.0),
            ..Head::default()
        }
    }

    #[test]
    fn merged_meshes_keep_every_triangle_on_its_own_vertices() {
        let a = TriMesh::uv_sphere(Vec3::ZERO, 1.0, 3, 4);
        let b = TriMesh::uv_sphere(Vec3::X * 5.0, 2.0, 2, 3);
        let m = TriMesh::merge(&[a.clone(), TriMesh::default(), b.clone()]).unwrap();
        assert_eq!(m.positions.len(), a.positions.len() + b.positions.len());
        assert_eq!(m.triangle_count(), a.triangle_count() + b.triangle_count());
        let tri = |mesh: &TriMesh, t: usize| -> [Vec3; 3] {
            [0, 1, 2].map(|k| mesh.positions[mesh.indices[3 * t + k] as usize])
        };
        for t in 0..b.triangle_count() {
            assert_eq!(tri(&m, a.triangle_count() + t), tri(&b, t));
        }
        assert_eq!(TriMesh::merge(&[TriMesh::default()]), None);
    }

    #[test]
    fn mesh_lies_on_the_ellipsoid_and_faces_out() {
        let h = head();
        let m = h.mesh(12);
        assert_eq!(m.positions.len(), 2 + 11 * 24);
        assert_eq!(m.triangle_count(), 2 * 12 * 24 - 2 * 24);
        for (p, n) in m.positions.iter().zip(&m.normals) {
            let q = (*p - h.center) / h.radii;
            assert!((q.length() - 1.0).abs() < 1e-5);
            assert!((n.length() - 1.0).abs() < 1e-5);
            // The ellipsoid's gradient is (p - c) / r^2.
            let grad = ((*p - h.center) / (h.radii * h.radii)).normalize();
            assert!(n.dot(grad) > 0.9999);
        }
        let mut area = 0.0;
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            let cross = (b - a).cross(c - a);
            assert!(cross.length() > 0.0, "degenerate triangle {t:?}");
            assert!(
                cross.dot((a + b + c) / 3.0 - h.center) > 0.0,
                "triangle {t:?} faces in"
            );
            area += 0.5 * cross.length();
        }
        // Knud Thomsen's approximation of the ellipsoid's area (error under 1.1%); the mesh's
        // inscribed facets are a little smaller.
        let (a, b, c) = (8.0f32, 10.5f32, 9.5f32);
        let pp = 1.6075;
        let expected = 4.0
            * PI
            * (((a * b).powf(pp) + (a * c).powf(pp) + (b * c).powf(pp)) / 3.0).powf(1.0 / pp);
        assert!(
            area < expected * 1.011 && area > expected * 0.97,
            "{area} vs {expected}"
        );
    }

    #[test]
    fn mesh_subdivisions_are_clamped_and_heads_validated() {
        assert_eq!(head().mesh(0), head().mesh(2));
        // Two bands of four sectors: an octahedron.
        assert_eq!(head().mesh(2).triangle_count(), 8);
        assert_eq!(head().mesh(2).positions.len(), 6);
        assert_eq!(head().mesh(u32::MAX).positions.len(), 2 + 1023 * 2048);
        assert!(head().validate().is_ok());
        assert!(
            Head {
                radii: Vec3::new(1.0, 0.0, 1.0),
                ..head()
            }
            .validate()
            .is_err()
        );
        assert!(
            Head {
                radii: Vec3::new(1.0, f32::INFINITY, 1.0),
                ..head()
            }
            .validate()
            .is_err()
        );
        assert!(
            Head {
                center: Vec3::NAN,
                ..head()
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn obj_parses_back() {
        let m = head().mesh(5);
        let obj = m.to_obj();
        let mut v = Vec::new();
        let (mut vn, mut faces) = (0usize, Vec::new());
        for line in obj.lines() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("v") => v.push(Vec3::from_array(
                    [0; 3].map(|_| it.next().unwrap().parse::<f32>().unwrap()),
                )),
                Some("vn") => vn += 1,
                Some("f") => faces.push(
                    it.map(|c| {
                        let (a, b) = c.split_once("//").unwrap();
                        assert_eq!(a, b);
                        a.parse::<usize>().unwrap()
                    })
                    .collect::<Vec<_>>(),
                ),
                Some("#") | None => {}
                Some(other) => panic!("unexpected OBJ line {other}"),
            }
        }
        assert_eq!(v.len(), m.positions.len());
        assert_eq!(vn, m.normals.len());
        assert_eq!(faces.len(), m.triangle_count());
        assert_eq!(v, m.positions, "positions round-trip exactly");
        for f in &faces {
            assert_eq!(f.len(), 3);
            assert!(f.iter().all(|&i| (1..=v.len()).contains(&i)));
        }
        assert_eq!(faces[0], vec![1, 2, 3]);
    }

    #[test]
    fn scalp_covers_the_top_and_back() {
        let h = head();
        let mut rng = Rng::new(5);
        let (mut front, mut back) = (0, 0);
        for _ in 0..5000 {
            let s = h.sample_scalp(&mut rng);
            assert!((h.level(s.position) - 1.0).abs() < 1e-5);
            let q = (s.position - h.center) / h.radii;
            // Never below the nape line (115° from the crown), never low on the face.
            assert!(q.y >= (115f32).to_radians().cos() - 1e-5, "{q}");
            if q.z > 0.5 && q.x.abs() < 0.3 {
                assert!(q.y > 0.5, "a root on the forehead: {q}");
                front += 1;
            }
            if q.z < -0.5 {
                back += 1;
            }
            assert!((0.0..1.0).contains(&s.uv.x) && (0.0..=1.0).contains(&s.uv.y));
            let again = h.scalp_point(s.uv);
            assert!(again.position.distance(s.position) < 1e-3);
            assert!(again.normal.distance(s.normal) < 1e-4);
            assert!(s.normal.dot(q) > 0.0);
        }
        assert!(
            back > 2 * front && front > 100,
            "front {front}, back {back}"
        );
    }
}
