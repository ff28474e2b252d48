//! `[simulation]`: every setting of the solver, its default and its check.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::SimError;

/// How followers are rebuilt from the simulated guides every step (the follow modes of
/// `tress_hair`'s follow hairs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FollowMode {
    /// From its three nearest guides' barycentric blend, the rest offset carried in the guides'
    /// blended frames, so the follower turns with them.
    #[default]
    Interpolate,
    /// From its nearest guide: the guide plus the rest offset, carried in the guide's frames.
    Offset,
}

/// Wind: a steady air velocity with turbulence, acting on the strands across their length.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Wind {
    /// Direction the air moves towards (normalized when used; zero with `strength = 0`).
    pub direction: Vec3,
    /// Air speed in world units a second.
    pub strength: f32,
    /// Relative variation of the air velocity in space and time, in [0, 1].
    pub turbulence: f32,
    /// How fast a strand takes the air's velocity across it, per second (a drag rate).
    pub drag: f32,
}

impl Default for Wind {
    fn default() -> Self {
        Wind {
            direction: Vec3::X,
            strength: 0.0,
            turbulence: 0.3,
            drag: 2.0,
        }
    }
}

/// A collision sphere in the head's space (it moves with the head).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (positive).
    pub radius: f32,
}

/// A collision capsule in the head's space: the points within `radius` of the segment `a`–`b`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Capsule {
    /// One end of the axis.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// Radius (positive).
    pub radius: f32,
}

/// `[simulation]` (see the crate docs for the model).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimSettings {
    /// Whether the hair is simulated (`--animate simulate` turns it on).
    pub enabled: bool,
    /// Simulation steps a second: the state advances in fixed steps whatever the display rate.
    pub rate_hz: f32,
    /// Substeps a step (the head's motion is interpolated across them).
    pub substeps: u32,
    /// Constraint iterations a substep.
    pub iterations: u32,
    /// Velocity damping rate per second: a free vertex's speed decays as `e^(-damping·t)`.
    pub damping: f32,
    /// Local shape stiffness in [0, 1]: how strongly each segment keeps its rest angle to the
    /// previous one (curls stay curls), per 1/60 s whatever the rate and iterations.
    pub local_stiffness: f32,
    /// Global shape stiffness in [0, 1]: how strongly a vertex is pulled to its rest position
    /// on the head (a styled groom keeps its style), per 1/60 s.
    pub global_stiffness: f32,
    /// Share of each strand, from the root, that global shape acts on, in [0, 1]; it fades
    /// linearly to zero across that share.
    pub global_range: f32,
    /// Gravity, world units a second squared (the scenes are in centimetres, y up).
    pub gravity: Vec3,
    /// Wind.
    pub wind: Wind,
    /// Distance hair keeps from the head and the colliders, world units.
    pub collision_margin: f32,
    /// Friction on the head and the colliders, in [0, 1]: the share of a touching vertex's
    /// tangential velocity removed each substep.
    pub friction: f32,
    /// Hair–hair friction in [0, 1]: the share of the difference between a vertex's velocity and
    /// the hair's mean velocity around it removed each substep.
    pub hair_friction: f32,
    /// Hair volume in [0, 1]: how strongly hair is pushed out of cells denser than at rest.
    pub hair_volume: f32,
    /// Cells along each axis of the hair–hair grid (4 to 128).
    pub hair_grid: u32,
    /// Share of the strands simulated as guides when the asset has no guides, in (0, 1]; the
    /// others follow them. 1 simulates every strand.
    pub guides: f32,
    /// How followers follow the guides.
    pub follow: FollowMode,
    /// Velocity shock propagation in [0, 1]: the share of the head's own motion in a substep
    /// that is given to the whole strand rigidly (adding no velocity) once the head turns
    /// faster than `shock_threshold`, so a fast turn carries the hair instead of dragging it.
    pub shock: f32,
    /// Head angular speed (radians a second) from which `shock` acts, reaching full strength at
    /// twice this speed.
    pub shock_threshold: f32,
    /// A head that moves further than this in one step (world units) teleported: the hair is
    /// moved with it rigidly, keeping its shape and velocity relative to the head.
    pub teleport_distance: f32,
    /// Collision spheres in the head's space.
    pub spheres: Vec<Sphere>,
    /// Collision capsules in the head's space.
    pub capsules: Vec<Capsule>,
    /// Cells along the longest axis of the head's signed distance field (16 to 256).
    pub sdf_resolution: u32,
}

impl Default for SimSettings {
    fn default() -> Self {
        SimSettings {
            enabled: false,
            rate_hz: 60.0,
            substeps: 2,
            iterations: 4,
            damping: 2.0,
            local_stiffness: 0.9,
            global_stiffness: 0.4,
            global_range: 0.5,
            gravity: Vec3::new(0.0, -981.0, 0.0),
            wind: Wind::default(),
            collision_margin: 0.2,
            friction: 0.3,
            hair_friction: 0.05,
            hair_volume: 0.1,
            hair_grid: 32,
            guides: 1.0 / 27.0,
            follow: FollowMode::Interpolate,
            shock: 0.8,
            shock_threshold: 6.0,
            teleport_distance: 50.0,
            spheres: Vec::new(),
            capsules: Vec::new(),
            sdf_resolution: 48,
        }
    }
}

fn unit(key: &str, v: f32) -> Result<(), SimError> {
    if !(0.0..=1.0).contains(&v) {
        return Err(SimError::setting(
            key,
            format!("must be in [0, 1], got {v}"),
        ));
    }
    Ok(())
}

fn finite(key: &str, v: Vec3) -> Result<(), SimError> {
    if !v.is_finite() {
        return Err(SimError::setting(key, format!("must be finite, got {v}")));
    }
    Ok(())
}

fn non_negative(key: &str, v: f32) -> Result<(), SimError> {
    if !v.is_finite() || v < 0.0 {
        return Err(SimError::setting(
            key,
            format!("must be finite and at least 0, got {v}"),
        ));
    }
    Ok(())
}

fn positive(key: &str, v: f32) -> Result<(), SimError> {
    if !v.is_finite() || v <= 0.0 {
        return Err(SimError::setting(
            key,
            format!("must be finite and above 0, got {v}"),
        ));
    }
    Ok(())
}

fn count(key: &str, v: u32, range: std::ops::RangeInclusive<u32>) -> Result<(), SimError> {
    if !range.contains(&v) {
        return Err(SimError::setting(
            key,
            format!("must be in {}..={}, got {v}", range.start(), range.end()),
        ));
    }
    Ok(())
}

impl SimSettings {
    /// Check every value; the error names the key (`simulation.KEY`).
    pub fn validate(&self) -> Result<(), SimError> {
        positive("simulation.rate_hz", self.rate_hz)?;
        if self.rate_hz > 10_000.0 {
            return Err(SimError::setting(
                "simulation.rate_hz",
                format!("must be at most 10000, got {}", self.rate_hz),
            ));
        }
        count("simulation.substeps", self.substeps, 1..=64)?;
        count("simulation.iterations", self.iterations, 1..=64)?;
        non_negative("simulation.damping", self.damping)?;
        unit("simulation.local_stiffness", self.local_stiffness)?;
        unit("simulation.global_stiffness", self.global_stiffness)?;
        unit("simulation.global_range", self.global_range)?;
        finite("simulation.gravity", self.gravity)?;
        finite("simulation.wind.direction", self.wind.direction)?;
        non_negative("simulation.wind.strength", self.wind.strength)?;
        unit("simulation.wind.turbulence", self.wind.turbulence)?;
        non_negative("simulation.wind.drag", self.wind.drag)?;
        if self.wind.strength > 0.0 && self.wind.direction.length_squared() == 0.0 {
            return Err(SimError::setting(
                "simulation.wind.direction",
                "must not be zero while the wind blows",
            ));
        }
        non_negative("simulation.collision_margin", self.collision_margin)?;
        unit("simulation.friction", self.friction)?;
        unit("simulation.hair_friction", self.hair_friction)?;
        unit("simulation.hair_volume", self.hair_volume)?;
        count("simulation.hair_grid", self.hair_grid, 4..=128)?;
        if !(self.guides > 0.0 && self.guides <= 1.0) {
            return Err(SimError::setting(
                "simulation.guides",
                format!("must be in (0, 1], got {}", self.guides),
            ));
        }
        unit("simulation.shock", self.shock)?;
        positive("simulation.shock_threshold", self.shock_threshold)?;
        positive("simulation.teleport_distance", self.teleport_distance)?;
        for (i, s) in self.spheres.iter().enumerate() {
            finite(&format!("simulation.spheres[{i}].center"), s.center)?;
            positive(&format!("simulation.spheres[{i}].radius"), s.radius)?;
        }
        for (i, c) in self.capsules.iter().enumerate() {
            finite(&format!("simulation.capsules[{i}].a"), c.a)?;
            finite(&format!("simulation.capsules[{i}].b"), c.b)?;
            positive(&format!("simulation.capsules[{i}].radius"), c.radius)?;
        }
        count("simulation.sdf_resolution", self.sdf_resolution, 16..=256)?;
        Ok(())
    }

    /// Seconds a substep.
    pub fn substep_dt(&self) -> f32 {
        1.0 / (self.rate_hz * self.substeps as f32)
    }

    /// The per-iteration stiffness of a constraint whose stiffness is `k` per 1/60 s: the
    /// iterations of all substeps of 1/60 s together remove the share `k` of the error, so the
    /// result does not depend on the rate, the substeps or the iteration count.
    pub fn per_iteration(&self, k: f32) -> f32 {
        if k >= 1.0 {
            return 1.0;
        }
        let applications = self.iterations as f32 / (60.0 * self.substep_dt());
        1.0 - (1.0 - k).powf(1.0 / applications)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate_and_bad_values_name_their_key() {
        SimSettings::default().validate().unwrap();
        let bad = |f: fn(&mut SimSettings), key: &str| {
            let mut s = SimSettings::default();
            f(&mut s);
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        };
        bad(|s| s.local_stiffness = 1.5, "simulation.local_stiffness");
        bad(|s| s.global_stiffness = -0.1, "simulation.global_stiffness");
        bad(|s| s.rate_hz = 0.0, "simulation.rate_hz");
        bad(
            |s| s.wind.direction = Vec3::new(f32::NAN, 0.0, 0.0),
            "simulation.wind.direction",
        );
        bad(
            |s| s.gravity = Vec3::splat(f32::INFINITY),
            "simulation.gravity",
        );
        bad(|s| s.iterations = 0, "simulation.iterations");
        bad(|s| s.guides = 0.0, "simulation.guides");
        bad(
            |s| {
                s.wind.strength = 10.0;
                s.wind.direction = Vec3::ZERO;
            },
            "simulation.wind.direction",
        );
    }

    #[test]
    fn per_iteration_stiffness_removes_the_same_share_at_any_rate_and_count() {
        for (rate, substeps, iterations) in
            [(60.0, 1, 1), (60.0, 2, 4), (120.0, 3, 7), (30.0, 1, 2)]
        {
            let s = SimSettings {
                rate_hz: rate,
                substeps,
                iterations,
                ..SimSettings::default()
            };
            let k = s.per_iteration(0.5);
            let applications = (iterations * substeps) as f32 * rate / 60.0;
            let kept = (1.0 - k).powf(applications);
            assert!(
                (kept - 0.5).abs() < 1e-5,
                "{rate} {substeps} {iterations}: {kept}"
            );
        }
    }
}
