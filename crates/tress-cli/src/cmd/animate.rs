//! `tress render --frames N --animate sway|simulate`: a procedural sway of the hair, or the
//! hair simulated with the head moving as the scene's `[head.motion]` says (`[simulation]`'s
//! settings), voxelized again every frame, written as numbered images.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use glam::{Quat, Vec3};
use serde::Serialize;
use tress_hair::HairAsset;
use tress_render::session::{FrameDetail, Session, TechniqueKind};
use tress_render::{COLOR_FORMAT, GpuContext, OffscreenTargets, read_texture};

use super::report::{Report, save, volume_report};

/// Frames per second of a sequence (the sway's time step).
pub(crate) const FPS: f32 = 24.0;
/// The sway: peak bend at the tips in radians, and its period in seconds.
const SWAY_AMPLITUDE: f32 = 0.35;
const SWAY_PERIOD_S: f32 = 2.0;

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
    /// With `--animate simulate`: each frame's simulation.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    simulation: Vec<SimulationReport>,
}

/// One frame's simulation in `--json`.
#[derive(Serialize)]
struct SimulationReport {
    /// Simulated seconds at the frame.
    time: f64,
    /// Steps run for the frame.
    steps: u64,
    /// Guides simulated and strands drawn (followers rebuilt from them).
    guides: usize,
    strands: usize,
    /// Milliseconds from recording the frame's steps to the GPU finishing them and writing the
    /// hair into the vertex buffers.
    wall_ms: Option<f64>,
    /// The simulation's GPU time for the frame (its passes' sum), where the device has
    /// timestamps.
    gpu_ms: Option<f64>,
    /// GPU memory of the simulation.
    bytes: u64,
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

impl Sequence<'_> {
    /// The number of frames, or why the sequence cannot be drawn with `technique`.
    pub(crate) fn check(&self, technique: TechniqueKind) -> Result<u32> {
        let frames = self
            .frames
            .context("--animate needs --frames N (the number of frames)")?;
        if frames == 0 || frames > 100_000 {
            bail!("--frames must be in 1..=100000, got {frames}");
        }
        match self.animate {
            None | Some("sway") | Some("simulate") => {}
            Some(other) => bail!("unknown --animate `{other}` (expected sway or simulate)"),
        }
        if !technique.draws_strands() {
            bail!("--frames renders the strands, volume and hybrid techniques, not `{technique}`");
        }
        Ok(frames)
    }
}

/// `tress render --frames N [--animate sway]` of the session's scene.
pub(crate) fn run(
    ctx: &GpuContext,
    session: &mut Session,
    seq: Sequence<'_>,
    output: &Path,
) -> Result<()> {
    let frames = seq.check(session.technique_kind())?;
    let size = [session.scene().output.width, session.scene().output.height];
    let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
    let camera = session.camera(size);
    let simulate = seq.animate == Some("simulate");
    // The hair at rest (a copy only when it sways).
    let rest = seq
        .animate
        .filter(|a| *a == "sway")
        .and(session.prepared().hair().map(std::borrow::Cow::into_owned));
    if simulate {
        let settings = session.scene().simulation_settings()?;
        let motion = session.scene().head.motion.clone().unwrap_or_default();
        session.start_simulation(ctx, settings, motion)?;
    }
    let mut reports = Vec::new();
    let mut sim_reports = Vec::new();
    for i in 0..frames {
        if let Some(asset) = &rest {
            session.update_hair_positions(ctx, &sway(asset, i as f32 / FPS))?;
        }
        if simulate {
            let f = session.simulate_to(ctx, f64::from(i) / f64::from(FPS), true)?;
            let sim = session.simulation().context("the simulation stopped")?;
            let (guides, strands) = sim.counts();
            sim_reports.push(SimulationReport {
                time: f.time,
                steps: f.steps,
                guides,
                strands,
                wall_ms: f.wall_ms,
                gpu_ms: f.gpu.total_ms(),
                bytes: sim.bytes(),
            });
        }
        let frame = session.render(ctx, &targets.targets(), &camera, None)?;
        let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
        let path = numbered(output, i);
        save(&image, &path)?;
        if !seq.json
            && let FrameDetail::Strands(stats) = &frame.detail
        {
            let total = stats.gpu.as_ref().and_then(|g| g.timings.total_ms());
            println!(
                "wrote {} ({}){}",
                path.display(),
                total.map_or("no GPU timestamps".to_string(), |ms| format!("{ms:.2} ms")),
                volume_report(stats).map_or(String::new(), |v| format!("; {v}"))
            );
        }
        reports.push(Report::new(ctx, session, &frame, &path));
    }
    if seq.json {
        let seq = SequenceReport {
            technique: session.technique().to_string(),
            frames: reports,
            simulation: sim_reports,
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
