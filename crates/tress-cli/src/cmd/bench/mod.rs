//! `tress bench [INPUT...] -o DIR [--quick] [--sweep NAME]... [--quality]`
//!
//! The hybrid paper's evaluation (§4.1) for every technique: sweeps of camera distance, strand
//! count, raymarch steps, volume resolution, PPLL k and the patch render scheme (see
//! [`sweeps`]). Each point renders warm-up frames, then averages per-pass GPU timestamps over
//! the timed frames (CPU wall time where the device has none, labelled), and measures the hair's
//! screen coverage and the GPU memory breakdown. Into `DIR`: `SWEEP.csv` per sweep, charts as
//! PNG and SVG, and `summary.md` naming the adapter. `--quality` adds the image-quality report
//! against the CPU reference ray tracer ([`quality`]).

mod agreement;
mod chart;
mod crowd;
mod measure;
mod quality;
mod quality_report;
mod report;
mod silhouette;
mod simulation;
mod sweeps;

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use tress_render::session::Session;
use tress_render::{COLOR_FORMAT, GpuContext, OffscreenTargets};
use tress_scene::Scene;

use self::chart::tick;
use self::measure::{camera_at, measure};
use self::report::Row;
use self::sweeps::{SWEEPS, Sweep, sweep};
use super::open::open_session;
use super::render::base_scene;
use crate::progress;

/// The share of the scene's strands a `--quick` run draws.
const QUICK_STRANDS: f32 = 0.25;

/// Arguments of `tress bench`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A scene file (`.toml`) or hair files; nothing: the built-in demo.
    inputs: Vec<PathBuf>,
    /// Output folder (created): CSV per sweep, charts (PNG, SVG), summary.md.
    #[arg(short, long)]
    output: PathBuf,
    /// A reduced run for a CPU Vulkan: two points per sweep, 320x180, 1 warm-up and 2 timed
    /// frames, a quarter of the scene's strands (with --quality: the first scene only, two
    /// distances, 16 spp, 192x108).
    #[arg(long)]
    quick: bool,
    /// Run only these sweeps (repeatable): distance, strands, steps, resolution, k, patches,
    /// oit, characters, simulation.
    #[arg(long = "sweep", value_name = "NAME")]
    sweeps: Vec<String>,
    /// Measure image quality against the CPU reference instead of speed (see `--spp`).
    #[arg(long)]
    quality: bool,
    /// `--quality`: the reference's first samples per pixel (default 64, 16 with --quick); it
    /// doubles until converged (`--converge`).
    #[arg(long)]
    spp: Option<u32>,
    /// `--quality`: the reference is converged when its seed pair's FLIP over the hair at the
    /// matched scale is at most this (default 0.01).
    #[arg(long, value_name = "FLIP", default_value_t = 0.01)]
    converge: f64,
    /// `--quality`: the most samples per pixel the reference is traced to (default 1024; with
    /// --quick, `--spp`: no doubling).
    #[arg(long, value_name = "N")]
    max_spp: Option<u32>,
    /// `--quality`: the matched scale's box factor (both images averaged over N x N blocks in
    /// linear light before the matched scores; default 3).
    #[arg(long, value_name = "N", default_value_t = tress_trace::matched::DEFAULT_SCALE)]
    scale: u32,
    /// `--quality` only: score only these techniques (repeatable; default all). The strand
    /// renderer is rendered anyway for the hair mask and the stray-hair silhouette test.
    #[arg(long = "technique", value_name = "NAME")]
    techniques: Vec<String>,
    /// `--quality` only: camera distances as multiples of the scene's (repeatable; default 1,
    /// 2, 4; 1, 3 with --quick).
    #[arg(long = "distance", value_name = "FACTOR")]
    distances: Vec<f32>,
    /// Image width (default 1280, 320 with --quick; --quality: 384, 192 with --quick).
    #[arg(long)]
    width: Option<u32>,
    /// Image height (default 720, 180 with --quick; --quality: 216, 108 with --quick).
    #[arg(long)]
    height: Option<u32>,
    /// Frames rendered before timing each point (default 5, 1 with --quick).
    #[arg(long)]
    warmup: Option<u32>,
    /// Frames timed per point (default 60, 2 with --quick).
    #[arg(long)]
    frames: Option<u32>,
    /// Shade every technique that can with this model: `kajiya-kay`, `scheuermann` (both set
    /// `strands.shading`) or `marschner` (sets `strands.shading` and `patches.shading`; with
    /// --quality the reference is then the path tracer with Chiang et al.'s fibres). SATF keeps
    /// its paper's lighting. `--set` still overrides either key.
    #[arg(long, value_name = "MODEL")]
    shading: Option<String>,
    /// Override any scene or technique setting (`key=value`), as for `render`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
}

/// The overrides `--shading` stands for (before the user's `--set`s, which win).
fn shading_sets(shading: Option<&str>) -> Result<Vec<String>> {
    let Some(name) = shading else {
        return Ok(Vec::new());
    };
    let model: tress_render::Shading = name.parse().with_context(|| "--shading".to_string())?;
    let mut sets = vec![format!("strands.shading=\"{model}\"")];
    if model == tress_render::Shading::Marschner {
        sets.push(format!("patches.shading=\"{model}\""));
    }
    Ok(sets)
}

/// Set each row's mean FLIP against the exact sorted composite of the reference row's frame
/// (`sweeps::OIT_REFERENCE`).
fn score_against_reference(
    rows: &mut [Row],
    images: &[Option<tress_render::LinearImage>],
    exact: Option<&tress_render::LinearImage>,
) {
    use tress_trace::{DisplayImage, metrics};
    let display =
        |i: &tress_render::LinearImage| DisplayImage::from_linear(&quality::linear_to_trace(i));
    let Some(reference) = exact.map(display) else {
        return;
    };
    for (r, image) in rows.iter_mut().zip(images) {
        if let (Ok(m), Some(image)) = (&mut r.result, image) {
            m.flip = metrics::compare(&reference, &display(image))
                .ok()
                .map(|c| c.scores.flip);
        }
    }
}

/// Resolved run settings.
pub(crate) struct Run {
    pub(crate) ctx: GpuContext,
    pub(crate) scene: Scene,
    pub(crate) auto_frame: bool,
    pub(crate) sets: Vec<String>,
    pub(crate) size: [u32; 2],
    pub(crate) dir: PathBuf,
    pub(crate) scene_name: String,
}

impl Run {
    /// A session on the run's scene with its overrides.
    pub(crate) fn session(&self) -> Result<Session> {
        open_session(
            &self.ctx,
            &self.scene,
            self.auto_frame,
            self.sets.clone(),
            None,
        )
    }
}

pub(crate) fn run(args: Args) -> Result<()> {
    let names: Vec<String> = if args.sweeps.is_empty() {
        SWEEPS.iter().map(|s| (*s).to_string()).collect()
    } else {
        args.sweeps.clone()
    };
    let (warmup, frames) = (
        args.warmup.unwrap_or(if args.quick { 1 } else { 5 }),
        args.frames.unwrap_or(if args.quick { 2 } else { 60 }),
    );
    if frames == 0 {
        bail!("--frames must be at least 1");
    }
    let size = [
        args.width.unwrap_or(if args.quick { 320 } else { 1280 }),
        args.height.unwrap_or(if args.quick { 180 } else { 720 }),
    ];
    let (mut scene, auto_frame) = base_scene(&args.inputs)?;
    let mut sets = shading_sets(args.shading.as_deref())?;
    sets.extend(args.sets.iter().cloned());
    scene.apply_overrides(&sets)?;
    if args.quick && !args.quality {
        // A quarter of the strands: the quick run is about the pipeline, not the asset.
        let quarter: Vec<String> = scene
            .hair
            .iter()
            .enumerate()
            .map(|(i, h)| format!("hair.{i}.strand_ratio={}", h.strand_ratio * QUICK_STRANDS))
            .collect();
        scene.apply_overrides(&quarter)?;
        sets.extend(quarter);
    }
    // Settings and every sweep are checked before any work starts.
    let settings = tress_render::PreparedScene::load_settings(&scene)?;
    settings.volume.validate()?;
    settings.strands.validate()?;
    let plan: Vec<Sweep> = names
        .iter()
        .map(|n| sweep(n, args.quick, &scene))
        .collect::<Result<_>>()?;
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: creating the output folder", args.output.display()))?;
    let scene_name = match args.inputs.as_slice() {
        [] => "the built-in demo (scenes/demo.toml)".to_string(),
        files => files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(" + "),
    };
    let run = Run {
        ctx: GpuContext::headless()?,
        scene,
        auto_frame,
        sets,
        size,
        dir: args.output.clone(),
        scene_name,
    };
    if args.quality {
        let spp = args.spp.unwrap_or(if args.quick { 16 } else { 64 });
        if !(1..=64).contains(&args.scale) {
            anyhow::bail!("--scale must lie in 1..=64, got {}", args.scale);
        }
        if !(args.converge.is_finite() && args.converge >= 0.0) {
            anyhow::bail!(
                "--converge must be a non-negative FLIP, got {}",
                args.converge
            );
        }
        if let Some(max) = args.max_spp
            && max < spp
        {
            anyhow::bail!("--max-spp {max} is below --spp {spp}");
        }
        let select = quality::Select {
            techniques: &args.techniques,
            distances: &args.distances,
            shading: args.shading.as_deref(),
            converge: quality::Converge {
                spp,
                threshold: args.converge,
                max_spp: args.max_spp.unwrap_or(if args.quick { spp } else { 1024 }),
                scale: args.scale,
            },
        };
        return quality::run(&run, args.quick, &select);
    }
    let info = &run.ctx.adapter_info;
    let targets = OffscreenTargets::new(&run.ctx, size, COLOR_FORMAT)?;
    let mut done = Vec::new();
    let (mut extra_summary, mut extra_points) = (String::new(), 0);
    for sw in plan {
        if sw.name == "simulation" {
            let mut session = run.session()?;
            let (rows, frame_ms, source) =
                simulation::run_sweep(&run, &mut session, &sw, &targets, warmup, frames)?;
            extra_summary += &simulation::write(&run, &rows, frame_ms, source)?;
            extra_points += rows.len();
            continue;
        }
        let mut rows = Vec::new();
        let mut frames_kept = Vec::new();
        let mut exact = None;
        // A fresh session per sweep: the sweep's overrides never leak into the next one.
        let mut session = run.session()?;
        // The scene as framed, which the characters sweep copies.
        let framed = session.scene().clone();
        for (i, p) in sw.points.iter().enumerate() {
            let point_start = rows.len();
            if let Some(n) = p.characters {
                let scene = crowd::crowd(&framed, n)
                    .ok_or_else(|| anyhow::anyhow!("the characters sweep needs hair"))?;
                let pb = progress::spinner(format!("loading {n} characters"));
                session = open_session(&run.ctx, &scene, false, Vec::new(), None)?;
                pb.finish_and_clear();
            }
            for series in &sw.series {
                let t = series.name;
                let pb = progress::spinner(format!(
                    "{} {}/{}: {t} at {} on {}",
                    sw.name,
                    i + 1,
                    sw.points.len(),
                    tick(p.x),
                    info.name
                ));
                let is_reference = sw.name == "oit" && (series.name, p.x) == sweeps::OIT_REFERENCE;
                let result = (|| -> Result<_> {
                    for s in p.sets.iter().chain(&series.sets) {
                        session.set(&run.ctx, s)?;
                    }
                    session.set_technique(&run.ctx, series.technique)?;
                    let camera = camera_at(&session, size, p.distance);
                    measure(
                        &run.ctx,
                        &mut session,
                        &targets,
                        &camera,
                        warmup,
                        frames,
                        is_reference,
                    )
                })();
                pb.finish_and_clear();
                let (result, image) = match result {
                    Ok((m, image, e)) => {
                        if e.is_some() {
                            exact = e;
                        }
                        (Ok(m), Some(image))
                    }
                    Err(e) => (Err(format!("{e:#}")), None),
                };
                match &result {
                    Ok(m) => eprintln!(
                        "{} {t} x={}: {:.2} ms ({}), coverage {:.2}%, {}",
                        sw.name,
                        tick(p.x),
                        m.frame_ms,
                        m.timing.name(),
                        m.coverage_pct,
                        m.memory
                    ),
                    Err(e) => eprintln!("{} {t} x={}: failed: {e}", sw.name, tick(p.x)),
                }
                rows.push(Row {
                    technique: t,
                    x: p.x,
                    result,
                });
                // Only the `oit` and `distance` sweeps score frames against a reference frame.
                frames_kept.push(image.filter(|_| matches!(sw.name, "oit" | "distance")));
            }
            if sw.name == "distance" {
                // Scored against the strands at this distance, then the frames are dropped: a
                // full sweep would otherwise hold every frame of every point at once.
                agreement::score_against_strands(
                    &mut rows[point_start..],
                    &frames_kept[point_start..],
                );
                frames_kept[point_start..].fill_with(|| None);
            }
        }
        if sw.name == "oit" {
            let images: Vec<_> = frames_kept
                .into_iter()
                .map(|f| f.map(|f| f.image))
                .collect();
            score_against_reference(&mut rows, &images, exact.as_ref());
        }
        if sw.name == "characters" {
            let series: Vec<&'static str> = sw.series.iter().map(|s| s.name).collect();
            if let Some(counts) = crowd::budget_counts(&rows, &series) {
                for (t, n) in counts {
                    eprintln!(
                        "characters: {t} fits {} in the time the strands need for 2",
                        tick(n)
                    );
                }
            }
        }
        report::write(
            &run.dir,
            &format!("{}.csv", sw.name),
            &report::csv(&sw, &rows),
        )?;
        let charts = report::charts(&run.dir, &sw, &rows)?;
        done.push((sw, rows, charts));
    }
    let header = report::Header {
        adapter: &info.name,
        backend: &format!("{:?}", info.backend).to_lowercase(),
        driver: &format!("{} {}", info.driver, info.driver_info),
        device_type: &format!("{:?}", info.device_type),
        scene: &run.scene_name,
        size,
        warmup,
        frames,
        quick: args.quick,
    };
    report::write(
        &run.dir,
        "summary.md",
        &(report::markdown(&header, &done) + &extra_summary),
    )?;
    for (sw, rows, _) in &done {
        if sw.name == "oit" {
            for r in rows.iter().filter(|r| r.result.is_ok()) {
                if let Ok(m) = &r.result {
                    eprintln!(
                        "oit {} k={}: {:.2} ms, {:.1} MiB, {}, mean FLIP vs exact sorting ({} k={}'s fragments) {}",
                        r.technique,
                        tick(r.x),
                        m.frame_ms,
                        m.memory.oit as f64 / f64::from(1 << 20),
                        m.oit.map_or("no OIT".to_string(), |o| format!(
                            "{} fragments, {} lost",
                            o.fragments, o.lost
                        )),
                        sweeps::OIT_REFERENCE.0,
                        sweeps::OIT_REFERENCE.1,
                        m.flip.map_or("-".to_string(), |f| format!("{f:.4}"))
                    );
                }
            }
        }
    }
    let failed = done
        .iter()
        .flat_map(|d| &d.1)
        .filter(|r| r.result.is_err())
        .count();
    println!(
        "wrote {} sweeps into {} ({} points, {failed} failed) on {}",
        done.len() + usize::from(!extra_summary.is_empty()),
        run.dir.display(),
        done.iter().map(|d| d.1.len()).sum::<usize>() + extra_points,
        info.name
    );
    Ok(())
}
