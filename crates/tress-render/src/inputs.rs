//! Plain frame inputs: camera, lights, material. The application (or the CLI, from a scene file)
//! fills these; the renderer turns them into uniforms.

use glam::{Mat4, Vec3};

use crate::RenderError;
use crate::gpu::types::{
    self, CameraUniform, DualScatteringGpu, HairLightingGpu, LightUniform, LightsUniform,
    MaterialUniform,
};

/// A camera: view and projection matrices and the viewport they render to.
///
/// Projections use wgpu's clip space (depth 0 near, 1 far), e.g. `Mat4::perspective_rh`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// View from world (a rigid transform).
    pub view_from_world: Mat4,
    /// Clip from view (projection).
    pub clip_from_view: Mat4,
    /// Viewport size in pixels; must match the targets.
    pub viewport: [u32; 2],
}

impl Camera {
    /// A perspective camera at `eye` looking at `target`, vertical field of view `fov_y`
    /// (radians), right-handed, `near`/`far` clip distances.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        near: f32,
        far: f32,
        viewport: [u32; 2],
    ) -> Self {
        let aspect = viewport[0].max(1) as f32 / viewport[1].max(1) as f32;
        Camera {
            view_from_world: Mat4::look_at_rh(eye, target, up),
            clip_from_view: Mat4::perspective_rh(fov_y, aspect, near, far),
            viewport,
        }
    }

    /// Clip from world.
    pub fn clip_from_world(&self) -> Mat4 {
        self.clip_from_view * self.view_from_world
    }

    /// Eye position in world space.
    pub fn eye(&self) -> Vec3 {
        self.view_from_world.inverse().transform_point3(Vec3::ZERO)
    }

    /// Unit view direction in world space.
    pub fn forward(&self) -> Vec3 {
        self.view_from_world
            .inverse()
            .transform_vector3(Vec3::NEG_Z)
            .normalize_or(Vec3::NEG_Z)
    }

    /// Whether the projection is orthographic (no perspective divide).
    pub fn is_orthographic(&self) -> bool {
        self.clip_from_view.w_axis.w != 0.0 && self.clip_from_view.z_axis.w == 0.0
    }

    /// Check the camera is usable: finite invertible matrices, non-empty viewport.
    pub fn validate(&self) -> Result<(), RenderError> {
        let m = self.clip_from_world();
        if !m.is_finite() || m.determinant().abs() < 1e-30 {
            return Err(RenderError::Invalid(
                "camera matrices are not finite and invertible".into(),
            ));
        }
        if self.viewport[0] == 0 || self.viewport[1] == 0 {
            return Err(RenderError::Invalid("camera viewport is empty".into()));
        }
        Ok(())
    }

    /// The GPU uniform.
    pub fn uniform(&self) -> CameraUniform {
        let vp = [self.viewport[0] as f32, self.viewport[1] as f32];
        CameraUniform {
            clip_from_world: types::mat4(self.clip_from_world()),
            eye: self.eye().to_array(),
            pixels_per_unit: self.clip_from_view.y_axis.y.abs() * vp[1] * 0.5,
            viewport: vp,
            orthographic: u32::from(self.is_orthographic()),
            _pad0: 0,
            forward: self.forward().to_array(),
            _pad1: 0.0,
        }
    }
}

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Direction the light travels (from the light into the scene); need not be unit length.
    pub direction: Vec3,
    /// Linear RGB color.
    pub color: Vec3,
    /// Multiplier of `color`.
    pub intensity: f32,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        DirectionalLight {
            direction: Vec3::new(-0.4, -0.6, -0.7),
            color: Vec3::ONE,
            intensity: 2.0,
        }
    }
}

impl DirectionalLight {
    /// Unit vector from the scene towards the light, or an error for a zero/non-finite direction.
    pub fn to_light(&self) -> Result<Vec3, RenderError> {
        (-self.direction)
            .try_normalize()
            .ok_or_else(|| RenderError::Invalid("light direction is zero or not finite".into()))
    }

    /// The light's orthographic shadow camera around a bounding sphere (`center`, `radius`) for a
    /// square map of `size` texels: returns the camera and the world length of its depth range.
    pub fn shadow_camera(
        &self,
        center: Vec3,
        radius: f32,
        size: u32,
    ) -> Result<(Camera, f32), RenderError> {
        let l = self.to_light()?;
        let r = radius.max(1e-4);
        let up = if l.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let camera = Camera {
            view_from_world: Mat4::look_at_rh(center + l * (2.0 * r), center, up),
            clip_from_view: Mat4::orthographic_rh(-r, r, -r, r, r, 3.0 * r),
            viewport: [size, size],
        };
        Ok((camera, 2.0 * r))
    }

    /// The GPU uniform given its shadow projection.
    pub fn uniform(
        &self,
        light_from_world: Mat4,
        depth_range: f32,
    ) -> Result<LightUniform, RenderError> {
        Ok(LightUniform {
            light_from_world: types::mat4(light_from_world),
            to_light: self.to_light()?.to_array(),
            intensity: self.intensity,
            color: self.color.to_array(),
            depth_range,
        })
    }
}

/// What every technique's frame inputs share ([`crate::FrameInputs`],
/// [`crate::PatchFrameInputs`], [`crate::SatfFrameInputs`]): the camera, the lights, the ambient
/// light, the opaque head and the clear colour.
#[derive(Clone, Copy, Debug)]
pub struct SharedInputs<'a> {
    /// The camera; its viewport must equal the targets' size.
    pub camera: Camera,
    /// Directional lights (at most [`crate::MAX_LIGHTS`]).
    pub lights: &'a [DirectionalLight],
    /// Ambient light, linear RGB.
    pub ambient: Vec3,
    /// The opaque head mesh, drawn first with depth writes, if any (several characters' heads
    /// and bodies in one mesh).
    pub head: Option<&'a crate::HeadGeometry>,
    /// Clear color and depth first (linear RGBA), or `None` to draw over what the targets hold.
    pub clear: Option<wgpu::Color>,
}

/// Hair and head material. Kajiya-Kay uses `base_color` as `K_d` and the primary highlight as
/// `K_s` and `p`; Scheuermann's dual highlight uses all of it (`tress_shading::HairLighting` with a
/// white diffuse multiplier and `base_color` as the base).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Hair base (diffuse) color, linear RGB.
    pub base_color: Vec3,
    /// Primary highlight color.
    pub primary_color: Vec3,
    /// Primary highlight exponent.
    pub primary_exponent: f32,
    /// Primary tangent shift (negative: towards the tip).
    pub primary_shift: f32,
    /// Secondary highlight color.
    pub secondary_color: Vec3,
    /// Secondary highlight exponent.
    pub secondary_exponent: f32,
    /// Secondary tangent shift (positive: towards the root).
    pub secondary_shift: f32,
    /// Head mesh color, linear RGB.
    pub head_color: Vec3,
    /// The physically based fibre (`strands.shading = "marschner"`).
    pub fiber: tress_shading::fiber::HairFiber,
}

impl Default for Material {
    fn default() -> Self {
        let h = tress_shading::HairLighting::default();
        Material {
            base_color: Vec3::new(0.30, 0.20, 0.12),
            primary_color: h.primary_color,
            primary_exponent: h.primary_exponent,
            primary_shift: h.primary_shift,
            secondary_color: h.secondary_color,
            secondary_exponent: h.secondary_exponent,
            secondary_shift: h.secondary_shift,
            head_color: Vec3::new(0.55, 0.40, 0.33),
            fiber: tress_shading::fiber::HairFiber::default(),
        }
    }
}

impl Material {
    /// Check for finite colors and positive exponents.
    pub fn validate(&self) -> Result<(), RenderError> {
        let colors = [
            self.base_color,
            self.primary_color,
            self.secondary_color,
            self.head_color,
        ];
        let ok = colors.iter().all(|c| c.is_finite())
            && self.primary_exponent > 0.0
            && self.secondary_exponent > 0.0
            && self.primary_shift.is_finite()
            && self.secondary_shift.is_finite();
        if !ok {
            return Err(RenderError::Invalid(
                "material colors and shifts must be finite, exponents positive".into(),
            ));
        }
        self.fiber
            .validate()
            .map_err(|e| RenderError::setting("material fibre", e))
    }

    /// Scheuermann's two shifted highlights of this material, with a white diffuse multiplier
    /// (`base_color` is the base).
    pub fn hair_lighting(&self) -> tress_shading::HairLighting {
        tress_shading::HairLighting {
            diffuse_color: Vec3::ONE,
            primary_exponent: self.primary_exponent,
            primary_color: self.primary_color,
            primary_shift: self.primary_shift,
            secondary_color: self.secondary_color,
            secondary_exponent: self.secondary_exponent,
            secondary_shift: self.secondary_shift,
        }
    }

    /// The GPU uniform.
    pub fn uniform(&self) -> MaterialUniform {
        MaterialUniform {
            lighting: HairLightingGpu {
                diffuse_color: [1.0; 3],
                primary_exponent: self.primary_exponent,
                primary_color: self.primary_color.to_array(),
                primary_shift: self.primary_shift,
                secondary_color: self.secondary_color.to_array(),
                secondary_exponent: self.secondary_exponent,
                secondary_shift: self.secondary_shift,
                _pad: [0.0; 3],
            },
            base_color: self.base_color.to_array(),
            _pad0: 0.0,
            head_color: self.head_color.to_array(),
            _pad1: 0.0,
            fiber: [[0.0; 4]; 2],
            dual: DualScatteringGpu::default(),
        }
    }
}

/// The sphere around what a frame draws (the hair or cards, and the head), if anything.
pub(crate) fn frame_sphere(a: Option<(Vec3, f32)>, b: Option<(Vec3, f32)>) -> Option<(Vec3, f32)> {
    match (a, b) {
        (Some(a), Some(b)) => Some(union_sphere(a, b)),
        (a, b) => a.or(b),
    }
}

/// At most [`crate::MAX_LIGHTS`] lights, or the error every renderer gives.
pub(crate) fn check_light_count(lights: usize) -> Result<(), RenderError> {
    if lights > crate::MAX_LIGHTS {
        return Err(RenderError::Invalid(format!(
            "{lights} lights given, at most {} supported",
            crate::MAX_LIGHTS
        )));
    }
    Ok(())
}

/// A frame's lights uniform: `ambient` and `lights` (at most [`crate::MAX_LIGHTS`]). With
/// `shadows = Some((sphere, size))` each light gets the shadow camera that frames `sphere` (the
/// unit sphere at the origin without one) in a `size`² map, whose uniforms are returned beside;
/// without, the lights carry no shadow transform (and no cameras are returned). The one place
/// every renderer fills `struct Lights` from.
pub(crate) fn lights_uniform(
    ambient: Vec3,
    lights: &[DirectionalLight],
    shadows: Option<(Option<(Vec3, f32)>, u32)>,
) -> Result<(LightsUniform, Vec<CameraUniform>), RenderError> {
    check_light_count(lights.len())?;
    let mut uniform = LightsUniform {
        ambient: ambient.to_array(),
        count: lights.len() as u32,
        ..Default::default()
    };
    let mut cameras = Vec::new();
    for (i, light) in lights.iter().enumerate() {
        uniform.lights[i] = match shadows {
            Some((sphere, size)) => {
                let (center, radius) = sphere.unwrap_or((Vec3::ZERO, 1.0));
                let (cam, range) = light.shadow_camera(center, radius, size)?;
                cameras.push(cam.uniform());
                light.uniform(cam.clip_from_world(), range)?
            }
            None => light.uniform(Mat4::IDENTITY, 1.0)?,
        };
    }
    Ok((uniform, cameras))
}

/// The sphere around two spheres (centre, radius).
pub(crate) fn union_sphere(a: (Vec3, f32), b: (Vec3, f32)) -> (Vec3, f32) {
    let d = a.0.distance(b.0);
    if d + b.1 <= a.1 {
        return a;
    }
    if d + a.1 <= b.1 {
        return b;
    }
    let r = (d + a.1 + b.1) * 0.5;
    (a.0 + (b.0 - a.0) / d * (r - a.1), r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_eye_forward_and_pixel_scale() {
        let cam = Camera::look_at(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            90f32.to_radians(),
            0.1,
            100.0,
            [200, 100],
        );
        assert!((cam.eye() - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-5);
        assert!((cam.forward() - Vec3::NEG_Z).length() < 1e-5);
        assert!(!cam.is_orthographic());
        let u = cam.uniform();
        // fov 90°: at distance 1 the half height (1 unit) spans 50 px.
        assert!((u.pixels_per_unit - 50.0).abs() < 1e-3);
        assert!(cam.validate().is_ok());
        let bad = Camera {
            viewport: [0, 10],
            ..cam
        };
        assert!(bad.validate().is_err());
    }

    #[test]
    fn frame_lights_count_shadow_cameras_and_reject_too_many() {
        let light = DirectionalLight {
            direction: Vec3::new(0.0, -1.0, -1.0),
            color: Vec3::ONE,
            intensity: 2.0,
        };
        let sphere = Some((Vec3::new(1.0, 2.0, 3.0), 4.0));
        let (u, cams) = lights_uniform(Vec3::splat(0.1), &[light; 2], Some((sphere, 256))).unwrap();
        assert_eq!((u.count, u.ambient, cams.len()), (2, [0.1; 3], 2));
        // The shadow camera looks at the sphere's centre: it projects to the map's middle.
        let clip = Mat4::from_cols_array_2d(&u.lights[0].light_from_world)
            * Vec3::new(1.0, 2.0, 3.0).extend(1.0);
        assert!(clip.x.abs() < 1e-4 && clip.y.abs() < 1e-4, "{clip}");
        let (u, cams) = lights_uniform(Vec3::ZERO, &[light], None).unwrap();
        assert_eq!((u.count, cams.len()), (1, 0));
        assert_eq!(u.lights[0].light_from_world, types::mat4(Mat4::IDENTITY));
        let err = lights_uniform(Vec3::ZERO, &[light; crate::MAX_LIGHTS + 1], None).unwrap_err();
        assert!(err.to_string().contains("lights given"), "{err}");
        assert_eq!(frame_sphere(None, None), None);
        assert_eq!(frame_sphere(sphere, None), sphere);
        assert_eq!(frame_sphere(None, sphere), sphere);
    }

    #[test]
    fn union_sphere_contains_both() {
        let a = (Vec3::ZERO, 1.0);
        let b = (Vec3::new(4.0, 0.0, 0.0), 1.0);
        let (c, r) = union_sphere(a, b);
        assert!((c - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6 && (r - 3.0).abs() < 1e-6);
        assert_eq!(union_sphere(a, (Vec3::ZERO, 0.5)), a);
        assert_eq!(union_sphere((Vec3::ZERO, 0.5), a), a);
    }

    #[test]
    fn shadow_projection_maps_sphere_into_unit_depth() {
        let light = DirectionalLight {
            direction: Vec3::new(0.0, -1.0, 0.0),
            ..Default::default()
        };
        let (cam, range) = light
            .shadow_camera(Vec3::new(1.0, 2.0, 3.0), 2.0, 64)
            .unwrap();
        assert_eq!(range, 4.0);
        assert!(cam.is_orthographic());
        assert!((cam.uniform().pixels_per_unit - 16.0).abs() < 1e-4);
        let m = cam.clip_from_world();
        let top = m.project_point3(Vec3::new(1.0, 4.0, 3.0));
        let bottom = m.project_point3(Vec3::new(1.0, 0.0, 3.0));
        assert!(
            top.z.abs() < 1e-5 && (bottom.z - 1.0).abs() < 1e-5,
            "{top} {bottom}"
        );
        let zero = DirectionalLight {
            direction: Vec3::ZERO,
            ..Default::default()
        };
        assert!(zero.to_light().is_err());
    }
}
