//! The tables of a scene file: camera, lights, hair entries (source, transform, follow hairs,
//! material), head and output. Each is a serde struct that rejects unknown keys and fills absent
//! keys from its `Default`.

use std::path::PathBuf;

use glam::{Affine3A, Mat4, Quat, Vec3};
use serde::{Deserialize, Serialize};
use tress_hair::generate::{Style, StyleParams};

use crate::SceneError;
pub use crate::follow::FollowSpec;
use crate::material::Material;

/// `[camera]`: a perspective camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Camera {
    /// Eye position (world units).
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Up direction (need not be unit or perpendicular to the view direction, but not parallel).
    pub up: Vec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_deg: f32,
    /// Near clip distance (> 0).
    pub near: f32,
    /// Far clip distance (> near).
    pub far: f32,
}

impl Default for Camera {
    /// A three-quarter view from the front right of the default head (centred at the origin,
    /// 21 units tall), looking below its centre so that 30-unit hair hanging from it is in frame:
    /// eye `[32, 4, 76]`, target `[0, -10, 0]`, up `+y`, 35° vertical field of view, near 1,
    /// far 500.
    fn default() -> Self {
        Camera {
            eye: Vec3::new(32.0, 4.0, 76.0),
            target: Vec3::new(0.0, -10.0, 0.0),
            up: Vec3::Y,
            fov_y_deg: 35.0,
            near: 1.0,
            far: 500.0,
        }
    }
}

impl Camera {
    /// The right-handed view matrix (`look_at_rh`).
    pub fn view_from_world(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye, self.target, self.up)
    }

    /// The perspective projection for an image of `aspect = width / height`, right-handed with
    /// wgpu's `[0, 1]` depth range.
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_y_deg.to_radians(), aspect, self.near, self.far)
    }

    /// `clip_from_view(aspect) * view_from_world()`.
    pub fn clip_from_world(&self, aspect: f32) -> Mat4 {
        self.clip_from_view(aspect) * self.view_from_world()
    }

    pub(crate) fn validate(&self) -> Result<(), SceneError> {
        for (key, v) in [
            ("camera.eye", self.eye),
            ("camera.target", self.target),
            ("camera.up", self.up),
        ] {
            finite3(key, v)?;
        }
        let forward = self.target - self.eye;
        if forward.length_squared() == 0.0 {
            return Err(SceneError::invalid(
                "camera.target",
                "must differ from camera.eye",
            ));
        }
        if forward
            .normalize()
            .cross(self.up.normalize_or_zero())
            .length_squared()
            < 1e-12
        {
            return Err(SceneError::invalid(
                "camera.up",
                "must be non-zero and not parallel to the view direction",
            ));
        }
        if !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            return Err(SceneError::invalid(
                "camera.fov_y_deg",
                format!("must lie in (0, 180), got {}", self.fov_y_deg),
            ));
        }
        if !(self.near > 0.0 && self.near.is_finite()) {
            return Err(SceneError::invalid(
                "camera.near",
                format!("must be positive, got {}", self.near),
            ));
        }
        if !(self.far > self.near && self.far.is_finite()) {
            return Err(SceneError::invalid(
                "camera.far",
                format!(
                    "must be finite and greater than camera.near ({}), got {}",
                    self.near, self.far
                ),
            ));
        }
        Ok(())
    }
}

/// `[[light]]`: a directional light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Light {
    /// Direction from the scene *towards* the light (any non-zero length; see
    /// [`Light::to_light`]). This is the shading code's `l`.
    pub direction: Vec3,
    /// Linear RGB color (non-negative).
    pub color: Vec3,
    /// Multiplies the color (non-negative).
    pub intensity: f32,
}

impl Default for Light {
    /// White, intensity 1, from above and in front (`[0, 1, 1]`).
    fn default() -> Self {
        Light {
            direction: Vec3::new(0.0, 1.0, 1.0),
            color: Vec3::ONE,
            intensity: 1.0,
        }
    }
}

impl Light {
    /// The scene's default lights: a warm key light from the upper front right (`[0.4, 0.7,
    /// 0.6]`, color `[1, 0.97, 0.92]`, intensity 1) and a cool fill light from the front left
    /// (`[-0.6, 0.1, 0.5]`, color `[0.85, 0.9, 1]`, intensity 0.35).
    pub fn default_rig() -> Vec<Light> {
        vec![
            Light {
                direction: Vec3::new(0.4, 0.7, 0.6),
                color: Vec3::new(1.0, 0.97, 0.92),
                intensity: 1.0,
            },
            Light {
                direction: Vec3::new(-0.6, 0.1, 0.5),
                color: Vec3::new(0.85, 0.9, 1.0),
                intensity: 0.35,
            },
        ]
    }

    /// Unit vector towards the light (the shading code's `l`).
    pub fn to_light(&self) -> Vec3 {
        self.direction.normalize_or(Vec3::Y)
    }

    /// `color * intensity`.
    pub fn radiance(&self) -> Vec3 {
        self.color * self.intensity
    }

    fn validate(&self, key: &str) -> Result<(), SceneError> {
        finite3(&format!("{key}.direction"), self.direction)?;
        if self.direction.length_squared() == 0.0 {
            return Err(SceneError::invalid(
                format!("{key}.direction"),
                "must be non-zero",
            ));
        }
        color(&format!("{key}.color"), self.color)?;
        non_negative(&format!("{key}.intensity"), self.intensity)
    }
}

/// `[[hair]]`: one hair asset, read from files or generated, then transformed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HairSpec {
    /// Hair files (`.hair`, `.tfx`, `.usda`/`.usdc`/`.usdz`/`.usd`, `.abc`, `.data`, `.bin`),
    /// merged in order; relative paths are relative to the scene file's folder. Give either
    /// `files` or `generator`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<PathBuf>,
    /// A procedural style instead of files.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub generator: Option<GeneratorSpec>,
    /// Placement in the scene.
    pub transform: Transform,
    /// Follow hairs added for every strand (interpolated between guides or TressFX offsets).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub follow: Option<FollowSpec>,
    /// Fraction of the strands kept, in `(0, 1]` (a deterministic, nested subset).
    pub strand_ratio: f32,
    /// Shading parameters.
    pub material: Material,
    /// Segments per span when cubic or NURBS curves (USD, Alembic) are tessellated (1 to 64;
    /// unset: 4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cubic_segments: Option<u32>,
    /// The frame of an animated file to read (Alembic `P` samples, USD `points` time samples;
    /// 0 the first, past the last the last); unset: the first. A still file reads the same at
    /// every frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<u32>,
    /// What draws this head of hair when the scene's technique is one of the strand renderer's
    /// (`strands`, `volume`, `hybrid`, `auto`); unset: the scene's `technique`. A front end that
    /// forces one technique ([`crate::Scene::force_technique`], `tress render --technique`)
    /// clears it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub technique: Option<String>,
}

impl Default for HairSpec {
    /// No source (one must be given), identity transform, no follow hairs, every strand, the
    /// default material.
    fn default() -> Self {
        HairSpec {
            files: Vec::new(),
            generator: None,
            transform: Transform::default(),
            follow: None,
            strand_ratio: 1.0,
            material: Material::default(),
            cubic_segments: None,
            frame: None,
            technique: None,
        }
    }
}

impl HairSpec {
    pub(crate) fn validate(&self, key: &str) -> Result<(), SceneError> {
        match (self.files.is_empty(), &self.generator) {
            (true, None) => {
                return Err(SceneError::invalid(
                    key,
                    "give either `files` or `generator`",
                ));
            }
            (false, Some(_)) => {
                return Err(SceneError::invalid(
                    key,
                    "give either `files` or `generator`, not both",
                ));
            }
            (true, Some(g)) => {
                g.style_params().map_err(|e| match e {
                    SceneError::Invalid { key: k, reason } => {
                        SceneError::invalid(format!("{key}.{k}"), reason)
                    }
                    e => e,
                })?;
            }
            (false, None) => {}
        }
        self.transform.validate(&format!("{key}.transform"))?;
        if let Some(f) = &self.follow {
            f.validate(&format!("{key}.follow"))?;
        }
        if !(self.strand_ratio > 0.0 && self.strand_ratio <= 1.0) {
            return Err(SceneError::invalid(
                format!("{key}.strand_ratio"),
                format!("must lie in (0, 1], got {}", self.strand_ratio),
            ));
        }
        if let Some(n) = self.cubic_segments
            && !(1..=tress_hair::formats::curves::MAX_CUBIC_SEGMENTS).contains(&n)
        {
            return Err(SceneError::invalid(
                format!("{key}.cubic_segments"),
                format!(
                    "must be 1 to {}, got {n}",
                    tress_hair::formats::curves::MAX_CUBIC_SEGMENTS
                ),
            ));
        }
        if let Some(t) = &self.technique {
            match t.parse::<crate::TechniqueKind>() {
                Ok(kind) if kind.per_object() => {}
                Ok(kind) => {
                    return Err(SceneError::invalid(
                        format!("{key}.technique"),
                        format!(
                            "`{kind}` draws the whole scene, not one head of hair (give it as \
                             the scene's `technique`; per head of hair: strands, volume, \
                             hybrid or auto)"
                        ),
                    ));
                }
                Err(e) => {
                    return Err(SceneError::invalid(
                        format!("{key}.technique"),
                        e.to_string(),
                    ));
                }
            }
        }
        self.material.validate(&format!("{key}.material"))
    }
}

/// `generator = { style = ..., ... }`: a procedural style of [`tress_hair::generate`]. Every
/// field but `style` is optional and defaults to the style's own
/// [`Style::default_params`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorSpec {
    /// `straight`, `wavy`, `curly`, `ponytail` or `fur`.
    pub style: String,
    /// Number of strands.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strands: Option<u32>,
    /// Vertices per strand.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertices: Option<u32>,
    /// Strand length (for the ponytail, the tail below the tie).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f32>,
    /// Wave amplitude or helix radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curl_radius: Option<f32>,
    /// Waves or turns per unit of length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curl_frequency: Option<f32>,
    /// Pull towards clump centres, `[0, 1]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clumping: Option<f32>,
    /// Largest random displacement (at the tip).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<f32>,
    /// Random seed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Root diameter (tapers to a tenth at the tip).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f32>,
}

impl GeneratorSpec {
    /// A generator of `style` with every parameter at the style's default.
    pub fn new(style: Style) -> Self {
        GeneratorSpec {
            style: style.name().to_owned(),
            strands: None,
            vertices: None,
            length: None,
            curl_radius: None,
            curl_frequency: None,
            clumping: None,
            noise: None,
            seed: None,
            thickness: None,
        }
    }

    /// The style and its parameters: the style's defaults with the given fields replaced,
    /// validated by [`StyleParams::validate`].
    pub fn style_params(&self) -> Result<(Style, StyleParams), SceneError> {
        let style: Style = self.style.parse().map_err(|e: tress_hair::HairError| {
            SceneError::invalid("generator.style", e.to_string())
        })?;
        let d = style.default_params();
        let params = StyleParams {
            strands: self.strands.unwrap_or(d.strands),
            vertices: self.vertices.unwrap_or(d.vertices),
            length: self.length.unwrap_or(d.length),
            curl_radius: self.curl_radius.unwrap_or(d.curl_radius),
            curl_frequency: self.curl_frequency.unwrap_or(d.curl_frequency),
            clumping: self.clumping.unwrap_or(d.clumping),
            noise: self.noise.unwrap_or(d.noise),
            seed: self.seed.unwrap_or(d.seed),
            thickness: self.thickness.unwrap_or(d.thickness),
        };
        params
            .validate()
            .map_err(|e| SceneError::invalid("generator", e.to_string()))?;
        Ok((style, params))
    }
}

/// `transform = { translate, rotate_deg, scale }`: `world = translate + R · (scale · p)` with
/// `R = Rz · Ry · Rx`, i.e. rotations about the x, then y, then z axis (fixed axes), in degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Transform {
    /// Translation (world units).
    pub translate: Vec3,
    /// Rotation angles about x, y, z in degrees, applied in that order.
    pub rotate_deg: Vec3,
    /// Uniform scale (> 0); strand thickness is scaled with it.
    pub scale: f32,
}

impl Default for Transform {
    /// The identity: no translation, no rotation, scale 1.
    fn default() -> Self {
        Transform {
            translate: Vec3::ZERO,
            rotate_deg: Vec3::ZERO,
            scale: 1.0,
        }
    }
}

impl Transform {
    /// The rotation `Rz · Ry · Rx`.
    pub fn rotation(&self) -> Quat {
        let r = self.rotate_deg * (std::f32::consts::PI / 180.0);
        Quat::from_rotation_z(r.z) * Quat::from_rotation_y(r.y) * Quat::from_rotation_x(r.x)
    }

    /// The affine map `p ↦ translate + R · (scale · p)`.
    pub fn affine(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(
            Vec3::splat(self.scale),
            self.rotation(),
            self.translate,
        )
    }

    /// Whether this is the identity.
    pub fn is_identity(&self) -> bool {
        *self == Transform::default()
    }

    fn validate(&self, key: &str) -> Result<(), SceneError> {
        finite3(&format!("{key}.translate"), self.translate)?;
        finite3(&format!("{key}.rotate_deg"), self.rotate_deg)?;
        if !(self.scale > 0.0 && self.scale.is_finite()) {
            return Err(SceneError::invalid(
                format!("{key}.scale"),
                format!("must be finite and positive, got {}", self.scale),
            ));
        }
        Ok(())
    }
}

/// `[head]`: the head mesh drawn under the hair.
///
/// - nothing given: the generated head: the ellipsoid with a face and a neck for head hair, the
///   bare ellipsoid for fur (`shape` chooses: `"face"` or `"ellipsoid"`);
/// - `obj = "path"`: a Wavefront OBJ mesh (relative to the scene file's folder);
/// - `generated = false` (and no `obj`): no head.
///
/// `center` and `radii` shape the generated head; absent, they are those of the ellipsoid the
/// first generated hair entry grows from ([`tress_hair::generate::head_for`]), or of the default
/// head when no entry is generated. Every generated hair entry grows on a generated head of its
/// own, placed by the entry's `transform`, so it moves with its hair (and so do the cards and
/// SATF clusters generated on the first one); a mesh given by `obj` is in world space, and meshes
/// that came in USD hair files move with their entry's transform.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HeadSpec {
    /// A head or body mesh file: OBJ, glTF (`.gltf`, `.glb`) or USD (its `Mesh` prims). The key
    /// is `obj` or `mesh`.
    #[serde(skip_serializing_if = "Option::is_none", alias = "mesh")]
    pub obj: Option<PathBuf>,
    /// Whether to draw the generated ellipsoid head (default: when no `obj` is given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub generated: Option<bool>,
    /// Centre of the generated head.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub center: Option<Vec3>,
    /// Semi-axes of the generated head (positive).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radii: Option<Vec3>,
    /// What the generated head is drawn as: `"face"` (the ellipsoid with a face and a neck) or
    /// `"ellipsoid"`; default: the first generated hair entry's ([`tress_hair::generate::shape_for`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<String>,
    /// `[head.motion]`: how the head moves when the hair is simulated (a preset or keyframes;
    /// see [`tress_sim::MotionSpec`]); none: it stays still.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<tress_sim::MotionSpec>,
}

impl HeadSpec {
    pub(crate) fn validate(&self) -> Result<(), SceneError> {
        if self.obj.is_some() && self.generated == Some(true) {
            return Err(SceneError::invalid(
                "head",
                "give either `obj` or `generated = true`, not both",
            ));
        }
        if let Some(c) = self.center {
            finite3("head.center", c)?;
        }
        if let Some(shape) = &self.shape {
            shape
                .parse::<tress_hair::generate::HeadShape>()
                .map_err(|e| SceneError::invalid("head.shape", e.to_string()))?;
        }
        if let Some(r) = self.radii
            && !(r.is_finite() && r.min_element() > 0.0)
        {
            return Err(SceneError::invalid(
                "head.radii",
                format!("must be finite and positive, got {r}"),
            ));
        }
        if let Some(m) = &self.motion {
            m.validate().map_err(crate::scene::sim_error)?;
        }
        Ok(())
    }
}

/// `[output]`: the rendered image.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Output {
    /// Width in pixels, `1..=16384`.
    pub width: u32,
    /// Height in pixels, `1..=16384`.
    pub height: u32,
}

impl Default for Output {
    /// 1280 × 720.
    fn default() -> Self {
        Output {
            width: 1280,
            height: 720,
        }
    }
}

impl Output {
    /// Largest accepted width or height (wgpu's usual texture limit).
    pub const MAX_SIZE: u32 = 16384;

    /// `width / height`.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    pub(crate) fn validate(&self) -> Result<(), SceneError> {
        for (key, v) in [("output.width", self.width), ("output.height", self.height)] {
            if !(1..=Self::MAX_SIZE).contains(&v) {
                return Err(SceneError::invalid(
                    key,
                    format!("must lie in 1..={}, got {v}", Self::MAX_SIZE),
                ));
            }
        }
        Ok(())
    }
}

pub(crate) fn validate_lights(lights: &[Light]) -> Result<(), SceneError> {
    lights
        .iter()
        .enumerate()
        .try_for_each(|(i, l)| l.validate(&format!("light.{i}")))
}

pub(crate) fn finite(key: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(SceneError::invalid(key, format!("must be finite, got {v}")))
    }
}

pub(crate) fn finite3(key: &str, v: Vec3) -> Result<(), SceneError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(SceneError::invalid(key, format!("must be finite, got {v}")))
    }
}

pub(crate) fn non_negative(key: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            key,
            format!("must be finite and non-negative, got {v}"),
        ))
    }
}

pub(crate) fn positive(key: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            key,
            format!("must be finite and positive, got {v}"),
        ))
    }
}

pub(crate) fn color(key: &str, c: Vec3) -> Result<(), SceneError> {
    if c.is_finite() && c.min_element() >= 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            key,
            format!("must be finite and non-negative, got {c}"),
        ))
    }
}
