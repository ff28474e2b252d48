//! The tracer: a scene's strands and head in one BVH, and the per-pixel integrator.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use serde::Deserialize;
use tress_hair::HairAsset;
use tress_hair::generate::TriMesh;
use tress_hair::rng::Rng;
use tress_scene::{HeadSource, Scene};
use tress_shading::{HairLighting, HairSample, KajiyaKay, hair_lighting, kajiya_kay, tip_fade};

use crate::bvh::{Bounds, Bvh, Visit};
use crate::geometry::{Ray, closest_segment_param, intersect_capsule, intersect_triangle};
use crate::sampling::{
    cosine_hemisphere, hash_unit, lattice_generator, lattice_point, strand_random,
};
use crate::{Aov, Image, StrandWidth, TraceError, TraceSettings};

/// Head mesh color (linear RGB): the value of `tress_render::Material::default().head_color`,
/// which the scene file does not set. Mirrored here because this crate has no GPU dependency.
pub const HEAD_COLOR: Vec3 = Vec3::new(0.55, 0.40, 0.33);
/// Subdivisions of the generated head's mesh, as `tress_render::scene_setup` draws it.
pub const HEAD_SUBDIVISIONS: u32 = 64;
/// A secondary ray whose transmittance falls below this counts as blocked.
const CUTOFF: f32 = 1e-4;

/// The `[strands]` keys the tracer shares with the GPU rasterizer (others are ignored here; the
/// rasterizer checks them). Defaults mirror `tress_render::StrandSettings::default()`.
#[derive(Deserialize, Default, Debug)]
#[serde(default)]
struct GpuStrandKeys {
    width_px: Option<f32>,
    alpha: Option<f32>,
    shading: Option<String>,
    thickness_fade: Option<String>,
}

/// The strand rasterizer's shading model (`strands.shading`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shading {
    KajiyaKay,
    Scheuermann,
}

/// The rasterizer's `strands.thickness_fade`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ThicknessFade {
    Off,
    Tip,
    Projected,
}

/// The strand settings of the GPU technique the reference follows.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GpuStrands {
    width_px: f32,
    alpha: f32,
    shading: Shading,
    thickness_fade: ThicknessFade,
}

impl GpuStrands {
    fn from_scene(scene: &Scene) -> Result<GpuStrands, TraceError> {
        let keys: GpuStrandKeys = scene.technique_settings("strands")?;
        let invalid = |m: String| Err(TraceError::Invalid(m));
        let width_px = keys.width_px.unwrap_or(1.5);
        if !(width_px > 0.0 && width_px <= 64.0) {
            return invalid("strands.width_px must be in (0, 64]".into());
        }
        let alpha = keys.alpha.unwrap_or(0.6);
        if !(0.0..=1.0).contains(&alpha) {
            return invalid("strands.alpha must be in [0, 1]".into());
        }
        let shading = match keys.shading.as_deref().unwrap_or("kajiya-kay") {
            "kajiya-kay" => Shading::KajiyaKay,
            "scheuermann" => Shading::Scheuermann,
            s => {
                return invalid(format!(
                    "unknown shading `{s}` (expected kajiya-kay or scheuermann)"
                ));
            }
        };
        let thickness_fade = match keys.thickness_fade.as_deref().unwrap_or("tip") {
            "off" => ThicknessFade::Off,
            "tip" => ThicknessFade::Tip,
            "projected" => ThicknessFade::Projected,
            s => {
                return invalid(format!(
                    "unknown thickness_fade `{s}` (expected off, tip or projected)"
                ));
            }
        };
        Ok(GpuStrands {
            width_px,
            alpha,
            shading,
            thickness_fade,
        })
    }
}

/// A scene's hair (all `[[hair]]` entries merged) and head mesh, loaded but not yet placed in
/// a BVH (the strand widths may depend on the camera).
#[derive(Clone, Debug)]
pub struct SceneGeometry {
    /// The merged hair, if the scene has any.
    pub hair: Option<HairAsset>,
    /// The head mesh, if the scene has one.
    pub head: Option<TriMesh>,
}

impl SceneGeometry {
    /// Load (or generate) the scene's hair and head, as the GPU path does: hair entries merged,
    /// the generated head meshed with [`HEAD_SUBDIVISIONS`], OBJ heads read with
    /// [`TriMesh::read_obj`]. Errors name the file or entry.
    pub fn load(scene: &Scene) -> Result<SceneGeometry, TraceError> {
        let assets = scene.load_hair()?;
        let hair = if assets.is_empty() {
            None
        } else {
            Some(HairAsset::merge(&assets)?)
        };
        let head = match scene.head_source() {
            HeadSource::None => None,
            HeadSource::Obj(path) => Some(TriMesh::read_obj(&path)?),
            HeadSource::Generated(head) => {
                head.validate()?;
                Some(head.mesh(HEAD_SUBDIVISIONS))
            }
        };
        Ok(SceneGeometry { hair, head })
    }
}

/// A pinhole camera matching the GPU's `look_at_rh` + `perspective_rh`: pixel `(x, y)` (origin
/// top-left, `y` down, centres at half-integers) looks through NDC `(2x/w - 1, 1 - 2y/h)`.
#[derive(Clone, Copy, Debug)]
struct PinholeCamera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_y: f32,
    aspect: f32,
    near: f32,
    far: f32,
    width: u32,
    height: u32,
}

impl PinholeCamera {
    fn new(scene: &Scene) -> PinholeCamera {
        let c = &scene.camera;
        let forward = (c.target - c.eye).normalize();
        let right = forward.cross(c.up).normalize();
        let up = right.cross(forward);
        PinholeCamera {
            eye: c.eye,
            forward,
            right,
            up,
            tan_half_y: (c.fov_y_deg.to_radians() * 0.5).tan(),
            aspect: scene.output.aspect(),
            near: c.near,
            far: c.far,
            width: scene.output.width,
            height: scene.output.height,
        }
    }

    /// The ray through film point `(x, y)` in pixels, clipped to the near and far planes.
    fn ray(&self, x: f32, y: f32) -> Ray {
        let ndc_x = 2.0 * x / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * y / self.height as f32;
        let d = self.forward
            + self.right * (ndc_x * self.tan_half_y * self.aspect)
            + self.up * (ndc_y * self.tan_half_y);
        let len = d.length();
        Ray::new(self.eye, d / len, self.near * len, self.far * len)
    }

    /// World units per pixel at view depth `depth`.
    fn world_per_pixel(&self, depth: f32) -> f32 {
        2.0 * self.tan_half_y * depth.max(self.near) / self.height as f32
    }
}

/// A strand segment as the tracer stores it.
#[derive(Clone, Copy, Debug)]
struct Segment {
    a: Vec3,
    b: Vec3,
    radius: [f32; 2],
    alpha: [f32; 2],
    strand: u32,
    /// Index of the first vertex (neighbouring segments of a strand differ by one).
    vertex: u32,
}

impl Segment {
    fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        let s = closest_segment_param(ray, self.a, self.b);
        let r = self.radius[0] + (self.radius[1] - self.radius[0]) * s;
        intersect_capsule(ray, self.a, self.b, r).map(|h| (h.t, h.s))
    }

    fn alpha_at(&self, s: f32) -> f32 {
        self.alpha[0] + (self.alpha[1] - self.alpha[0]) * s
    }
}

/// A triangle as the tracer stores it.
#[derive(Clone, Copy, Debug)]
struct Triangle {
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    id: u32,
}

/// A primitive in BVH leaf order.
#[derive(Clone, Copy, Debug)]
enum Prim {
    Segment(Segment),
    Triangle(Triangle),
}

/// Where a secondary ray starts, so the primitives it starts on are not hit.
#[derive(Clone, Copy, Debug)]
enum Origin {
    /// On a strand's axis: the segment and its two neighbours on the strand are skipped.
    Strand { strand: u32, vertex: u32 },
    /// On a triangle: that triangle is skipped.
    Triangle(u32),
}

impl Origin {
    fn skips(&self, prim: &Prim) -> bool {
        match (self, prim) {
            (Origin::Strand { strand, vertex }, Prim::Segment(s)) => {
                s.strand == *strand && s.vertex.abs_diff(*vertex) <= 1
            }
            (Origin::Triangle(id), Prim::Triangle(t)) => t.id == *id,
            _ => false,
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum HitKind {
    Segment { seg: Segment, s: f32 },
    Triangle { tri: Triangle, u: f32, v: f32 },
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
    base_color: Vec3,
    vertex_colors: Option<Vec<Vec3>>,
    hair_center: Vec3,
    background: Vec3,
    bvh: Bvh,
    prims: Vec<Prim>,
    tri_normals: Vec<[Vec3; 3]>,
    segment_count: usize,
    triangle_count: usize,
    strand_width: StrandWidth,
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
        let start = Instant::now();
        settings.validate()?;
        scene.validate()?;
        let gpu = GpuStrands::from_scene(scene)?;
        let camera = PinholeCamera::new(scene);
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

        let mut prims = Vec::new();
        let mut bounds = Vec::new();
        let mut strand_width = settings.width;
        if let Some(hair) = &geometry.hair {
            let (segments, width) =
                strand_segments(hair, &camera, gpu, settings, material.thickness);
            strand_width = width;
            for s in segments {
                let r = s.radius[0].max(s.radius[1]);
                bounds.push(Bounds {
                    min: s.a.min(s.b) - Vec3::splat(r),
                    max: s.a.max(s.b) + Vec3::splat(r),
                });
                prims.push(Prim::Segment(s));
            }
        }
        let segment_count = prims.len();
        let mut tri_normals = Vec::new();
        if let Some(mesh) = &geometry.head {
            for (id, t) in mesh.indices.chunks_exact(3).enumerate() {
                let corner = |k: usize| -> Result<(Vec3, Vec3), TraceError> {
                    let i = t[k] as usize;
                    let p = *mesh.positions.get(i).ok_or_else(|| {
                        TraceError::Invalid(format!("head mesh: index {i} out of range"))
                    })?;
                    let n = mesh.normals.get(i).copied().unwrap_or(Vec3::ZERO);
                    Ok((p, n))
                };
                let (p0, n0) = corner(0)?;
                let (p1, n1) = corner(1)?;
                let (p2, n2) = corner(2)?;
                if !(p0.is_finite() && p1.is_finite() && p2.is_finite()) {
                    return Err(TraceError::Invalid(format!(
                        "head mesh: triangle {id} has a non-finite corner"
                    )));
                }
                let id = u32::try_from(id)
                    .map_err(|_| TraceError::Invalid("head mesh: too many triangles".into()))?;
                bounds.push(Bounds::EMPTY.grow(p0).grow(p1).grow(p2));
                prims.push(Prim::Triangle(Triangle {
                    v0: p0,
                    e1: p1 - p0,
                    e2: p2 - p0,
                    id,
                }));
                tri_normals.push([n0, n1, n2]);
            }
        }
        let triangle_count = prims.len() - segment_count;
        let bvh = Bvh::build(&bounds);
        let prims = bvh.order().iter().map(|&i| prims[i as usize]).collect();
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
            base_color: material.base_color,
            vertex_colors,
            hair_center,
            background: scene.background,
            bvh,
            prims,
            tri_normals,
            segment_count,
            triangle_count,
            strand_width,
            build_seconds: start.elapsed().as_secs_f64(),
        })
    }

    /// Number of strand segments traced.
    pub fn segment_count(&self) -> usize {
        self.segment_count
    }

    /// Number of head triangles traced.
    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    /// The strand width mode in effect ([`StrandWidth::Auto`] resolved).
    pub fn strand_width(&self) -> StrandWidth {
        self.strand_width
    }

    /// Seconds spent building the BVH and the primitive arrays.
    pub fn build_seconds(&self) -> f64 {
        self.build_seconds
    }

    /// The settings.
    pub fn settings(&self) -> &TraceSettings {
        &self.settings
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
            let v = self.sample(&ray, key, &mut ao_points, rays);
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
        let hit = self.bvh.nearest(ray, |pos, ray| match &self.prims[pos] {
            Prim::Segment(seg) => {
                let (t, s) = seg.intersect(ray)?;
                (hash_unit(key, pos as u64) < seg.alpha_at(s))
                    .then_some((t, HitKind::Segment { seg: *seg, s }))
            }
            Prim::Triangle(tri) => intersect_triangle(ray, tri.v0, tri.e1, tri.e2).map(|h| {
                (
                    h.t,
                    HitKind::Triangle {
                        tri: *tri,
                        u: h.u,
                        v: h.v,
                    },
                )
            }),
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
        let want_ao = aov == Aov::Ao || (aov == Aov::Color && self.settings.ambient > 0.0);
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
                    self.ambient_occlusion(p, n, origin, ao_points, rays)
                } else {
                    1.0
                };
                let base = self.vertex_colors.as_ref().map_or(self.base_color, |c| {
                    let (i, j) = (seg.vertex as usize, seg.vertex as usize + 1);
                    c[i] + (c[j] - c[i]) * s
                });
                let mut color = Vec3::splat(self.settings.ambient) * base * ao;
                let (mut vis_sum, mut weight) = (0.0, 0.0);
                for &(l, radiance) in &self.lights {
                    let vis = if want_shadow && self.settings.shadows {
                        *rays += 1;
                        self.transmittance(&Ray::new(p, l, 0.0, f32::INFINITY), origin)
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
            HitKind::Triangle { tri, u, v: bv } => {
                let p = ray.at(t);
                let geo = tri.e1.cross(tri.e2).normalize_or(v);
                let geo = if geo.dot(v) < 0.0 { -geo } else { geo };
                let [n0, n1, n2] = self.tri_normals[tri.id as usize];
                let interp = (n0 * (1.0 - u - bv) + n1 * u + n2 * bv).normalize_or(geo);
                // Two-sided, like the GPU's head pass: face the viewer.
                let n = if interp.dot(v) < 0.0 { -interp } else { interp };
                let eps = 1e-4 * (1.0 + p.abs().max_element());
                let start = p + geo * eps;
                let origin = Origin::Triangle(tri.id);
                let ao = if want_ao {
                    self.ambient_occlusion(start, geo, origin, ao_points, rays)
                } else {
                    1.0
                };
                let mut light = Vec3::splat(self.settings.ambient) * ao;
                let (mut vis_sum, mut weight) = (0.0, 0.0);
                for &(l, radiance) in &self.lights {
                    let n_dot_l = n.dot(l).max(0.0);
                    let vis = if want_shadow && self.settings.shadows && n_dot_l > 0.0 {
                        *rays += 1;
                        self.transmittance(&Ray::new(start, l, 0.0, f32::INFINITY), origin)
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
        rays: &mut u64,
    ) -> f32 {
        let mut sum = 0.0;
        let mut count = 0;
        for (u0, u1) in points {
            let dir = cosine_hemisphere(n, u0, u1);
            sum += self.transmittance(&Ray::new(p, dir, 0.0, self.settings.ao_radius), origin);
            count += 1;
        }
        *rays += count;
        if count == 0 { 1.0 } else { sum / count as f32 }
    }

    /// The fraction of light that gets through along `ray`: the product of `1 - alpha` over the
    /// strands it enters, 0 at any triangle (the head is opaque).
    fn transmittance(&self, ray: &Ray, origin: Origin) -> f32 {
        let mut left = 1.0f32;
        self.bvh.for_each_hit(ray, |pos| {
            let prim = &self.prims[pos];
            if origin.skips(prim) {
                return Visit::Continue;
            }
            match prim {
                Prim::Segment(seg) => {
                    if let Some((_, s)) = seg.intersect(ray) {
                        left *= 1.0 - seg.alpha_at(s).clamp(0.0, 1.0);
                    }
                }
                Prim::Triangle(tri) => {
                    if intersect_triangle(ray, tri.v0, tri.e1, tri.e2).is_some() {
                        left = 0.0;
                    }
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

/// The segments of `hair` with their radii and alphas (see the crate docs, "Strands"), and the
/// width mode used.
fn strand_segments(
    hair: &HairAsset,
    camera: &PinholeCamera,
    gpu: GpuStrands,
    settings: &TraceSettings,
    material_thickness: Option<f32>,
) -> (Vec<Segment>, StrandWidth) {
    let thickness = hair.thickness();
    let has_thickness =
        material_thickness.is_some() || thickness.is_some_and(|t| t.iter().any(|&x| x > 0.0));
    let mode = match settings.width {
        StrandWidth::Auto | StrandWidth::Thickness if has_thickness => StrandWidth::Thickness,
        StrandWidth::Auto | StrandWidth::Thickness => StrandWidth::Screen,
        StrandWidth::Screen => StrandWidth::Screen,
    };
    let max_thickness = thickness.map_or(0.0, |t| t.iter().copied().fold(0.0, f32::max));
    let width_px = settings.width_px.unwrap_or(gpu.width_px * 0.5);
    let transparency = hair.transparency();
    let positions = hair.positions();
    let per_vertex = |i: usize| -> (f32, f32) {
        let opacity = gpu.alpha * transparency.map_or(1.0, |t| (1.0 - t[i]).clamp(0.0, 1.0));
        let thick = thickness.map_or(0.0, |t| t[i]);
        match mode {
            StrandWidth::Thickness => (0.5 * material_thickness.unwrap_or(thick), opacity),
            _ => {
                let depth = (positions[i] - camera.eye).dot(camera.forward);
                let wpp = camera.world_per_pixel(depth);
                let fade = match gpu.thickness_fade {
                    ThicknessFade::Tip if max_thickness > 0.0 => tip_fade(thick, max_thickness),
                    ThicknessFade::Projected if thickness.is_some() => {
                        tip_fade(thick / wpp, gpu.width_px)
                    }
                    _ => 1.0,
                };
                (0.5 * width_px * wpp, opacity * fade)
            }
        }
    };
    let attrs: Vec<(f32, f32)> = (0..positions.len())
        .into_par_iter()
        .map(per_vertex)
        .collect();
    let mut segments = Vec::with_capacity(hair.segment_count());
    for strand in 0..hair.strand_count() {
        let range = hair.strand_range(strand);
        for i in range.start..range.end.saturating_sub(1) {
            let (r0, a0) = attrs[i];
            let (r1, a1) = attrs[i + 1];
            segments.push(Segment {
                a: positions[i],
                b: positions[i + 1],
                radius: [r0, r1],
                alpha: [a0, a1],
                strand: strand as u32,
                vertex: i as u32,
            });
        }
    }
    (segments, mode)
}

#[cfg(test)]
mod tests;
