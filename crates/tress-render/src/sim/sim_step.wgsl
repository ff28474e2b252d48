// One simulation substep, the twin of tress_sim::Simulation's substep (see tress_sim's crate
// docs for the model). Entry points, dispatched in order each substep by `SimStep`:
//
//   shock        (a vertex)  velocity shock propagation, in place
//   integrate    (a vertex)  roots onto the head; Verlet with damping, gravity and wind, from
//                            `cur` and `prev` into `next` (the three position buffers then turn:
//                            prev ← cur, cur ← next, so no invocation reads what another writes)
//   grid_clear   (a node)    the hair–hair grid's sums to zero
//   grid_splat   (a vertex)  weights and velocities onto the grid (i32 atomics: the sums do not
//                            depend on the order)
//   grid_apply   (a vertex)  hair–hair friction and the volume push
//   constraints  (a strand)  lengths, local and global shape, collisions, `iterations` times;
//                            then follow-the-leader and collision rounds
//   friction     (a vertex)  friction with the colliders
//
// Group 0 holds the state; group 1 the next positions (integrate), the grid (grid passes) or
// the colliders (constraints, friction), so no pipeline binds more than 6 storage buffers.

#include "common/sim.wgsl"

@group(0) @binding(0) var<uniform> sim: SimParams;
@group(0) @binding(1) var<storage, read_write> prev: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> cur: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> rest: array<SimRest>;

fn thread_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

fn is_root(i: u32) -> bool {
    return (rest[i].flags & SIM_ROOT) != 0u;
}

@compute @workgroup_size(64)
fn shock(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= sim.counts.x || is_root(i) {
        return;
    }
    let w = sim.shape.z;
    let x = cur[i].xyz;
    let xp = prev[i].xyz;
    cur[i] = vec4<f32>(mix(x, rigid_apply(sim.delta, x), w), 0.0);
    prev[i] = vec4<f32>(mix(xp, rigid_apply(sim.delta, xp), w), 0.0);
}

// Group 1 of `integrate`: where the new positions go.
@group(1) @binding(0) var<storage, read_write> next: array<vec4<f32>>;

@compute @workgroup_size(64)
fn integrate(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= sim.counts.x {
        return;
    }
    if is_root(i) {
        next[i] = vec4<f32>(rigid_apply(sim.h1, rest[i].position), 0.0);
        return;
    }
    let dt = sim.gravity.w;
    let x = cur[i].xyz;
    let xp = prev[i].xyz;
    let tangent = normalize_or_zero(x - cur[i - 1u].xyz);
    let air = air_velocity(sim.wind_dir.xyz, sim.wind_dir.w, sim.wind.x, x, sim.wind.z);
    let accel = sim.gravity.xyz + wind_drag(sim.wind.y, air, (x - xp) / dt, tangent);
    // tress_sim::step::integrate: the last displacement damped, then the acceleration.
    let v = (x - xp) * sim.wind.w;
    next[i] = vec4<f32>(x + v + accel * (dt * dt), 0.0);
}

// Group 1 of the grid passes: 4 i32 a node (weight, then the weighted velocity's x y z).
@group(1) @binding(1) var<storage, read_write> grid: array<atomic<i32>>;

fn grid_dims() -> vec3<u32> {
    return sim.grid_dims.xyz;
}

// tress_sim::grid::corners: node `k` of the 8 around grid-space `g`, and its weight.
struct Corner {
    index: u32,
    weight: f32,
}

fn grid_corner(g_in: vec3<f32>, k: u32) -> Corner {
    let dims = grid_dims();
    let hi = vec3<f32>(dims - vec3<u32>(1u));
    let g = clamp(g_in, vec3<f32>(0.0), hi);
    let base = max(min(floor(g), hi - vec3<f32>(1.0)), vec3<f32>(0.0));
    let f = g - base;
    let o = vec3<u32>(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
    let w = select(1.0 - f.x, f.x, o.x == 1u) * select(1.0 - f.y, f.y, o.y == 1u)
        * select(1.0 - f.z, f.z, o.z == 1u);
    let c = vec3<u32>(base) + o;
    return Corner(c.x + dims.x * (c.y + dims.y * c.z), w);
}

fn to_grid(p_head: vec3<f32>) -> vec3<f32> {
    return (p_head - sim.grid_origin.xyz) / sim.grid_origin.w;
}

@compute @workgroup_size(64)
fn grid_clear(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let n = thread_index(id, groups);
    let dims = grid_dims();
    if n >= dims.x * dims.y * dims.z {
        return;
    }
    for (var a = 0u; a < 4u; a = a + 1u) {
        atomicStore(&grid[4u * n + a], 0);
    }
}

@compute @workgroup_size(64)
fn grid_splat(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= sim.counts.x || is_root(i) {
        return;
    }
    let x = cur[i].xyz;
    let local = rigid_inverse_apply(sim.h1, x);
    let v_cells = quat_rotate(quat_conj(sim.h1.rotation), x - prev[i].xyz) / sim.grid_origin.w;
    let v = clamp(v_cells, vec3<f32>(-GRID_MAX_CELLS), vec3<f32>(GRID_MAX_CELLS));
    let g = to_grid(local);
    for (var k = 0u; k < 8u; k = k + 1u) {
        let c = grid_corner(g, k);
        atomicAdd(&grid[4u * c.index], i32(round(c.weight * GRID_WEIGHT_ONE)));
        for (var a = 0u; a < 3u; a = a + 1u) {
            atomicAdd(&grid[4u * c.index + 1u + a], i32(round(c.weight * v[a] * GRID_VELOCITY_ONE)));
        }
    }
}

fn grid_excess(c_in: vec3<i32>) -> f32 {
    let dims = vec3<i32>(grid_dims());
    let c = clamp(c_in, vec3<i32>(0), dims - vec3<i32>(1));
    let n = u32(c.x + dims.x * (c.y + dims.y * c.z));
    // tress_sim::grid::HairGrid::excess: denser than the rest pose's densest node.
    return max(f32(atomicLoad(&grid[4u * n])) - sim.grid_params.y, 0.0) / sim.grid_params.y;
}

@compute @workgroup_size(64)
fn grid_apply(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= sim.counts.x || is_root(i) {
        return;
    }
    var x = cur[i].xyz;
    let local = rigid_inverse_apply(sim.h1, x);
    let g = to_grid(local);
    let dims = grid_dims();
    // tress_sim::grid::HairGrid::velocity and excess_gradient.
    var rho = 0.0;
    var m = vec3<f32>(0.0);
    var grad = vec3<f32>(0.0);
    for (var k = 0u; k < 8u; k = k + 1u) {
        let c = grid_corner(g, k);
        rho += c.weight * f32(atomicLoad(&grid[4u * c.index]));
        m += c.weight * vec3<f32>(
            f32(atomicLoad(&grid[4u * c.index + 1u])),
            f32(atomicLoad(&grid[4u * c.index + 2u])),
            f32(atomicLoad(&grid[4u * c.index + 3u])),
        );
        if c.weight != 0.0 {
            let n = c.index;
            let cc = vec3<i32>(vec3<u32>(n % dims.x, (n / dims.x) % dims.y, n / (dims.x * dims.y)));
            let d = vec3<f32>(
                0.5 * (grid_excess(cc + vec3<i32>(1, 0, 0)) - grid_excess(cc - vec3<i32>(1, 0, 0))),
                0.5 * (grid_excess(cc + vec3<i32>(0, 1, 0)) - grid_excess(cc - vec3<i32>(0, 1, 0))),
                0.5 * (grid_excess(cc + vec3<i32>(0, 0, 1)) - grid_excess(cc - vec3<i32>(0, 0, 1))),
            );
            grad += c.weight * d;
        }
    }
    var v_cells = vec3<f32>(0.0);
    if rho > 0.0 {
        v_cells = m / rho * (GRID_WEIGHT_ONE / GRID_VELOCITY_ONE);
    }
    let cell = sim.grid_origin.w;
    let v_grid = quat_rotate(sim.h1.rotation, v_cells) * cell;
    let v = x - prev[i].xyz;
    x += (v_grid - v) * sim.shape.w;
    var push = grad * (-sim.grid_params.x);
    let len = length(push);
    if len > GRID_MAX_PUSH_CELLS {
        push = push * (GRID_MAX_PUSH_CELLS / len);
    }
    x += quat_rotate(sim.h1.rotation, push) * cell;
    cur[i] = vec4<f32>(x, 0.0);
}

// Group 1 of the collider passes: the strands' vertex offsets, the head's signed distance
// field (x fastest) and the shapes (a sphere: (centre, radius), (0, 0, 0, 0); a capsule:
// (a, radius), (b, 1)).
@group(1) @binding(3) var<storage, read> offsets: array<u32>;
@group(1) @binding(4) var<storage, read> sdf: array<f32>;
@group(1) @binding(5) var<storage, read> shapes: array<vec4<f32>>;

fn sdf_at(c_in: vec3<i32>) -> f32 {
    let dims = vec3<i32>(sim.sdf_dims.xyz);
    let c = clamp(c_in, vec3<i32>(0), dims - vec3<i32>(1));
    return sdf[u32(c.x + dims.x * (c.y + dims.y * c.z))];
}

// tress_sim::collide::Sdf::distance.
fn sdf_distance(p: vec3<f32>) -> f32 {
    let cell = sim.sdf_origin.w;
    let g = (p - sim.sdf_origin.xyz) / cell;
    let hi = vec3<f32>(sim.sdf_dims.xyz - vec3<u32>(1u));
    let inside = clamp(g, vec3<f32>(0.0), hi);
    let outside = length(g - inside) * cell;
    let base = max(min(floor(inside), hi - vec3<f32>(1.0)), vec3<f32>(0.0));
    let f = inside - base;
    let b = vec3<i32>(base);
    var sum = 0.0;
    for (var k = 0; k < 8; k = k + 1) {
        let o = vec3<i32>(k & 1, (k >> 1u) & 1, (k >> 2u) & 1);
        let w = select(1.0 - f.x, f.x, o.x == 1) * select(1.0 - f.y, f.y, o.y == 1)
            * select(1.0 - f.z, f.z, o.z == 1);
        sum += w * sdf_at(b + o);
    }
    return sum + outside;
}

// tress_sim::collide::Sdf::normal.
fn sdf_normal(p: vec3<f32>) -> vec3<f32> {
    let h = 0.5 * sim.sdf_origin.w;
    let g = vec3<f32>(
        sdf_distance(p + vec3<f32>(h, 0.0, 0.0)) - sdf_distance(p - vec3<f32>(h, 0.0, 0.0)),
        sdf_distance(p + vec3<f32>(0.0, h, 0.0)) - sdf_distance(p - vec3<f32>(0.0, h, 0.0)),
        sdf_distance(p + vec3<f32>(0.0, 0.0, h)) - sdf_distance(p - vec3<f32>(0.0, 0.0, h)),
    );
    let l = length(g);
    return select(vec3<f32>(0.0, 1.0, 0.0), g / l, l > 0.0);
}

// tress_sim::collide::Colliders::nearest: (signed distance, normal) in head space; w < 0 when
// nothing is near (no colliders: distance +inf).
fn nearest_collider(p: vec3<f32>) -> vec4<f32> {
    var best = vec4<f32>(0.0, 1.0, 0.0, 3.0e38);
    if sim.sdf_dims.w != 0u {
        let d = sdf_distance(p);
        if d < 4.0 * sim.sdf_origin.w {
            best = vec4<f32>(sdf_normal(p), d);
        } else {
            best = vec4<f32>(0.0, 1.0, 0.0, d);
        }
    }
    for (var s = 0u; s < sim.counts.w; s = s + 1u) {
        let a = shapes[2u * s];
        let v = p - a.xyz;
        let l = length(v);
        let d = l - a.w;
        if d < best.w {
            best = vec4<f32>(select(vec3<f32>(0.0, 1.0, 0.0), v / l, l > 0.0), d);
        }
    }
    for (var c = 0u; c < sim.counts2.x; c = c + 1u) {
        let a = shapes[2u * (sim.counts.w + c)];
        let b = shapes[2u * (sim.counts.w + c) + 1u];
        let ab = b.xyz - a.xyz;
        let t = clamp(dot(p - a.xyz, ab) / max(dot(ab, ab), 1e-12), 0.0, 1.0);
        let v = p - (a.xyz + ab * t);
        let l = length(v);
        let d = l - a.w;
        if d < best.w {
            best = vec4<f32>(select(vec3<f32>(0.0, 1.0, 0.0), v / l, l > 0.0), d);
        }
    }
    return best;
}

fn has_colliders() -> bool {
    return sim.sdf_dims.w != 0u || sim.counts.w != 0u || sim.counts2.x != 0u;
}

// tress_sim::step::collide: the position out of the colliders, and whether it touched (w = 1).
fn collide(x: vec3<f32>, margin: f32) -> vec4<f32> {
    if !has_colliders() {
        return vec4<f32>(x, 0.0);
    }
    let local = rigid_inverse_apply(sim.h1, x);
    let near = nearest_collider(local);
    if near.w < margin {
        let n = quat_rotate(sim.h1.rotation, near.xyz);
        return vec4<f32>(x + n * (margin - near.w), 1.0);
    }
    return vec4<f32>(x, 0.0);
}

@compute @workgroup_size(64)
fn constraints(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let s = thread_index(id, groups);
    if s >= sim.counts.y {
        return;
    }
    let first = offsets[s];
    let n = offsets[s + 1u] - first;
    if n < 2u {
        return;
    }
    var x: array<vec3<f32>, SIM_MAX_VERTICES>;
    for (var k = 0u; k < n; k = k + 1u) {
        x[k] = cur[first + k].xyz;
    }
    var dir: array<vec3<f32>, SIM_MAX_VERTICES>;
    var diag: array<f32, SIM_MAX_VERTICES>;
    var upper: array<f32, SIM_MAX_VERTICES>;
    var lambda: array<f32, SIM_MAX_VERTICES>;
    let m = n - 1u;
    let head_rotation = sim.h1.rotation;
    for (var it = 0u; it < sim.counts.z; it = it + 1u) {
        // tress_sim::step::project_lengths.
        for (var step = 0u; step < SIM_PROJECTION_STEPS; step = step + 1u) {
            for (var k = 0u; k < m; k = k + 1u) {
                let d = x[k + 1u] - x[k];
                let len = length(d);
                dir[k] = select(vec3<f32>(0.0), d / len, len > 1e-12);
                lambda[k] = -(len - rest[first + k + 1u].rest_len);
            }
            for (var k = 0u; k < m; k = k + 1u) {
                diag[k] = select(2.0, 1.0, k == 0u);
                upper[k] = select(0.0, -dot(dir[k], dir[k + 1u]), k + 1u < m);
            }
            for (var k = 1u; k < m; k = k + 1u) {
                let f = upper[k - 1u] / diag[k - 1u];
                diag[k] -= f * upper[k - 1u];
                lambda[k] -= f * lambda[k - 1u];
            }
            lambda[m - 1u] /= diag[m - 1u];
            for (var kk = 0u; kk + 1u < m; kk = kk + 1u) {
                let k = m - 2u - kk;
                lambda[k] = (lambda[k] - upper[k] * lambda[k + 1u]) / diag[k];
            }
            for (var k = 0u; k < m; k = k + 1u) {
                let dx = dir[k] * lambda[k];
                if k > 0u {
                    x[k] -= dx;
                }
                x[k + 1u] += dx;
            }
        }
        // Local shape (tress_sim::step::solve_strand).
        let k_local = sim.shape.x;
        if k_local > 0.0 {
            var frame = head_rotation;
            for (var k = 0u; k < m; k = k + 1u) {
                let r = rest[first + k + 1u].position - rest[first + k].position;
                let aim = x[k] + quat_rotate(frame, r);
                let delta = (aim - x[k + 1u]) * k_local;
                if k == 0u {
                    x[1u] += delta;
                } else {
                    x[k] -= delta * 0.5;
                    x[k + 1u] += delta * 0.5;
                }
                let want = normalize_or_zero(quat_rotate(frame, r));
                let got = normalize_or_zero(x[k + 1u] - x[k]);
                if any(want != vec3<f32>(0.0)) && any(got != vec3<f32>(0.0)) {
                    frame = normalize(quat_mul(quat_arc(want, got), frame));
                }
            }
        }
        // Global shape.
        let k_global = sim.shape.y;
        if k_global > 0.0 {
            for (var k = 1u; k < n; k = k + 1u) {
                let r = rest[first + k];
                let w = k_global * r.global_w;
                if w > 0.0 {
                    x[k] += (rigid_apply(sim.h1, r.position) - x[k]) * w;
                }
            }
        }
        for (var k = 1u; k < n; k = k + 1u) {
            x[k] = collide(x[k], rest[first + k].margin).xyz;
        }
    }
    // Follow the leader and collide, alternately (the previous position moves with the length
    // correction, so the correction adds no velocity).
    for (var k = 1u; k < n; k = k + 1u) {
        let r = rest[first + k];
        var p = prev[first + k].xyz;
        for (var round = 0u; round < SIM_FINAL_ROUNDS; round = round + 1u) {
            let d = x[k] - x[k - 1u];
            let len = length(d);
            if len > 1e-12 {
                let moved = x[k - 1u] + d * (r.rest_len / len);
                p += moved - x[k];
                x[k] = moved;
            }
            let c = collide(x[k], r.margin);
            x[k] = c.xyz;
            if c.w == 0.0 {
                break;
            }
        }
        prev[first + k] = vec4<f32>(p, 0.0);
    }
    for (var k = 0u; k < n; k = k + 1u) {
        cur[first + k] = vec4<f32>(x[k], 0.0);
    }
}

@compute @workgroup_size(64)
fn friction(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = thread_index(id, groups);
    if i >= sim.counts.x || is_root(i) || !has_colliders() || sim.grid_params.z <= 0.0 {
        return;
    }
    let x = cur[i].xyz;
    let local = rigid_inverse_apply(sim.h1, x);
    let near = nearest_collider(local);
    if near.w >= rest[i].margin * 1.001 + 1e-5 {
        return;
    }
    // tress_sim::step::friction.
    let normal = quat_rotate(sim.h1.rotation, near.xyz);
    let surface = x - rigid_apply(sim.h0, local);
    let rel = (x - prev[i].xyz) - surface;
    let vn = dot(rel, normal);
    let tangential = rel - normal * vn;
    let kept = tangential * (1.0 - sim.grid_params.z) + normal * max(vn, 0.0);
    prev[i] = vec4<f32>(x - (surface + kept), 0.0);
}
