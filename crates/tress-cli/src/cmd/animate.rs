//! The renderer setup shared by `render`, `compare` and sequences, the `volume` part of the JSON
//! report, and `tress render --frames N --animate sway`: a procedural sway of the hair, voxelized
//! again every frame, written as numbered images.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use glam::{Quat, Vec3};
use serde::Serialize;
use tress_hair::HairAsset;
use tress_render::scene_setup::PreparedScene;
use tress_render::{
    COLOR_FORMAT, FrameStats, GpuContext, OffscreenTargets, Renderer, TargetFormats, Technique,
    read_texture,
};
use tress_scene::Scene;

use super::render::{Report, frame_inputs, hair_counts, report, save, upload_head};

/// Frames per second of a sequence (the sway's time step).
pub(crate) const FPS: f32 = 24.0;
/// The sway: peak bend at the tips in radians, and its period in seconds.
const SWAY_AMPLITUDE: f32 = 0.35;
const SWAY_PERIOD_S: f32 = 2.0;

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

/// A renderer with the scene's strand, volume and hybrid settings and its technique.
pub(crate) fn renderer(
    ctx: &GpuContext,
    scene: &Scene,
    prepared: &PreparedScene,
) -> Result<Renderer> {
    let mut renderer = Renderer::new(ctx, TargetFormats::default(), prepared.strands.clone())?;
    renderer.set_volume_settings(ctx, prepared.volume.clone())?;
    renderer.set_hybrid_settings(prepared.hybrid.clone())?;
    renderer.set_technique(scene.technique.parse::<Technique>()?);
    Ok(renderer)
}

/// The hair at time `t` seconds of the sway: every strand bends about a horizontal axis through
/// its root, each segment turned by `θ · k / n` (segment `k` of `n`), so roots stay put, tips
/// move most and segment lengths are kept; the phase drifts across the head like a gust.
pub(crate) fn sway(asset: &HairAsset, t: f32) -> HairAsset {
    let mut out = asset.clone();
    let phase = std::f32::consts::TAU * t / SWAY_PERIOD_S;
    for s in 0..asset.strand_count() {
        let range = asset.strand_range(s);
        let src = &asset.positions()[range.clone()];
        let n = src.len().saturating_sub(1).max(1) as f32;
        let root = src[0];
        let theta = SWAY_AMPLITUDE * (phase + 0.15 * root.x).sin();
        let dst = &mut out.positions_mut()[range];
        let mut p = root;
        for k in 1..src.len() {
            let bend = Quat::from_axis_angle(Vec3::Z, theta * k as f32 / n);
            p += bend * (src[k] - src[k - 1]);
            dst[k] = p;
        }
    }
    out
}

/// `OUT-0000.png` for `OUT.png`.
pub(crate) fn numbered(output: &Path, i: u32) -> PathBuf {
    let stem = output
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("frame");
    let ext = output.extension().and_then(|e| e.to_str()).unwrap_or("png");
    output.with_file_name(format!("{stem}-{i:04}.{ext}"))
}

#[derive(Serialize)]
struct SequenceReport {
    technique: String,
    frames: Vec<Report>,
}

/// What a sequence renders: `--frames N` and `--animate MOTION`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sequence<'a> {
    /// Number of frames.
    pub(crate) frames: Option<u32>,
    /// The motion (`sway`), or none for a still sequence.
    pub(crate) animate: Option<&'a str>,
    /// Print one JSON object instead of lines.
    pub(crate) json: bool,
}

/// `tress render --frames N [--animate sway]`.
pub(crate) fn run(
    ctx: &GpuContext,
    seq: Sequence<'_>,
    output: &Path,
    scene: &Scene,
    prepared: &PreparedScene,
    size: [u32; 2],
) -> Result<()> {
    let frames = seq
        .frames
        .context("--animate needs --frames N (the number of frames)")?;
    if frames == 0 || frames > 100_000 {
        bail!("--frames must be in 1..=100000, got {frames}");
    }
    match seq.animate {
        None | Some("sway") => {}
        Some(other) => bail!("unknown --animate `{other}` (expected sway)"),
    }
    let technique = scene.technique.as_str();
    if !["strands", "volume", "hybrid"].contains(&technique) {
        bail!("--frames renders the strands, volume and hybrid techniques, not `{technique}`");
    }
    let mut renderer = renderer(ctx, scene, prepared)?;
    let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
    let mut hair = prepared
        .hair
        .as_ref()
        .map(|h| renderer.upload_hair(ctx, h))
        .transpose()?;
    let head = upload_head(ctx, prepared)?;
    let camera = PreparedScene::camera(scene, size);
    let (strands, segments) = hair_counts(prepared);
    let mut reports = Vec::new();
    for i in 0..frames {
        if let (Some(asset), Some(g), Some(_)) = (&prepared.hair, &mut hair, seq.animate) {
            g.update_positions(ctx, &sway(asset, i as f32 / FPS))?;
        }
        let inputs = frame_inputs(camera, prepared, hair.as_ref(), head.as_ref());
        let stats = renderer.render(ctx, &targets.targets(), &inputs)?;
        let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
        let path = numbered(output, i);
        save(&image, &path)?;
        if !seq.json {
            let total = stats.gpu.as_ref().and_then(|g| g.timings.total_ms());
            println!(
                "wrote {} ({}){}",
                path.display(),
                total.map_or("no GPU timestamps".to_string(), |ms| format!("{ms:.2} ms")),
                volume_report(&stats).map_or(String::new(), |v| format!("; {v}"))
            );
        }
        reports.push(report(ctx, scene, &path, strands, segments, &stats));
    }
    if seq.json {
        let seq = SequenceReport {
            technique: scene.technique.clone(),
            frames: reports,
        };
        println!("{}", serde_json::to_string(&seq)?);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sway_keeps_roots_and_segment_lengths_and_moves_tips() {
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, -2.0, 0.0),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(3.0, -1.5, 1.0),
        ];
        let asset = HairAsset::from_counts(positions, &[3, 2]).unwrap();
        let moved = sway(&asset, 0.5);
        for s in 0..2 {
            let (a, b) = (asset.strand(s), moved.strand(s));
            assert_eq!(a[0], b[0], "roots stay");
            for k in 1..a.len() {
                let (la, lb) = (a[k].distance(a[k - 1]), b[k].distance(b[k - 1]));
                assert!((la - lb).abs() < 1e-5, "segment lengths kept");
            }
            assert!(
                a.last().unwrap().distance(*b.last().unwrap()) > 0.1,
                "tips move"
            );
        }
        // Periodic.
        let again = sway(&asset, 0.5 + SWAY_PERIOD_S);
        for (p, q) in moved.positions().iter().zip(again.positions()) {
            assert!(p.distance(*q) < 1e-4);
        }
    }

    #[test]
    fn numbered_outputs() {
        assert_eq!(
            numbered(Path::new("a/out.png"), 7),
            PathBuf::from("a/out-0007.png")
        );
        assert_eq!(
            numbered(Path::new("x.exr"), 12),
            PathBuf::from("x-0012.exr")
        );
    }
}
