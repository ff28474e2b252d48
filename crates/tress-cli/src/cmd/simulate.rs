//! `tress simulate [INPUT...] -o OUT.(abc|usdc|usda) --frames N [--fps F] [--motion PRESET]
//! [--set key=value]... [--json]`: the hair simulated on the GPU (the scene's `[simulation]`,
//! the head moving as `[head.motion]` or `--motion` says), each frame read back and written as
//! an animated cache that DCC tools (Blender, Houdini, Maya) and `tress render --frame K` play.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use serde::Serialize;
use tress_render::GpuContext;

use super::open::open_session;
use crate::progress;

/// Arguments of `tress simulate`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A scene file (`.toml`) or hair files (merged; the generated head as the collider when
    /// the scene has one). Nothing simulates the built-in demo scene.
    inputs: Vec<PathBuf>,
    /// The cache: `.abc` (Alembic, `P` sampled once a frame), `.usda` or `.usdc` (USD,
    /// `points.timeSamples`, `timeCodesPerSecond` = `--fps`).
    #[arg(short, long)]
    output: PathBuf,
    /// Frames to write (the first is the hair at time 0).
    #[arg(long, value_name = "N", default_value_t = 48)]
    frames: u32,
    /// Frames a second of the cache (the simulation itself steps at `simulation.rate_hz`).
    #[arg(long, value_name = "F", default_value_t = 24.0)]
    fps: f64,
    /// How the head moves: `turn`, `nod`, `shake` or `run` (sets `head.motion.preset`; the
    /// scene's `[head.motion]` otherwise, else still).
    #[arg(long, value_name = "PRESET")]
    motion: Option<String>,
    /// Override any scene or simulation setting by its dotted name, e.g.
    /// `simulation.damping=4`, `simulation.wind.strength=200`. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print exactly one JSON object: guides, strands, frames, steps, timings and memory.
    #[arg(long)]
    json: bool,
}

/// One simulation pass's mean GPU time a frame.
#[derive(Serialize)]
struct PassReport {
    name: &'static str,
    gpu_ms: f64,
}

/// What `--json` prints.
#[derive(Serialize)]
struct SimulateReport {
    output: String,
    frames: u32,
    fps: f64,
    /// Characters simulated, and their guides and strands in all.
    characters: usize,
    guides: usize,
    strands: usize,
    vertices: usize,
    /// Simulation steps taken in all (at `rate_hz`, each with its substeps).
    steps: u64,
    rate_hz: f32,
    substeps: u32,
    /// Wall time of the simulation (GPU steps, waited for) per frame, mean and worst, ms.
    simulate_ms_mean: f64,
    simulate_ms_max: f64,
    /// GPU time of the simulation per frame (the sum of `passes`), ms; absent without GPU
    /// timestamps.
    simulate_gpu_ms_mean: Option<f64>,
    /// Each simulation pass's GPU time per frame (mean over the frames), ms: `sim/integrate`,
    /// `sim/grid`, `sim/constraints`, `sim/output`. Empty without GPU timestamps.
    passes: Vec<PassReport>,
    /// Wall time of reading every frame back and of writing the cache, ms.
    readback_ms: f64,
    write_ms: f64,
    /// GPU memory the simulation holds, bytes; the cache's size on disk, bytes.
    simulation_bytes: u64,
    cache_bytes: u64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let ext = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("abc" | "usda" | "usdc" | "usd")) {
        bail!(
            "{}: a simulation cache is written as .abc, .usda, .usdc or .usd",
            args.output.display()
        );
    }
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if !(args.fps.is_finite() && args.fps > 0.0 && args.fps <= 1000.0) {
        bail!("--fps must lie in (0, 1000], got {}", args.fps);
    }
    let (mut scene, auto_frame) = super::render::base_scene(&args.inputs)?;
    let mut sets = args.sets.clone();
    if let Some(p) = &args.motion {
        p.parse::<tress_sim::Preset>()
            .map_err(|e| anyhow::anyhow!("--motion: {e}"))?;
        sets.insert(0, format!("head.motion.preset=\"{p}\""));
    }
    super::render::apply_options(&mut scene, None, None, None, &sets)?;
    let settings = scene.simulation_settings()?;
    let technique: tress_render::session::TechniqueKind = scene.technique.parse()?;
    if !technique.draws_strands() {
        // The cache holds strands: simulate them under the strand renderer.
        scene.force_technique("strands")?;
    }
    let ctx = GpuContext::headless()?;
    let pb = progress::spinner("loading the scene");
    let session = open_session(&ctx, &scene, auto_frame, sets, None);
    pb.finish_and_clear();
    let mut session = session?;
    let hair = session
        .prepared()
        .hair()
        .context("the scene has no hair to simulate")?
        .into_owned();
    let motion = session.scene().head.motion.clone().unwrap_or_default();
    session.start_simulation(&ctx, settings.clone(), motion)?;

    let pb = progress::bar(u64::from(args.frames), "simulating");
    let mut frames = Vec::with_capacity(args.frames as usize);
    let (mut steps, mut sim_ms, mut sim_max, mut readback_ms) = (0u64, 0.0f64, 0.0f64, 0.0f64);
    let mut gpu: Option<Vec<(&'static str, f64)>> = None;
    for k in 0..args.frames {
        let f = session.simulate_to(&ctx, f64::from(k) / args.fps, true)?;
        steps += f.steps;
        let ms = f.wall_ms.unwrap_or(0.0);
        sim_ms += ms;
        sim_max = sim_max.max(ms);
        if let tress_render::Timings::Passes(p) = &f.gpu {
            let sums = gpu.get_or_insert_with(|| p.iter().map(|t| (t.name, 0.0)).collect());
            for t in p {
                if let Some(s) = sums.iter_mut().find(|s| s.0 == t.name) {
                    s.1 += t.ms;
                }
            }
        }
        let t = std::time::Instant::now();
        let p = session.read_hair_positions(&ctx)?;
        readback_ms += t.elapsed().as_secs_f64() * 1e3;
        if p.len() != hair.positions().len() {
            bail!(
                "the simulation drew {} vertices, the hair has {}",
                p.len(),
                hair.positions().len()
            );
        }
        frames.push(p);
        pb.inc(1);
    }
    pb.finish_and_clear();
    let t = std::time::Instant::now();
    tress_hair::formats::write_cache_path(&args.output, &hair, &frames, args.fps)?;
    let write_ms = t.elapsed().as_secs_f64() * 1e3;
    let sim = session.simulation().context("the simulation stopped")?;
    let (guides, strands) = sim.counts();
    let report = SimulateReport {
        output: args.output.display().to_string(),
        frames: args.frames,
        fps: args.fps,
        characters: sim.characters().count(),
        guides,
        strands,
        vertices: hair.positions().len(),
        steps,
        rate_hz: settings.rate_hz,
        substeps: settings.substeps,
        simulate_ms_mean: sim_ms / f64::from(args.frames),
        simulate_ms_max: sim_max,
        simulate_gpu_ms_mean: gpu
            .as_ref()
            .map(|g| g.iter().map(|p| p.1).sum::<f64>() / f64::from(args.frames)),
        passes: gpu
            .unwrap_or_default()
            .into_iter()
            .map(|(name, ms)| PassReport {
                name,
                gpu_ms: ms / f64::from(args.frames),
            })
            .collect(),
        readback_ms,
        write_ms,
        simulation_bytes: sim.bytes(),
        cache_bytes: std::fs::metadata(&args.output).map_or(0, |m| m.len()),
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!(
            "wrote {} ({} frames at {} fps: {} strands from {} guides, {} steps; {:.2} ms a frame \
             simulating{}, {:.1} MB)",
            report.output,
            report.frames,
            report.fps,
            report.strands,
            report.guides,
            report.steps,
            report.simulate_ms_mean,
            report
                .simulate_gpu_ms_mean
                .map_or(String::new(), |g| format!(" ({g:.2} ms on the GPU)")),
            report.cache_bytes as f64 / 1e6
        );
    }
    Ok(())
}
