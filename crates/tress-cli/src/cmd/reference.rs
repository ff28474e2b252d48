//! `tress reference [INPUT...] -o OUT.(png|exr) [--spp N] [--aov color|ao|shadow] [--seed S]
//! [--width W --height H] [--set key=value]... [--json]`: the ray-traced reference image of a
//! scene (`tress-trace`).
//!
//! Inputs are read exactly like `tress render`'s (a scene file, hair files framed automatically,
//! or the built-in demo). `--set trace.NAME=VALUE` sets a tracer setting
//! (`tress_trace::SETTING_NAMES`); every other `--set` goes to the scene. `--spp`, `--aov` and
//! `--seed` win over `--set trace.*`.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use tress_render::scene_setup::frame_bounds;
use tress_trace::{ImageKind, SceneGeometry, TraceSettings, Tracer};

use crate::cmd::render::{apply_options, base_scene};
use crate::progress;

/// Arguments of `tress reference`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A scene file (`.toml`), or hair files (`.hair`, `.tfx`, USD, `.abc`, `.data`, `.bin`; merged, framed automatically,
    /// default lights, no head). Nothing traces the built-in demo scene.
    inputs: Vec<PathBuf>,
    /// Output image: `.png` (8-bit sRGB) or `.exr` (linear float).
    #[arg(short, long)]
    output: PathBuf,
    /// Camera samples per pixel (default 64).
    #[arg(long)]
    spp: Option<u32>,
    /// What to write: `color`, `ao` (ambient occlusion) or `shadow` (light visibility).
    #[arg(long)]
    aov: Option<String>,
    /// Random seed (default 0); the same seed gives the same image.
    #[arg(long)]
    seed: Option<u64>,
    /// Image width in pixels (default: the scene's, else 1280).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's, else 720).
    #[arg(long)]
    height: Option<u32>,
    /// Override a scene setting by its dotted name (`camera.fov_y_deg=30`, `strands.alpha=0.5`)
    /// or a tracer setting with a `trace.` prefix (`trace.ao_radius=2`, `trace.width=screen`).
    /// Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print exactly one JSON object describing the render.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Report {
    output: String,
    width: u32,
    height: u32,
    spp: u32,
    aov: String,
    strand_width: String,
    strands: usize,
    segments: usize,
    triangles: usize,
    build_seconds: f64,
    render_seconds: f64,
    samples: u64,
    rays: u64,
    rays_per_second: f64,
}

/// Split `--set` values into tracer settings (`trace.NAME=VALUE`) and scene overrides, and
/// apply the former.
fn trace_settings(args: &Args) -> Result<(TraceSettings, Vec<String>)> {
    let mut settings = TraceSettings::default();
    let mut scene_sets = Vec::new();
    for set in &args.sets {
        match set.strip_prefix("trace.") {
            Some(rest) => {
                let (name, value) = rest
                    .split_once('=')
                    .with_context(|| format!("--set `{set}`: expected trace.NAME=VALUE"))?;
                settings.set(name.trim(), value)?;
            }
            None => scene_sets.push(set.clone()),
        }
    }
    if let Some(spp) = args.spp {
        settings.set("spp", &spp.to_string())?;
    }
    if let Some(aov) = &args.aov {
        settings.set("aov", aov)?;
    }
    if let Some(seed) = args.seed {
        settings.seed = seed;
    }
    Ok((settings, scene_sets))
}

pub(crate) fn run(args: Args) -> Result<()> {
    ImageKind::from_path(&args.output)?;
    let (settings, scene_sets) = trace_settings(&args)?;
    let (mut scene, auto_frame) = base_scene(&args.inputs)?;
    apply_options(&mut scene, None, args.width, args.height, &scene_sets)?;

    let pb = progress::spinner("loading hair");
    let geometry = SceneGeometry::load(&scene);
    pb.finish_and_clear();
    let geometry = geometry?;
    let mut settings = settings;
    if let (true, Some(h)) = (auto_frame, &geometry.hair) {
        let b = h.bounds();
        frame_bounds(&mut scene, b.min, b.max);
        // The command line's --set still wins over the automatic framing.
        scene.apply_overrides(&scene_sets)?;
        // The AO radius is in world units too (`frame_bounds` fits the scene's).
        let given = args
            .sets
            .iter()
            .any(|s| s.trim_start().starts_with("trace.ao_radius"));
        if !given && settings.ao_radius.is_finite() {
            settings.ao_radius *= tress_render::scene_setup::unit_scale(b.min, b.max);
        }
    }

    let pb = progress::spinner("building the BVH");
    let tracer = Tracer::new(&scene, &geometry, &settings);
    pb.finish_and_clear();
    let tracer = tracer?;

    let (w, h) = (scene.output.width, scene.output.height);
    let pb = ProgressBar::new(u64::from(h));
    pb.set_style(
        ProgressStyle::with_template(
            "tracing {msg} [{bar:30}] {pos}/{len} rows ({elapsed}, about {eta} left)",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    pb.set_message(format!("{w}x{h} at {} spp", settings.spp));
    pb.enable_steady_tick(Duration::from_millis(200));
    let rendered = tracer.render(&|rows| pb.inc(u64::from(rows)));
    pb.finish_and_clear();
    rendered.image.save(&args.output)?;

    let stats = rendered.stats;
    let (strands, segments) = geometry
        .hair
        .as_ref()
        .map_or((0, 0), |h| (h.strand_count(), h.segment_count()));
    let report = Report {
        output: args.output.display().to_string(),
        width: w,
        height: h,
        spp: settings.spp,
        aov: settings.aov.to_string(),
        strand_width: tracer.strand_width().name().to_owned(),
        strands,
        segments,
        triangles: tracer.triangle_count(),
        build_seconds: tracer.build_seconds(),
        render_seconds: stats.seconds,
        samples: stats.samples,
        rays: stats.rays,
        rays_per_second: stats.rays_per_second(),
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!(
            "wrote {} ({w}x{h}, {} spp, {}; {strands} strands, {segments} segments, {} triangles, \
             {} strand width)",
            report.output, report.spp, report.aov, report.triangles, report.strand_width
        );
        println!(
            "BVH {:.2} s; traced {} rays in {:.2} s ({:.2} M rays/s)",
            report.build_seconds,
            report.rays,
            report.render_seconds,
            report.rays_per_second / 1e6
        );
    }
    Ok(())
}
