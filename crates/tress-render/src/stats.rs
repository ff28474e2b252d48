//! Frame statistics and their readback: PPLL counters and GPU timestamps are copied into a small
//! ring of mappable buffers each frame and read when the GPU is done with them.

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

use crate::gpu::types::{PpllCounters, SatfCounters, VoxelStats};
use crate::gpu::{GpuTimer, Timings};
use crate::strands::PpllStats;
use crate::strands::oit::{OitKind, OitStats};
use crate::volume::VolumeStats;
use crate::{GpuContext, RenderError};

/// When `render` returns GPU results.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StatsReadback {
    /// Wait for the frame to finish and report its own counters and timings (offline rendering,
    /// tests, benchmarks).
    #[default]
    Wait,
    /// Never block: report the newest earlier frame whose results have arrived, read before
    /// the frame is submitted (interactive use; the report lags a frame or two behind and is
    /// never the frame's own).
    Deferred,
}

/// What the GPU reported about one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuReport {
    /// The frame these results belong to.
    pub frame: u64,
    /// PPLL occupancy (zero counts when the PPLL did not draw).
    pub ppll: PpllStats,
    /// The OIT that drew the strands, what it was given and what it lost (`None` when no
    /// strands were drawn).
    pub oit: Option<OitStats>,
    /// Voxel counter occupancy, when the frame voxelized the hair (summed over the objects
    /// voxelized).
    pub volume: Option<VolumeStats>,
    /// Each object's voxel counters, in the frame's object order (`None`: not voxelized).
    pub object_volumes: Vec<Option<VolumeStats>>,
    /// SATF's index-calculation counters, when the frame drew SATF clusters.
    pub satf: Option<SatfCounters>,
    /// Per-pass GPU times (a pass run for several objects summed over them).
    pub timings: Timings,
    /// Each object's own passes (voxelization, raymarch, blend), in the frame's object order.
    pub object_timings: Vec<Timings>,
}

/// What `render` returns.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameStats {
    /// Index of this frame (from 0).
    pub frame: u64,
    /// Target size in pixels.
    pub size: [u32; 2],
    /// Strand segments drawn.
    pub segments: u32,
    /// PPLL node capacity this frame (0 when the PPLL did not draw).
    pub ppll_capacity: u32,
    /// Bytes of PPLL nodes + heads this frame (0 when the PPLL did not draw).
    pub ppll_bytes: u64,
    /// The OIT that drew the strands this frame and the bytes of its buffers (`None` when no
    /// strands were drawn).
    pub oit: Option<(OitKind, u64)>,
    /// Times the frame was rendered (more than 1 when a full PPLL pool grew and the frame was
    /// repeated; see `Renderer::render`).
    pub attempts: u32,
    /// GPU results: this frame's with [`StatsReadback::Wait`], the newest available otherwise.
    pub gpu: Option<GpuReport>,
    /// The level-of-detail blend factor of the frame (0 strands only, 1 volume only).
    pub lod: f32,
    /// The hair volume, when the frame voxelized the hair (the shared voxel counters and
    /// every voxelized head of hair's volume).
    pub volume: Option<VolumeFrame>,
    /// Each head of hair drawn, in the frame's order (`hair`, then `objects`; empty without
    /// hair).
    pub objects: Vec<ObjectFrame>,
}

/// What one head of hair of a frame was drawn as.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectFrame {
    /// What drew it: strands, volume or hybrid (`auto` resolved, budget fallbacks applied).
    pub technique: crate::TechniqueKind,
    /// Its level-of-detail blend factor (0 strands only, 1 volume only).
    pub lod: f32,
    /// Its bounding sphere's diameter on screen, pixels.
    pub size_px: f32,
    /// The share of the frame the square around its projected bounding sphere covers.
    pub coverage: f32,
    /// Strand segments.
    pub segments: u32,
    /// Bytes of its own volume (texture and occupancy), 0 when not voxelized.
    pub volume_bytes: u64,
    /// Voxels per axis of its own volume (by its size on screen; 0 when not voxelized).
    pub volume_resolution: u32,
    /// Bytes of its own strand geometry buffers (the frame's head, OIT, shadow maps and
    /// voxel counters are shared: [`crate::session::Memory`]).
    pub geometry_bytes: u64,
    /// Why it was drawn otherwise than asked (`"volume.budget_mib"`: its volume did not fit).
    pub fallback: Option<&'static str>,
}

/// The hair volume of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VolumeFrame {
    /// Voxels per axis.
    pub resolution: u32,
    /// Bytes of voxel counters, volume texture and occupancy blocks.
    pub bytes: u64,
}

const IDLE: u8 = 0;
const PENDING: u8 = 1;
const READY: u8 = 2;
const FAILED: u8 = 3;

#[derive(Debug)]
struct Slot {
    buffer: wgpu::Buffer,
    state: Arc<AtomicU8>,
    frame: u64,
    capacity: u32,
    head_bytes: u64,
    oit: Option<(OitKind, u64)>,
    /// Which objects' voxel counters were copied.
    volumes: Vec<bool>,
    /// Objects the frame drew (their timings are parsed).
    objects: usize,
    satf: bool,
    written: Vec<bool>,
}

/// A ring of readback buffers. A slot holds the OIT (or SATF) counters at 0, each object's
/// voxel counters from [`VOLUME_OFFSET`], and the timestamps from `timestamp_offset`.
#[derive(Debug)]
pub(crate) struct ReadbackRing {
    slots: Vec<Slot>,
    size: u64,
    /// Where the timestamps start (256-byte aligned, after the voxel counters).
    timestamp_offset: u64,
    /// Objects whose voxel counters a slot holds.
    volume_objects: usize,
}

/// What a frame recorded into its slot.
pub(crate) struct SlotInfo {
    pub(crate) frame: u64,
    pub(crate) capacity: u32,
    pub(crate) head_bytes: u64,
    /// The OIT whose counters were copied and its bytes (`None`: no strand passes ran).
    pub(crate) oit: Option<(OitKind, u64)>,
    /// The counters copied are SATF's (`SatfCounters`).
    pub(crate) satf: bool,
    /// Objects the frame drew.
    pub(crate) objects: usize,
}

impl SlotInfo {
    /// A frame that recorded no OIT counters (timestamps only, or SATF's counters).
    pub(crate) fn without_oit(frame: u64) -> Self {
        SlotInfo {
            frame,
            capacity: 0,
            head_bytes: 0,
            oit: None,
            satf: false,
            objects: 0,
        }
    }
}

/// Offset of the voxel statistics in a slot (after the 16 bytes of PPLL counters), 16 bytes
/// per object.
const VOLUME_OFFSET: u64 = 16;

impl ReadbackRing {
    /// `count` slots, each with room for the voxel counters of as many objects as `timer`
    /// times (at least one).
    pub(crate) fn new(ctx: &GpuContext, timer: &GpuTimer, count: usize) -> Self {
        let volume_objects = timer.objects().max(1);
        let timestamp_offset = (VOLUME_OFFSET + 16 * volume_objects as u64).next_multiple_of(256);
        let size = timestamp_offset + timer.resolved_bytes().max(8);
        let slots = (0..count)
            .map(|i| Slot {
                buffer: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&format!("frame/stats/readback-{i}")),
                    size,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: Arc::new(AtomicU8::new(IDLE)),
                frame: 0,
                capacity: 0,
                head_bytes: 0,
                oit: None,
                volumes: Vec::new(),
                objects: 0,
                satf: false,
                written: Vec::new(),
            })
            .collect();
        ReadbackRing {
            slots,
            size,
            timestamp_offset,
            volume_objects,
        }
    }

    /// An idle slot's index, if any.
    pub(crate) fn idle(&self) -> Option<usize> {
        self.slots
            .iter()
            .position(|s| s.state.load(Ordering::Acquire) == IDLE)
    }

    /// Record the copies of this frame's results into slot `i`.
    pub(crate) fn record(
        &mut self,
        i: usize,
        encoder: &mut wgpu::CommandEncoder,
        counters: Option<&wgpu::Buffer>,
        timer: &GpuTimer,
        info: SlotInfo,
    ) {
        let slot = &mut self.slots[i];
        if let Some(c) = counters {
            encoder.copy_buffer_to_buffer(c, 0, &slot.buffer, 0, Some(16));
        }
        slot.volumes.clear();
        timer.resolve(encoder, &slot.buffer, self.timestamp_offset);
        slot.objects = info.objects;
        slot.frame = info.frame;
        slot.capacity = info.capacity;
        slot.head_bytes = info.head_bytes;
        slot.oit = info.oit;
        slot.satf = info.satf;
        slot.written = timer.written();
    }

    /// Also copy object `object`'s voxel counters' statistics into slot `i` (after
    /// [`ReadbackRing::record`]; objects past the slot's room are not reported).
    pub(crate) fn record_volume(
        &mut self,
        i: usize,
        encoder: &mut wgpu::CommandEncoder,
        object: usize,
        stats: &wgpu::Buffer,
    ) {
        if object >= self.volume_objects {
            return;
        }
        let slot = &mut self.slots[i];
        let offset = VOLUME_OFFSET + 16 * object as u64;
        encoder.copy_buffer_to_buffer(stats, 0, &slot.buffer, offset, Some(16));
        if slot.volumes.len() <= object {
            slot.volumes.resize(object + 1, false);
        }
        slot.volumes[object] = true;
    }

    /// Request the mapping of slot `i` (after the frame was submitted).
    pub(crate) fn map(&mut self, i: usize) {
        let slot = &self.slots[i];
        slot.state.store(PENDING, Ordering::Release);
        let state = slot.state.clone();
        slot.buffer
            .map_async(wgpu::MapMode::Read, 0..self.size, move |r| {
                state.store(if r.is_ok() { READY } else { FAILED }, Ordering::Release);
            });
    }

    /// Read every slot that has arrived; returns the newest report.
    pub(crate) fn harvest(
        &mut self,
        ctx: &GpuContext,
        timer: &GpuTimer,
    ) -> Result<Option<GpuReport>, RenderError> {
        ctx.device.poll(wgpu::PollType::Poll)?;
        let mut newest: Option<GpuReport> = None;
        let mut failed = false;
        for slot in &mut self.slots {
            match slot.state.load(Ordering::Acquire) {
                READY => {
                    let bytes = slot.buffer.get_mapped_range(..)?.to_vec();
                    slot.buffer.unmap();
                    slot.state.store(IDLE, Ordering::Release);
                    let counters = if slot.oit.is_some() {
                        bytemuck::pod_read_unaligned::<PpllCounters>(&bytes[..16])
                    } else {
                        PpllCounters::default()
                    };
                    let oit = slot.oit.map(|(kind, bytes)| OitStats {
                        kind,
                        fragments: counters.requested,
                        lost: counters.dropped,
                        tail: match kind {
                            OitKind::Ppll => counters.tail,
                            OitKind::Shortcut => 0,
                        },
                        bytes,
                    });
                    let ppll_counters = match slot.oit {
                        Some((OitKind::Ppll, _)) => counters,
                        _ => PpllCounters::default(),
                    };
                    let object_volumes: Vec<Option<VolumeStats>> = slot
                        .volumes
                        .iter()
                        .enumerate()
                        .map(|(object, &copied)| {
                            copied.then(|| {
                                let o = (VOLUME_OFFSET + 16 * object as u64) as usize;
                                let v =
                                    bytemuck::pod_read_unaligned::<VoxelStats>(&bytes[o..o + 16]);
                                VolumeStats {
                                    deposits: v.deposits,
                                    dropped: v.dropped,
                                    saturated: v.saturated,
                                }
                            })
                        })
                        .collect();
                    let volume =
                        object_volumes
                            .iter()
                            .flatten()
                            .copied()
                            .reduce(|a, b| VolumeStats {
                                deposits: a.deposits.saturating_add(b.deposits),
                                dropped: a.dropped.saturating_add(b.dropped),
                                saturated: a.saturated.saturating_add(b.saturated),
                            });
                    let stamps = &bytes[self.timestamp_offset as usize..];
                    let satf = slot
                        .satf
                        .then(|| bytemuck::pod_read_unaligned::<SatfCounters>(&bytes[..16]));
                    let report = GpuReport {
                        frame: slot.frame,
                        satf,
                        ppll: PpllStats::from_counters(
                            ppll_counters,
                            slot.capacity,
                            slot.head_bytes,
                        ),
                        oit,
                        volume,
                        object_volumes,
                        timings: timer.parse(stamps, &slot.written),
                        object_timings: timer.parse_objects(stamps, &slot.written, slot.objects),
                    };
                    if newest.as_ref().is_none_or(|n| n.frame < report.frame) {
                        newest = Some(report);
                    }
                }
                FAILED => {
                    slot.state.store(IDLE, Ordering::Release);
                    failed = true;
                }
                _ => {}
            }
        }
        if failed && newest.is_none() {
            return Err(RenderError::Readback(
                "mapping a statistics buffer failed".into(),
            ));
        }
        Ok(newest)
    }

    /// Block until slot `i` has arrived, then harvest.
    pub(crate) fn wait(
        &mut self,
        ctx: &GpuContext,
        timer: &GpuTimer,
        i: usize,
    ) -> Result<Option<GpuReport>, RenderError> {
        while self.slots[i].state.load(Ordering::Acquire) == PENDING {
            ctx.device.poll(wgpu::PollType::wait_indefinitely())?;
        }
        self.harvest(ctx, timer)
    }
}
