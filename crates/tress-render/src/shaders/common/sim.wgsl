// Strand simulation: the types and math every simulation pass shares, twins of tress-sim's CPU
// step (`tress_sim::{motion, collide, grid, wind, step}`).

// The most vertices a simulated strand has (the constraint pass keeps a strand in registers).
const SIM_MAX_VERTICES: u32 = 64u;
// Fixed-point scales of the hair–hair grid (tress_sim::grid).
const GRID_WEIGHT_ONE: f32 = 256.0;
const GRID_VELOCITY_ONE: f32 = 4096.0;
const GRID_MAX_CELLS: f32 = 4.0;
const GRID_MAX_PUSH_CELLS: f32 = 0.5;
// Rounds of length and collision in the last pass (tress_sim::step::FINAL_ROUNDS) and Newton
// steps of the length projection (tress_sim::step::PROJECTION_STEPS).
const SIM_FINAL_ROUNDS: u32 = 8u;
const SIM_PROJECTION_STEPS: u32 = 2u;
// SimRest.flags: the strand's root.
const SIM_ROOT: u32 = 1u;

// A rigid transform (tress_sim::Rigid): rotate by the quaternion (x, y, z, w), then translate.
struct Rigid {
    rotation: vec4<f32>,
    translation: vec4<f32>,
}

// Mirrored by `gpu::types::SimParams`: one substep's uniforms.
struct SimParams {
    // The head at the start and the end of the substep, and the motion between.
    h0: Rigid,
    h1: Rigid,
    delta: Rigid,
    // xyz: gravity; w: dt (seconds a substep).
    gravity: vec4<f32>,
    // xyz: unit wind direction; w: wind strength.
    wind_dir: vec4<f32>,
    // x: turbulence, y: drag, z: time (seconds), w: velocity decay a substep.
    wind: vec4<f32>,
    // x: local stiffness an iteration, y: global stiffness an iteration, z: shock weight,
    // w: hair friction.
    shape: vec4<f32>,
    // x: hair volume, y: rest peak density, z: collider friction, w: unused.
    grid_params: vec4<f32>,
    // xyz: the grid's node (0, 0, 0) in head space; w: node spacing.
    grid_origin: vec4<f32>,
    // xyz: nodes along each axis.
    grid_dims: vec4<u32>,
    // xyz: the SDF's cell (0, 0, 0) in head space; w: cell size.
    sdf_origin: vec4<f32>,
    // xyz: cells along each axis; w: 1 when there is an SDF.
    sdf_dims: vec4<u32>,
    // x: simulated vertices, y: simulated strands, z: iterations, w: spheres.
    counts: vec4<u32>,
    // x: capsules, y: followers' vertices, z: whether the grid acts, w: unused.
    counts2: vec4<u32>,
}

// Mirrored by `gpu::types::SimRest`: a simulated vertex's rest data.
struct SimRest {
    // Head space.
    position: vec3<f32>,
    // Rest length of the segment ending here (0 at the root).
    rest_len: f32,
    // Global shape weight (with its fade).
    global_w: f32,
    // Collision margin of this vertex.
    margin: f32,
    // SIM_ROOT for a root.
    flags: u32,
    // Its strand.
    strand: u32,
}

fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

fn quat_conj(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(-q.xyz, q.w);
}

fn quat_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz),
        a.w * b.w - dot(a.xyz, b.xyz),
    );
}

// The smallest rotation taking unit `a` to unit `b` (glam's Quat::from_rotation_arc).
fn quat_arc(a: vec3<f32>, b: vec3<f32>) -> vec4<f32> {
    let d = dot(a, b);
    if d < -1.0 + 1e-6 {
        // Opposite: half a turn about any axis across `a`.
        var axis = cross(vec3<f32>(1.0, 0.0, 0.0), a);
        if dot(axis, axis) < 1e-6 {
            axis = cross(vec3<f32>(0.0, 1.0, 0.0), a);
        }
        return vec4<f32>(normalize(axis), 0.0);
    }
    let c = cross(a, b);
    return normalize(vec4<f32>(c, 1.0 + d));
}

fn rigid_apply(r: Rigid, p: vec3<f32>) -> vec3<f32> {
    return quat_rotate(r.rotation, p) + r.translation.xyz;
}

fn rigid_inverse_apply(r: Rigid, p: vec3<f32>) -> vec3<f32> {
    return quat_rotate(quat_conj(r.rotation), p - r.translation.xyz);
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    return select(vec3<f32>(0.0), v / l, l > 0.0);
}

// tress_sim::wind::noise.
fn wind_noise(p: vec3<f32>, t: f32, seed: f32) -> f32 {
    let a = sin(p.x * 0.11 + p.y * 0.05 + t * 1.3 + seed * 1.7);
    let b = sin(p.y * 0.09 - p.z * 0.13 + t * 0.9 + seed * 2.9);
    let c = sin(p.z * 0.07 + p.x * 0.06 - t * 1.7 + seed * 4.1);
    return (a + b + c) / 3.0;
}

// tress_sim::wind::air_velocity.
fn air_velocity(dir: vec3<f32>, strength: f32, turbulence: f32, p: vec3<f32>, t: f32) -> vec3<f32> {
    if strength <= 0.0 {
        return vec3<f32>(0.0);
    }
    let gust = wind_noise(p, t, 0.0);
    let side = vec3<f32>(wind_noise(p, t, 1.0), wind_noise(p, t, 2.0), wind_noise(p, t, 3.0));
    return strength * (dir * (1.0 + turbulence * gust) + side * (0.5 * turbulence));
}

// tress_sim::wind::drag.
fn wind_drag(drag: f32, air: vec3<f32>, velocity: vec3<f32>, tangent: vec3<f32>) -> vec3<f32> {
    let u = air - velocity;
    return drag * (u - tangent * dot(u, tangent));
}
