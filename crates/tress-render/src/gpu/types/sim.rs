//! The strand simulation's GPU structs (`shaders/common/sim.wgsl`, `sim/sim_output.wgsl`).

use bytemuck::{Pod, Zeroable};

/// `struct Rigid` in `shaders/common/sim.wgsl`: rotate by the quaternion, then translate.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RigidGpu {
    /// Quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Translation (xyz; w unused).
    pub translation: [f32; 4],
}

impl From<tress_sim::Rigid> for RigidGpu {
    fn from(r: tress_sim::Rigid) -> Self {
        RigidGpu {
            rotation: r.rotation.to_array(),
            translation: r.translation.extend(0.0).to_array(),
        }
    }
}

/// `struct SimParams` in `shaders/common/sim.wgsl`: one substep's uniforms (see the WGSL for
/// each member's packing).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SimParams {
    /// The head at the substep's start.
    pub h0: RigidGpu,
    /// The head at its end.
    pub h1: RigidGpu,
    /// `h1` after the inverse of `h0`.
    pub delta: RigidGpu,
    /// Gravity; w: seconds a substep.
    pub gravity: [f32; 4],
    /// Unit wind direction; w: strength.
    pub wind_dir: [f32; 4],
    /// Turbulence, drag, time, velocity decay a substep.
    pub wind: [f32; 4],
    /// Local and global stiffness an iteration, shock weight, hair friction.
    pub shape: [f32; 4],
    /// Hair volume, rest peak weight, collider friction, unused.
    pub grid_params: [f32; 4],
    /// The grid's node (0, 0, 0) in head space; w: node spacing.
    pub grid_origin: [f32; 4],
    /// Nodes along each axis; w unused.
    pub grid_dims: [u32; 4],
    /// The SDF's cell (0, 0, 0) in head space; w: cell size.
    pub sdf_origin: [f32; 4],
    /// Cells along each axis; w: 1 when there is an SDF.
    pub sdf_dims: [u32; 4],
    /// Simulated vertices, strands, iterations, spheres.
    pub counts: [u32; 4],
    /// Capsules, follower vertices, whether the grid acts, unused.
    pub counts2: [u32; 4],
}

/// `struct SimRest` in `shaders/common/sim.wgsl`: a simulated vertex's rest data.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SimRest {
    /// Rest position, head space.
    pub position: [f32; 3],
    /// Rest length of the segment ending here.
    pub rest_len: f32,
    /// Global shape weight.
    pub global_w: f32,
    /// Collision margin.
    pub margin: f32,
    /// 1 for a root.
    pub flags: u32,
    /// Its strand.
    pub strand: u32,
}

/// `struct SimOutputParams` in `sim/sim_output.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SimOutputParams {
    /// The head's rotation now.
    pub head_rotation: [f32; 4],
    /// Guide vertices, follower vertices, followers, unused.
    pub counts: [u32; 4],
}

/// `struct SimFollower` in `sim/sim_output.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SimFollower {
    /// Its three guides; w: its vertex count.
    pub guides: [u32; 4],
    /// The guides' weights; w unused.
    pub weights: [f32; 4],
    /// Its first vertex among the follower vertices.
    pub first: u32,
    /// Its first vertex in the renderers' buffer.
    pub asset_first: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// `struct SimFollowerVertex` in `sim/sim_output.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SimFollowerVertex {
    /// Rest offset from the guides' blend, head space.
    pub offset: [f32; 3],
    /// Its follower.
    pub follower: u32,
}
