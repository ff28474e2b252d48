//! What hair collides with, in the head's space: the head mesh's signed distance field (built
//! once at load, since the head is rigid), spheres and capsules.
//!
//! # The signed distance field
//!
//! A grid over the mesh's bounds padded by a few cells, `sdf_resolution` cells along its
//! longest axis. Cells within [`BAND`] cells of a triangle get the exact distance to the
//! nearest triangle (each triangle visits the cells of its padded bounding box), signed by the
//! side of that triangle's plane the cell lies on; the others get a chamfer distance propagated
//! from the band in two sweeps (forward and backward over the 26 neighbours), taking the sign of
//! the neighbour it came from. Hair only meets the field near the surface, where it is exact. A
//! point is sampled trilinearly; the normal is the field's central-difference gradient.

use glam::{IVec3, UVec3, Vec3};
use tress_hair::generate::TriMesh;

use crate::settings::{Capsule, Sphere};

/// Cells around each triangle that get exact distances.
pub const BAND: i32 = 3;

/// A signed distance field on a grid (negative inside).
#[derive(Clone, Debug, PartialEq)]
pub struct Sdf {
    /// Corner of cell (0, 0, 0)'s centre.
    pub origin: Vec3,
    /// Cell size.
    pub cell: f32,
    /// Cells along x, y, z.
    pub dims: UVec3,
    /// Distances, x fastest.
    pub values: Vec<f32>,
}

fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    // Ericson, Real-Time Collision Detection, 5.1.5.
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

impl Sdf {
    /// The field of `mesh` with `resolution` cells along its longest axis (`None` for a mesh
    /// without triangles).
    pub fn build(mesh: &TriMesh, resolution: u32) -> Option<Sdf> {
        let tris: Vec<[Vec3; 3]> = mesh
            .indices
            .chunks_exact(3)
            .filter_map(|t| {
                let get = |i: u32| mesh.positions.get(i as usize).copied();
                Some([get(t[0])?, get(t[1])?, get(t[2])?])
            })
            .collect();
        if tris.is_empty() {
            return None;
        }
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for t in &tris {
            for v in t {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        let cell = (hi - lo).max_element().max(1e-6) / resolution.max(1) as f32;
        let pad = (BAND + 2) as f32 * cell;
        let origin = lo - Vec3::splat(pad);
        let dims = (((hi + Vec3::splat(pad)) - origin) / cell)
            .ceil()
            .as_uvec3()
            + UVec3::ONE;
        let n = (dims.x * dims.y * dims.z) as usize;
        let mut dist = vec![f32::MAX; n];
        let mut sign = vec![1.0f32; n];
        let index = |c: UVec3| (c.x + dims.x * (c.y + dims.y * c.z)) as usize;
        for [a, b, c] in &tris {
            let normal = (*b - *a).cross(*c - *a);
            let tlo = a.min(*b).min(*c);
            let thi = a.max(*b).max(*c);
            let clo =
                (((tlo - origin) / cell).floor().as_ivec3() - IVec3::splat(BAND)).max(IVec3::ZERO);
            let chi = (((thi - origin) / cell).ceil().as_ivec3() + IVec3::splat(BAND))
                .min(dims.as_ivec3() - IVec3::ONE);
            for z in clo.z..=chi.z {
                for y in clo.y..=chi.y {
                    for x in clo.x..=chi.x {
                        let c3 = UVec3::new(x as u32, y as u32, z as u32);
                        let p = origin + c3.as_vec3() * cell;
                        let q = closest_on_triangle(p, *a, *b, *c);
                        let d = p.distance(q);
                        let i = index(c3);
                        if d < dist[i] {
                            dist[i] = d;
                            sign[i] = if (p - q).dot(normal) < 0.0 { -1.0 } else { 1.0 };
                        }
                    }
                }
            }
        }
        // Chamfer sweeps: forward then backward over the 26 neighbours.
        let offsets: Vec<(IVec3, f32)> = (-1..=1)
            .flat_map(|z| (-1..=1).flat_map(move |y| (-1..=1).map(move |x| IVec3::new(x, y, z))))
            .filter(|o| *o != IVec3::ZERO)
            .map(|o| (o, o.as_vec3().length() * cell))
            .collect();
        let d = dims.as_ivec3();
        for pass in 0..2 {
            let order: Box<dyn Iterator<Item = i32>> = if pass == 0 {
                Box::new(0..d.x * d.y * d.z)
            } else {
                Box::new((0..d.x * d.y * d.z).rev())
            };
            for flat in order {
                let c = IVec3::new(flat % d.x, (flat / d.x) % d.y, flat / (d.x * d.y));
                let i = flat as usize;
                for (o, len) in &offsets {
                    let nb = c + *o;
                    if nb.cmplt(IVec3::ZERO).any() || nb.cmpge(d).any() {
                        continue;
                    }
                    let j = index(nb.as_uvec3());
                    if dist[j] + len < dist[i] {
                        dist[i] = dist[j] + len;
                        sign[i] = sign[j];
                    }
                }
            }
        }
        let values = dist.iter().zip(&sign).map(|(d, s)| d * s).collect();
        Some(Sdf {
            origin,
            cell,
            dims,
            values,
        })
    }

    fn at(&self, c: IVec3) -> f32 {
        let c = c
            .clamp(IVec3::ZERO, self.dims.as_ivec3() - IVec3::ONE)
            .as_uvec3();
        self.values[(c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize]
    }

    /// The distance at `p` (trilinear; outside the grid, the nearest cell's value plus the
    /// distance to the grid, which is positive there).
    pub fn distance(&self, p: Vec3) -> f32 {
        let g = (p - self.origin) / self.cell;
        let max = (self.dims - UVec3::ONE).as_vec3();
        let inside = g.clamp(Vec3::ZERO, max);
        let outside = (g - inside).length() * self.cell;
        let base = inside.floor().min(max - Vec3::ONE).max(Vec3::ZERO);
        let f = inside - base;
        let b = base.as_ivec3();
        let mut sum = 0.0;
        for k in 0..8 {
            let o = IVec3::new(k & 1, (k >> 1) & 1, (k >> 2) & 1);
            let w = (if o.x == 1 { f.x } else { 1.0 - f.x })
                * (if o.y == 1 { f.y } else { 1.0 - f.y })
                * (if o.z == 1 { f.z } else { 1.0 - f.z });
            sum += w * self.at(b + o);
        }
        sum + outside
    }

    /// The field's gradient at `p` (central differences half a cell apart), normalized.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        let h = 0.5 * self.cell;
        let g = Vec3::new(
            self.distance(p + Vec3::X * h) - self.distance(p - Vec3::X * h),
            self.distance(p + Vec3::Y * h) - self.distance(p - Vec3::Y * h),
            self.distance(p + Vec3::Z * h) - self.distance(p - Vec3::Z * h),
        );
        g.try_normalize().unwrap_or(Vec3::Y)
    }
}

/// Every collider, in the head's space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Colliders {
    /// The head mesh's field, if it has one.
    pub sdf: Option<Sdf>,
    /// Spheres.
    pub spheres: Vec<Sphere>,
    /// Capsules.
    pub capsules: Vec<Capsule>,
}

impl Colliders {
    /// The signed distance at `p` (head space) to the nearest collider and the direction out of
    /// it; `None` without colliders.
    pub fn nearest(&self, p: Vec3) -> Option<(f32, Vec3)> {
        let mut best: Option<(f32, Vec3)> = None;
        let mut take = |d: f32, n: Vec3| {
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, n));
            }
        };
        if let Some(sdf) = &self.sdf {
            let d = sdf.distance(p);
            // The gradient only matters near the surface.
            if d < 4.0 * sdf.cell {
                take(d, sdf.normal(p));
            } else {
                take(d, Vec3::Y);
            }
        }
        for s in &self.spheres {
            let v = p - s.center;
            take(v.length() - s.radius, v.try_normalize().unwrap_or(Vec3::Y));
        }
        for c in &self.capsules {
            let ab = c.b - c.a;
            let t = ((p - c.a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
            let v = p - (c.a + ab * t);
            take(v.length() - c.radius, v.try_normalize().unwrap_or(Vec3::Y));
        }
        best
    }

    /// Whether there is anything to collide with.
    pub fn is_empty(&self) -> bool {
        self.sdf.is_none() && self.spheres.is_empty() && self.capsules.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tress_hair::generate::TriMesh;

    #[test]
    fn the_field_of_a_sphere_mesh_is_its_signed_distance() {
        let mesh = TriMesh::uv_sphere(Vec3::new(1.0, 2.0, 3.0), 5.0, 48, 96);
        let sdf = Sdf::build(&mesh, 48).unwrap();
        for p in [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(7.0, 2.0, 3.0),
            Vec3::new(1.0, 6.5, 3.0),
            Vec3::new(1.0, 2.0, -5.0),
            Vec3::new(3.0, 3.0, 4.0),
        ] {
            let exact = p.distance(Vec3::new(1.0, 2.0, 3.0)) - 5.0;
            let d = sdf.distance(p);
            // Exact near the surface (within the tessellation's error), chamfer far from it.
            let tol = if exact.abs() < 1.0 {
                0.08
            } else {
                0.1 * exact.abs() + 0.1
            };
            assert!((d - exact).abs() < tol, "{p}: {d} against {exact}");
        }
        let n = sdf.normal(Vec3::new(1.0, 7.1, 3.0));
        assert!(n.dot(Vec3::Y) > 0.99, "{n}");
        // Far outside the grid the distance keeps growing.
        assert!(sdf.distance(Vec3::new(100.0, 2.0, 3.0)) > 80.0);
    }

    #[test]
    fn spheres_and_capsules_give_exact_distances() {
        let c = Colliders {
            sdf: None,
            spheres: vec![Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            }],
            capsules: vec![Capsule {
                a: Vec3::new(5.0, 0.0, 0.0),
                b: Vec3::new(5.0, 4.0, 0.0),
                radius: 0.5,
            }],
        };
        let (d, n) = c.nearest(Vec3::new(0.0, 0.5, 0.0)).unwrap();
        assert!((d + 0.5).abs() < 1e-6 && n == Vec3::Y);
        let (d, n) = c.nearest(Vec3::new(4.0, 2.0, 0.0)).unwrap();
        assert!((d - 0.5).abs() < 1e-6 && (n + Vec3::X).length() < 1e-6);
        assert!(Colliders::default().nearest(Vec3::ZERO).is_none());
    }
}
