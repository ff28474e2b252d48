//! The `simulation` sweep: the scene's hair simulated with more and more guides (the other
//! strands followers rebuilt from them every step), the head turning (`turn`), at the scene's
//! `[simulation]` settings otherwise. At each point: warm-up frames, then timed frames one
//! simulation step (1 / `rate_hz`) apart; the simulation's time per frame is its wall-clock time
//! with the GPU waited for (recording, submission, every substep and the followers' rebuild into
//! the vertex buffer), beside the strand frame's time (GPU timestamps where the device has them),
//! its share of that frame, and the simulation's GPU memory. Into `simulation.csv` and a section
//! of `summary.md`.

use std::fmt::Write as _;

use anyhow::{Context, Result};
use tress_render::OffscreenTargets;
use tress_render::session::Session;
use tress_sim::{MotionSpec, Preset};

use super::measure::{camera_at, measure};
use super::sweeps::Sweep;
use super::{Run, report};

/// One point's figures.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SimRow {
    /// Guides asked for and simulated.
    pub(crate) target: u64,
    pub(crate) guides: usize,
    pub(crate) strands: usize,
    pub(crate) vertices: usize,
    /// Wall time of a frame's simulation step: mean and worst, ms.
    pub(crate) mean_ms: f64,
    pub(crate) max_ms: f64,
    /// GPU time of a frame's simulation (its passes' sum), mean, ms: where the device has
    /// timestamps.
    pub(crate) gpu_ms: Option<f64>,
    pub(crate) bytes: u64,
}

/// The share of strands a point simulates to get about `target` guides (at least one strand
/// in every 1,000, at most all).
pub(crate) fn guide_share(target: f64, strands: usize) -> f32 {
    ((target / strands.max(1) as f64).clamp(1e-3, 1.0)) as f32
}

/// Run the sweep on `session` (the run's scene, strands technique); returns the rows and the
/// strand frame's time (ms) and its source.
pub(crate) fn run_sweep(
    run: &Run,
    session: &mut Session,
    sweep: &Sweep,
    targets: &OffscreenTargets,
    warmup: u32,
    frames: u32,
) -> Result<(Vec<SimRow>, f64, &'static str)> {
    let ctx = &run.ctx;
    session.set_technique(ctx, "strands")?;
    let camera = camera_at(session, run.size, 1.0);
    let (m, _, _) = measure(ctx, session, targets, &camera, warmup, frames, false)?;
    let (frame_ms, source) = (m.frame_ms, m.timing.name());
    let (strands, vertices) = {
        let hair = session
            .prepared()
            .hair()
            .context("the simulation sweep needs hair")?;
        (hair.strand_count(), hair.positions().len())
    };
    let base = session.scene().simulation_settings()?;
    let rate = f64::from(base.rate_hz);
    let mut rows = Vec::new();
    for p in &sweep.points {
        let settings = tress_sim::SimSettings {
            guides: guide_share(p.x, strands),
            ..base.clone()
        };
        session.start_simulation(ctx, settings, MotionSpec::preset(Preset::Turn))?;
        let mut step = 0u32;
        for _ in 0..warmup {
            step += 1;
            session.simulate_to(ctx, f64::from(step) / rate, true)?;
        }
        let mut times = Vec::with_capacity(frames as usize);
        let mut gpu = Vec::with_capacity(frames as usize);
        for _ in 0..frames.max(1) {
            step += 1;
            let f = session.simulate_to(ctx, f64::from(step) / rate, true)?;
            times.push(f.wall_ms.unwrap_or(0.0));
            gpu.extend(f.gpu.total_ms());
        }
        let sim = session.simulation().context("the simulation stopped")?;
        let (guides, strands) = sim.counts();
        let row = SimRow {
            target: p.x as u64,
            guides,
            strands,
            vertices,
            mean_ms: times.iter().sum::<f64>() / times.len() as f64,
            max_ms: times.iter().copied().fold(0.0, f64::max),
            gpu_ms: (gpu.len() == times.len()).then(|| gpu.iter().sum::<f64>() / gpu.len() as f64),
            bytes: sim.bytes(),
        };
        eprintln!(
            "simulation {} guides ({} of {} strands): {:.2} ms a frame ({:.1}% of the strands' \
             {frame_ms:.2} ms), {:.1} MiB",
            row.target,
            row.guides,
            row.strands,
            row.mean_ms,
            100.0 * row.mean_ms / frame_ms,
            row.bytes as f64 / f64::from(1 << 20)
        );
        rows.push(row);
        session.stop_simulation(ctx)?;
    }
    Ok((rows, frame_ms, source))
}

/// `simulation.csv`.
pub(crate) fn csv(rows: &[SimRow], frame_ms: f64, source: &str) -> String {
    let mut out = String::from(
        "sweep,guides_target,guides,strands,vertices,sim_ms_mean,sim_ms_max,strand_frame_ms,\
         strand_frame_timing,share_pct,sim_bytes,sim_gpu_ms\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "simulation,{},{},{},{},{:.4},{:.4},{:.4},{source},{:.2},{},{}",
            r.target,
            r.guides,
            r.strands,
            r.vertices,
            r.mean_ms,
            r.max_ms,
            frame_ms,
            100.0 * r.mean_ms / frame_ms,
            r.bytes,
            r.gpu_ms.map_or(String::new(), |g| format!("{g:.4}"))
        );
    }
    out
}

/// The sweep's section of `summary.md`.
pub(crate) fn markdown(rows: &[SimRow], frame_ms: f64, source: &str) -> String {
    let mut out = format!(
        "\n## simulation\n\nThe hair simulated with more and more guides (every other strand a \
         follower rebuilt from them each step), the head turning. Simulation: wall time a frame \
         with the GPU waited for; the strands' frame: {frame_ms:.2} ms ({source}).\n\n\
         | guides | strands | simulation ms (mean / worst) | of which GPU ms | share of the strand frame | memory MiB |\n\
         | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    );
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.2} / {:.2} | {} | {:.1}% | {:.1} |",
            r.guides,
            r.strands,
            r.mean_ms,
            r.max_ms,
            r.gpu_ms.map_or("-".to_string(), |g| format!("{g:.2}")),
            100.0 * r.mean_ms / frame_ms,
            r.bytes as f64 / f64::from(1 << 20)
        );
    }
    out
}

/// Write `simulation.csv` into the run's folder; returns the summary section.
pub(crate) fn write(run: &Run, rows: &[SimRow], frame_ms: f64, source: &str) -> Result<String> {
    report::write(&run.dir, "simulation.csv", &csv(rows, frame_ms, source))?;
    Ok(markdown(rows, frame_ms, source))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_give_the_guides_asked_for_within_the_strands() {
        assert!((guide_share(5000.0, 136_320) * 136_320.0 - 5000.0).abs() < 1.0);
        assert_eq!(guide_share(50_000.0, 13_632), 1.0);
        assert_eq!(guide_share(1.0, 1_000_000), 1e-3);
    }

    #[test]
    fn the_share_of_the_frame_is_simulation_over_strands() {
        let row = SimRow {
            target: 1000,
            guides: 998,
            strands: 27_000,
            vertices: 351_000,
            mean_ms: 0.5,
            max_ms: 0.7,
            gpu_ms: Some(0.25),
            bytes: 3 << 20,
        };
        let csv = csv(std::slice::from_ref(&row), 10.0, "GPU timestamps");
        let line = csv.lines().nth(1).unwrap();
        assert_eq!(
            line,
            "simulation,1000,998,27000,351000,0.5000,0.7000,10.0000,GPU timestamps,5.00,3145728,0.2500"
        );
        let md = markdown(&[row], 10.0, "GPU timestamps");
        assert!(
            md.contains("| 998 | 27000 | 0.50 / 0.70 | 0.25 | 5.0% | 3.0 |"),
            "{md}"
        );
    }
}
