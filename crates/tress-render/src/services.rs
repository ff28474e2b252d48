//! [`FrameServices`]: what every technique's renderer draws a frame with, in one place. The view
//! and light uniforms (written once a frame, bound by the technique's passes), the GPU timer
//! (timestamps, or wall clock per stage: [`TimerMode`]), the statistics readback ring and its
//! mode ([`StatsReadback`], honoured by every technique), and the frame counter.
//!
//! A renderer owns one: [`crate::Renderer`], [`crate::PatchRenderer`] and
//! [`crate::SatfRenderer`] are each usable alone by an embedding application, so each holds its
//! services rather than borrowing the session's. A frame goes: [`FrameServices::earlier`]
//! (deferred results, read before the frame is submitted), [`FrameServices::write_view`],
//! [`FrameServices::begin`], the technique's passes into a [`crate::gpu::FrameEncoder`],
//! [`FrameTicket::submit`], [`FrameServices::results`].

use crate::gpu::types::{CameraUniform, LightsUniform};
use crate::gpu::{GpuTimer, TimerMode, Timings, uniform_buffer};
use crate::stats::{ReadbackRing, SlotInfo};
use crate::{Camera, GpuContext, GpuReport, RenderError, StatsReadback};

/// Readback slots per renderer: a frame in flight, one being read, one free.
const RING_SLOTS: usize = 3;

/// The shared frame services of one renderer (see the module's docs).
#[derive(Debug)]
pub(crate) struct FrameServices {
    /// The camera uniform (`CameraUniform`).
    pub(crate) camera: wgpu::Buffer,
    /// The lights uniform (`LightsUniform`).
    pub(crate) lights: wgpu::Buffer,
    pub(crate) timer: GpuTimer,
    pub(crate) ring: ReadbackRing,
    /// How `render` reports the GPU's results.
    pub(crate) readback: StatsReadback,
    frame: u64,
}

/// A frame begun by [`FrameServices::begin`]: its index and its readback slot (`None` when
/// every slot is still in flight: the frame reports no results of its own).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameTicket {
    pub(crate) frame: u64,
    pub(crate) slot: Option<usize>,
}

impl FrameServices {
    /// Services for passes named `names` (see [`GpuTimer`]), timing up to `objects` objects'
    /// passes each on their own; buffers labelled `label/...`.
    pub(crate) fn new(
        ctx: &GpuContext,
        label: &str,
        names: &'static [&'static str],
        objects: usize,
    ) -> Result<Self, RenderError> {
        let (camera, lights) = ctx.scoped("creating the view and light uniforms", || {
            (
                uniform_buffer(
                    ctx,
                    &format!("{label}/uniforms/camera"),
                    &CameraUniform::default(),
                ),
                uniform_buffer(
                    ctx,
                    &format!("{label}/uniforms/lights"),
                    &LightsUniform::default(),
                ),
            )
        })?;
        let timer = GpuTimer::with_objects(ctx, label, names, objects);
        let ring = ReadbackRing::new(ctx, &timer, RING_SLOTS);
        Ok(FrameServices {
            camera,
            lights,
            timer,
            ring,
            readback: StatsReadback::Wait,
            frame: 0,
        })
    }

    /// Time the passes with timestamps or by wall clock from the next frame on.
    pub(crate) fn set_timer_mode(&mut self, mode: TimerMode) {
        self.timer.set_mode(mode);
    }

    /// Write the frame's camera and lights (once a frame; every pass binds these buffers).
    pub(crate) fn write_view(&self, ctx: &GpuContext, camera: &Camera, lights: &LightsUniform) {
        let q = &ctx.queue;
        q.write_buffer(&self.camera, 0, bytemuck::bytes_of(&camera.uniform()));
        q.write_buffer(&self.lights, 0, bytemuck::bytes_of(lights));
    }

    /// Every earlier frame's results that have arrived, the newest, without waiting.
    pub(crate) fn harvest(&mut self, ctx: &GpuContext) -> Result<Option<GpuReport>, RenderError> {
        self.ring.harvest(ctx, &self.timer)
    }

    /// With [`StatsReadback::Deferred`], the newest earlier frame's results, read before this
    /// frame is submitted (so a deferred frame never reports itself); `None` when waiting.
    pub(crate) fn earlier(&mut self, ctx: &GpuContext) -> Result<Option<GpuReport>, RenderError> {
        match self.readback {
            StatsReadback::Deferred => self.harvest(ctx),
            StatsReadback::Wait => Ok(None),
        }
    }

    /// Begin a frame: its index, a free readback slot, and the timer reset (in wall-clock mode
    /// after waiting for earlier work).
    pub(crate) fn begin(&mut self, ctx: &GpuContext) -> Result<FrameTicket, RenderError> {
        let ticket = FrameTicket {
            frame: self.frame,
            slot: self.ring.idle(),
        };
        self.frame += 1;
        self.timer.begin_frame(ctx)?;
        Ok(ticket)
    }

    /// The results `render` reports: with [`StatsReadback::Wait`] this frame's (waited for),
    /// or the newest that arrived when the frame had no slot; with `Deferred`, `earlier`.
    pub(crate) fn results(
        &mut self,
        ctx: &GpuContext,
        ticket: FrameTicket,
        earlier: Option<GpuReport>,
    ) -> Result<Option<GpuReport>, RenderError> {
        match (self.readback, ticket.slot) {
            (StatsReadback::Wait, Some(i)) => self.ring.wait(ctx, &self.timer, i),
            (StatsReadback::Wait, None) => self.harvest(ctx),
            (StatsReadback::Deferred, _) => Ok(earlier),
        }
    }

    /// The frame's timings: the stages' wall-clock times in that mode, else `report`'s
    /// timestamps; none yet (an empty list) before results arrive on a device with timestamps.
    pub(crate) fn timings(&self, ctx: &GpuContext, report: Option<&GpuReport>) -> Timings {
        match (self.timer.wall_timings(), report) {
            (Some(wall), _) => wall,
            (None, Some(r)) => r.timings.clone(),
            (None, None) if ctx.caps.timestamps => Timings::Passes(Vec::new()),
            (None, None) => Timings::NotSupported,
        }
    }
}

impl FrameTicket {
    /// Copy the frame's results into its slot (the OIT or SATF `counters`, each listed
    /// object's voxel statistics, the timestamps), submit `commands` with the copies, and map
    /// the slot.
    pub(crate) fn submit(
        self,
        ctx: &GpuContext,
        (ring, timer): (&mut ReadbackRing, &GpuTimer),
        mut encoder: wgpu::CommandEncoder,
        counters: Option<&wgpu::Buffer>,
        volumes: &[(usize, &wgpu::Buffer)],
        info: SlotInfo,
    ) {
        if let Some(i) = self.slot {
            ring.record(i, &mut encoder, counters, timer, info);
            for &(object, stats) in volumes {
                ring.record_volume(i, &mut encoder, object, stats);
            }
        }
        ctx.queue.submit([encoder.finish()]);
        if let Some(i) = self.slot {
            ring.map(i);
        }
    }
}
