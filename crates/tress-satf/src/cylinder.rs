//! The generalized cylinder of a hair cluster (Xu et al. 2006, §3.2, equations 1–2): an ellipse
//! of half-axes `A(t)`, `B(t)` and twist `q(t)` swept along a cubic B-spline trajectory `T(τ)`,
//! always lying in the trajectory's normal plane.
//!
//! # Choices (the paper leaves them open)
//!
//! - **`t` is relative arc length** (§3.2: "t is the relative arc length along the sweeping
//!   trajectory"). `T` is a spline in its own parameter `τ`; a table of [`FRAME_TABLE`] samples maps
//!   `t → τ` (piecewise linear in the cumulative chord length). `A`, `B` and `q` are splines in `t`.
//! - **Rotation-minimizing frame**, not Frenet: the Frenet frame is undefined on straight pieces
//!   of hair (zero curvature) and flips at inflections. The frame is propagated along the table by
//!   the double-reflection method (Wang, Jüttler, Zheng and Liu 2008), starting from
//!   [`Vec3::any_orthonormal_vector`] of the first tangent; between table entries the normal is
//!   interpolated and re-projected onto the exact normal plane of `T'(τ)`, so the ellipse lies in
//!   the normal plane to rounding.
//! - **Twist** ([`TwistMode`]): equation 1 writes the twist as a phase, `x = A v cos(q + u)`,
//!   `y = B v sin(q + u)`, which turns the parameterization but not the ellipse's axes. Fitting a
//!   cluster whose cross-section turns needs the axes to turn, so the default
//!   [`TwistMode::RotateAxes`] rotates the ellipse by `q`: `(x, y) = R(q) (A v cos u, B v sin u)`.
//!   The two agree for circles (`A = B`); [`TwistMode::Phase`] keeps equation 1 literally.
//!
//! Frame axes: `(normal, binormal, tangent)` is right-handed (`binormal = tangent × normal`); `x`
//! runs along the normal, `y` along the binormal, and `u` increases counter-clockwise seen from
//! the tip (from `+x` toward `+y`).

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use crate::bspline::BSpline;
use crate::error::{SatfError, param};

/// Samples of the arc-length and frame table along the trajectory.
pub const FRAME_TABLE: usize = 256;
/// Smallest accepted trajectory length (world units).
const MIN_LENGTH: f32 = 1e-6;

/// How the twist `q(t)` acts on the ellipse (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TwistMode {
    /// `(x, y) = R(q) (A v cos u, B v sin u)`: the ellipse's axes turn by `q` (default).
    #[default]
    RotateAxes,
    /// Equation 1 literally: `x = A v cos(q + u)`, `y = B v sin(q + u)`.
    Phase,
}

/// The moving frame at a point of the trajectory.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// `T(t)`.
    pub position: Vec3,
    /// Unit tangent, from the root (`t = 0`) to the tip.
    pub tangent: Vec3,
    /// Unit normal (the ellipse's `x` axis before twisting).
    pub normal: Vec3,
    /// Unit binormal `tangent × normal` (the ellipse's `y` axis before twisting).
    pub binormal: Vec3,
}

/// A point on a shell surface `v = const` of the cylinder, with the directions the online
/// phase needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position `P(t, v, u)`.
    pub position: Vec3,
    /// Unit trajectory tangent (hair direction, root to tip).
    pub tangent: Vec3,
    /// Unit outward normal of the ellipse `v = const` in the normal plane.
    pub normal: Vec3,
    /// Unit direction of increasing `u` (the sector's `s` axis).
    pub s_axis: Vec3,
}

/// The generalized cylinder `H = Modeling(T(t), A(t), B(t), q(t))` (equation 2).
#[derive(Clone, Debug, PartialEq)]
pub struct GeneralizedCylinder {
    trajectory: BSpline<Vec3>,
    half_a: BSpline<f32>,
    half_b: BSpline<f32>,
    twist: BSpline<f32>,
    twist_mode: TwistMode,
    /// Normalized cumulative length at `τ = i / (FRAME_TABLE - 1)`.
    arc: Vec<f32>,
    /// Rotation-minimizing normal at the same samples.
    normals: Vec<Vec3>,
    /// `T(τ)` at the same samples.
    points: Vec<Vec3>,
    length: f32,
}

impl GeneralizedCylinder {
    /// A cylinder from its four splines. `A` and `B` must have positive control points (so the
    /// half-axes are positive everywhere) and the trajectory a length of at least 10⁻⁶.
    pub fn new(
        trajectory: BSpline<Vec3>,
        half_a: BSpline<f32>,
        half_b: BSpline<f32>,
        twist: BSpline<f32>,
        twist_mode: TwistMode,
    ) -> Result<Self, SatfError> {
        for (name, s) in [("A", &half_a), ("B", &half_b)] {
            if s.control_points().iter().any(|c| *c <= 0.0) {
                return Err(param(format!(
                    "half-axis {name}(t) must have positive control points"
                )));
            }
        }
        let c = trajectory.control_points();
        let scale = c.iter().fold(1.0f32, |m, p| m.max(p.abs().max_element()));
        let extent = c.iter().fold(0.0f32, |m, p| m.max(p.distance(c[0])));
        if extent <= MIN_LENGTH * scale {
            return Err(param("the trajectory's control points all coincide"));
        }
        let n = FRAME_TABLE;
        let positions: Vec<Vec3> = (0..n)
            .map(|i| trajectory.eval(i as f32 / (n - 1) as f32))
            .collect();
        let mut arc = Vec::with_capacity(n);
        let mut acc = 0.0f32;
        arc.push(0.0);
        for w in positions.windows(2) {
            acc += w[0].distance(w[1]);
            arc.push(acc);
        }
        if !(acc.is_finite() && acc >= MIN_LENGTH) {
            return Err(param(format!(
                "trajectory length {acc} is too short or not finite"
            )));
        }
        for a in &mut arc {
            *a /= acc;
        }
        let tangents: Vec<Vec3> = (0..n)
            .map(|i| table_tangent(&trajectory, &positions, i))
            .collect();
        let mut normals = Vec::with_capacity(n);
        normals.push(tangents[0].any_orthonormal_vector());
        for i in 0..n - 1 {
            let r = double_reflection(
                positions[i],
                tangents[i],
                normals[i],
                positions[i + 1],
                tangents[i + 1],
            );
            normals.push(r);
        }
        Ok(GeneralizedCylinder {
            trajectory,
            half_a,
            half_b,
            twist,
            twist_mode,
            arc,
            normals,
            points: positions,
            length: acc,
        })
    }

    /// The trajectory `T(τ)` (in its own spline parameter).
    pub fn trajectory(&self) -> &BSpline<Vec3> {
        &self.trajectory
    }
    /// Half-axis `A(t)` (`t`: relative arc length).
    pub fn half_a(&self) -> &BSpline<f32> {
        &self.half_a
    }
    /// Half-axis `B(t)`.
    pub fn half_b(&self) -> &BSpline<f32> {
        &self.half_b
    }
    /// Twist `q(t)` in radians.
    pub fn twist(&self) -> &BSpline<f32> {
        &self.twist
    }
    /// How the twist acts.
    pub fn twist_mode(&self) -> TwistMode {
        self.twist_mode
    }
    /// Length of the trajectory (world units, from the table's chords).
    pub fn length(&self) -> f32 {
        self.length
    }

    /// The spline parameter `τ` at relative arc length `t` (clamped to `[0, 1]`).
    pub fn tau_of(&self, t: f32) -> f32 {
        let t = t.clamp(0.0, 1.0);
        let i = self
            .arc
            .partition_point(|&a| a <= t)
            .clamp(1, FRAME_TABLE - 1);
        let (a0, a1) = (self.arc[i - 1], self.arc[i]);
        let f = if a1 > a0 { (t - a0) / (a1 - a0) } else { 0.0 };
        ((i - 1) as f32 + f.clamp(0.0, 1.0)) / (FRAME_TABLE - 1) as f32
    }

    /// The relative arc length `t` at spline parameter `τ`.
    pub fn t_of(&self, tau: f32) -> f32 {
        let x = tau.clamp(0.0, 1.0) * (FRAME_TABLE - 1) as f32;
        let i = (x.floor() as usize).min(FRAME_TABLE - 2);
        let f = x - i as f32;
        self.arc[i] + (self.arc[i + 1] - self.arc[i]) * f
    }

    /// The rotation-minimizing frame at relative arc length `t`.
    pub fn frame(&self, t: f32) -> Frame {
        let tau = self.tau_of(t);
        let x = tau * (FRAME_TABLE - 1) as f32;
        let i = (x.floor() as usize).min(FRAME_TABLE - 2);
        let f = x - i as f32;
        let position = self.trajectory.eval(tau);
        let tangent = self
            .trajectory
            .derivative(tau)
            .try_normalize()
            .unwrap_or_else(|| {
                (self.trajectory.eval((tau + 1e-3).min(1.0))
                    - self.trajectory.eval((tau - 1e-3).max(0.0)))
                .normalize_or(Vec3::Y)
            });
        let r = self.normals[i].lerp(self.normals[i + 1], f);
        let normal = (r - r.dot(tangent) * tangent)
            .try_normalize()
            .unwrap_or_else(|| tangent.any_orthonormal_vector());
        Frame {
            position,
            tangent,
            normal,
            binormal: tangent.cross(normal),
        }
    }

    /// Half-axes and twist at `t`: `(A, B, q)`.
    pub fn profile(&self, t: f32) -> (f32, f32, f32) {
        (self.half_a.eval(t), self.half_b.eval(t), self.twist.eval(t))
    }

    /// In-plane coordinates `(x, y)` of the ellipse point `(v, u)` at `t` (equation 1).
    pub fn ellipse_xy(&self, t: f32, v: f32, u: f32) -> Vec2 {
        let (a, b, q) = self.profile(t);
        ellipse_xy(self.twist_mode, a, b, q, v, u)
    }

    /// `P(t, v, u)`: the point at relative arc length `t`, radius fraction `v` and phase `u`.
    pub fn point(&self, t: f32, v: f32, u: f32) -> Vec3 {
        let f = self.frame(t);
        let xy = self.ellipse_xy(t, v, u);
        f.position + xy.x * f.normal + xy.y * f.binormal
    }

    /// The point `P(t, v, u)` with its tangent, outward normal and `s` axis (the directions do
    /// not depend on `v`; at `v = 0` they are those of `v = 1`).
    pub fn surface(&self, t: f32, v: f32, u: f32) -> SurfacePoint {
        let f = self.frame(t);
        let (a, b, q) = self.profile(t);
        let xy = ellipse_xy(self.twist_mode, a, b, q, v, u);
        let d = ellipse_du(self.twist_mode, a, b, q, u);
        let s_axis = (d.x * f.normal + d.y * f.binormal).normalize_or(f.binormal);
        SurfacePoint {
            position: f.position + xy.x * f.normal + xy.y * f.binormal,
            tangent: f.tangent,
            normal: s_axis.cross(f.tangent).normalize_or(f.normal),
            s_axis,
        }
    }

    /// The relative arc length of the table point nearest `p`, searched downhill from the hint
    /// (a relative arc length) and refined on the neighbouring chords.
    pub fn closest_t(&self, p: Vec3, hint: f32) -> f32 {
        let n = FRAME_TABLE;
        let pos = |i: usize| self.points[i];
        let d2 = |i: usize| pos(i).distance_squared(p);
        let mut i = ((self.tau_of(hint) * (n - 1) as f32).round() as usize).min(n - 1);
        let mut best = d2(i);
        loop {
            let down = if i > 0 { d2(i - 1) } else { f32::INFINITY };
            let up = if i + 1 < n { d2(i + 1) } else { f32::INFINITY };
            if down < best && down <= up {
                i -= 1;
                best = down;
            } else if up < best {
                i += 1;
                best = up;
            } else {
                break;
            }
        }
        // Refine on the chords to either side: projection onto the segment.
        let mut tau = i as f32 / (n - 1) as f32;
        let mut best_d = best;
        for j in [i.saturating_sub(1), i] {
            if j + 1 >= n {
                continue;
            }
            let (a, b) = (pos(j), pos(j + 1));
            let ab = b - a;
            let f = if ab.length_squared() > 0.0 {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let d = (a + ab * f).distance_squared(p);
            if d < best_d {
                best_d = d;
                tau = (j as f32 + f) / (n - 1) as f32;
            }
        }
        self.t_of(tau)
    }

    /// Local coordinates `(t, v, u)` of a world point: `t` from [`GeneralizedCylinder::closest_t`]
    /// and `(v, u)` by inverting equation 1 in that normal plane (`u` in `[0, 2π)`; `v` may
    /// exceed 1 outside the cylinder).
    pub fn local_coords(&self, p: Vec3, hint: f32) -> (f32, f32, f32) {
        let t = self.closest_t(p, hint);
        let f = self.frame(t);
        let d = p - f.position;
        let (a, b, q) = self.profile(t);
        let (v, u) = ellipse_vu(
            self.twist_mode,
            a,
            b,
            q,
            Vec2::new(d.dot(f.normal), d.dot(f.binormal)),
        );
        (t, v, u)
    }
}

/// Equation 1: in-plane coordinates of `(v, u)` on the ellipse of half-axes `a`, `b`, twist `q`.
pub fn ellipse_xy(mode: TwistMode, a: f32, b: f32, q: f32, v: f32, u: f32) -> Vec2 {
    match mode {
        TwistMode::RotateAxes => {
            let p = Vec2::new(a * v * u.cos(), b * v * u.sin());
            Vec2::from_angle(q).rotate(p)
        }
        TwistMode::Phase => Vec2::new(a * v * (q + u).cos(), b * v * (q + u).sin()),
    }
}

/// `∂(x, y)/∂u` at `v = 1`.
fn ellipse_du(mode: TwistMode, a: f32, b: f32, q: f32, u: f32) -> Vec2 {
    match mode {
        TwistMode::RotateAxes => Vec2::from_angle(q).rotate(Vec2::new(-a * u.sin(), b * u.cos())),
        TwistMode::Phase => Vec2::new(-a * (q + u).sin(), b * (q + u).cos()),
    }
}

/// The inverse of [`ellipse_xy`]: `(v, u)` with `u` in `[0, 2π)`.
pub fn ellipse_vu(mode: TwistMode, a: f32, b: f32, q: f32, xy: Vec2) -> (f32, f32) {
    let (p, phase) = match mode {
        TwistMode::RotateAxes => (Vec2::from_angle(-q).rotate(xy), 0.0),
        TwistMode::Phase => (xy, q),
    };
    let (x, y) = (p.x / a, p.y / b);
    let v = x.hypot(y);
    let u = (y.atan2(x) - phase).rem_euclid(TAU);
    (v, if u >= TAU { 0.0 } else { u })
}

fn table_tangent(trajectory: &BSpline<Vec3>, positions: &[Vec3], i: usize) -> Vec3 {
    let n = positions.len();
    trajectory
        .derivative(i as f32 / (n - 1) as f32)
        .try_normalize()
        .unwrap_or_else(|| {
            let (a, b) = (
                positions[i.saturating_sub(1)],
                positions[(i + 1).min(n - 1)],
            );
            (b - a).normalize_or(Vec3::Y)
        })
}

/// One step of the double-reflection rotation-minimizing frame.
fn double_reflection(x0: Vec3, t0: Vec3, r0: Vec3, x1: Vec3, t1: Vec3) -> Vec3 {
    let v1 = x1 - x0;
    let c1 = v1.dot(v1);
    let (r_l, t_l) = if c1 > 1e-20 {
        (
            r0 - (2.0 / c1) * v1.dot(r0) * v1,
            t0 - (2.0 / c1) * v1.dot(t0) * v1,
        )
    } else {
        (r0, t0)
    };
    let v2 = t1 - t_l;
    let c2 = v2.dot(v2);
    let r = if c2 > 1e-20 {
        r_l - (2.0 / c2) * v2.dot(r_l) * v2
    } else {
        r_l
    };
    (r - r.dot(t1) * t1)
        .try_normalize()
        .unwrap_or_else(|| t1.any_orthonormal_vector())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curved() -> GeneralizedCylinder {
        let traj = BSpline::new(vec![
            Vec3::ZERO,
            Vec3::new(0.0, -3.0, 1.0),
            Vec3::new(2.0, -6.0, 3.0),
            Vec3::new(5.0, -8.0, 2.0),
            Vec3::new(6.0, -12.0, -1.0),
            Vec3::new(4.0, -15.0, -3.0),
        ])
        .unwrap();
        GeneralizedCylinder::new(
            traj,
            BSpline::linear(1.0, 0.5),
            BSpline::linear(0.6, 0.2),
            BSpline::linear(0.0, 3.0),
            TwistMode::RotateAxes,
        )
        .unwrap()
    }

    #[test]
    fn ellipse_stays_in_the_normal_plane() {
        for mode in [TwistMode::RotateAxes, TwistMode::Phase] {
            let mut c = curved();
            c.twist_mode = mode;
            for i in 0..=40 {
                let t = i as f32 / 40.0;
                let tau = c.tau_of(t);
                let tangent = c.trajectory.derivative(tau).normalize();
                let centre = c.trajectory.eval(tau);
                for k in 0..12 {
                    let u = k as f32 / 12.0 * TAU;
                    let p = c.point(t, 0.8, u);
                    assert!((p - centre).dot(tangent).abs() < 1e-4, "t {t} u {u}");
                    let s = c.surface(t, 0.8, u);
                    assert!(
                        s.normal.dot(tangent).abs() < 1e-4 && s.s_axis.dot(tangent).abs() < 1e-4
                    );
                    assert!(s.normal.dot(s.s_axis).abs() < 1e-4);
                }
            }
        }
    }

    #[test]
    fn ellipse_has_the_half_axes_and_twist() {
        let c = curved();
        let t = 0.5;
        let (a, b, q) = c.profile(t);
        assert!((a - 0.75).abs() < 1e-5 && (b - 0.4).abs() < 1e-5 && (q - 1.5).abs() < 1e-5);
        let f = c.frame(t);
        // u = 0 lies on the major axis, turned by q from the normal.
        let p = c.point(t, 1.0, 0.0) - f.position;
        let expect = a * (q.cos() * f.normal + q.sin() * f.binormal);
        assert!((p - expect).length() < 1e-4);
        let p = c.point(t, 0.5, std::f32::consts::FRAC_PI_2) - f.position;
        assert!((p.length() - 0.5 * b).abs() < 1e-4);
        // The outward normal at u = 0 is the major axis direction.
        assert!((c.surface(t, 1.0, 0.0).normal - expect / a).length() < 1e-4);
    }

    #[test]
    fn frame_is_orthonormal_and_rotation_minimizing_on_a_line() {
        let c = GeneralizedCylinder::new(
            BSpline::linear(Vec3::ZERO, Vec3::new(0.0, -10.0, 0.0)),
            BSpline::constant(1.0),
            BSpline::constant(1.0),
            BSpline::constant(0.0),
            TwistMode::RotateAxes,
        )
        .unwrap();
        assert!((c.length() - 10.0).abs() < 1e-4);
        let n0 = c.frame(0.0).normal;
        for i in 0..=10 {
            let f = c.frame(i as f32 / 10.0);
            assert!((f.tangent - Vec3::NEG_Y).length() < 1e-6);
            assert!(
                (f.normal - n0).length() < 1e-5,
                "no rotation along a straight line"
            );
            assert!((f.position.y + i as f32).abs() < 1e-4, "t is arc length");
        }
    }

    #[test]
    fn arc_length_parameterization_and_inverse() {
        let c = curved();
        for i in 0..=20 {
            let t = i as f32 / 20.0;
            assert!((c.t_of(c.tau_of(t)) - t).abs() < 1e-5);
        }
        // Equal steps in t are equal lengths along the curve.
        let step = c.frame(0.11).position.distance(c.frame(0.1).position);
        let step2 = c.frame(0.81).position.distance(c.frame(0.8).position);
        assert!((step - step2).abs() < 0.02 * step, "{step} {step2}");
        for &(t, v, u) in &[(0.3f32, 0.5f32, 1.0f32), (0.7, 0.9, 4.0), (0.05, 0.2, 6.0)] {
            let p = c.point(t, v, u);
            let (t2, v2, u2) = c.local_coords(p, 0.5);
            assert!(
                (t - t2).abs() < 2e-3 && (v - v2).abs() < 1e-2 && (u - u2).abs() < 1e-2,
                "{t2} {v2} {u2}"
            );
        }
    }

    #[test]
    fn rejects_degenerate_cylinders() {
        let line = BSpline::linear(Vec3::ZERO, Vec3::X);
        let one = BSpline::constant(1.0);
        let zero = BSpline::constant(0.0);
        let mode = TwistMode::RotateAxes;
        assert!(
            GeneralizedCylinder::new(line.clone(), zero.clone(), one.clone(), zero.clone(), mode)
                .is_err()
        );
        let point = BSpline::constant(Vec3::ONE);
        assert!(
            GeneralizedCylinder::new(point, one.clone(), one.clone(), zero.clone(), mode).is_err()
        );
        assert!(GeneralizedCylinder::new(line, one.clone(), one, zero, mode).is_ok());
    }
}
