//! The physically based integrator (`strands.shading = "marschner"`): a unidirectional path
//! tracer with next-event estimation for the directional lights, Chiang et al. 2016's fibre BSDF
//! on the strands ([`crate::chiang`]) and a Lambertian head.
//!
//! - **Fibres are opaque**: a strand's light transport is its BSDF (TT carries the light
//!   through it), so `strands.alpha`, the asset's transparency and `thickness_fade` are ignored;
//!   camera, shadow and bounce rays stop at the first strand they enter (as in Mitsuba 3 and pbrt).
//! - **Lights**: a tress light's `color · intensity` is the radiance of a white Lambertian surface
//!   facing it, the GPU head pass's convention, so its irradiance is `E = π · color · intensity`;
//!   a fibre lit by it returns `f · E`, the head `HEAD_COLOR / π · E · max(n·l, 0)`.
//! - **Environment**: a ray that leaves the scene after at least one bounce sees a uniform sky of
//!   radiance `trace.ambient`, else the scene's `ambient` (so a white Lambertian surface under an open sky returns
//!   `ambient`, like the Kajiya-Kay tracer's `ambient · AO`); camera rays see the background.
//! - **Paths**: at every hit the lights are sampled (a shadow ray each; `trace.shadows = false`
//!   counts every light as unoccluded), then the BSDF
//!   ([`ChiangBsdf::sample`], cosine-weighted for the head) picks the next direction and the
//!   throughput is multiplied by `f / pdf`. After `trace.bounces` bounces the path ends; from the
//!   third bounce on it plays Russian roulette, surviving with probability `min(1, max(β))`
//!   and dividing by it (unbiased; a white fibre keeps `β = 1` and is never cut short).
//! - Secondary rays start at the hit point on the strand's surface, where Chiang's model puts
//!   the whole walk through the fibre (its light enters and leaves there), and skip the segment
//!   and its neighbours, so a ray through the fibre (TT) leaves it. The offset `h` and the frame
//!   come from the surface normal at the hit ([`FiberFrame`]). They do not start on the axis as
//!   the Kajiya-Kay tracer's shadow rays do: a strand overlapping this one (clumped generated
//!   hair has many) holds the axis point, a ray that starts inside a capsule does not hit it,
//!   and light came through the overlapping strand (found by the Mitsuba 3 comparison in
//!   `docs/mitsuba/`; tested by `an_overlapping_strand_shadows_the_fibre`).

use glam::Vec3;
use tress_hair::rng::Rng;

use super::setup::TRIANGLE;
use super::{HEAD_COLOR, HitKind, Origin, Tracer};
use crate::bvh::Visit;
use crate::chiang::{ChiangBsdf, FiberFrame};
use crate::geometry::{Ray, intersect_triangle};
use crate::sampling::cosine_hemisphere;

/// Bounces after which Russian roulette starts.
const ROULETTE_DEPTH: u32 = 3;

impl Tracer {
    /// The nearest opaque surface along `ray` that `origin` does not skip.
    pub(super) fn nearest_opaque(
        &self,
        ray: &Ray,
        origin: Option<Origin>,
    ) -> Option<(f32, HitKind)> {
        let p = &self.prims;
        p.bvh.nearest(ray, |pos, ray| {
            let r = p.refs[pos];
            if r.id & TRIANGLE != 0 {
                let id = r.id & !TRIANGLE;
                if origin.is_some_and(|o| o.skips_triangle(id)) {
                    return None;
                }
                let tri = &p.triangles[id as usize];
                intersect_triangle(ray, tri.v0, tri.e1, tri.e2).map(|h| {
                    (
                        h.t,
                        HitKind::Triangle {
                            tri: *tri,
                            id,
                            u: h.u,
                            v: h.v,
                        },
                    )
                })
            } else {
                let seg = &p.segments[r.id as usize];
                if origin.is_some_and(|o| o.skips_segment(seg)) {
                    return None;
                }
                let (t, s) = seg.intersect(ray)?;
                r.owns(s).then_some((t, HitKind::Segment { seg: *seg, s }))
            }
        })
    }

    /// Whether anything opaque lies along `ray` (shadow rays of the path tracer).
    fn occluded(&self, ray: &Ray, origin: Origin) -> bool {
        let p = &self.prims;
        let mut hit = false;
        p.bvh.for_each_hit(ray, |pos| {
            let r = p.refs[pos];
            hit = if r.id & TRIANGLE != 0 {
                let id = r.id & !TRIANGLE;
                let tri = &p.triangles[id as usize];
                !origin.skips_triangle(id)
                    && intersect_triangle(ray, tri.v0, tri.e1, tri.e2).is_some()
            } else {
                let seg = &p.segments[r.id as usize];
                !origin.skips_segment(seg) && seg.intersect(ray).is_some_and(|(_, s)| r.owns(s))
            };
            if hit { Visit::Stop } else { Visit::Continue }
        });
        hit
    }

    /// The radiance along the camera ray `ray` (see the module docs); `rng` is the sample's own
    /// stream, `rays` counts every ray traced.
    pub(super) fn path_radiance(&self, ray: &Ray, rng: &mut Rng, rays: &mut u64) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut ray = *ray;
        let mut origin: Option<Origin> = None;
        let env = Vec3::splat(self.ambient);
        for depth in 0..=self.settings.bounces {
            *rays += 1;
            let Some((t, kind)) = self.nearest_opaque(&ray, origin) else {
                radiance += beta * if depth == 0 { self.background } else { env };
                break;
            };
            let wo = -ray.dir;
            // The point secondary rays start from, what they skip, and the surface's BSDF.
            let (start, from, surface) = match kind {
                HitKind::Segment { seg, s } => {
                    let axis = seg.a + (seg.b - seg.a) * s;
                    let t_axis = (seg.b - seg.a).try_normalize().unwrap_or(Vec3::Y);
                    let n = (ray.at(t) - axis).try_normalize().unwrap_or(wo);
                    let Some(frame) = FiberFrame::new(t_axis, wo, n) else {
                        break;
                    };
                    let from = Origin::Strand {
                        strand: seg.strand,
                        vertex: seg.vertex,
                    };
                    let bsdf = ChiangBsdf::new(&self.fiber, frame.h);
                    (ray.at(t), from, Surface::Fiber(frame, bsdf))
                }
                HitKind::Triangle { tri, id, u, v } => {
                    let p = ray.at(t);
                    let geo = tri.e1.cross(tri.e2).normalize_or(wo);
                    let geo = if geo.dot(wo) < 0.0 { -geo } else { geo };
                    let [n0, n1, n2] = tri.normals;
                    let interp = (n0 * (1.0 - u - v) + n1 * u + n2 * v).normalize_or(geo);
                    let n = if interp.dot(wo) < 0.0 {
                        -interp
                    } else {
                        interp
                    };
                    let eps = 1e-4 * (1.0 + p.abs().max_element());
                    (
                        p + geo * eps,
                        Origin::Triangle(id),
                        Surface::Head { n, geo },
                    )
                }
            };
            // Next-event estimation: every directional light, one shadow ray each.
            for &(l, light) in &self.lights {
                let f = surface.eval(wo, l);
                if f.max_element() <= 0.0 {
                    continue;
                }
                *rays += 1;
                let lit = !self.settings.shadows
                    || !self.occluded(&Ray::new(start, l, 0.0, f32::INFINITY), from);
                if lit {
                    radiance += beta * f * (std::f32::consts::PI * light);
                }
            }
            if depth == self.settings.bounces {
                break;
            }
            // The next direction.
            let Some((dir, weight)) = surface.sample(wo, rng) else {
                break;
            };
            beta *= weight;
            if depth + 1 >= ROULETTE_DEPTH {
                let survive = beta.max_element().min(1.0);
                if survive <= 0.0 || rng.f32() >= survive {
                    break;
                }
                beta /= survive;
            }
            ray = Ray::new(start, dir, 0.0, f32::INFINITY);
            origin = Some(from);
        }
        radiance
    }
}

/// What a path hit: a fibre (its frame and BSDF) or the Lambertian head.
enum Surface {
    Fiber(FiberFrame, ChiangBsdf),
    Head { n: Vec3, geo: Vec3 },
}

impl Surface {
    /// The BSDF value for light arriving from the world direction `wi` (per solid angle, no
    /// cosine for fibres; the head's includes `max(n·wi, 0)`).
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            Surface::Fiber(frame, bsdf) => bsdf.eval(frame.to_local(wo), frame.to_local(wi)),
            Surface::Head { n, .. } => {
                HEAD_COLOR * (n.dot(wi).max(0.0) * std::f32::consts::FRAC_1_PI)
            }
        }
    }

    /// A sampled world direction and the throughput weight `f cos / pdf`.
    fn sample(&self, wo: Vec3, rng: &mut Rng) -> Option<(Vec3, Vec3)> {
        match self {
            Surface::Fiber(frame, bsdf) => {
                let s = bsdf.sample(frame.to_local(wo), rng.f32(), rng.f32(), rng.f32())?;
                let dir = frame.to_world(s.wi).try_normalize()?;
                Some((dir, s.f / s.pdf))
            }
            Surface::Head { n, geo } => {
                let dir = cosine_hemisphere(*n, rng.f32(), rng.f32());
                (dir.dot(*geo) > 0.0).then_some((dir, HEAD_COLOR))
            }
        }
    }
}

#[cfg(test)]
mod tests;
