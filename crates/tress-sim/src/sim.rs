//! [`Simulation`]: the CPU twin of the solver, a whole step.

use glam::{Quat, Vec3};
use rayon::prelude::*;
use tress_hair::HairAsset;
use tress_hair::generate::TriMesh;

use crate::SimError;
use crate::collide::{Colliders, Sdf};
use crate::follow::Binding;
use crate::follow::{bind, keep_lengths, sample_at, segment_frames};
use crate::grid::HairGrid;
use crate::motion::Rigid;
use crate::settings::SimSettings;
use crate::step::{StrandParams, friction, integrate, solve_strand};
use crate::wind::{air_velocity, drag};

/// Which of an asset's strands are simulated.
#[derive(Clone, Debug, PartialEq)]
pub enum GuideChoice {
    /// Every `stride`-th strand from the first (`simulation.guides` as `1/stride`).
    Share(f32),
    /// These strands (an asset whose guides are known, as after `follow`).
    Strands(Vec<u32>),
}

/// One simulated head of hair: its guides' state, the followers' bindings, the colliders and the
/// hair–hair grid, advanced in fixed steps (see the crate docs).
#[derive(Clone, Debug)]
pub struct Simulation {
    settings: SimSettings,
    /// Vertex offsets of the guides (CSR).
    offsets: Vec<u32>,
    /// Rest positions, head space.
    rest: Vec<Vec3>,
    rest_len: Vec<f32>,
    global_w: Vec<f32>,
    /// Collision margin a vertex (see [`StrandParams::margin`]).
    margin: Vec<f32>,
    /// Positions and previous positions, world space.
    x: Vec<Vec3>,
    x_prev: Vec<Vec3>,
    colliders: Colliders,
    grid: HairGrid,
    head: Rigid,
    steps: u64,
    /// Per asset strand: `(true, guide)` or `(false, follower)`.
    strands: Vec<(bool, u32)>,
    /// Vertex offsets of the followers (CSR), their bindings and rest offsets (head space).
    follower_offsets: Vec<u32>,
    bindings: Vec<Binding>,
    follower_rest: Vec<Vec3>,
    /// Rest length of the segment ending at each follower vertex (0 at a root).
    follower_len: Vec<f32>,
    /// The asset's vertex offsets, for output in its order.
    asset_offsets: Vec<u32>,
}

/// A simulation's arrays, for a GPU twin to upload (see the fields of [`Simulation`]).
#[derive(Clone, Debug)]
pub struct SimLayout<'a> {
    /// Guide vertex offsets (CSR, guides + 1 entries).
    pub offsets: &'a [u32],
    /// Rest positions, head space.
    pub rest: &'a [Vec3],
    /// Rest length of the segment ending at each vertex.
    pub rest_len: &'a [f32],
    /// Global shape weight of each vertex.
    pub global_w: &'a [f32],
    /// Collision margin of each vertex.
    pub margin: &'a [f32],
    /// Positions and previous positions now.
    pub x: &'a [Vec3],
    /// Previous positions now.
    pub x_prev: &'a [Vec3],
    /// The first asset vertex of each guide.
    pub guide_first: Vec<u32>,
    /// Follower vertex offsets (CSR), bindings and rest offsets.
    pub follower_offsets: &'a [u32],
    /// Each follower's guides and weights.
    pub bindings: &'a [Binding],
    /// Each follower vertex's rest offset from its guides' blend, head space.
    pub follower_rest: &'a [Vec3],
    /// Rest length of the segment ending at each follower vertex (0 at a root).
    pub follower_len: &'a [f32],
    /// The first asset vertex of each follower.
    pub follower_first: Vec<u32>,
    /// The hair–hair grid (its placement and rest weights).
    pub grid: &'a HairGrid,
}

/// What a step did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// The head moved further than `teleport_distance`: the hair was moved with it.
    pub teleported: bool,
}

/// One substep's head motion and time (see [`Simulation::substeps_of`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Substep {
    /// The head at its start.
    pub h0: Rigid,
    /// The head at its end.
    pub h1: Rigid,
    /// `h1` after the inverse of `h0`.
    pub delta: Rigid,
    /// The shock propagation weight.
    pub shock: f32,
    /// Seconds at its end (the wind's time).
    pub time: f32,
}

fn strand_offsets(asset: &HairAsset, strands: impl Iterator<Item = usize>) -> Vec<u32> {
    let mut offsets = vec![0u32];
    for s in strands {
        let n = asset.strand_range(s).len() as u32;
        offsets.push(offsets.last().copied().unwrap_or(0) + n);
    }
    offsets
}

impl Simulation {
    /// Set up the simulation of `asset` (head space: where it is at rest), colliding with
    /// `head_mesh` (head space) and the settings' spheres and capsules, starting with the head
    /// at `head` (the asset is moved there).
    pub fn new(
        asset: &HairAsset,
        head_mesh: Option<&TriMesh>,
        settings: &SimSettings,
        guides: &GuideChoice,
        head: Rigid,
    ) -> Result<Simulation, SimError> {
        settings.validate()?;
        let count = asset.strand_count();
        let is_guide: Vec<bool> = match guides {
            GuideChoice::Share(share) => {
                let stride = (1.0 / share.clamp(1e-6, 1.0)).round().max(1.0) as usize;
                (0..count).map(|s| s % stride == 0).collect()
            }
            GuideChoice::Strands(list) => {
                let mut flags = vec![false; count];
                for &s in list {
                    *flags.get_mut(s as usize).ok_or_else(|| {
                        SimError::Invalid(format!("guide strand {s} of {count} strands"))
                    })? = true;
                }
                flags
            }
        };
        if !is_guide.iter().any(|&g| g) {
            return Err(SimError::Invalid("no strand is a guide".into()));
        }
        let guide_ids: Vec<usize> = (0..count).filter(|&s| is_guide[s]).collect();
        let follower_ids: Vec<usize> = (0..count).filter(|&s| !is_guide[s]).collect();
        let offsets = strand_offsets(asset, guide_ids.iter().copied());
        let positions = asset.positions();
        let mut rest = Vec::with_capacity(*offsets.last().unwrap_or(&0) as usize);
        let mut rest_len = Vec::with_capacity(rest.capacity());
        let mut global_w = Vec::with_capacity(rest.capacity());
        for &s in &guide_ids {
            let r = asset.strand_range(s);
            let n = r.len();
            for (k, i) in r.enumerate() {
                rest.push(positions[i]);
                rest_len.push(if k == 0 {
                    0.0
                } else {
                    positions[i].distance(positions[i - 1])
                });
                // Linear fade from the root to `global_range` of the strand.
                let f = k as f32 / (n.max(2) - 1) as f32;
                let range = settings.global_range;
                global_w.push(if range > 0.0 && f < range {
                    1.0 - f / range
                } else {
                    0.0
                });
            }
        }
        let x: Vec<Vec3> = rest.iter().map(|p| head.apply(*p)).collect();
        // Followers.
        let guide_roots: Vec<Vec3> = guide_ids
            .iter()
            .map(|&s| positions[asset.strand_range(s).start])
            .collect();
        let follower_roots: Vec<Vec3> = follower_ids
            .iter()
            .map(|&s| positions[asset.strand_range(s).start])
            .collect();
        let bindings = bind(&guide_roots, &follower_roots, settings.follow);
        let follower_offsets = strand_offsets(asset, follower_ids.iter().copied());
        let mut follower_rest = Vec::with_capacity(*follower_offsets.last().unwrap_or(&0) as usize);
        let mut follower_len = Vec::with_capacity(follower_rest.capacity());
        for (f, &s) in follower_ids.iter().enumerate() {
            let r = asset.strand_range(s);
            let m = r.len();
            for (j, i) in r.enumerate() {
                let frac = if m < 2 {
                    0.0
                } else {
                    j as f32 / (m - 1) as f32
                };
                let blend = blend_at(&offsets, &rest, &bindings[f], frac);
                follower_rest.push(positions[i] - blend);
                follower_len.push(if j == 0 {
                    0.0
                } else {
                    positions[i].distance(positions[i - 1])
                });
            }
        }
        let mut strands = vec![(false, 0); count];
        for (g, &s) in guide_ids.iter().enumerate() {
            strands[s] = (true, g as u32);
        }
        for (f, &s) in follower_ids.iter().enumerate() {
            strands[s] = (false, f as u32);
        }
        let colliders = Colliders {
            sdf: head_mesh.and_then(|m| Sdf::build(m, settings.sdf_resolution)),
            spheres: settings.spheres.clone(),
            capsules: settings.capsules.clone(),
        };
        // The grid covers the rest hair padded by its longest strand.
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &rest {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let longest = (0..guide_ids.len())
            .map(|g| {
                rest_len[offsets[g] as usize..offsets[g + 1] as usize]
                    .iter()
                    .sum::<f32>()
            })
            .fold(0.0f32, f32::max);
        let pad = Vec3::splat(longest * 0.5 + 1e-3);
        let mut grid = HairGrid::new(lo - pad, hi + pad, settings.hair_grid);
        for p in &rest {
            grid.splat(*p, Vec3::ZERO);
        }
        grid.keep_as_rest();
        // A vertex closer to a collider at rest than the margin (near a root) keeps its rest
        // distance instead, so the rest pose is a fixed point.
        let margin = rest
            .iter()
            .map(|p| match colliders.nearest(*p) {
                Some((d, _)) => d.min(settings.collision_margin),
                None => settings.collision_margin,
            })
            .collect();
        let asset_offsets = strand_offsets(asset, 0..count);
        Ok(Simulation {
            margin,
            settings: settings.clone(),
            offsets,
            rest,
            rest_len,
            global_w,
            x_prev: x.clone(),
            x,
            colliders,
            grid,
            head,
            steps: 0,
            strands,
            follower_offsets,
            bindings,
            follower_rest,
            follower_len,
            asset_offsets,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &SimSettings {
        &self.settings
    }

    /// Change settings that need no new set-up (stiffness, damping, wind, gravity, friction,
    /// volume, iterations, substeps, rate, shock, margin); the others keep their values.
    pub fn set_live(&mut self, s: &SimSettings) -> Result<(), SimError> {
        s.validate()?;
        let keep = self.settings.clone();
        self.settings = SimSettings {
            global_range: keep.global_range,
            hair_grid: keep.hair_grid,
            guides: keep.guides,
            follow: keep.follow,
            spheres: keep.spheres,
            capsules: keep.capsules,
            sdf_resolution: keep.sdf_resolution,
            ..s.clone()
        };
        Ok(())
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Simulated seconds.
    pub fn time(&self) -> f64 {
        self.steps as f64 / f64::from(self.settings.rate_hz)
    }

    /// The head at the last step.
    pub fn head(&self) -> Rigid {
        self.head
    }

    /// Number of guides, and of followers.
    pub fn counts(&self) -> (usize, usize) {
        (self.offsets.len() - 1, self.bindings.len())
    }

    /// The guides' positions (world), their vertex offsets and rest lengths a vertex.
    pub fn guides(&self) -> (&[Vec3], &[u32], &[f32]) {
        (&self.x, &self.offsets, &self.rest_len)
    }

    /// The arrays a GPU twin uploads.
    pub fn layout(&self) -> SimLayout<'_> {
        let (mut guide_first, mut follower_first) = (
            vec![0; self.offsets.len() - 1],
            vec![0; self.bindings.len()],
        );
        for (s, &(is_guide, k)) in self.strands.iter().enumerate() {
            let first = self.asset_offsets[s];
            if is_guide {
                guide_first[k as usize] = first;
            } else {
                follower_first[k as usize] = first;
            }
        }
        SimLayout {
            offsets: &self.offsets,
            rest: &self.rest,
            rest_len: &self.rest_len,
            global_w: &self.global_w,
            margin: &self.margin,
            x: &self.x,
            x_prev: &self.x_prev,
            guide_first,
            follower_offsets: &self.follower_offsets,
            bindings: &self.bindings,
            follower_rest: &self.follower_rest,
            follower_len: &self.follower_len,
            follower_first,
            grid: &self.grid,
        }
    }

    /// The per-substep values of the step that moves the head from where it is to `head`:
    /// what the GPU twin puts in its uniforms. Also returns whether the step teleports.
    pub fn substeps_of(&self, head: Rigid) -> (Vec<Substep>, bool) {
        let s = &self.settings;
        let teleport = (head.translation - self.head.translation).length() > s.teleport_distance;
        let from = if teleport { head } else { self.head };
        let dt = s.substep_dt();
        let t0 = self.time() as f32;
        let subs = (0..s.substeps)
            .map(|sub| {
                let a = sub as f32 / s.substeps as f32;
                let b = (sub + 1) as f32 / s.substeps as f32;
                let (h0, h1) = (Rigid::lerp(&from, &head, a), Rigid::lerp(&from, &head, b));
                let delta = h1.then(&h0.inverse());
                let omega = delta.rotation.angle_between(Quat::IDENTITY) / dt;
                let shock =
                    s.shock * ((omega - s.shock_threshold) / s.shock_threshold).clamp(0.0, 1.0);
                Substep {
                    h0,
                    h1,
                    delta,
                    shock,
                    time: t0 + b / s.rate_hz,
                }
            })
            .collect();
        (subs, teleport)
    }

    /// Record a step taken elsewhere (by a GPU twin): the head and the step count advance as
    /// [`Simulation::step`] would advance them, the positions do not.
    pub fn advance_clock(&mut self, head: Rigid) {
        self.head = head;
        self.steps += 1;
    }

    /// The colliders (head space).
    pub fn colliders(&self) -> &Colliders {
        &self.colliders
    }

    /// Put the hair back at rest on the head at `head`, with no velocity.
    pub fn reset(&mut self, head: Rigid) {
        self.x = self.rest.iter().map(|p| head.apply(*p)).collect();
        self.x_prev = self.x.clone();
        self.head = head;
        self.steps = 0;
    }

    /// One step of `1 / rate_hz` seconds, the head moving from where it was to `head`.
    pub fn step(&mut self, head: Rigid) -> StepReport {
        let s = self.settings.clone();
        let mut report = StepReport::default();
        let mut from = self.head;
        if (head.translation - from.translation).length() > s.teleport_distance {
            // Teleport: move the hair with the head, keeping its shape and velocity.
            let delta = head.then(&from.inverse());
            for (x, xp) in self.x.iter_mut().zip(&mut self.x_prev) {
                *x = delta.apply(*x);
                *xp = delta.apply(*xp);
            }
            from = head;
            report.teleported = true;
        }
        let dt = s.substep_dt();
        let decay = (-s.damping * dt).exp();
        let params = (
            s.per_iteration(s.local_stiffness),
            s.per_iteration(s.global_stiffness),
        );
        let t0 = self.time() as f32;
        for sub in 0..s.substeps {
            let a = sub as f32 / s.substeps as f32;
            let b = (sub + 1) as f32 / s.substeps as f32;
            let (h0, h1) = (Rigid::lerp(&from, &head, a), Rigid::lerp(&from, &head, b));
            let time = t0 + b / s.rate_hz;
            self.substep(&h0, &h1, dt, decay, params, time);
        }
        self.head = head;
        self.steps += 1;
        report
    }

    fn substep(
        &mut self,
        h0: &Rigid,
        h1: &Rigid,
        dt: f32,
        decay: f32,
        (k_local, k_global): (f32, f32),
        time: f32,
    ) {
        let s = &self.settings;
        let delta = h1.then(&h0.inverse());
        // Velocity shock propagation.
        let omega = delta.rotation.angle_between(Quat::IDENTITY) / dt;
        let shock = s.shock * ((omega - s.shock_threshold) / s.shock_threshold).clamp(0.0, 1.0);
        let roots: Vec<bool> = {
            let mut r = vec![false; self.x.len()];
            for g in 0..self.offsets.len() - 1 {
                r[self.offsets[g] as usize] = true;
            }
            r
        };
        // Shock propagation, then integration from the positions as they were (the GPU runs a
        // vertex a thread: the tangent reads the parent's position before anything moved it).
        let (x, xp) = (&mut self.x, &mut self.x_prev);
        if shock > 0.0 {
            for i in 0..x.len() {
                if !roots[i] {
                    x[i] = x[i].lerp(delta.apply(x[i]), shock);
                    xp[i] = xp[i].lerp(delta.apply(xp[i]), shock);
                }
            }
        }
        let cur = x.clone();
        for i in 0..x.len() {
            if roots[i] {
                xp[i] = cur[i];
                x[i] = h1.apply(self.rest[i]);
                continue;
            }
            let tangent = (cur[i] - cur[i - 1]).normalize_or_zero();
            let air = air_velocity(&s.wind, cur[i], time);
            let accel = s.gravity + drag(&s.wind, air, (cur[i] - xp[i]) / dt, tangent);
            (x[i], xp[i]) = integrate(cur[i], xp[i], decay, accel, dt);
        }
        // Hair–hair interaction.
        if s.hair_friction > 0.0 || s.hair_volume > 0.0 {
            let inv = h1.inverse();
            self.grid.clear();
            for i in 0..x.len() {
                if !roots[i] {
                    let v = inv.turn(x[i] - xp[i]) / self.grid.cell;
                    self.grid.splat(inv.apply(x[i]), v);
                }
            }
            for i in 0..x.len() {
                if roots[i] {
                    continue;
                }
                let local = inv.apply(x[i]);
                let v_grid = h1.turn(self.grid.velocity(local)) * self.grid.cell;
                let v = x[i] - xp[i];
                x[i] += (v_grid - v) * s.hair_friction;
                let push = self.grid.excess_gradient(local) * (-s.hair_volume);
                let push = push.clamp_length_max(crate::grid::MAX_PUSH_CELLS);
                x[i] += h1.turn(push) * self.grid.cell;
            }
        }
        // Constraints, a strand at a time.
        let colliders = &self.colliders;
        let iterations = s.iterations;
        let (offsets, rest, rest_len, global_w, margins) = (
            &self.offsets,
            &self.rest,
            &self.rest_len,
            &self.global_w,
            &self.margin,
        );
        let mut slices: Vec<(&mut [Vec3], &mut [Vec3])> = Vec::with_capacity(offsets.len() - 1);
        let (mut tail, mut tail_prev): (&mut [Vec3], &mut [Vec3]) = (x, xp);
        for g in 0..offsets.len() - 1 {
            let n = (offsets[g + 1] - offsets[g]) as usize;
            let (a, b) = tail.split_at_mut(n);
            let (ap, bp) = tail_prev.split_at_mut(n);
            slices.push((a, ap));
            tail = b;
            tail_prev = bp;
        }
        slices
            .into_par_iter()
            .enumerate()
            .for_each(|(g, (strand, strand_prev))| {
                let r = offsets[g] as usize..offsets[g + 1] as usize;
                let p = StrandParams {
                    rest: &rest[r.clone()],
                    rest_len: &rest_len[r.clone()],
                    global_w: &global_w[r.clone()],
                    margin: &margins[r],
                    head: *h1,
                    k_local,
                    k_global,
                    iterations,
                };
                solve_strand(strand, strand_prev, &p, colliders);
            });
        let (x, xp) = (&mut self.x, &mut self.x_prev);
        // Friction with the colliders.
        if !colliders.is_empty() && s.friction > 0.0 {
            for i in 0..x.len() {
                if roots[i] {
                    continue;
                }
                let local = h1.inverse().apply(x[i]);
                if let Some((d, n)) = colliders.nearest(local)
                    && d < self.margin[i] * 1.001 + 1e-5
                {
                    let surface = x[i] - h0.apply(local);
                    xp[i] = friction(x[i], xp[i], h1.turn(n), surface, s.friction);
                }
            }
        }
    }

    /// Run the steps that end by `t` seconds of simulated time (`floor(t · rate_hz)` steps in
    /// all since the start), step `k` ending with the head at `motion(k / rate_hz)`. The state
    /// at a time depends only on that time, not on how often this is called: a display at any
    /// rate sees the same states. Returns the steps run.
    pub fn advance_to(&mut self, t: f64, motion: impl Fn(f32) -> Rigid) -> u64 {
        let rate = f64::from(self.settings.rate_hz);
        let target = (t * rate + 1e-9).floor().max(0.0) as u64;
        let mut ran = 0;
        while self.steps < target {
            let end = (self.steps + 1) as f64 / rate;
            self.step(motion(end as f32));
            ran += 1;
        }
        ran
    }

    /// Every strand's positions (world), in the asset's order: guides as simulated, followers
    /// rebuilt from them.
    pub fn positions(&self) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; *self.asset_offsets.last().unwrap_or(&0) as usize];
        let head_rotation = self.head.rotation;
        // Each guide's segment frames.
        let frames: Vec<Vec<Quat>> = (0..self.offsets.len() - 1)
            .into_par_iter()
            .map(|g| {
                let r = self.offsets[g] as usize..self.offsets[g + 1] as usize;
                let mut f = Vec::new();
                segment_frames(&self.rest[r.clone()], &self.x[r], head_rotation, &mut f);
                f
            })
            .collect();
        let mut slices: Vec<&mut [Vec3]> = Vec::with_capacity(self.strands.len());
        let mut tail: &mut [Vec3] = &mut out;
        for s in 0..self.strands.len() {
            let n = (self.asset_offsets[s + 1] - self.asset_offsets[s]) as usize;
            let (a, b) = tail.split_at_mut(n);
            slices.push(a);
            tail = b;
        }
        slices.into_par_iter().enumerate().for_each(|(s, dst)| {
            let (is_guide, k) = self.strands[s];
            if is_guide {
                let r = self.offsets[k as usize] as usize..self.offsets[k as usize + 1] as usize;
                dst.copy_from_slice(&self.x[r]);
                return;
            }
            let b = &self.bindings[k as usize];
            let first = self.follower_offsets[k as usize] as usize;
            let m = dst.len();
            for (j, out) in dst.iter_mut().enumerate() {
                let frac = if m < 2 {
                    0.0
                } else {
                    j as f32 / (m - 1) as f32
                };
                let blend = blend_at(&self.offsets, &self.x, b, frac);
                // A root turns with the head alone, so it sits exactly where the head carries
                // it (the guides' first segments may have swung).
                let turn = if j == 0 {
                    head_rotation
                } else {
                    blend_frames(&self.offsets, &frames, b, frac)
                };
                *out = blend + turn * self.follower_rest[first + j];
            }
            keep_lengths(dst, &self.follower_len[first..first + m]);
        });
        out
    }

    /// The hair now, as `asset` with its positions replaced.
    pub fn to_asset(&self, asset: &HairAsset) -> Result<HairAsset, SimError> {
        let mut out = asset.clone();
        let positions = self.positions();
        if positions.len() != out.positions().len() {
            return Err(SimError::Invalid(format!(
                "the asset has {} vertices, the simulation {}",
                out.positions().len(),
                positions.len()
            )));
        }
        out.positions_mut().copy_from_slice(&positions);
        Ok(out)
    }
}

/// The blend of a follower's guides at fraction `frac` of their length.
fn blend_at(offsets: &[u32], x: &[Vec3], b: &Binding, frac: f32) -> Vec3 {
    let mut p = Vec3::ZERO;
    for k in 0..3 {
        let w = b.weights[k];
        if w == 0.0 {
            continue;
        }
        let g = b.guides[k] as usize;
        let first = offsets[g] as usize;
        let n = (offsets[g + 1] - offsets[g]) as usize;
        let (seg, t) = sample_at(frac, n);
        let a = x[first + seg];
        let c = if n > 1 { x[first + seg + 1] } else { a };
        p += a.lerp(c, t) * w;
    }
    p
}

/// The blend of a follower's guides' segment frames at fraction `frac`.
fn blend_frames(offsets: &[u32], frames: &[Vec<Quat>], b: &Binding, frac: f32) -> Quat {
    let mut sum = glam::Vec4::ZERO;
    let mut reference: Option<glam::Vec4> = None;
    for k in 0..3 {
        let w = b.weights[k];
        if w == 0.0 {
            continue;
        }
        let g = b.guides[k] as usize;
        let n = (offsets[g + 1] - offsets[g]) as usize;
        let (seg, _) = sample_at(frac, n);
        let q = glam::Vec4::from(frames[g][seg.min(frames[g].len() - 1)]);
        // Quaternions q and -q are one rotation: blend on the same side.
        let q = match reference {
            Some(r) if r.dot(q) < 0.0 => -q,
            _ => q,
        };
        reference.get_or_insert(q);
        sum += q * w;
    }
    let len = sum.length();
    if len > 0.0 {
        Quat::from_vec4(sum / len)
    } else {
        Quat::IDENTITY
    }
}
