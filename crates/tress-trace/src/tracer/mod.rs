//! The tracer: a scene's strands and head in one BVH, and the per-pixel integrator.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

mod path;
mod setup;

use glam::Vec3;
use rayon::prelude::*;
use tress_hair::rng::Rng;
use tress_scene::Scene;
use tress_shading::fiber::HairFiber;
use tress_shading::{HairLighting, HairSample, KajiyaKay, hair_lighting, kajiya_kay};

use crate::bvh::Visit;
use crate::geometry::{Ray, intersect_triangle};
use crate::sampling::{
    cosine_hemisphere, hash_unit, hash2, lattice_generator, lattice_point, strand_random,
};
use crate::{Aov, Image, StrandWidth, TraceError, TraceSettings};
use setup::{GpuStrands, PinholeCamera, Primitives, Segment, Shading, TRIANGLE, Triangle};
pub use setup::{HEAD_SUBDIVISIONS, SceneGeometry};

/// Head mesh color (linear RGB): the value of `tress_render::Material::default().head_color`,
/// which the scene file does not set. Mirrored here because this crate has no GPU dependency.
pub const HEAD_COLOR: Vec3 = Vec3::new(0.55, 0.40, 0.33);
/// A secondary ray whose transmittance falls below this counts as blocked (exact mode, tests).
const CUTOFF: f32 = 1e-4;
/// Below this transmittance, shadow and AO rays play Russian roulette (see
/// [`Tracer::transmittance`]).
const ROULETTE: f32 = 0.25;
/// Hash streams of a camera sample's key: the transparency decisions of the camera ray use the
/// primitive index (below 2^32); shadow and AO rays' roulette keys start here.
const SHADOW_STREAM: u64 = 1 << 40;
const AO_STREAM: u64 = 1 << 41;

/// Where a secondary ray starts, so the primitives it starts on are not hit.
#[derive(Clone, Copy, Debug)]
enum Origin {
    /// On a strand (on its axis for the direct tracer's shadow and AO rays, on its surface for
    /// the path tracer's rays): the segment and its two neighbours on the strand are skipped.
    Strand { strand: u32, vertex: u32 },
    /// On a triangle: that triangle is skipped.
    Triangle(u32),
}

impl Origin {
    fn skips_segment(&self, s: &Segment) -> bool {
        matches!(self, Origin::Strand { strand, vertex }
            if s.strand == *strand && s.vertex.abs_diff(*vertex) <= 1)
    }

    fn skips_triangle(&self, id: u32) -> bool {
        matches!(self, Origin::Triangle(t) if *t == id)
    }
}

#[derive(Clone, Copy, Debug)]
enum HitKind {
    Segment {
        seg: Segment,
        s: f32,
    },
    Triangle {
        tri: Triangle,
        id: u32,
        u: f32,
        v: f32,
    },
}

/// One camera sample's result.
#[derive(Clone, Copy, Debug)]
struct SampleValue {
    color: Vec3,
    ao: f32,
    shadow: f32,
}

/// Counts and timings of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TraceStats {
    /// Rays traced: camera rays, shadow rays and AO rays.
    pub rays: u64,
    /// Camera samples traced (`width · height · spp`).
    pub samples: u64,
    /// Wall-clock seconds of the render (not counting the BVH build).
    pub seconds: f64,
}

impl TraceStats {
    /// Rays per second.
    pub fn rays_per_second(&self) -> f64 {
        if self.seconds > 0.0 {
            self.rays as f64 / self.seconds
        } else {
            0.0
        }
    }
}

/// A camera given as matrices, for [`Tracer::with_camera`]: the GPU renderer's convention
/// (`tress_render::Camera`). Pixel `(x, y)` (origin top-left, `y` down) looks through NDC
/// `(2x/w - 1, 1 - 2y/h)`; the ray runs from the point at clip depth 0 to the one at depth 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewCamera {
    /// World to view space (OpenGL axes: x right, y up, looking down -z).
    pub view_from_world: glam::Mat4,
    /// View to wgpu clip space (x, y in `[-1, 1]`, +y up, depth in `[0, 1]`), perspective or
    /// orthographic.
    pub clip_from_view: glam::Mat4,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// A rendered image and its statistics.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image (the AOV of the settings).
    pub image: Image,
    /// Ray counts and time.
    pub stats: TraceStats,
}

/// A scene ready to trace: camera, lights, material, and every strand segment and head
/// triangle in one BVH. See the crate docs for the model.
#[derive(Debug)]
pub struct Tracer {
    settings: TraceSettings,
    camera: PinholeCamera,
    lights: Vec<(Vec3, Vec3)>,
    shading: Shading,
    kajiya_kay: KajiyaKay,
    lighting: HairLighting,
    /// The physically based fibre (`[hair.material]`), used with [`Shading::Marschner`].
    fiber: HairFiber,
    base_color: Vec3,
    vertex_colors: Option<Vec<Vec3>>,
    hair_center: Vec3,
    background: Vec3,
    /// The ambient light: `trace.ambient`, else the scene's.
    ambient: f32,
    prims: Primitives,
    build_seconds: f64,
}

impl Tracer {
    /// Prepare `geometry` (loaded from `scene`) for tracing with the scene's camera, output
    /// size, lights, first hair material and `[strands]` width, alpha and shading; builds the
    /// BVH (on rayon's threads).
    pub fn new(
        scene: &Scene,
        geometry: &SceneGeometry,
        settings: &TraceSettings,
    ) -> Result<Tracer, TraceError> {
        Tracer::build(scene, geometry, settings, PinholeCamera::new(scene))
    }

    /// As [`Tracer::new`], but seen through `camera` (any view and projection matrix pair, at
    /// its own size) instead of the scene's `[camera]` and `[output]`.
    pub fn with_camera(
        scene: &Scene,
        geometry: &SceneGeometry,
        settings: &TraceSettings,
        camera: &ViewCamera,
    ) -> Result<Tracer, TraceError> {
        Tracer::build(
            scene,
            geometry,
            settings,
            PinholeCamera::from_matrices(camera)?,
        )
    }

    fn build(
        scene: &Scene,
        geometry: &SceneGeometry,
        settings: &TraceSettings,
        camera: PinholeCamera,
    ) -> Result<Tracer, TraceError> {
        let start = Instant::now();
        settings.validate()?;
        scene.validate()?;
        let gpu = GpuStrands::from_scene(scene)?;
        let material = scene
            .hair
            .first()
            .map(|h| h.material.clone())
            .unwrap_or_default();
        let lights = scene
            .lights
            .iter()
            .map(|l| (l.to_light(), l.radiance()))
            .collect();

        let fiber = material.fiber()?;
        let prims = Primitives::build(geometry, &camera, gpu, settings, material.thickness)?;
        let vertex_colors = geometry
            .hair
            .as_ref()
            .and_then(|h| h.color().map(<[Vec3]>::to_vec));
        let hair_center = geometry
            .hair
            .as_ref()
            .map_or(Vec3::ZERO, |h| h.bounds().center());
        Ok(Tracer {
            settings: settings.clone(),
            camera,
            lights,
            shading: gpu.shading,
            kajiya_kay: material.kajiya_kay(),
            lighting: material.hair_lighting(),
            fiber,
            base_color: material.base_color,
            vertex_colors,
            hair_center,
            background: scene.background,
            ambient: settings.ambient.unwrap_or(scene.ambient),
            prims,
            build_seconds: start.elapsed().as_secs_f64(),
        })
    }

    /// Number of strand segments traced.
    pub fn segment_count(&self) -> usize {
        self.prims.segments.len()
    }

    /// Number of BVH references (segments are referenced in pieces, see the crate docs).
    pub fn reference_count(&self) -> usize {
        self.prims.refs.len()
    }

    /// Number of head triangles traced.
    pub fn triangle_count(&self) -> usize {
        self.prims.triangles.len()
    }

    /// The strand width mode in effect ([`StrandWidth::Auto`] resolved).
    pub fn strand_width(&self) -> StrandWidth {
        self.prims.strand_width
    }

    /// Seconds spent building the BVH and the primitive arrays.
    pub fn build_seconds(&self) -> f64 {
        self.build_seconds
    }

    /// The settings.
    pub fn settings(&self) -> &TraceSettings {
        &self.settings
    }

    /// Trace the next renders with another seed (the BVH is kept).
    pub fn set_seed(&mut self, seed: u64) {
        self.settings.seed = seed;
    }

    /// Trace the next renders with `spp` samples a pixel (the BVH is kept); an error outside
    /// the settings' range.
    pub fn set_spp(&mut self, spp: u32) -> Result<(), TraceError> {
        let next = TraceSettings {
            spp,
            ..self.settings.clone()
        };
        next.validate()?;
        self.settings = next;
        Ok(())
    }

    /// Render the image, rows in parallel on rayon's threads; `rows_done(n)` is called as rows
    /// finish (for a progress bar). Deterministic: the same scene and settings give the same
    /// image on any number of threads.
    pub fn render(&self, rows_done: &(dyn Fn(u32) + Sync)) -> Rendered {
        let start = Instant::now();
        let (w, h) = (self.camera.width as usize, self.camera.height as usize);
        let mut pixels = vec![Vec3::ZERO; w * h];
        let rays = AtomicU64::new(0);
        pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            let mut count = 0u64;
            for (x, px) in row.iter_mut().enumerate() {
                *px = self.pixel(x as u32, y as u32, &mut count);
            }
            rays.fetch_add(count, Ordering::Relaxed);
            rows_done(1);
        });
        Rendered {
            image: Image {
                width: self.camera.width,
                height: self.camera.height,
                pixels,
            },
            stats: TraceStats {
                rays: rays.load(Ordering::Relaxed),
                samples: (w * h) as u64 * u64::from(self.settings.spp),
                seconds: start.elapsed().as_secs_f64(),
            },
        }
    }

    /// The value of one pixel: the box-filtered mean of `spp` camera samples on a jittered
    /// rank-1 lattice over the pixel.
    fn pixel(&self, x: u32, y: u32, rays: &mut u64) -> Vec3 {
        let n = self.settings.spp;
        let pixel_index = u64::from(y) * u64::from(self.camera.width) + u64::from(x);
        let mut rng = Rng::stream(self.settings.seed, pixel_index);
        let g = lattice_generator(n);
        let ao_n = n * self.settings.ao_samples.max(1);
        let ao_g = lattice_generator(ao_n);
        // Random offsets decorrelate the AO strata from the pixel strata.
        let ao_shift = (
            rng.below(u64::from(ao_n)) as u32,
            rng.below(u64::from(ao_n)) as u32,
        );
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            let (sx, sy) = lattice_point(i, n, g, rng.f32(), rng.f32());
            let ray = self.camera.ray(x as f32 + sx, y as f32 + sy);
            let key = rng.next_u64();
            let mut ao_points = (0..self.settings.ao_samples).map(|k| {
                let j = (i * self.settings.ao_samples + k + ao_shift.0) % ao_n;
                let (u0, u1) = lattice_point(j, ao_n, ao_g, rng.f32(), rng.f32());
                (u0, (u1 + ao_shift.1 as f32 / ao_n as f32).fract())
            });
            let v = if self.shading == Shading::Marschner && self.settings.aov == Aov::Color {
                let color = self.path_radiance(&ray, &mut Rng::new(key), rays);
                SampleValue {
                    color,
                    ao: 1.0,
                    shadow: 1.0,
                }
            } else {
                self.sample(&ray, key, &mut ao_points, rays)
            };
            sum += match self.settings.aov {
                Aov::Color => v.color,
                Aov::Ao => Vec3::splat(v.ao),
                Aov::Shadow => Vec3::splat(v.shadow),
            };
        }
        sum / n as f32
    }

    /// One camera sample: the nearest surface the ray stops at (stochastic transparency: each
    /// strand crossed stops it with probability alpha, decided by a hash of the sample's `key`
    /// and the primitive), shaded.
    fn sample(
        &self,
        ray: &Ray,
        key: u64,
        ao_points: &mut dyn Iterator<Item = (f32, f32)>,
        rays: &mut u64,
    ) -> SampleValue {
        *rays += 1;
        let p = &self.prims;
        let hit = p.bvh.nearest(ray, |pos, ray| {
            let r = p.refs[pos];
            if r.id & TRIANGLE != 0 {
                let id = r.id & !TRIANGLE;
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
                let (t, s) = seg.intersect(ray)?;
                (r.owns(s) && hash_unit(key, u64::from(r.id)) < seg.alpha_at(s))
                    .then_some((t, HitKind::Segment { seg: *seg, s }))
            }
        });
        let Some((t, kind)) = hit else {
            return SampleValue {
                color: self.background,
                ao: 1.0,
                shadow: 1.0,
            };
        };
        let v = -ray.dir;
        let aov = self.settings.aov;
        let want_ao = aov == Aov::Ao || (aov == Aov::Color && self.ambient > 0.0);
        let want_shadow = aov != Aov::Ao;
        match kind {
            HitKind::Segment { seg, s } => {
                let t_axis = (seg.b - seg.a).try_normalize().unwrap_or(Vec3::Y);
                let p = seg.a + (seg.b - seg.a) * s;
                let n = self.strand_normal(p, t_axis, v);
                let origin = Origin::Strand {
                    strand: seg.strand,
                    vertex: seg.vertex,
                };
                let ao = if want_ao {
                    self.ambient_occlusion(p, n, origin, ao_points, Some(key), rays)
                } else {
                    1.0
                };
                let base = self.vertex_colors.as_ref().map_or(self.base_color, |c| {
                    let (i, j) = (seg.vertex as usize, seg.vertex as usize + 1);
                    c[i] + (c[j] - c[i]) * s
                });
                let mut color = Vec3::splat(self.ambient) * base * ao;
                let (mut vis_sum, mut weight) = (0.0, 0.0);
                for (light, &(l, radiance)) in self.lights.iter().enumerate() {
                    let vis = if want_shadow && self.settings.shadows {
                        *rays += 1;
                        self.transmittance(
                            &Ray::new(p, l, 0.0, f32::INFINITY),
                            origin,
                            Some(hash2(key, SHADOW_STREAM + light as u64)),
                        )
                    } else {
                        1.0
                    };
                    let c = match self.shading {
                        Shading::KajiyaKay => {
                            let kk = KajiyaKay {
                                diffuse: base,
                                ..self.kajiya_kay
                            };
                            kajiya_kay(&kk, t_axis, l, v) * radiance
                        }
                        Shading::Scheuermann => {
                            let sample = HairSample {
                                tangent: t_axis,
                                shift_tex: strand_random(seg.strand, 0),
                                normal: n,
                                spec_mask: strand_random(seg.strand, 1),
                                base_color: base,
                                amb_occ: 1.0,
                            };
                            hair_lighting(&self.lighting, &sample, l, radiance, v)
                        }
                        // The path tracer shades the colour (`path.rs`); this runs only for the
                        // AO and shadow AOVs.
                        Shading::Marschner => Vec3::ZERO,
                    };
                    color += c * vis;
                    let w = luminance(radiance);
                    vis_sum += vis * w;
                    weight += w;
                }
                SampleValue {
                    color,
                    ao,
                    shadow: if weight > 0.0 { vis_sum / weight } else { 1.0 },
                }
            }
            HitKind::Triangle { tri, id, u, v: bv } => {
                let p = ray.at(t);
                let geo = tri.e1.cross(tri.e2).normalize_or(v);
                let geo = if geo.dot(v) < 0.0 { -geo } else { geo };
                let [n0, n1, n2] = tri.normals;
                let interp = (n0 * (1.0 - u - bv) + n1 * u + n2 * bv).normalize_or(geo);
                // Two-sided, like the GPU's head pass: face the viewer.
                let n = if interp.dot(v) < 0.0 { -interp } else { interp };
                let eps = 1e-4 * (1.0 + p.abs().max_element());
                let start = p + geo * eps;
                let origin = Origin::Triangle(id);
                let ao = if want_ao {
                    self.ambient_occlusion(start, geo, origin, ao_points, Some(key), rays)
                } else {
                    1.0
                };
                let mut light = Vec3::splat(self.ambient) * ao;
                let (mut vis_sum, mut weight) = (0.0, 0.0);
                for (index, &(l, radiance)) in self.lights.iter().enumerate() {
                    let n_dot_l = n.dot(l).max(0.0);
                    let vis = if want_shadow && self.settings.shadows && n_dot_l > 0.0 {
                        *rays += 1;
                        self.transmittance(
                            &Ray::new(start, l, 0.0, f32::INFINITY),
                            origin,
                            Some(hash2(key, SHADOW_STREAM + index as u64)),
                        )
                    } else if n_dot_l > 0.0 || !want_shadow {
                        1.0
                    } else {
                        0.0
                    };
                    light += radiance * n_dot_l * vis;
                    let w = luminance(radiance);
                    vis_sum += vis * w;
                    weight += w;
                }
                SampleValue {
                    color: HEAD_COLOR * light,
                    ao,
                    shadow: if weight > 0.0 { vis_sum / weight } else { 1.0 },
                }
            }
        }
    }

    /// The strands' shading normal, as the GPU rasterizer defines it for Scheuermann's model:
    /// the direction from the centre of the hair's bounds to `p`, made perpendicular to the
    /// tangent (the view direction when that is degenerate).
    fn strand_normal(&self, p: Vec3, t: Vec3, v: Vec3) -> Vec3 {
        let mut n = p - self.hair_center;
        n -= n.dot(t) * t;
        if n.length() < 1e-6 {
            n = v - v.dot(t) * t;
        }
        n.try_normalize().unwrap_or(Vec3::Z)
    }

    /// Mean transmittance of `ao_samples` cosine-distributed rays of length `ao_radius` around
    /// `n` from `p`.
    fn ambient_occlusion(
        &self,
        p: Vec3,
        n: Vec3,
        origin: Origin,
        points: &mut dyn Iterator<Item = (f32, f32)>,
        roulette: Option<u64>,
        rays: &mut u64,
    ) -> f32 {
        let mut sum = 0.0;
        let mut count = 0;
        for (u0, u1) in points {
            let dir = cosine_hemisphere(n, u0, u1);
            let ray = Ray::new(p, dir, 0.0, self.settings.ao_radius);
            let key = roulette.map(|k| hash2(k, AO_STREAM + count));
            sum += self.transmittance(&ray, origin, key);
            count += 1;
        }
        *rays += count;
        if count == 0 { 1.0 } else { sum / count as f32 }
    }

    /// The fraction of light that gets through along `ray`: the product of `1 - alpha` over the
    /// strands it enters, 0 at any triangle (the head is opaque).
    ///
    /// With a `roulette` key the result is an unbiased estimate instead: once the product falls
    /// below [`ROULETTE`] the ray survives with probability `product / ROULETTE` and goes on with
    /// the product set to `ROULETTE`, else it returns 0. The expected value is unchanged, and a
    /// ray inside dense hair stops after a few strands instead of the ~10 it takes an alpha-0.6
    /// product to fall below [`CUTOFF`] (rays in hair visit many boxes per strand they meet).
    fn transmittance(&self, ray: &Ray, origin: Origin, roulette: Option<u64>) -> f32 {
        let mut left = 1.0f32;
        let mut crossings = 0u64;
        let p = &self.prims;
        p.bvh.for_each_hit(ray, |pos| {
            let r = p.refs[pos];
            if r.id & TRIANGLE != 0 {
                let id = r.id & !TRIANGLE;
                let tri = &p.triangles[id as usize];
                if !origin.skips_triangle(id)
                    && intersect_triangle(ray, tri.v0, tri.e1, tri.e2).is_some()
                {
                    left = 0.0;
                }
            } else {
                let seg = &p.segments[r.id as usize];
                if !origin.skips_segment(seg)
                    && let Some((_, s)) = seg.intersect(ray)
                    && r.owns(s)
                {
                    left *= 1.0 - seg.alpha_at(s).clamp(0.0, 1.0);
                }
            }
            if let Some(key) = roulette
                && left < ROULETTE
                && left > 0.0
            {
                crossings += 1;
                if hash_unit(key, crossings) * ROULETTE < left {
                    left = ROULETTE;
                } else {
                    left = 0.0;
                }
            }
            if left < CUTOFF {
                left = 0.0;
                Visit::Stop
            } else {
                Visit::Continue
            }
        });
        left
    }
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests;
