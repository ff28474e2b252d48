//! The strand simulation on the GPU: [`GpuSimulation`], the twin of [`tress_sim::Simulation`].
//!
//! Its state (three position buffers that take turns as previous, current and next, the rest
//! data, the hair–hair grid, the head's signed distance field) lives on the GPU, and
//! [`GpuSimulation::write_positions`] writes the simulated hair straight into a renderer's
//! vertex buffer ([`crate::StrandGeometry`]), so a frame reads nothing back. The CPU
//! [`tress_sim::Simulation`] it is made from keeps the clock and the head (it decides each
//! step's substeps, [`tress_sim::Simulation::substeps_of`]); the math of every pass is the CPU
//! twin's, compared in `tests/sim_gpu.rs`.
//!
//! # Implementation
//!
//! A substep is one compute pass of `sim_step.wgsl`'s entry points (`SimStep`): `shock` (when the
//! head turns fast enough), `integrate` (into the next buffer), the grid's `grid_clear`,
//! `grid_splat`, `grid_apply` (when hair–hair friction or volume is on), `constraints` (a strand
//! an invocation, the strand in registers, at most [`MAX_SIM_VERTICES`] vertices) and `friction`
//! (when there are colliders). Each substep's uniforms are one slot of a ring bound with a
//! dynamic offset, so a frame's steps are recorded into one encoder. A teleport moves the state
//! rigidly first (`teleport`). A frame then runs `sim_output.wgsl`: each guide segment's frame,
//! the guides' positions, and the followers rebuilt from them.
//!
//! # Timing
//!
//! With [`GpuSimulation::set_timing`] on (and a device with timestamp queries), a substep runs
//! as three compute passes, `sim/integrate` (shock propagation and integration), `sim/grid` (the
//! hair–hair grid) and `sim/constraints` (constraints, collisions, friction), and the output as
//! `sim/output`, each writing GPU timestamps; every submission's are resolved, read back and
//! summed over its substeps ([`GpuSimulation::take_timings`]). The substep's passes are the same
//! with timing off; only the timestamps and the readback are skipped.

mod buffers;
mod sim_output;
mod sim_step;

use glam::Vec3;
use tress_sim::{Rigid, Simulation};

use crate::gpu::types::{RigidGpu, SimOutputParams, SimParams};
use crate::gpu::{GpuTimer, PassTiming, Timings, read_whole_buffer};
use crate::{GpuContext, RenderError, StrandGeometry};

/// The simulation's timed passes, in the order a step runs them.
pub const SIM_PASS_NAMES: [&str; 4] =
    ["sim/integrate", "sim/grid", "sim/constraints", "sim/output"];

pub(crate) use buffers::SimBuffers;
use sim_output::SimOutput;
use sim_step::SimStep;

/// The most vertices a simulated strand may have (the constraint pass keeps a strand in
/// registers; `shaders/common/sim.wgsl`'s `SIM_MAX_VERTICES`).
pub const MAX_SIM_VERTICES: usize = 64;

/// Bytes between two substeps' uniforms (a multiple of every device's uniform offset alignment).
pub const UNIFORM_STRIDE: u64 = 512;
/// Substeps a ring of uniforms holds; more in one call are recorded in several submissions.
pub(crate) const UNIFORM_SLOTS: usize = 64;

/// A simulation on the GPU (see the module docs).
#[derive(Debug)]
pub struct GpuSimulation {
    cpu: Simulation,
    step: SimStep,
    output: SimOutput,
    buffers: SimBuffers,
    /// Which position buffer is the current one.
    phase: usize,
    /// Timestamps (a slot a substep of a submission) and their readback copy, while timing.
    timer: Option<(GpuTimer, wgpu::Buffer)>,
    /// GPU milliseconds a pass, summed since the last [`GpuSimulation::take_timings`].
    timed: Vec<f64>,
}

impl GpuSimulation {
    /// Upload `sim` (its state now) to the GPU. Strands of more than [`MAX_SIM_VERTICES`]
    /// vertices are an error.
    pub fn new(ctx: &GpuContext, sim: Simulation) -> Result<Self, RenderError> {
        let layout = sim.layout();
        if let Some(g) = (0..layout.offsets.len() - 1)
            .find(|&g| (layout.offsets[g + 1] - layout.offsets[g]) as usize > MAX_SIM_VERTICES)
        {
            return Err(RenderError::Invalid(format!(
                "simulated strand {g} has {} vertices; the GPU simulation takes at most {MAX_SIM_VERTICES} (resample the hair)",
                layout.offsets[g + 1] - layout.offsets[g]
            )));
        }
        let buffers = SimBuffers::new(ctx, &sim)?;
        let step = SimStep::new(ctx, &buffers)?;
        let output = SimOutput::new(ctx, &buffers)?;
        Ok(GpuSimulation {
            cpu: sim,
            step,
            output,
            buffers,
            phase: 0,
            timer: None,
            timed: vec![0.0; SIM_PASS_NAMES.len()],
        })
    }

    /// Time the passes with GPU timestamps from now on (on a device that has them), or stop.
    pub fn set_timing(&mut self, ctx: &GpuContext, on: bool) {
        if !on || !ctx.caps.timestamps {
            self.timer = None;
            return;
        }
        if self.timer.is_none() {
            let timer = GpuTimer::with_objects(ctx, "sim/timer", &SIM_PASS_NAMES, UNIFORM_SLOTS);
            let copy = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sim/timer/copy"),
                size: timer.resolved_bytes(),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            self.timer = Some((timer, copy));
        }
    }

    /// The GPU time of each pass since the last call (summed over its substeps and
    /// submissions), or `NotSupported` when the passes were not timed.
    pub fn take_timings(&mut self) -> Timings {
        if self.timer.is_none() {
            return Timings::NotSupported;
        }
        let passes = SIM_PASS_NAMES
            .iter()
            .zip(&self.timed)
            .map(|(name, &ms)| PassTiming { name, ms })
            .collect();
        self.timed.fill(0.0);
        Timings::Passes(passes)
    }

    /// Submit `encoder`; while timing, resolve its timestamps first and add them up.
    fn submit_timed(
        &mut self,
        ctx: &GpuContext,
        mut encoder: wgpu::CommandEncoder,
    ) -> Result<(), RenderError> {
        let Some((timer, copy)) = &self.timer else {
            ctx.queue.submit([encoder.finish()]);
            return Ok(());
        };
        timer.resolve(&mut encoder, copy, 0);
        ctx.queue.submit([encoder.finish()]);
        let bytes = read_whole_buffer(ctx, copy, "sim/timer/readback")?;
        if let Timings::Passes(passes) = timer.parse(&bytes, &timer.written()) {
            for p in passes {
                if let Some(i) = SIM_PASS_NAMES.iter().position(|n| *n == p.name) {
                    self.timed[i] += p.ms;
                }
            }
        }
        timer.begin_frame(ctx)?;
        Ok(())
    }

    /// The CPU side: settings, clock, head.
    pub fn simulation(&self) -> &Simulation {
        &self.cpu
    }

    /// Bytes of GPU memory the simulation holds.
    pub fn bytes(&self) -> u64 {
        self.buffers.bytes
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.cpu.steps()
    }

    /// Run the steps due by `t` seconds (as [`Simulation::advance_to`]), the head at
    /// `motion(time)` at the end of each; returns the steps run.
    pub fn advance_to(
        &mut self,
        ctx: &GpuContext,
        t: f64,
        motion: impl Fn(f32) -> Rigid,
    ) -> Result<u64, RenderError> {
        let rate = f64::from(self.cpu.settings().rate_hz);
        let target = (t * rate + 1e-9).floor().max(0.0) as u64;
        let mut heads = Vec::new();
        let mut k = self.cpu.steps();
        while k < target {
            heads.push(motion(((k + 1) as f64 / rate) as f32));
            k += 1;
        }
        self.steps_to(ctx, &heads)?;
        Ok(heads.len() as u64)
    }

    /// One step, the head moving to `head`.
    pub fn step(&mut self, ctx: &GpuContext, head: Rigid) -> Result<(), RenderError> {
        self.steps_to(ctx, &[head])
    }

    /// Steps ending with the head at each of `heads`, recorded and submitted in as few
    /// submissions as the uniform ring allows.
    fn steps_to(&mut self, ctx: &GpuContext, heads: &[Rigid]) -> Result<(), RenderError> {
        let mut pending: Vec<SimParams> = Vec::new();
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sim/step/encoder"),
            });
        let mut recorded = 0usize;
        for &head in heads {
            let (subs, teleport) = self.cpu.substeps_of(head);
            if pending.len() + subs.len() > UNIFORM_SLOTS {
                self.submit(ctx, encoder, &pending)?;
                pending.clear();
                recorded = 0;
                encoder = ctx
                    .device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("sim/step/encoder"),
                    });
            }
            if teleport {
                // Teleports are rare: submit what is recorded, then move the state rigidly.
                self.submit(ctx, encoder, &pending)?;
                pending.clear();
                recorded = 0;
                let delta = head.then(&self.cpu.head().inverse());
                self.teleport(ctx, delta)?;
                encoder = ctx
                    .device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("sim/step/encoder"),
                    });
            }
            for sub in &subs {
                let params = self.buffers.params(self.cpu.settings(), sub);
                let slot = pending.len();
                pending.push(params);
                self.step.encode(
                    &mut encoder,
                    &self.buffers,
                    (self.phase, slot),
                    &params,
                    self.timer.as_ref().map(|t| &t.0),
                );
                self.phase = (self.phase + 1) % 3;
                recorded += 1;
            }
            self.cpu.advance_clock(head);
        }
        let _ = recorded;
        self.submit(ctx, encoder, &pending)
    }

    fn submit(
        &mut self,
        ctx: &GpuContext,
        encoder: wgpu::CommandEncoder,
        params: &[SimParams],
    ) -> Result<(), RenderError> {
        if !params.is_empty() {
            ctx.queue.write_buffer(
                &self.buffers.uniforms,
                0,
                &params
                    .iter()
                    .flat_map(|p| {
                        let mut slot = bytemuck::bytes_of(p).to_vec();
                        slot.resize(UNIFORM_STRIDE as usize, 0);
                        slot
                    })
                    .collect::<Vec<u8>>(),
            );
        }
        self.submit_timed(ctx, encoder)
    }

    /// Move every position rigidly by `delta` (a teleport): read back, moved, written again.
    fn teleport(&mut self, ctx: &GpuContext, delta: Rigid) -> Result<(), RenderError> {
        let (prev, cur) = self.buffers.read_state(ctx, self.phase)?;
        let moved = |v: Vec<Vec3>| -> Vec<[f32; 4]> {
            v.into_iter()
                .map(|p| delta.apply(p).extend(0.0).to_array())
                .collect()
        };
        self.buffers
            .write_state(ctx, self.phase, &moved(prev), &moved(cur));
        Ok(())
    }

    /// Write the simulated hair (guides and followers) into `geometry`'s vertex buffer, whose
    /// strands must be those the simulation was made from, in the same order.
    pub fn write_positions(
        &mut self,
        ctx: &GpuContext,
        geometry: &StrandGeometry,
    ) -> Result<(), RenderError> {
        let total = self.buffers.asset_vertices;
        if geometry.vertex_count() as usize != total {
            return Err(RenderError::Invalid(format!(
                "the simulation has {total} vertices, the geometry {}",
                geometry.vertex_count()
            )));
        }
        let params = SimOutputParams {
            head_rotation: RigidGpu::from(self.cpu.head()).rotation,
            counts: [
                self.buffers.guide_vertices,
                self.buffers.follower_vertices,
                self.buffers.followers_count,
                0,
            ],
        };
        ctx.queue
            .write_buffer(&self.buffers.output_uniform, 0, bytemuck::bytes_of(&params));
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sim/output/encoder"),
            });
        self.output.encode(
            ctx,
            &mut encoder,
            &self.buffers,
            self.phase,
            geometry,
            self.timer.as_ref().map(|t| &t.0),
        );
        self.submit_timed(ctx, encoder)
    }

    /// The guides' positions now (read back: for tests and caches, not frames).
    pub fn read_guides(&self, ctx: &GpuContext) -> Result<Vec<Vec3>, RenderError> {
        Ok(self.buffers.read_state(ctx, self.phase)?.1)
    }
}
