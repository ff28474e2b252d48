//! The viewer's orbit camera: the scene camera's eye and target turned into a distance and two
//! angles about the target, changed by mouse drags and the wheel.
//!
//! The eye sits at `target + distance · (cos φ (cos θ f + sin θ r) + sin φ u)`, with `u` the
//! scene camera's up axis, `f` the initial view offset projected onto the plane normal to `u`
//! (so the first frame is exactly the scene's camera), `r = u × f`, `θ` the yaw about `u` and
//! `φ` the pitch above the plane, kept short of the poles so the view never flips. The near and
//! far planes move with the distance, so what the scene's planes enclosed stays enclosed.

use glam::Vec3;
use tress_render::Camera;

/// Radians of yaw or pitch per pixel of drag.
pub const RADIANS_PER_PIXEL: f32 = 0.01;

/// Distance factor per wheel line: one line towards the target brings the eye 10 % closer.
pub const ZOOM_PER_LINE: f32 = 0.9;

/// Largest pitch, just short of the pole (radians).
const MAX_PITCH: f32 = std::f32::consts::FRAC_PI_2 - 0.01;

/// An orbit about a target point (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point orbited and looked at.
    pub target: Vec3,
    /// Eye distance from the target.
    pub distance: f32,
    /// Yaw `θ` about the up axis, radians.
    pub yaw: f32,
    /// Pitch `φ` above the plane normal to the up axis, radians.
    pub pitch: f32,
    /// Unit up axis `u`.
    up: Vec3,
    /// Unit axis `f` of zero yaw, normal to `up`.
    front: Vec3,
    /// Vertical field of view, radians.
    fov_y: f32,
    /// The scene's near and far planes and the distance they were given for.
    near0: f32,
    far0: f32,
    distance0: f32,
}

impl OrbitCamera {
    /// The orbit that reproduces a look-at camera: `eye` looking at `target` with `up`, vertical
    /// field of view `fov_y` (radians) and clip planes `near`, `far`.
    pub fn new(eye: Vec3, target: Vec3, up: Vec3, fov_y: f32, near: f32, far: f32) -> Self {
        let up = up.try_normalize().unwrap_or(Vec3::Y);
        let offset = eye - target;
        let distance = offset.length().max(1e-4);
        let dir = offset / distance;
        let pitch = dir
            .dot(up)
            .clamp(-1.0, 1.0)
            .asin()
            .clamp(-MAX_PITCH, MAX_PITCH);
        // Zero yaw points along the offset's part in the plane, or any direction in the plane
        // when the eye is straight above or below the target.
        let front = (dir - up * dir.dot(up))
            .try_normalize()
            .unwrap_or_else(|| up.any_orthonormal_vector());
        OrbitCamera {
            target,
            distance,
            yaw: 0.0,
            pitch,
            up,
            front,
            fov_y,
            near0: near,
            far0: far,
            distance0: distance,
        }
    }

    /// The orbit of a scene's camera.
    pub fn from_scene(c: &tress_scene::Camera) -> Self {
        OrbitCamera::new(
            c.eye,
            c.target,
            c.up,
            c.fov_y_deg.to_radians(),
            c.near,
            c.far,
        )
    }

    /// Unit vector from the target towards the eye.
    pub fn direction(&self) -> Vec3 {
        let right = self.up.cross(self.front);
        let (sin_th, cos_th) = self.yaw.sin_cos();
        let (sin_ph, cos_ph) = self.pitch.sin_cos();
        (self.front * cos_th + right * sin_th) * cos_ph + self.up * sin_ph
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        self.target + self.direction() * self.distance
    }

    /// The up axis.
    pub fn up(&self) -> Vec3 {
        self.up
    }

    /// The camera's right and up vectors on screen (unit, world space).
    fn screen_axes(&self) -> (Vec3, Vec3) {
        let forward = -self.direction();
        let right = forward.cross(self.up).normalize();
        (right, right.cross(forward))
    }

    /// Left drag by `(dx, dy)` pixels: dragging right turns the scene right (the eye moves left
    /// about the up axis), dragging down tilts the scene towards the viewer (the eye rises).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw = (self.yaw - dx * RADIANS_PER_PIXEL).rem_euclid(std::f32::consts::TAU);
        self.pitch = (self.pitch + dy * RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Wheel by `lines` (positive: towards the target).
    pub fn zoom(&mut self, lines: f32) {
        let min = self.distance0 * 1e-3;
        let max = self.distance0 * 1e3;
        self.distance = (self.distance * ZOOM_PER_LINE.powf(lines)).clamp(min, max);
    }

    /// Middle drag by `(dx, dy)` pixels in a view `height` pixels tall: the point under the
    /// cursor at the target's depth follows the cursor.
    pub fn pan(&mut self, dx: f32, dy: f32, height: u32) {
        let (right, up, units_per_pixel) = self.view_plane(height);
        self.target += (-right * dx + up * dy) * units_per_pixel;
    }

    /// The screen's right and up axes (unit, world space) and the world units a pixel spans at
    /// the target's depth, in a view `height` pixels tall: how a drag in the view plane moves
    /// things (the viewer's head drag).
    pub(crate) fn view_plane(&self, height: u32) -> (Vec3, Vec3, f32) {
        let units_per_pixel = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1) as f32;
        let (right, up) = self.screen_axes();
        (right, up, units_per_pixel)
    }

    /// Near and far planes at the current distance: the scene's, moved by how much closer or
    /// farther the eye is, with the near plane kept in front of the eye.
    pub fn clip_planes(&self) -> (f32, f32) {
        let shift = self.distance - self.distance0;
        let near = (self.near0 + shift).max(self.near0.min(self.distance * 0.01));
        let far = (self.far0 + shift).max(near * 2.0);
        (near, far)
    }

    /// The renderer's camera for a target of `size` pixels.
    pub fn camera(&self, size: [u32; 2]) -> Camera {
        let (near, far) = self.clip_planes();
        Camera::look_at(
            self.eye(),
            self.target,
            self.up,
            self.fov_y,
            near,
            far,
            size,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4 * (1.0 + b.length())
    }

    fn demo() -> OrbitCamera {
        OrbitCamera::new(
            Vec3::new(32.0, 4.0, 76.0),
            Vec3::new(0.0, -10.0, 0.0),
            Vec3::Y,
            35f32.to_radians(),
            1.0,
            500.0,
        )
    }

    #[test]
    fn starts_at_the_scene_camera() {
        let o = demo();
        assert!(close(o.eye(), Vec3::new(32.0, 4.0, 76.0)), "{}", o.eye());
        assert_eq!(o.clip_planes(), (1.0, 500.0));
        let cam = o.camera([640, 360]);
        let scene = Camera::look_at(
            Vec3::new(32.0, 4.0, 76.0),
            Vec3::new(0.0, -10.0, 0.0),
            Vec3::Y,
            35f32.to_radians(),
            1.0,
            500.0,
            [640, 360],
        );
        assert!(
            cam.clip_from_world()
                .abs_diff_eq(scene.clip_from_world(), 1e-4)
        );
        // Straight above the target: still a valid orbit.
        let top = OrbitCamera::new(Vec3::Y * 5.0, Vec3::ZERO, Vec3::Y, 1.0, 0.1, 10.0);
        assert!(top.eye().is_finite() && (top.eye().length() - 5.0).abs() < 1e-3);
    }

    #[test]
    fn orbiting_keeps_the_distance_and_turns_about_the_up_axis() {
        let mut o = demo();
        let (d, h) = (o.distance, o.eye().y);
        // A full turn of yaw in pixels comes back to the start.
        let turn = std::f32::consts::TAU / RADIANS_PER_PIXEL;
        o.orbit(turn * 0.25, 0.0);
        assert!((o.eye() - o.target).length() - d < 1e-3);
        assert!((o.eye().y - h).abs() < 1e-3, "yaw keeps the height");
        // Dragging right moves the eye to the left of where it looked from.
        let before = demo();
        let (right, _) = before.screen_axes();
        assert!((o.eye() - before.eye()).dot(right) < 0.0);
        o.orbit(turn * 0.75, 0.0);
        assert!(
            close(o.eye(), before.eye()),
            "{} vs {}",
            o.eye(),
            before.eye()
        );
        // Pitch stops short of the pole.
        o.orbit(0.0, 1e6);
        assert!(o.pitch < std::f32::consts::FRAC_PI_2);
        assert!(o.direction().dot(Vec3::Y) > 0.99);
        assert!(o.camera([64, 64]).clip_from_world().is_finite());
    }

    #[test]
    fn zoom_scales_the_distance_and_moves_the_clip_planes() {
        let mut o = demo();
        let d = o.distance;
        o.zoom(1.0);
        assert!((o.distance - d * ZOOM_PER_LINE).abs() < 1e-3);
        o.zoom(-2.0);
        assert!((o.distance - d / ZOOM_PER_LINE).abs() < 1e-3);
        let (near, far) = o.clip_planes();
        let shift = o.distance - d;
        assert!((near - (1.0 + shift)).abs() < 1e-3 && (far - (500.0 + shift)).abs() < 1e-3);
        // Very close: the near plane stays positive and in front of the eye.
        o.zoom(60.0);
        let (near, far) = o.clip_planes();
        assert!(near > 0.0 && near < o.distance && far > near);
        o.zoom(-1e4);
        assert!(o.distance <= d * 1e3 + 1.0);
    }

    #[test]
    fn panning_moves_the_target_with_the_cursor() {
        let mut o = demo();
        let start = o.target;
        let (right, up) = o.screen_axes();
        o.pan(10.0, 0.0, 360);
        let moved = o.target - start;
        assert!(moved.dot(right) < 0.0, "the scene follows the cursor right");
        assert!(moved.dot(up).abs() < 1e-5 && moved.dot(o.direction()).abs() < 1e-5);
        // The target point projects 10 pixels right of the centre after the pan.
        let cam = o.camera([640, 360]);
        let clip = cam.clip_from_world() * start.extend(1.0);
        let px = (clip.x / clip.w) * 320.0;
        assert!((px - 10.0).abs() < 0.05, "{px}");
        o.pan(0.0, 10.0, 360);
        assert!((o.target - start).dot(up) > 0.0);
    }
}
