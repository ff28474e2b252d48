//! The pieces of a substep, each on one vertex or one strand, as the WGSL passes run them.

use glam::{Quat, Vec3};

use crate::collide::Colliders;
use crate::motion::Rigid;

/// Verlet integration with damping that does not depend on the step: the displacement of the
/// last substep (its velocity) is scaled by `decay = e^(−damping·dt)`, so a free vertex's speed
/// after `T` seconds is `v0·e^(−damping·T)` at any rate; then the acceleration is added.
/// Returns the new (position, previous position).
pub fn integrate(x: Vec3, x_prev: Vec3, decay: f32, accel: Vec3, dt: f32) -> (Vec3, Vec3) {
    let v = (x - x_prev) * decay;
    (x + v + accel * (dt * dt), x)
}

/// What one strand's constraint solve needs besides its positions.
#[derive(Clone, Copy, Debug)]
pub struct StrandParams<'a> {
    /// Rest positions, head space.
    pub rest: &'a [Vec3],
    /// Rest length of the segment ending at each vertex (the root's is unused).
    pub rest_len: &'a [f32],
    /// Global shape weight of each vertex (its fade included).
    pub global_w: &'a [f32],
    /// The head at the end of this substep.
    pub head: Rigid,
    /// Per-iteration stiffnesses.
    pub k_local: f32,
    /// Per-iteration global stiffness.
    pub k_global: f32,
    /// Constraint iterations.
    pub iterations: u32,
    /// Collision margin of each vertex: the setting's, or less for a vertex closer to a
    /// collider at rest (near the root), which keeps at least its rest distance.
    pub margin: &'a [f32],
}

/// Project a vertex out of the colliders (head space there): returns the corrected position and
/// the world-space normal when it touched (signed distance below the margin).
pub fn collide(x: Vec3, head: &Rigid, colliders: &Colliders, margin: f32) -> (Vec3, Option<Vec3>) {
    if colliders.is_empty() {
        return (x, None);
    }
    let local = head.inverse().apply(x);
    match colliders.nearest(local) {
        Some((d, n)) if d < margin => {
            let n = head.turn(n);
            (x + n * (margin - d), Some(n))
        }
        _ => (x, None),
    }
}

/// Solve one strand's constraints for a substep (Gauss–Seidel along the strand, root first),
/// `iterations` times: inextensibility (each segment back to its rest length, split by inverse
/// mass, the root's being 0), local shape (each segment towards its rest direction carried in
/// the frame of the segment before it, both ends moving, the root not), global shape (each
/// vertex towards its rest position on the head), and collisions. Then a follow-the-leader pass
/// from the root makes every segment exactly its rest length and puts each vertex outside the
/// colliders (its previous position moved with the length correction, so the correction adds
/// no velocity: a follow-the-leader pass that did made a hanging chain gain energy every swing).
pub fn solve_strand(
    x: &mut [Vec3],
    x_prev: &mut [Vec3],
    p: &StrandParams<'_>,
    colliders: &Colliders,
) {
    let n = x.len();
    if n < 2 {
        return;
    }
    let scratch = &mut LengthScratch::default();
    let head_rotation = p.head.rotation;
    for _ in 0..p.iterations {
        // Inextensibility: every segment's constraint projected at once.
        project_lengths(x, p.rest_len, scratch);
        // Local shape: the frame starts as the head's and follows each segment as solved.
        if p.k_local > 0.0 {
            let mut frame = head_rotation;
            for i in 0..n - 1 {
                let r = p.rest[i + 1] - p.rest[i];
                let target = x[i] + frame * r;
                let delta = (target - x[i + 1]) * p.k_local;
                if i == 0 {
                    x[1] += delta;
                } else {
                    x[i] -= delta * 0.5;
                    x[i + 1] += delta * 0.5;
                }
                let want = (frame * r).normalize_or_zero();
                let got = (x[i + 1] - x[i]).normalize_or_zero();
                if want != Vec3::ZERO && got != Vec3::ZERO {
                    frame = (Quat::from_rotation_arc(want, got) * frame).normalize();
                }
            }
        }
        // Global shape.
        if p.k_global > 0.0 {
            for ((xi, rest), gw) in x.iter_mut().zip(p.rest).zip(p.global_w).skip(1) {
                let w = p.k_global * gw;
                if w > 0.0 {
                    *xi += (p.head.apply(*rest) - *xi) * w;
                }
            }
        }
        for (i, xi) in x.iter_mut().enumerate().skip(1) {
            *xi = collide(*xi, &p.head, colliders, p.margin[i]).0;
        }
    }
    // Follow the leader, root to tip: each segment exactly its rest length (the correction
    // moves the previous position too, so it adds no velocity: removing error is not motion),
    // then out of the colliders; alternately, until a round touches nothing, so a vertex pushed
    // out slides back to its length (on a curved surface one round leaves the segment a chord's
    // sagitta long or short; at most `FINAL_ROUNDS` rounds, ending with the collision).
    for i in 1..n {
        for _ in 0..FINAL_ROUNDS {
            let d = x[i] - x[i - 1];
            let len = d.length();
            if len > 1e-12 {
                let moved = x[i - 1] + d * (p.rest_len[i] / len);
                x_prev[i] += moved - x[i];
                x[i] = moved;
            }
            let (out, touched) = collide(x[i], &p.head, colliders, p.margin[i]);
            x[i] = out;
            if touched.is_none() {
                break;
            }
        }
    }
}

/// Working arrays of [`project_lengths`].
#[derive(Default)]
pub struct LengthScratch {
    dir: Vec<Vec3>,
    c: Vec<f32>,
    diag: Vec<f32>,
    upper: Vec<f32>,
    lambda: Vec<f32>,
}

/// Newton steps of the projection of a strand onto its rest lengths, every segment at once (the
/// root fixed, every other vertex of unit mass): with `n_i` the direction of segment `i` and
/// `C_i = |x_i − x_{i−1}| − L_i`, the multipliers solve the tridiagonal system
/// `(J W Jᵀ) λ = −C` (diagonal `w_{i−1} + w_i`, off-diagonal `−w_i n_i·n_{i+1}`) by the Thomas
/// algorithm, and each vertex moves by `W Jᵀ λ`. This is the position-based projection of all
/// the strand's distance constraints together, so it converges in a few steps where
/// Gauss–Seidel along a long strand leaves it stretched, and moves the vertices as their masses
/// say, where follow-the-leader does not (a chain swings with its physical modes).
pub fn project_lengths(x: &mut [Vec3], rest_len: &[f32], s: &mut LengthScratch) {
    let n = x.len();
    if n < 2 {
        return;
    }
    let m = n - 1;
    for _ in 0..PROJECTION_STEPS {
        s.dir.clear();
        s.c.clear();
        for i in 1..n {
            let d = x[i] - x[i - 1];
            let len = d.length();
            s.dir.push(if len > 1e-12 { d / len } else { Vec3::ZERO });
            s.c.push(len - rest_len[i]);
        }
        // Segment k joins vertices k and k + 1; vertex 0 (the root) has no mass to move.
        s.diag.clear();
        s.upper.clear();
        for k in 0..m {
            let w_lo = if k == 0 { 0.0 } else { 1.0 };
            s.diag.push(w_lo + 1.0);
            s.upper.push(if k + 1 < m {
                -s.dir[k].dot(s.dir[k + 1])
            } else {
                0.0
            });
        }
        // Thomas algorithm on the symmetric tridiagonal system (positive definite).
        s.lambda.clear();
        s.lambda.extend(s.c.iter().map(|c| -c));
        for k in 1..m {
            let f = s.upper[k - 1] / s.diag[k - 1];
            s.diag[k] -= f * s.upper[k - 1];
            s.lambda[k] -= f * s.lambda[k - 1];
        }
        s.lambda[m - 1] /= s.diag[m - 1];
        for k in (0..m - 1).rev() {
            s.lambda[k] = (s.lambda[k] - s.upper[k] * s.lambda[k + 1]) / s.diag[k];
        }
        for k in 0..m {
            let dx = s.dir[k] * s.lambda[k];
            if k > 0 {
                x[k] -= dx;
            }
            x[k + 1] += dx;
        }
    }
}

/// Rounds of length and collision of each vertex in the last pass of [`solve_strand`].
pub const FINAL_ROUNDS: u32 = 8;

/// Newton steps of [`project_lengths`] an iteration.
pub const PROJECTION_STEPS: u32 = 2;

/// Friction with a collider a vertex touches: its velocity relative to the surface (which moves
/// with the head, `surface` being the displacement of the surface point under it this substep)
/// loses its part into the surface and the share `friction` of its tangential part. Returns the
/// new previous position.
pub fn friction(x: Vec3, x_prev: Vec3, normal: Vec3, surface: Vec3, friction: f32) -> Vec3 {
    let rel = (x - x_prev) - surface;
    let vn = rel.dot(normal);
    let tangential = rel - normal * vn;
    let kept = tangential * (1.0 - friction) + normal * vn.max(0.0);
    x - (surface + kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_is_the_same_law_at_any_rate() {
        let damping = 3.0;
        for rate in [30.0f32, 60.0, 120.0, 144.0] {
            let dt = 1.0 / rate;
            let (mut x, mut xp) = (Vec3::ZERO, Vec3::new(-10.0 * dt, 0.0, 0.0));
            let steps = (rate * 2.0).round() as usize;
            for _ in 0..steps {
                (x, xp) = integrate(x, xp, (-damping * dt).exp(), Vec3::ZERO, dt);
            }
            let speed = (x - xp).length() / dt;
            let want = 10.0 * (-damping * 2.0f32).exp();
            // Within f32's cancellation in x − x_prev (positions of ~3, steps of ~1e-4).
            assert!(
                (speed - want).abs() < want * 5e-3,
                "{rate} Hz: {speed} against {want}"
            );
        }
    }

    #[test]
    fn friction_keeps_a_share_of_the_sliding_and_none_of_the_push() {
        let n = Vec3::Y;
        let xp = friction(Vec3::ZERO, Vec3::new(-1.0, 1.0, 0.0), n, Vec3::ZERO, 0.25);
        // Velocity was (1, -1, 0): the push into the surface is gone, 75% of the slide stays.
        assert!((Vec3::ZERO - xp - Vec3::new(0.75, 0.0, 0.0)).length() < 1e-6);
        // Moving with the surface: nothing changes.
        let s = Vec3::new(0.3, 0.0, 0.1);
        assert!((friction(s, Vec3::ZERO, n, s, 0.9) - Vec3::ZERO).length() < 1e-6);
    }
}
