//! GPU timestamp queries: one begin/end pair per named pass, written through the passes'
//! `timestamp_writes` when the device has `TIMESTAMP_QUERY`.

use std::cell::{Cell, RefCell};
use std::fmt;
use std::time::Instant;

use crate::{GpuContext, RenderError};

/// GPU time of one pass.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTiming {
    /// Pass name (one of `PASS_NAMES`: `strands/shadow`, `head`, `strands/ppll_build`, ...).
    pub name: &'static str,
    /// Milliseconds between the pass's begin and end timestamps.
    pub ms: f64,
}

/// Per-pass GPU times of a frame.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Timings {
    /// The device has no timestamp queries.
    #[default]
    NotSupported,
    /// One entry per pass that ran, in order.
    Passes(Vec<PassTiming>),
}

impl Timings {
    /// Milliseconds of the pass called `name`, if it ran and was timed.
    pub fn get(&self, name: &str) -> Option<f64> {
        match self {
            Timings::NotSupported => None,
            Timings::Passes(p) => p.iter().find(|t| t.name == name).map(|t| t.ms),
        }
    }

    /// Sum over all timed passes.
    pub fn total_ms(&self) -> Option<f64> {
        match self {
            Timings::NotSupported => None,
            Timings::Passes(p) => Some(p.iter().map(|t| t.ms).sum()),
        }
    }
}

impl fmt::Display for Timings {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Timings::NotSupported => write!(f, "GPU timestamps: not supported by this device"),
            Timings::Passes(p) => {
                for (i, t) in p.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{} {:.3} ms", t.name, t.ms)?;
                }
                Ok(())
            }
        }
    }
}

/// How a [`GpuTimer`] times a frame's passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TimerMode {
    /// Timestamp queries written by the passes themselves (when the device has them).
    Timestamps,
    /// Each stage submitted alone and waited for ([`FrameEncoder::cut`]): CPU wall-clock
    /// milliseconds, for devices whose timestamps are not trustworthy. The passes write no
    /// timestamps.
    WallClock,
}

/// A query set with two timestamps per pass and the buffer they resolve into, or, in
/// [`TimerMode::WallClock`], the wall-clock time of each stage cut by a [`FrameEncoder`].
///
/// Passes are named (`names`); a frame that draws several objects (heads of hair) times a pass
/// once for the frame ([`GpuTimer::render_writes`]) or once per object
/// ([`GpuTimer::object_render_writes`]), each in a slot of its own. [`GpuTimer::parse`] sums a
/// pass over the frame and its objects; [`GpuTimer::parse_objects`] gives each object's.
#[derive(Debug)]
pub(crate) struct GpuTimer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer)>,
    names: &'static [&'static str],
    /// Objects timed on their own (slots after the frame's).
    objects: usize,
    /// Which passes of which slot wrote their end timestamp this frame (cells: the passes take
    /// timestamp writes while other parts of the renderer are borrowed).
    written: Vec<Cell<bool>>,
    /// Slots in use this frame (the frame's and those of the objects timed so far).
    used: Cell<usize>,
    period_ns: f64,
    mode: TimerMode,
    /// Wall-clock mode: when the current stage began, and the stages timed this frame.
    wall_start: Cell<Option<Instant>>,
    wall_times: RefCell<Vec<PassTiming>>,
}

impl GpuTimer {
    /// Bytes the resolved timestamps occupy (copied into a frame's readback buffer).
    pub(crate) fn resolved_bytes(&self) -> u64 {
        self.names.len() as u64 * 16 * (1 + self.objects as u64)
    }

    /// Objects this timer times on their own.
    pub(crate) fn objects(&self) -> usize {
        self.objects
    }

    /// A timer that also times up to `objects` objects' passes each on their own.
    pub(crate) fn with_objects(
        ctx: &GpuContext,
        label: &str,
        names: &'static [&'static str],
        objects: usize,
    ) -> Self {
        let slots = 1 + objects;
        let queries = ctx.caps.timestamps.then(|| {
            let count = (names.len() * slots) as u32 * 2;
            let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(&format!("{label}/timestamps")),
                ty: wgpu::QueryType::Timestamp,
                count,
            });
            let resolve = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("{label}/timestamps-resolve")),
                size: u64::from(count) * 8,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            (set, resolve)
        });
        GpuTimer {
            queries,
            names,
            objects,
            written: vec![Cell::new(false); names.len() * slots],
            used: Cell::new(1),
            period_ns: f64::from(ctx.queue.get_timestamp_period()),
            mode: TimerMode::Timestamps,
            wall_start: Cell::new(None),
            wall_times: RefCell::new(Vec::new()),
        }
    }

    /// Time the passes with timestamps or by wall clock from the next frame on.
    pub(crate) fn set_mode(&mut self, mode: TimerMode) {
        self.mode = mode;
    }

    /// Forget which passes were written (call at the start of a frame). In wall-clock mode,
    /// wait for earlier work first, so it does not count toward the first stage.
    pub(crate) fn begin_frame(&self, ctx: &GpuContext) -> Result<(), RenderError> {
        self.written.iter().for_each(|w| w.set(false));
        self.used.set(1);
        self.wall_times.borrow_mut().clear();
        if self.mode == TimerMode::WallClock {
            ctx.wait_idle()?;
            self.wall_start.set(Some(Instant::now()));
        }
        Ok(())
    }

    /// In wall-clock mode, the stages timed this frame (`None` in timestamp mode).
    pub(crate) fn wall_timings(&self) -> Option<Timings> {
        (self.mode == TimerMode::WallClock)
            .then(|| Timings::Passes(self.wall_times.borrow().clone()))
    }

    /// Record the end of wall-clock stage `name` (the work before it has finished).
    fn end_wall_stage(&self, name: &'static str) {
        let now = Instant::now();
        let start = self.wall_start.replace(Some(now)).unwrap_or(now);
        self.wall_times.borrow_mut().push(PassTiming {
            name,
            ms: (now - start).as_secs_f64() * 1e3,
        });
    }

    /// The pass's index over all slots: `name` in slot 0 (the frame) or in object `object`'s.
    fn index(&self, name: &str, object: Option<usize>) -> Option<usize> {
        let slot = match object {
            None => 0,
            Some(o) if o < self.objects => o + 1,
            Some(_) => return None,
        };
        let i = self.names.iter().position(|n| *n == name)?;
        self.used.set(self.used.get().max(slot + 1));
        Some(slot * self.names.len() + i)
    }

    /// Timestamp writes for a render pass of object `object` (see [`GpuTimer::render_writes`];
    /// none beyond the objects this timer times).
    pub(crate) fn object_render_writes(
        &self,
        name: &str,
        object: usize,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.render_writes_of(name, Some(object), begin, end)
    }

    /// Timestamp writes for a compute pass of object `object`.
    pub(crate) fn object_compute_writes(
        &self,
        name: &str,
        object: usize,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.compute_writes_of(name, Some(object), begin, end)
    }

    fn render_writes_of(
        &self,
        name: &str,
        object: Option<usize>,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let i = self.index(name, object)?;
        self.pass_writes(i, begin, end)
            .map(|(query_set, b, e)| wgpu::RenderPassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: b,
                end_of_pass_write_index: e,
            })
    }

    fn compute_writes_of(
        &self,
        name: &str,
        object: Option<usize>,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let i = self.index(name, object)?;
        self.pass_writes(i, begin, end)
            .map(|(query_set, b, e)| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: b,
                end_of_pass_write_index: e,
            })
    }

    /// The query set and the begin and end query indices of pass `i` (over all slots), marking
    /// it written when the end is.
    fn pass_writes(
        &self,
        i: usize,
        begin: bool,
        end: bool,
    ) -> Option<(&wgpu::QuerySet, Option<u32>, Option<u32>)> {
        // A pass between the first and the last of a timed run writes nothing (wgpu rejects
        // timestamp writes with neither index: a scene with three lights failed every frame).
        if !(begin || end) || self.mode == TimerMode::WallClock {
            return None;
        }
        let (set, _) = self.queries.as_ref()?;
        if end {
            self.written[i].set(true);
        }
        Some((
            set,
            begin.then_some(2 * i as u32),
            end.then_some(2 * i as u32 + 1),
        ))
    }

    /// Timestamp writes for a render pass. `begin`/`end` select which of the pass's two
    /// timestamps this render pass writes (a pass split over several render passes, like one
    /// shadow map per light, writes begin in the first and end in the last).
    pub(crate) fn render_writes(
        &self,
        name: &str,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.render_writes_of(name, None, begin, end)
    }

    /// Timestamp writes for a compute pass (`begin`/`end` as in [`GpuTimer::render_writes`]).
    pub(crate) fn compute_writes(
        &self,
        name: &str,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.compute_writes_of(name, None, begin, end)
    }

    /// Resolve the queries of the slots used this frame and copy them to `dst` at `offset`
    /// (at most `resolved_bytes` bytes).
    pub(crate) fn resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        dst: &wgpu::Buffer,
        offset: u64,
    ) {
        if let Some((set, resolve)) = &self.queries {
            let count = (self.names.len() * self.used.get()) as u32 * 2;
            encoder.resolve_query_set(set, 0..count, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, dst, offset, Some(u64::from(count) * 8));
        }
    }

    /// Which passes were written this frame.
    pub(crate) fn written(&self) -> Vec<bool> {
        self.written.iter().map(Cell::get).collect()
    }

    /// The milliseconds of pass `i` (over all slots) if it was written and resolved.
    fn pass_ms(&self, bytes: &[u8], written: &[bool], i: usize) -> Option<f64> {
        if !written.get(i).copied().unwrap_or(false) || bytes.len() < (i + 1) * 16 {
            return None;
        }
        let ts = |q: usize| {
            let b = &bytes[q * 8..q * 8 + 8];
            u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
        };
        Some(ts(2 * i + 1).saturating_sub(ts(2 * i)) as f64 * self.period_ns * 1e-6)
    }

    /// Turn resolved timestamps into timings, keeping the passes flagged in `written`: each
    /// pass once, its time summed over the frame's slot and every object's.
    pub(crate) fn parse(&self, bytes: &[u8], written: &[bool]) -> Timings {
        if self.queries.is_none() {
            return Timings::NotSupported;
        }
        let n = self.names.len();
        let passes = self
            .names
            .iter()
            .enumerate()
            .filter_map(|(i, name)| {
                let times: Vec<f64> = (0..=self.objects)
                    .filter_map(|slot| self.pass_ms(bytes, written, slot * n + i))
                    .collect();
                (!times.is_empty()).then(|| PassTiming {
                    name,
                    ms: times.iter().sum(),
                })
            })
            .collect();
        Timings::Passes(passes)
    }

    /// Each object's own passes (those timed with [`GpuTimer::object_render_writes`] or
    /// [`GpuTimer::object_compute_writes`]), for the first `count` objects.
    pub(crate) fn parse_objects(
        &self,
        bytes: &[u8],
        written: &[bool],
        count: usize,
    ) -> Vec<Timings> {
        let n = self.names.len();
        (0..count.min(self.objects))
            .map(|o| {
                if self.queries.is_none() {
                    return Timings::NotSupported;
                }
                Timings::Passes(
                    self.names
                        .iter()
                        .enumerate()
                        .filter_map(|(i, name)| {
                            self.pass_ms(bytes, written, (o + 1) * n + i)
                                .map(|ms| PassTiming { name, ms })
                        })
                        .collect(),
                )
            })
            .collect()
    }
}

/// A frame's command encoder. In [`TimerMode::WallClock`], [`FrameEncoder::cut`] ends a stage:
/// it submits what was recorded, waits for it and records the stage's wall-clock time; with
/// timestamps it does nothing, and the frame is one submission.
pub(crate) struct FrameEncoder<'a> {
    ctx: &'a GpuContext,
    timer: &'a GpuTimer,
    label: &'static str,
    /// The encoder the current stage records into.
    pub(crate) encoder: wgpu::CommandEncoder,
}

impl<'a> FrameEncoder<'a> {
    pub(crate) fn new(ctx: &'a GpuContext, timer: &'a GpuTimer, label: &'static str) -> Self {
        FrameEncoder {
            ctx,
            timer,
            label,
            encoder: Self::encoder(ctx, label),
        }
    }

    fn encoder(ctx: &GpuContext, label: &str) -> wgpu::CommandEncoder {
        ctx.device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    /// End stage `name` (wall-clock mode: submit, wait, record its time).
    pub(crate) fn cut(&mut self, name: &'static str) -> Result<(), RenderError> {
        if self.timer.mode != TimerMode::WallClock {
            return Ok(());
        }
        let done = std::mem::replace(&mut self.encoder, Self::encoder(self.ctx, self.label));
        self.ctx.queue.submit([done.finish()]);
        self.ctx.wait_idle()?;
        self.timer.end_wall_stage(name);
        Ok(())
    }

    /// The encoder of the frame's last stage (its submission is the caller's).
    pub(crate) fn into_encoder(self) -> wgpu::CommandEncoder {
        self.encoder
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_says_not_supported() {
        assert!(Timings::NotSupported.to_string().contains("not supported"));
        let t = Timings::Passes(vec![
            PassTiming {
                name: "head",
                ms: 1.0,
            },
            PassTiming {
                name: "strands/ppll_build",
                ms: 2.5,
            },
        ]);
        assert_eq!(t.get("head"), Some(1.0));
        assert_eq!(t.get("other"), None);
        assert_eq!(t.total_ms(), Some(3.5));
        assert_eq!(t.to_string(), "head 1.000 ms, strands/ppll_build 2.500 ms");
    }
}
