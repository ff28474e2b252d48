//! `tress render [INPUT...] -o OUT.(png|exr) [--technique T] [--width W --height H]
//! [--set key=value]... [--json]`

use std::path::PathBuf;

use anyhow::{Context, Result};
use tress_render::session::{FrameDetail, Session, SessionFrame, TechniqueKind};
use tress_render::{COLOR_FORMAT, GpuContext, LinearImage, OffscreenTargets, read_texture};
use tress_scene::Scene;

use super::open::{DatabaseFile, open_session};
use super::report::{Report, check_output, save, timings_line};
use crate::progress;

/// Arguments of `tress render`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A scene file (`.toml`), or hair files (`.hair`, `.tfx`, USD, `.abc`, `.data`, `.bin`; merged, framed automatically,
    /// default lights, no head), or one hair-card OBJ file (technique `patches`). Nothing renders
    /// the built-in demo scene.
    inputs: Vec<PathBuf>,
    /// Output image: `.png` (8-bit sRGB) or `.exr` (linear float).
    #[arg(short, long)]
    output: PathBuf,
    /// Rendering technique (default: the scene's, else `strands`).
    #[arg(long)]
    technique: Option<String>,
    /// Image width in pixels (default: the scene's, else 1280).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's, else 720).
    #[arg(long)]
    height: Option<u32>,
    /// Override any scene or technique setting by its dotted name, e.g. `strands.k=8`,
    /// `camera.fov_y_deg=30`, `light.0.intensity=2`. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print exactly one JSON object describing the frame.
    #[arg(long)]
    json: bool,
    /// Render a sequence of N frames, written as OUT-0000.png, OUT-0001.png, ... (with
    /// `--animate`; strands, volume and hybrid techniques).
    #[arg(long, value_name = "N")]
    frames: Option<u32>,
    /// Move the hair over the sequence: `sway` (a procedural pendulum sway) or `simulate` (the
    /// strand simulation on the GPU, `[simulation]`, with the head moving as `[head.motion]`
    /// says; frames 1/24 s apart); the volume is voxelized again every frame.
    #[arg(long, value_name = "MOTION")]
    animate: Option<String>,
    /// The frame of animated hair files to draw (Alembic `P` samples, USD `points` time
    /// samples, as `tress simulate` writes them; 0 the first): sets `frame` of every hair entry.
    #[arg(long, value_name = "K")]
    frame: Option<u32>,
    /// Write the exact sorted composite of the strands instead of the OIT's (a reference for
    /// `tress compare-images`): drawn with the PPLL holding every fragment, its lists read back
    /// and every pixel's fragments blended in depth order on the CPU. Technique `strands`.
    #[arg(long)]
    exact_oit: bool,
}

/// Build the scene the inputs describe, before any settings from the command line (see
/// [`tress_render::session::scene_from_inputs`]).
pub(crate) fn base_scene(inputs: &[PathBuf]) -> Result<(Scene, bool)> {
    Ok(tress_render::session::scene_from_inputs(inputs)?)
}

/// Apply the command line's size, technique and `--set` options to a scene.
pub(crate) fn apply_options(
    scene: &mut Scene,
    technique: Option<&str>,
    width: Option<u32>,
    height: Option<u32>,
    sets: &[String],
) -> Result<()> {
    if let Some(w) = width {
        scene.apply_override(&format!("output.width={w}"))?;
    }
    if let Some(h) = height {
        scene.apply_override(&format!("output.height={h}"))?;
    }
    if let Some(t) = technique {
        // Every head of hair with this technique (their own `technique` keys dropped).
        scene.force_technique(t)?;
    }
    scene.apply_overrides(sets)?;
    Ok(())
}

pub(crate) fn run(args: Args) -> Result<()> {
    check_output(&args.output)?;
    let (mut scene, auto_frame) = base_scene(&args.inputs)?;
    if let Some(k) = args.frame {
        for h in &mut scene.hair {
            h.frame = Some(k);
        }
    }
    let sets: Vec<String> = if args.exact_oit {
        super::exact_oit::SETS
            .iter()
            .map(|s| s.to_string())
            .chain(args.sets.iter().cloned())
            .collect()
    } else {
        args.sets.clone()
    };
    apply_options(
        &mut scene,
        args.technique.as_deref(),
        args.width,
        args.height,
        &sets,
    )?;
    // A scene whose `[simulation]` is enabled simulates a sequence without `--animate`.
    let simulated = args.frames.is_some() && scene.simulation_settings()?.enabled;
    let animate = args.animate.as_deref().or(simulated.then_some("simulate"));
    let seq = (args.frames.is_some() || animate.is_some()).then_some(super::animate::Sequence {
        frames: args.frames,
        animate,
        json: args.json,
    });
    if let Some(seq) = &seq {
        seq.check(scene.technique.parse()?)?;
    }
    let ctx = GpuContext::headless()?;
    let database = DatabaseFile::default();
    let pb = progress::spinner("loading the scene");
    let session = open_session(&ctx, &scene, auto_frame, sets, Some(&database));
    pb.finish_and_clear();
    let mut session = session?;

    if let Some(seq) = seq {
        return super::animate::run(&ctx, &mut session, seq, &args.output);
    }
    if session.technique_kind() == TechniqueKind::Satf {
        return super::render_satf::run(&ctx, &mut session, &args.output, args.json, &database);
    }
    let size = [session.scene().output.width, session.scene().output.height];
    let pb = rendering_spinner(&ctx, size);
    let result = if args.exact_oit {
        super::exact_oit::render(&ctx, &mut session, size)
    } else {
        render_frame(&ctx, &mut session, size)
    };
    pb.finish_and_clear();
    let (image, frame) = result?;
    save(&image, &args.output)?;

    let report = Report::new(&ctx, &session, &frame, &args.output);
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    match (&frame.detail, &report.patches) {
        (FrameDetail::Patches(stats), Some(p)) => println!(
            "wrote {} ({}x{}, {} triangles in {} patches from {}, {}) on {} ({})",
            report.output,
            size[0],
            size[1],
            stats.triangles,
            p.components,
            p.source,
            stats.scheme,
            report.adapter.name,
            report.adapter.backend
        ),
        _ => println!(
            "wrote {} ({}x{}, {} strands, {} segments) on {} ({})",
            report.output,
            size[0],
            size[1],
            report.strands,
            report.segments,
            report.adapter.name,
            report.adapter.backend
        ),
    }
    println!("{}", timings_line(frame.timings.as_ref()));
    if report.ppll.capacity > 0 {
        println!(
            "PPLL: {} of {} nodes used, {} fragments dropped ({:.1} MiB)",
            report.ppll.used,
            report.ppll.capacity,
            report.ppll.dropped,
            report.ppll.bytes as f64 / (1u64 << 20) as f64
        );
    }
    if let Some(o) = &report.oit {
        println!("{o}");
    }
    if let Some(v) = &report.volume {
        println!("{v}");
    }
    if report.objects.len() > 1 {
        for (i, o) in report.objects.iter().enumerate() {
            println!(
                "hair {i}: {} (lod {:.2}, {:.0} px across, {:.1}% of the frame{})",
                o.technique,
                o.lod,
                o.size_px,
                o.coverage * 100.0,
                o.fallback
                    .map_or(String::new(), |f| format!("; over {f}, drawn as strands"))
            );
        }
    }
    Ok(())
}

/// Render one frame of the session's scene at `size` offscreen and read it back. In the
/// default `Wait` readback the strand renderer itself repeats a frame that dropped fragments
/// with a grown PPLL pool (up to its cap), so one call gives the best frame the budget allows.
pub(crate) fn render_frame(
    ctx: &GpuContext,
    session: &mut Session,
    size: [u32; 2],
) -> Result<(LinearImage, SessionFrame)> {
    let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
    let camera = session.camera(size);
    let frame = session.render(ctx, &targets.targets(), &camera, None)?;
    let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
    Ok((image, frame))
}

/// The spinner shown while a frame of `size` renders.
pub(crate) fn rendering_spinner(ctx: &GpuContext, size: [u32; 2]) -> indicatif::ProgressBar {
    progress::spinner(format!(
        "rendering {}x{} on {}",
        size[0], size[1], ctx.adapter_info.name
    ))
}
