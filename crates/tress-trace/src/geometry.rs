//! Rays and the two primitives the tracer intersects: strand segments (capsules) and triangles.
//!
//! # Strand segments
//!
//! A segment from `a` to `b` with radii `r_a`, `r_b` at its ends is intersected as a *capsule*:
//! the points within distance `r` of the segment (a cylinder of radius `r` around it, closed by
//! two half-spheres). A strand is a chain of them, so joints at bent vertices have no gaps. For a
//! tapered segment (`r_a ≠ r_b`) the radius used for one ray is the strand's radius at the point
//! of the segment closest to that ray, `r = lerp(r_a, r_b, s*)`: exact for constant radius,
//! and for hair (radius changes by under 1% along a segment's visible part) the difference to a
//! truncated cone is far below the strand's own width.
//!
//! The capsule test, with `w = o - a`, `e = b - a`, `ê = e / |e|` and `x⊥ = x - (x·ê) ê` the part
//! of a vector perpendicular to the axis:
//!
//! 1. *Infinite cylinder.* Points of the ray `o + t·d` lie at distance `r` from the axis where
//!    `|w⊥ + t·d⊥|² = r²`, i.e. `A t² + 2 B t + C = 0` with `A = d⊥·d⊥`, `B = w⊥·d⊥`,
//!    `C = w⊥·w⊥ - r²`. No real root: the ray misses the cylinder, hence the capsule inside it.
//! 2. *Body.* The entry root `t = (-B - sqrt(B² - A C)) / A` is a body hit when its axial
//!    parameter `s = (w + t·d)·e / e·e` lies in `[0, 1]`.
//! 3. *Cap.* Otherwise the ray enters the cylinder beyond the end nearer to `s` and can only
//!    reach the capsule through that end's sphere (the sphere fills the cylinder's cross-section
//!    at the end, so every path from there into the body crosses it): the hit is the sphere's
//!    entry `t = -(q·d) - sqrt((q·d)² - q·q + r²)`, `q = o - end`.
//!
//! A ray parallel to the axis (`A ≈ 0`) hits the nearer end's sphere when it runs inside the
//! cylinder. Only entries count: a ray that starts inside a capsule does not hit it, so secondary
//! rays leave the strand they start on.
//!
//! # Triangles
//!
//! Two-sided Möller–Trumbore: barycentrics `(u, v)` from the edge vectors and the ray, accepted
//! when `u ≥ 0`, `v ≥ 0`, `u + v ≤ 1` and `t` lies in the ray's interval.

use glam::Vec3;

pub use tress_hair::bvh::Ray;

/// A ray's entry into a capsule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CapsuleHit {
    /// Distance along the ray.
    pub t: f32,
    /// Axial parameter of the hit point's projection onto the segment, clamped to `[0, 1]`
    /// (0 at `a`, 1 at `b`): where to interpolate per-vertex attributes.
    pub s: f32,
}

/// Parameter in `[0, 1]` of the segment point `a + s·(b - a)` closest to the ray's line (0.5
/// when they are parallel).
pub fn closest_segment_param(ray: &Ray, a: Vec3, b: Vec3) -> f32 {
    let e = b - a;
    let w = ray.origin - a;
    let ee = e.dot(e);
    let ed = e.dot(ray.dir);
    let denom = ee - ed * ed;
    if denom <= ee * 1e-7 || ee <= 0.0 {
        return 0.5;
    }
    // Minimizing |a + s e - o - t d|² over s and t: s (e·e) - t (e·d) = e·w and t = s (e·d) - d·w.
    ((e.dot(w) - ed * ray.dir.dot(w)) / denom).clamp(0.0, 1.0)
}

/// The entry of `ray` into the capsule of radius `r` around the segment `a`–`b` (see the module
/// docs), if it lies in `(t_min, t_max)`.
pub fn intersect_capsule(ray: &Ray, a: Vec3, b: Vec3, r: f32) -> Option<CapsuleHit> {
    if r <= 0.0 {
        return None;
    }
    let d = ray.dir;
    let e = b - a;
    let ee = e.dot(e);
    let w = ray.origin - a;
    let r2 = r * r;
    let axial = |t: f32| ((w + t * d).dot(e) / ee).clamp(0.0, 1.0);
    if ee <= 0.0 {
        return sphere_entry(ray, a, r2).map(|t| CapsuleHit { t, s: 0.0 });
    }
    let e_hat = e / ee.sqrt();
    let d_perp = d - d.dot(e_hat) * e_hat;
    let w_perp = w - w.dot(e_hat) * e_hat;
    let big_a = d_perp.dot(d_perp);
    let big_b = w_perp.dot(d_perp);
    let end = if big_a <= 1e-12 {
        // Parallel to the axis: inside the cylinder or never near it.
        if w_perp.dot(w_perp) > r2 {
            return None;
        }
        if d.dot(e) > 0.0 { a } else { b }
    } else {
        // Solved about the ray's point of closest approach to the axis, t0 = -B/A: there the
        // quadratic reads A dt² + |q|² - r² = 0 with the perpendicular offset q, whose size is
        // the strand's. Solving B² - AC directly subtracts squares of the distance to the
        // strand, which in f32 loses everything below distance² · 1e-7: at 70 units that is
        // 5e-4, more than the r² = 1.2e-5 of a 70 µm hair.
        let t0 = -big_b / big_a;
        let q = w_perp + t0 * d_perp;
        let c0 = q.dot(q) - r2;
        if c0 > 0.0 {
            return None;
        }
        let t = t0 - (-c0 / big_a).sqrt();
        let s = (w + t * d).dot(e) / ee;
        if (0.0..=1.0).contains(&s) {
            return (t > ray.t_min && t < ray.t_max).then_some(CapsuleHit { t, s });
        }
        if s < 0.0 { a } else { b }
    };
    sphere_entry(ray, end, r2).map(|t| CapsuleHit { t, s: axial(t) })
}

/// The entry of `ray` into the sphere of squared radius `r2` around `c`, inside the ray's
/// interval; solved about the ray's point closest to `c` for the precision reason of
/// [`intersect_capsule`].
fn sphere_entry(ray: &Ray, c: Vec3, r2: f32) -> Option<f32> {
    let q = ray.origin - c;
    let t0 = -q.dot(ray.dir);
    let closest = q + t0 * ray.dir;
    let disc = r2 - closest.dot(closest);
    if disc < 0.0 {
        return None;
    }
    let t = t0 - disc.sqrt();
    (t > ray.t_min && t < ray.t_max).then_some(t)
}

/// A ray's hit on a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the ray.
    pub t: f32,
    /// Barycentric weight of the second corner.
    pub u: f32,
    /// Barycentric weight of the third corner.
    pub v: f32,
}

/// Two-sided ray–triangle intersection (Möller–Trumbore) with the triangle given by its first
/// corner `v0` and the edges `e1 = v1 - v0`, `e2 = v2 - v0`. Degenerate triangles are never hit.
pub fn intersect_triangle(ray: &Ray, v0: Vec3, e1: Vec3, e2: Vec3) -> Option<TriangleHit> {
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-20 {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - v0;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > ray.t_min && t < ray.t_max).then_some(TriangleHit { t, u, v })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: Vec3, d: Vec3) -> Ray {
        Ray::new(o, d.normalize(), 0.0, f32::INFINITY)
    }

    #[test]
    fn perpendicular_ray_enters_the_cylinder_at_d_minus_sqrt_r2_minus_h2() {
        // Axis along x from -5 to 5, radius 0.5; rays along -z from z = 10, offset h in y.
        let (a, b, r) = (Vec3::new(-5.0, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0), 0.5);
        for h in [0.0f32, 0.1, 0.3, 0.49] {
            let hit = intersect_capsule(&ray(Vec3::new(1.0, h, 10.0), Vec3::NEG_Z), a, b, r)
                .expect("inside the radius");
            let expected = 10.0 - (r * r - h * h).sqrt();
            // Near grazing (h → r) the square root of a small difference loses f32 digits.
            assert!(
                (hit.t - expected).abs() < 1e-4,
                "h {h}: {} vs {expected}",
                hit.t
            );
            assert!((hit.s - 0.6).abs() < 1e-6);
        }
        assert!(
            intersect_capsule(&ray(Vec3::new(1.0, 0.51, 10.0), Vec3::NEG_Z), a, b, r).is_none()
        );
    }

    #[test]
    fn oblique_ray_matches_the_closed_form() {
        // Axis along x; the ray lies in the plane y = h and makes angle θ with the axis. Its
        // distance to the axis in the yz plane shrinks as z = z0 - t sin θ, so it enters where
        // h² + z² = r²: t = (z0 - sqrt(r² - h²)) / sin θ.
        let (a, b, r) = (Vec3::new(-50.0, 0.0, 0.0), Vec3::new(50.0, 0.0, 0.0), 1.0);
        for (theta_deg, h) in [(30.0f32, 0.0f32), (60.0, 0.5), (15.0, 0.9)] {
            let th = theta_deg.to_radians();
            let dir = Vec3::new(th.cos(), 0.0, -th.sin());
            let z0 = 4.0;
            let hit = intersect_capsule(&ray(Vec3::new(0.0, h, z0), dir), a, b, r).unwrap();
            let expected = (z0 - (r * r - h * h).sqrt()) / th.sin();
            assert!(
                (hit.t - expected).abs() < 1e-4,
                "{theta_deg}°: {} vs {expected}",
                hit.t
            );
        }
    }

    #[test]
    fn caps_are_half_spheres() {
        // A ray along the axis from outside hits the sphere at the near end: t = dist - r.
        let (a, b, r) = (Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.25);
        let hit = intersect_capsule(&ray(Vec3::new(0.0, 0.0, -3.0), Vec3::Z), a, b, r).unwrap();
        assert!((hit.t - 2.75).abs() < 1e-6 && hit.s == 0.0);
        let hit = intersect_capsule(&ray(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z), a, b, r).unwrap();
        assert!((hit.t - 2.75).abs() < 1e-6 && hit.s == 1.0);
        // A perpendicular ray just beyond the end, within the cap: t = 10 - sqrt(r² - dx²).
        let dx = 0.2f32;
        let hit =
            intersect_capsule(&ray(Vec3::new(0.0, 10.0, 2.0 + dx), Vec3::NEG_Y), a, b, r).unwrap();
        assert!((hit.t - (10.0 - (r * r - dx * dx).sqrt())).abs() < 1e-5);
        // Beyond the cap: a miss.
        assert!(intersect_capsule(&ray(Vec3::new(0.0, 10.0, 2.3), Vec3::NEG_Y), a, b, r).is_none());
        // Parallel outside the cylinder: a miss.
        assert!(intersect_capsule(&ray(Vec3::new(0.3, 0.0, -3.0), Vec3::Z), a, b, r).is_none());
    }

    #[test]
    fn interval_and_inside_rules() {
        let (a, b, r) = (Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.5);
        let o = Vec3::new(0.0, 0.0, 3.0);
        let mut rr = ray(o, Vec3::NEG_Z);
        rr.t_max = 2.4;
        assert!(
            intersect_capsule(&rr, a, b, r).is_none(),
            "hit at 2.5 is beyond t_max"
        );
        rr.t_max = 2.6;
        assert!(intersect_capsule(&rr, a, b, r).is_some());
        // Starting inside: no entry ahead.
        assert!(intersect_capsule(&ray(Vec3::ZERO, Vec3::Z), a, b, r).is_none());
        assert!(intersect_capsule(&ray(o, Vec3::NEG_Z), a, b, 0.0).is_none());
        // A zero-length segment is a sphere.
        let hit = intersect_capsule(&ray(o, Vec3::NEG_Z), Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
        assert!((hit.t - 2.0).abs() < 1e-6);
    }

    #[test]
    fn thin_strands_far_away_are_hit_where_they_are() {
        // A 70 µm strand (r = 0.0035) seen from 70 units: the entry point lies on the surface
        // and a ray at offset y hits exactly when |y| < r, at the cylinder's entry distance.
        let (a, b, r) = (Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.0035);
        let o = Vec3::new(0.3, 0.0, 70.0);
        let mut hits = 0;
        for k in 0..200 {
            let y = -1.5 * r + 3.0 * r * (k as f32 + 0.5) / 200.0;
            let target = Vec3::new(0.2, y, 0.0);
            let d = (target - o).normalize();
            match intersect_capsule(&ray(o, d), a, b, r) {
                Some(hit) => {
                    hits += 1;
                    let p = o + hit.t * d;
                    let dist = (p.y * p.y + p.z * p.z).sqrt();
                    assert!((dist - r).abs() < 2e-3 * r, "y {y}: {dist} vs {r}");
                }
                None => assert!(y.abs() > 0.99 * r, "y {y} missed"),
            }
        }
        // 2r of the 3r the rays span.
        assert!((hits as f32 / 200.0 - 2.0 / 3.0).abs() < 0.02, "{hits}");
        // The same for a cap far away.
        let d = (Vec3::new(1.0 + 0.5 * r, 0.0, 0.0) - o).normalize();
        let hit = intersect_capsule(&ray(o, d), a, b, r).expect("cap");
        assert!(((o + hit.t * d - b).length() - r).abs() < 2e-3 * r);
    }

    #[test]
    fn closest_param_of_skew_lines() {
        // Segment along x from 0 to 4, ray along z through x = 1: s = 0.25.
        let r = ray(Vec3::new(1.0, 2.0, -5.0), Vec3::Z);
        assert!(
            (closest_segment_param(&r, Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)) - 0.25).abs() < 1e-6
        );
        // Clamped beyond the ends, 0.5 when parallel.
        let r = ray(Vec3::new(9.0, 2.0, -5.0), Vec3::Z);
        assert_eq!(
            closest_segment_param(&r, Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)),
            1.0
        );
        let r = ray(Vec3::new(0.0, 1.0, 0.0), Vec3::X);
        assert_eq!(
            closest_segment_param(&r, Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)),
            0.5
        );
    }

    #[test]
    fn triangle_hits_match_barycentrics_and_plane_distance() {
        let (v0, v1, v2) = (
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        );
        let (e1, e2) = (v1 - v0, v2 - v0);
        let hit =
            intersect_triangle(&ray(Vec3::new(0.5, 0.25, 3.0), Vec3::NEG_Z), v0, e1, e2).unwrap();
        assert!((hit.t - 3.0).abs() < 1e-6);
        assert!((hit.u - 0.25).abs() < 1e-6 && (hit.v - 0.125).abs() < 1e-6);
        // Two-sided, and an oblique ray meets the plane z = 0 at t = 3 / cos.
        let d = Vec3::new(0.0, 0.6, 0.8);
        let hit = intersect_triangle(&ray(Vec3::new(0.5, 0.0, -1.6), d), v0, e1, e2).unwrap();
        assert!((hit.t - 2.0).abs() < 1e-6 && (hit.v - 0.6).abs() < 1e-6);
        // Outside, parallel, behind.
        assert!(
            intersect_triangle(&ray(Vec3::new(1.5, 1.5, 3.0), Vec3::NEG_Z), v0, e1, e2).is_none()
        );
        assert!(intersect_triangle(&ray(Vec3::new(0.5, 0.5, 3.0), Vec3::X), v0, e1, e2).is_none());
        assert!(intersect_triangle(&ray(Vec3::new(0.5, 0.5, 3.0), Vec3::Z), v0, e1, e2).is_none());
        // Degenerate.
        assert!(
            intersect_triangle(&ray(Vec3::new(0.5, 0.0, 3.0), Vec3::NEG_Z), v0, e1, e1).is_none()
        );
    }
}
