//! From a scene to the tracer's primitives: the GPU settings it follows, the camera, strand
//! segments with their radii and alphas, head triangles, and the BVH references over them.

use glam::{DMat4, DVec3, Vec3};
use rayon::prelude::*;
use serde::Deserialize;
use tress_hair::HairAsset;
use tress_hair::generate::TriMesh;
use tress_scene::{HeadSource, Scene};
use tress_shading::tip_fade;

use crate::geometry::{Ray, closest_segment_param, intersect_capsule};
use crate::{StrandWidth, TraceError, TraceSettings};
use tress_hair::Aabb;

/// Subdivisions of the generated head's mesh, as `tress_render::scene_setup` draws it.
pub const HEAD_SUBDIVISIONS: u32 = 64;
/// Long segments are referenced by the BVH in pieces no longer than the hair's bounding-box
/// diagonal over this (see [`Primitives::build`]).
const PIECES_PER_DIAGONAL: f32 = 128.0;
/// At most this many pieces per segment.
const MAX_PIECES: u32 = 4;
/// Flag of a BVH reference to a triangle.
pub(super) const TRIANGLE: u32 = 1 << 31;

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
pub(super) enum Shading {
    KajiyaKay,
    Scheuermann,
    /// Physically based: the path tracer with Chiang et al. 2016's fibres ([`super::path`]).
    Marschner,
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
pub(super) struct GpuStrands {
    width_px: f32,
    alpha: f32,
    pub(super) shading: Shading,
    thickness_fade: ThicknessFade,
}

impl GpuStrands {
    pub(super) fn from_scene(scene: &Scene) -> Result<GpuStrands, TraceError> {
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
            "marschner" => Shading::Marschner,
            s => {
                return invalid(format!(
                    "strands.shading: unknown shading `{s}` (expected kajiya-kay, scheuermann or \
                     marschner)"
                ));
            }
        };
        // The patches follow their own key: `patches.shading = "marschner"` with the patches
        // technique traces the physically based reference too.
        let patches_marschner = scene.technique == "patches"
            && scene.patches.get("shading").and_then(|v| v.as_str()) == Some("marschner");
        let shading = if patches_marschner {
            Shading::Marschner
        } else {
            shading
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
            HeadSource::Generated(_) => {
                // One head per generated character, as on the GPU.
                let heads = scene.generated_heads();
                let mut meshes = Vec::with_capacity(heads.len());
                for g in &heads {
                    g.head.validate()?;
                    meshes.push(g.mesh(HEAD_SUBDIVISIONS));
                }
                TriMesh::merge(&meshes)
            }
        };
        Ok(SceneGeometry { hair, head })
    }
}

/// A pinhole camera matching the GPU's `look_at_rh` + `perspective_rh`: pixel `(x, y)` (origin
/// top-left, `y` down, centres at half-integers) looks through NDC `(2x/w - 1, 1 - 2y/h)`. Made
/// from the scene's `[camera]`, or from any view and projection matrix pair
/// ([`PinholeCamera::from_matrices`]), whose rays go through the same NDC.
#[derive(Clone, Copy, Debug)]
pub(super) struct PinholeCamera {
    pub(super) width: u32,
    pub(super) height: u32,
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_y: f32,
    aspect: f32,
    near: f32,
    far: f32,
    /// With a matrix camera: world-from-clip, rays unproject NDC points at depth 0 and 1.
    world_from_clip: Option<DMat4>,
    /// With a matrix camera: orthographic (constant world units per pixel).
    orthographic: bool,
}

impl PinholeCamera {
    pub(super) fn new(scene: &Scene) -> PinholeCamera {
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
            world_from_clip: None,
            orthographic: false,
        }
    }

    /// A camera from a view (world to view, OpenGL axes) and projection (view to wgpu clip,
    /// depth in `[0, 1]`) matrix pair, as the GPU's `Camera` takes them: any perspective or
    /// orthographic projection, off-centre and skewed ones included. The strand width's world
    /// units per pixel use the projection's vertical scale (`2 / (P₁₁ · height)`, times the
    /// depth for a perspective projection).
    pub(super) fn from_matrices(camera: &crate::ViewCamera) -> Result<PinholeCamera, TraceError> {
        let view = camera.view_from_world.as_dmat4();
        let proj = camera.clip_from_view.as_dmat4();
        let clip_from_world = proj * view;
        let det = clip_from_world.determinant();
        let invertible = det.is_finite() && det.abs() > 1e-30 && proj.is_finite();
        if !invertible {
            return Err(TraceError::Invalid(
                "camera matrices must be finite and invertible".into(),
            ));
        }
        if camera.width == 0 || camera.height == 0 {
            return Err(TraceError::Invalid(
                "camera width and height must be at least 1".into(),
            ));
        }
        let world_from_view = view.inverse();
        let forward = world_from_view
            .transform_vector3(DVec3::NEG_Z)
            .normalize()
            .as_vec3();
        let up = world_from_view
            .transform_vector3(DVec3::Y)
            .normalize()
            .as_vec3();
        let right = forward.cross(up).normalize();
        // wgpu's perspective: row z = (0, 0, r, r·near), row w = (0, 0, -1, 0).
        let orthographic = proj.w_axis.w != 0.0 && proj.z_axis.w == 0.0;
        let near = if orthographic || proj.z_axis.z == 0.0 {
            0.0
        } else {
            (proj.w_axis.z / proj.z_axis.z) as f32
        };
        Ok(PinholeCamera {
            width: camera.width,
            height: camera.height,
            eye: world_from_view.w_axis.truncate().as_vec3(),
            forward,
            right,
            up,
            tan_half_y: (1.0 / proj.y_axis.y.abs()) as f32,
            aspect: camera.width as f32 / camera.height as f32,
            near: near.max(0.0),
            far: f32::INFINITY,
            world_from_clip: Some(clip_from_world.inverse()),
            orthographic,
        })
    }

    /// The ray through film point `(x, y)` in pixels, clipped to the near and far planes.
    pub(super) fn ray(&self, x: f32, y: f32) -> Ray {
        let ndc_x = 2.0 * x / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * y / self.height as f32;
        if let Some(m) = self.world_from_clip {
            let (nx, ny) = (f64::from(ndc_x), f64::from(ndc_y));
            let a = m.project_point3(DVec3::new(nx, ny, 0.0));
            let b = m.project_point3(DVec3::new(nx, ny, 1.0));
            let d = b - a;
            let len = d.length();
            return Ray::new(a.as_vec3(), (d / len).as_vec3(), 0.0, len as f32);
        }
        let d = self.forward
            + self.right * (ndc_x * self.tan_half_y * self.aspect)
            + self.up * (ndc_y * self.tan_half_y);
        let len = d.length();
        Ray::new(self.eye, d / len, self.near * len, self.far * len)
    }

    /// World units per pixel at view depth `depth`.
    pub(super) fn world_per_pixel(&self, depth: f32) -> f32 {
        if self.orthographic {
            return 2.0 * self.tan_half_y / self.height as f32;
        }
        2.0 * self.tan_half_y * depth.max(self.near) / self.height as f32
    }
}

/// A strand segment as the tracer stores it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Segment {
    pub(super) a: Vec3,
    pub(super) b: Vec3,
    radius: [f32; 2],
    alpha: [f32; 2],
    pub(super) strand: u32,
    /// Index of the first vertex (neighbouring segments of a strand differ by one).
    pub(super) vertex: u32,
    /// Whether this is the strand's first segment (the only one whose `a` cap counts).
    first: bool,
    /// Whether this is the strand's last segment (the only one whose `b` cap counts).
    last: bool,
}

impl Segment {
    /// The ray's entry into the segment's capsule: distance and axial parameter.
    ///
    /// Caps count only at the strand's root and tip. At a joint between two segments the
    /// shared sphere lies inside the two bodies for a straight strand, so a ray entering it
    /// has already entered a body: counting the cap too would cross the strand twice (and
    /// darken every joint of a translucent strand). At a bend this leaves a wedge of the sphere
    /// uncovered on the outer side, `r · θ` wide for a bend of `θ`, far below a pixel for hair.
    #[inline]
    pub(super) fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        let s = closest_segment_param(ray, self.a, self.b);
        let r = self.radius[0] + (self.radius[1] - self.radius[0]) * s;
        // Cheap rejection: the segment's closest point is farther than r from the ray's line.
        // (The perpendicular part itself, not |q|² - along²: see `intersect_capsule`.)
        let q = self.a + (self.b - self.a) * s - ray.origin;
        let perp = q - q.dot(ray.dir) * ray.dir;
        if perp.length_squared() > r * r {
            return None;
        }
        let hit = intersect_capsule(ray, self.a, self.b, r)?;
        if (hit.s <= 0.0 && !self.first) || (hit.s >= 1.0 && !self.last) {
            return None;
        }
        Some((hit.t, hit.s))
    }

    /// Alpha at axial parameter `s`.
    pub(super) fn alpha_at(&self, s: f32) -> f32 {
        self.alpha[0] + (self.alpha[1] - self.alpha[0]) * s
    }
}

/// A triangle as the tracer stores it: a corner, the two edges from it, and its normals.
#[derive(Clone, Copy, Debug)]
pub(super) struct Triangle {
    pub(super) v0: Vec3,
    pub(super) e1: Vec3,
    pub(super) e2: Vec3,
    pub(super) normals: [Vec3; 3],
}

/// A BVH reference: a piece `[s0, s1)` of a segment (the last piece includes `s1 = 1`), or a
/// triangle (`id` with [`TRIANGLE`] set).
#[derive(Clone, Copy, Debug)]
pub(super) struct Ref {
    pub(super) id: u32,
    s0: f32,
    s1: f32,
}

impl Ref {
    /// Whether a hit at axial parameter `s` of the segment belongs to this piece.
    #[inline]
    pub(super) fn owns(&self, s: f32) -> bool {
        s >= self.s0 && (s < self.s1 || self.s1 >= 1.0)
    }
}

/// Every primitive of a scene and the BVH references to them, in leaf order.
#[derive(Debug)]
pub(super) struct Primitives {
    pub(super) segments: Vec<Segment>,
    pub(super) triangles: Vec<Triangle>,
    pub(super) refs: Vec<Ref>,
    pub(super) bvh: crate::bvh::Bvh,
    pub(super) strand_width: StrandWidth,
}

impl Primitives {
    /// Segments and triangles of `geometry` and a BVH over them.
    ///
    /// Thin strand segments are poorly bounded by boxes (a diagonal segment's box is mostly
    /// empty), which makes shadow and AO rays through hair test many segments they miss. Long
    /// segments are therefore referenced in pieces (up to [`MAX_PIECES`], each at most the hair's
    /// diagonal over [`PIECES_PER_DIAGONAL`] long), each with the box of its part of the
    /// capsule; a piece only reports hits whose axial parameter falls in its range, so every
    /// crossing is counted once.
    pub(super) fn build(
        geometry: &SceneGeometry,
        camera: &PinholeCamera,
        gpu: GpuStrands,
        settings: &TraceSettings,
        material_thickness: Option<f32>,
    ) -> Result<Primitives, TraceError> {
        let mut refs = Vec::new();
        let mut bounds = Vec::new();
        let (segments, strand_width) = match &geometry.hair {
            Some(hair) => strand_segments(hair, camera, gpu, settings, material_thickness),
            None => (Vec::new(), settings.width),
        };
        if u32::try_from(segments.len()).map_or(true, |n| n >= TRIANGLE) {
            return Err(TraceError::Invalid("too many strand segments".into()));
        }
        let piece_len = geometry
            .hair
            .as_ref()
            .map_or(1.0, |h| h.bounds().size().length() / PIECES_PER_DIAGONAL)
            .max(f32::MIN_POSITIVE);
        for (id, s) in segments.iter().enumerate() {
            let e = s.b - s.a;
            let r = Vec3::splat(s.radius[0].max(s.radius[1]));
            let pieces = ((e.length() / piece_len).ceil() as u32).clamp(1, MAX_PIECES);
            for k in 0..pieces {
                let s0 = k as f32 / pieces as f32;
                let s1 = (k + 1) as f32 / pieces as f32;
                let (p0, p1) = (s.a + e * s0, s.a + e * s1);
                bounds.push(Aabb {
                    min: p0.min(p1) - r,
                    max: p0.max(p1) + r,
                });
                refs.push(Ref {
                    id: id as u32,
                    s0,
                    s1,
                });
            }
        }
        let mut triangles = Vec::new();
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
                    .ok()
                    .filter(|&i| i < TRIANGLE)
                    .ok_or_else(|| TraceError::Invalid("head mesh: too many triangles".into()))?;
                bounds.push(Aabb::EMPTY.grow(p0).grow(p1).grow(p2));
                refs.push(Ref {
                    id: id | TRIANGLE,
                    s0: 0.0,
                    s1: 1.0,
                });
                triangles.push(Triangle {
                    v0: p0,
                    e1: p1 - p0,
                    e2: p2 - p0,
                    normals: [n0, n1, n2],
                });
            }
        }
        // Median splits: 1.6-2x faster than SAH on strands, measured (tress_hair::bvh docs).
        let bvh = crate::bvh::Bvh::build(&bounds, crate::bvh::Split::Median);
        let refs = bvh.order().iter().map(|&i| refs[i as usize]).collect();
        Ok(Primitives {
            segments,
            triangles,
            refs,
            bvh,
            strand_width,
        })
    }
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
    // Physically based fibres are opaque: their transmission is the BSDF's.
    let opaque = gpu.shading == Shading::Marschner;
    let per_vertex = |i: usize| -> (f32, f32) {
        let opacity = if opaque {
            1.0
        } else {
            gpu.alpha * transparency.map_or(1.0, |t| (1.0 - t[i]).clamp(0.0, 1.0))
        };
        let thick = thickness.map_or(0.0, |t| t[i]);
        match mode {
            StrandWidth::Thickness => (0.5 * material_thickness.unwrap_or(thick), opacity),
            _ => {
                let depth = (positions[i] - camera.eye).dot(camera.forward);
                let wpp = camera.world_per_pixel(depth);
                let fade = match gpu.thickness_fade {
                    _ if opaque => 1.0,
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
                first: i == range.start,
                last: i + 2 == range.end,
            });
        }
    }
    (segments, mode)
}
