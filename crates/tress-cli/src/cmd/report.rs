//! What `tress render` prints: the JSON report of a frame (the keys every technique reports,
//! then the technique's own part), built from a [`SessionFrame`], and writing images.
//!
//! `render`, its sequences (`--frames`), its SATF frames and `compare` all report through here,
//! so none of them imports another.

use std::path::Path;

use anyhow::{Result, bail};
use serde::Serialize;
use tress_render::session::{FrameDetail, Memory, SatfInfo, Session, SessionFrame};
use tress_render::{FrameStats, GpuContext, LinearImage, SatfFrameStats, Timings};

/// The JSON report of a frame: the keys every technique reports, then the technique's own part.
#[derive(Serialize)]
pub(crate) struct Report {
    pub(crate) technique: String,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) strands: usize,
    pub(crate) segments: usize,
    pub(crate) adapter: Adapter,
    pub(crate) passes: Vec<Pass>,
    pub(crate) frame_gpu_ms: Option<f64>,
    pub(crate) ppll: Ppll,
    /// The frame's GPU memory by part.
    pub(crate) memory: MemoryReport,
    /// The strand rasterizer's OIT, when strands were drawn.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) oit: Option<OitReport>,
    pub(crate) output: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) patches: Option<PatchReport>,
    /// The hair volume, when the frame voxelized it (volume, hybrid, or strands with volume
    /// shadows or AO).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) volume: Option<VolumeReport>,
    /// The `satf` technique's part (added by `render_satf`, which knows the database's file).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) satf: Option<SatfReport>,
    /// Each head of hair the strand renderer drew (strands, volume, hybrid, auto): one per
    /// `[[hair]]` entry, in order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) objects: Vec<ObjectReport>,
}

/// One head of hair of a frame: what drew it and what it cost.
#[derive(Serialize)]
pub(crate) struct ObjectReport {
    /// What drew it: `strands`, `volume` or `hybrid` (`auto` resolved).
    pub(crate) technique: &'static str,
    /// Its level-of-detail blend factor (0 strands only, 1 volume only).
    pub(crate) lod: f32,
    /// Its bounding sphere's diameter on screen, pixels (what `auto` decides by).
    pub(crate) size_px: f32,
    /// The share of the frame the square around its bounding sphere covers.
    pub(crate) coverage: f32,
    /// Strand segments.
    pub(crate) segments: u32,
    /// Bytes of its own volume (0 when not voxelized).
    pub(crate) volume_bytes: u64,
    /// Voxels per axis of its own volume, by its size on screen (0 when not voxelized).
    pub(crate) volume_resolution: u32,
    /// Its own GPU memory: its strand buffers and its volume (the shared parts are the
    /// frame's, in the report's `memory`).
    pub(crate) memory: ObjectMemory,
    /// Why it was drawn otherwise than asked (`volume.budget_mib`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) fallback: Option<&'static str>,
    /// Its own passes (voxelization, raymarch, blend); the OIT, shadow and head passes are
    /// the frame's.
    pub(crate) passes: Vec<Pass>,
}

/// A head of hair's own GPU memory, bytes.
#[derive(Serialize)]
pub(crate) struct ObjectMemory {
    pub(crate) total: u64,
    pub(crate) geometry: u64,
    pub(crate) volume: u64,
}

/// The frame's GPU memory, bytes: `total` and each part ([`tress_render::session::Memory`],
/// the breakdown the viewer and the bench CSV show).
#[derive(Serialize, Default)]
pub(crate) struct MemoryReport {
    pub(crate) total: u64,
    pub(crate) geometry: u64,
    pub(crate) oit: u64,
    pub(crate) volumes: u64,
    pub(crate) shadow_maps: u64,
    pub(crate) textures: u64,
    pub(crate) database: u64,
}

impl From<&Memory> for MemoryReport {
    fn from(m: &Memory) -> MemoryReport {
        MemoryReport {
            total: m.total(),
            geometry: m.geometry,
            oit: m.oit,
            volumes: m.volumes,
            shadow_maps: m.shadow_maps,
            textures: m.textures,
            database: m.database,
        }
    }
}

impl ObjectReport {
    /// Every head of hair of a strand renderer's frame.
    pub(crate) fn all(stats: &FrameStats) -> Vec<ObjectReport> {
        stats
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| ObjectReport {
                technique: o.technique.name(),
                lod: o.lod,
                size_px: o.size_px,
                coverage: o.coverage,
                segments: o.segments,
                volume_bytes: o.volume_bytes,
                volume_resolution: o.volume_resolution,
                memory: ObjectMemory {
                    total: o.geometry_bytes + o.volume_bytes,
                    geometry: o.geometry_bytes,
                    volume: o.volume_bytes,
                },
                fallback: o.fallback,
                passes: passes(stats.gpu.as_ref().and_then(|g| g.object_timings.get(i))),
            })
            .collect()
    }
}

impl Report {
    /// The report of `frame`, drawn by `session` and written to `output`; the technique's part
    /// except SATF's (see [`SatfReport::new`]).
    pub(crate) fn new(
        ctx: &GpuContext,
        session: &Session,
        frame: &SessionFrame,
        output: &Path,
    ) -> Report {
        let (strands, segments) = session.prepared().hair_counts();
        let mut report = Report {
            technique: frame.technique.to_string(),
            width: frame.size[0],
            height: frame.size[1],
            strands,
            segments,
            adapter: Adapter {
                name: ctx.adapter_info.name.clone(),
                backend: format!("{:?}", ctx.adapter_info.backend).to_lowercase(),
            },
            passes: Vec::new(),
            frame_gpu_ms: None,
            ppll: Ppll::default(),
            memory: MemoryReport::from(&frame.memory),
            oit: None,
            output: output.display().to_string(),
            patches: None,
            volume: None,
            satf: None,
            objects: Vec::new(),
        };
        match &frame.detail {
            FrameDetail::Strands(stats) => {
                let timings = stats.gpu.as_ref().map(|g| &g.timings);
                report.passes = passes(timings);
                report.frame_gpu_ms = match timings {
                    Some(Timings::Passes(p)) => Some(p.iter().map(|t| t.ms).sum()),
                    _ => None,
                };
                let ppll = stats.gpu.as_ref().map(|g| &g.ppll);
                report.ppll = Ppll {
                    capacity: stats.ppll_capacity,
                    used: ppll.map_or(0, |p| p.used),
                    dropped: ppll.map_or(0, |p| p.dropped),
                    bytes: stats.ppll_bytes,
                };
                report.volume = volume_report(stats);
                report.oit = OitReport::from_stats(stats);
                report.objects = ObjectReport::all(stats);
            }
            FrameDetail::Patches(stats) => {
                report.passes = passes(stats.timings.as_ref());
                report.frame_gpu_ms = (!report.passes.is_empty())
                    .then(|| report.passes.iter().map(|p| p.gpu_ms).sum());
                report.patches = session.patch_scene().map(|p| PatchReport {
                    scheme: stats.scheme.name().to_string(),
                    source: p.source.name().to_string(),
                    triangles: stats.triangles,
                    components: p.mesh.component_count(),
                    ao_bake_s: p.ao_bake_seconds,
                });
            }
            FrameDetail::Satf(stats) => {
                report.passes = passes(Some(&stats.timings));
                report.frame_gpu_ms = stats.timings.total_ms();
            }
        }
        report
    }
}

/// The `patches` technique's part of the report.
#[derive(Serialize)]
pub(crate) struct PatchReport {
    pub(crate) scheme: String,
    pub(crate) source: String,
    pub(crate) triangles: u32,
    pub(crate) components: usize,
    pub(crate) ao_bake_s: Option<f64>,
}

#[derive(Serialize)]
pub(crate) struct Adapter {
    pub(crate) name: String,
    pub(crate) backend: String,
}

#[derive(Serialize)]
pub(crate) struct Pass {
    name: String,
    gpu_ms: f64,
}

/// The per-pixel linked lists; all zero for the techniques that have none (patches, SATF), so
/// every report has the same keys.
#[derive(Serialize, Default)]
pub(crate) struct Ppll {
    pub(crate) capacity: u32,
    pub(crate) used: u32,
    pub(crate) dropped: u32,
    pub(crate) bytes: u64,
}

/// Which OIT drew the strands, what it was given and lost, and its memory.
#[derive(Serialize)]
pub(crate) struct OitReport {
    /// `"ppll"` or `"shortcut"`.
    pub(crate) kind: &'static str,
    /// Fragments that did not reach the image (a full PPLL pool).
    pub(crate) lost: u32,
    /// Bytes of the OIT's buffers.
    pub(crate) bytes: u64,
    /// Strand fragments the OIT was given.
    pub(crate) fragments: u32,
    /// PPLL: fragments merged unsorted behind their pixel's `k` nearest (0 for ShortCut).
    pub(crate) tail: u32,
}

impl OitReport {
    /// From a frame's GPU report, if strands were drawn.
    pub(crate) fn from_stats(stats: &FrameStats) -> Option<OitReport> {
        let o = stats.gpu.as_ref()?.oit?;
        Some(OitReport {
            kind: o.kind.name(),
            lost: o.lost,
            bytes: o.bytes,
            fragments: o.fragments,
            tail: o.tail,
        })
    }
}

impl std::fmt::Display for OitReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "OIT: {}, {} fragments, {} lost ({:.1} MiB)",
            self.kind,
            self.fragments,
            self.lost,
            self.bytes as f64 / (1u64 << 20) as f64
        )
    }
}

/// The `volume` object of the JSON report.
#[derive(Serialize, Clone, Debug)]
pub(crate) struct VolumeReport {
    /// Voxels per axis.
    pub(crate) resolution: u32,
    /// GPU time of the voxelization (bounds, counters, resolve), when timestamps exist.
    pub(crate) voxelize_ms: Option<f64>,
    /// Bytes of voxel counters, volume texture and occupancy blocks.
    pub(crate) bytes: u64,
}

impl std::fmt::Display for VolumeReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "volume: {}³ voxels ({:.1} MiB), voxelized in {}",
            self.resolution,
            self.bytes as f64 / (1u64 << 20) as f64,
            self.voxelize_ms
                .map_or("(untimed)".to_string(), |ms| format!("{ms:.3} ms"))
        )
    }
}

/// The volume part of a frame's report, when the frame voxelized the hair.
pub(crate) fn volume_report(stats: &FrameStats) -> Option<VolumeReport> {
    stats.volume.map(|v| VolumeReport {
        resolution: v.resolution,
        voxelize_ms: stats
            .gpu
            .as_ref()
            .and_then(|g| g.timings.get("volume/voxelize")),
        bytes: v.bytes,
    })
}

/// The `satf` part of the report.
#[derive(Serialize)]
pub(crate) struct SatfReport {
    pub(crate) database: String,
    pub(crate) database_samples: u32,
    pub(crate) cluster_source: &'static str,
    pub(crate) clusters: u32,
    pub(crate) macro_clusters: usize,
    pub(crate) layers: u32,
    pub(crate) cluster_strands: usize,
    /// Strands of the scene's hair in no cluster, by reason (`too_short`, `degenerate`).
    pub(crate) skipped_strands: Skipped,
    pub(crate) hsvs: u32,
    pub(crate) uniform_hsvs: u32,
    pub(crate) interpolated_hsvs: u32,
    pub(crate) atlas: [u32; 2],
    /// `timestamps` (GPU) or `wall_clock` (each stage submitted alone, CPU clock).
    pub(crate) stage_timing: &'static str,
    pub(crate) clusters_cpu_ms: f64,
    pub(crate) features_cpu_ms: f64,
    /// GPU milliseconds of Table 1's stages (null without timestamps).
    pub(crate) stages_ms: Stages,
}

/// Strands the cluster fit left out, by reason.
#[derive(Serialize)]
pub(crate) struct Skipped {
    pub(crate) total: usize,
    pub(crate) too_short: usize,
    pub(crate) degenerate: usize,
}

#[derive(Serialize)]
pub(crate) struct Stages {
    index_calculation: Option<f64>,
    map_construction: Option<f64>,
    texture_mapping: Option<f64>,
    lighting: Option<f64>,
    shadowing: Option<f64>,
}

impl SatfReport {
    /// The SATF part of a frame's report: what the technique was prepared with (`info`, its
    /// database read from `database`) and what the frame counted and timed.
    pub(crate) fn new(info: SatfInfo<'_>, stats: &SatfFrameStats, database: &Path) -> SatfReport {
        use tress_render::satf::StageTiming;
        use tress_render::satf::scene::ClusterSource;
        let [i, c, m, l, s] = stats.table1_ms().map(|(_, ms)| ms);
        let counts = info.geometry.stats();
        SatfReport {
            database: database.display().to_string(),
            database_samples: info.database.sample_count(),
            cluster_source: match info.settings.clusters {
                ClusterSource::Fit(_) => "fit",
                ClusterSource::Generate(_) => "generate",
            },
            clusters: stats.clusters,
            macro_clusters: counts.macro_clusters,
            layers: stats.layers,
            cluster_strands: counts.strands,
            skipped_strands: Skipped {
                total: counts.skipped.total(),
                too_short: counts.skipped.too_short,
                degenerate: counts.skipped.degenerate,
            },
            hsvs: stats.hsvs,
            uniform_hsvs: stats.uniform_hsvs,
            interpolated_hsvs: stats.interpolated_hsvs,
            atlas: info.geometry.atlas_size(),
            stage_timing: match info.settings.settings.stage_timing {
                StageTiming::Timestamps => "timestamps",
                StageTiming::WallClock => "wall_clock",
            },
            clusters_cpu_ms: info.clusters_ms,
            features_cpu_ms: info.geometry.features_ms(),
            stages_ms: Stages {
                index_calculation: i,
                map_construction: c,
                texture_mapping: m,
                lighting: l,
                shadowing: s,
            },
        }
    }
}

/// The passes of `timings` (none without timestamps).
pub(crate) fn passes(timings: Option<&Timings>) -> Vec<Pass> {
    match timings {
        Some(Timings::Passes(p)) => p
            .iter()
            .map(|t| Pass {
                name: t.name.to_string(),
                gpu_ms: t.ms,
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// The line that reports a frame's GPU passes (or that the device has no timestamps).
pub(crate) fn timings_line(timings: Option<&Timings>) -> String {
    match timings {
        Some(t @ Timings::Passes(_)) => {
            format!("{t}; frame {:.3} ms", t.total_ms().unwrap_or(0.0))
        }
        _ => "GPU timestamps: not supported by this device".to_string(),
    }
}

/// Check that `path` names an image tress can write (`.png` or `.exr`, any case).
pub(crate) fn check_output(path: &Path) -> Result<()> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png" | "exr") => Ok(()),
        _ => bail!("{}: the output must end in .png or .exr", path.display()),
    }
}

/// Write `image` to `path` (checked by [`check_output`]): OpenEXR for `.exr` (any case), PNG
/// otherwise.
pub(crate) fn save(image: &LinearImage, path: &Path) -> Result<()> {
    check_output(path)?;
    match path.extension() {
        Some(e) if e.eq_ignore_ascii_case("exr") => image.save_exr(path)?,
        _ => image.save_png(path)?,
    }
    Ok(())
}
