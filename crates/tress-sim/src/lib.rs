//! Strand simulation for tress: the settings (`[simulation]`), the head's motion
//! (`[head.motion]`), the colliders, and the CPU twin of the GPU solver's step. No GPU.
//!
//! ```
//! use glam::Vec3;
//! use tress_hair::HairAsset;
//! use tress_sim::{GuideChoice, Rigid, SimSettings, Simulation};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // One strand of 8 vertices hanging from its root at the origin, every strand a guide.
//! let asset = HairAsset::from_counts((0..8).map(|i| -0.5 * i as f32 * Vec3::Y).collect(), &[8])?;
//! let settings = SimSettings::default();
//! let guides = GuideChoice::Share(1.0);
//! let mut sim = Simulation::new(&asset, None, &settings, &guides, Rigid::IDENTITY)?;
//!
//! // One second with the head sliding 2 units along x: 60 fixed steps at the default 60 Hz.
//! let slide = |t: f32| Rigid { translation: Vec3::new(2.0 * t, 0.0, 0.0), ..Rigid::IDENTITY };
//! assert_eq!(sim.advance_to(1.0, slide), 60);
//! let moved = sim.to_asset(&asset)?;
//! assert!(moved.strand(0)[0].abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-4)); // the root follows
//! # Ok(()) }
//! ```
//!
//! # The model
//!
//! Guides are simulated; followers are rebuilt from them ([`follow`]). An asset without guides
//! simulates a share of its strands (`simulation.guides`, default 1/27: the ponytail's 136k
//! strands give about 5k guides), or all of them.
//!
//! A step is `1 / rate_hz` seconds, always: [`Simulation::advance_to`] runs the steps due by a
//! time, so what is displayed does not depend on the display rate. A step has `substeps`
//! substeps, the head's rigid transform interpolated across them (slerp and lerp). A substep:
//!
//! 1. **Velocity shock propagation**: when the head turns faster than `shock_threshold`, a share
//!    of its motion in the substep is given to the whole strand rigidly (position and previous
//!    position alike, so it adds no velocity), as TressFX does, so a fast turn carries the hair.
//! 2. **Integration** ([`step::integrate`]): roots are put on the head exactly; every other vertex
//!    moves by Verlet with damping `e^(−damping·dt)` on its velocity (a free vertex's speed decays
//!    as `e^(−damping·t)` at any rate), gravity and the wind's drag across the strand ([`wind`]).
//! 3. **Hair–hair interaction** ([`grid`]): the vertices' weights and velocities on a grid in
//!    fixed point (integer sums, order-independent); friction pulls each vertex's velocity
//!    towards the mean around it, and a push down the gradient of the density above the rest
//!    pose's densest node keeps the hair's volume (nothing happens at rest).
//! 4. **Constraints** ([`step::solve_strand`]), Gauss–Seidel along each strand from the root,
//!    `iterations` times: inextensibility (position-based distance constraints, split by inverse
//!    mass), local shape (each segment towards its rest direction in the frame of the segment
//!    before it: curls stay curls), global shape (towards the rest pose on the head, over
//!    `global_range` of the strand, fading), collisions. Then a follow-the-leader pass from the
//!    root makes every segment exactly its rest length, and a last collision pass puts every
//!    vertex outside the colliders. Stiffnesses are per 1/60 s and turned into per-iteration
//!    values ([`SimSettings::per_iteration`]), so a stiffness means the same at any rate,
//!    substep and iteration count (the TressFX #19 complaint), and the rest pose is a fixed point:
//!    at rest every constraint is already met.
//! 5. **Friction** with the colliders ([`step::friction`]): a touching vertex loses its velocity
//!    into the surface and a share of its sliding, relative to the moving head.
//!
//! A head that moves further than `teleport_distance` in one step teleported: the hair moves
//! with it rigidly, keeping its shape. Colliders ([`collide`]) are the head mesh's signed
//! distance field, built once (the head is rigid), and spheres and capsules, all in the head's
//! space.

pub mod collide;
pub mod follow;
pub mod grid;
pub mod motion;
pub mod settings;
mod sim;
pub mod step;
pub mod wind;

pub use motion::{Keyframe, MotionSpec, Preset, Rigid};
pub use settings::{Capsule, FollowMode, SimSettings, Sphere, Wind};
pub use sim::{GuideChoice, SimLayout, Simulation, StepReport, Substep};

/// What can go wrong setting up a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A setting is out of range; `key` is its dotted name.
    #[error("{key}: {reason}")]
    Setting {
        /// The dotted key (`simulation.local_stiffness`).
        key: String,
        /// Why.
        reason: String,
    },
    /// The inputs do not fit together.
    #[error("{0}")]
    Invalid(String),
}

impl SimError {
    pub(crate) fn setting(key: &str, reason: impl Into<String>) -> SimError {
        SimError::Setting {
            key: key.to_string(),
            reason: reason.into(),
        }
    }
}
