//! `tress render [INPUT...] -o OUT.(png|exr) [--technique T] [--width W --height H]
//! [--set key=value]... [--json]`

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use glam::Vec3;
use serde::Serialize;
use tress_render::patches::scene::PatchScene;
use tress_render::scene_setup::{PreparedScene, frame_bounds, load_patches};
use tress_render::{
    COLOR_FORMAT, FrameInputs, FrameStats, GpuContext, HeadGeometry, OffscreenTargets,
    PatchFrameInputs, PatchFrameStats, PatchRenderer, Renderer, TargetFormats, Timings,
    read_texture,
};
use tress_scene::Scene;

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
    /// Move the hair over the sequence: `sway` (a procedural pendulum sway; the volume is
    /// voxelized again every frame).
    #[arg(long, value_name = "MOTION")]
    animate: Option<String>,
    /// Write the exact sorted composite of the strands instead of the OIT's (a reference for
    /// `tress compare-images`): drawn with the PPLL holding every fragment, its lists read back
    /// and every pixel's fragments blended in depth order on the CPU. Technique `strands`.
    #[arg(long)]
    exact_oit: bool,
}

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
    /// The strand rasterizer's OIT, when strands were drawn.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) oit: Option<OitReport>,
    pub(crate) output: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) patches: Option<PatchReport>,
    /// The hair volume, when the frame voxelized it (volume, hybrid, or strands with volume
    /// shadows or AO).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) volume: Option<super::animate::VolumeReport>,
    /// The `satf` technique's part.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) satf: Option<super::render_satf::SatfReport>,
}

impl Report {
    /// The keys every technique reports, for a frame of `size` of `scene` written to `output`;
    /// no PPLL (zeros) and no technique part.
    pub(crate) fn new(
        ctx: &GpuContext,
        scene: &Scene,
        size: [u32; 2],
        (strands, segments): (usize, usize),
        output: &Path,
        passes: Vec<Pass>,
        frame_gpu_ms: Option<f64>,
    ) -> Report {
        Report {
            technique: scene.technique.clone(),
            width: size[0],
            height: size[1],
            strands,
            segments,
            adapter: Adapter {
                name: ctx.adapter_info.name.clone(),
                backend: format!("{:?}", ctx.adapter_info.backend).to_lowercase(),
            },
            passes,
            frame_gpu_ms,
            ppll: Ppll::default(),
            oit: None,
            output: output.display().to_string(),
            patches: None,
            volume: None,
            satf: None,
        }
    }
}

/// The `patches` technique's part of the report.
#[derive(Serialize)]
pub(crate) struct PatchReport {
    scheme: String,
    source: String,
    triangles: u32,
    components: usize,
    ao_bake_s: Option<f64>,
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

/// Strands and segments of the scene's hair (zeros without hair).
pub(crate) fn hair_counts(prepared: &PreparedScene) -> (usize, usize) {
    prepared
        .hair
        .as_ref()
        .map_or((0, 0), |h| (h.strand_count(), h.segment_count()))
}

/// The scene's head mesh uploaded, if it has one.
pub(crate) fn upload_head(
    ctx: &GpuContext,
    prepared: &PreparedScene,
) -> Result<Option<HeadGeometry>> {
    Ok(prepared
        .head
        .as_ref()
        .map(|m| HeadGeometry::new(ctx, m))
        .transpose()?)
}

/// Write `image` to `path`: OpenEXR for `.exr` (any case), PNG otherwise.
pub(crate) fn save(image: &tress_render::LinearImage, path: &Path) -> Result<()> {
    match path.extension() {
        Some(e) if e.eq_ignore_ascii_case("exr") => image.save_exr(path)?,
        _ => image.save_png(path)?,
    }
    Ok(())
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
        scene.apply_override(&format!("technique=\"{t}\""))?;
    }
    scene.apply_overrides(sets)?;
    Ok(())
}

pub(crate) fn run(args: Args) -> Result<()> {
    check_output(&args.output)?;
    let (mut scene, auto_frame) = base_scene(&args.inputs)?;
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
    let pb = progress::spinner("loading hair");
    let prepared = PreparedScene::load(&scene);
    pb.finish_and_clear();
    let mut prepared = prepared?;
    if let (true, Some(h)) = (auto_frame, &prepared.hair) {
        let b = h.bounds();
        frame_bounds(&mut scene, b.min, b.max);
        // The command line's --set still wins over the automatic framing.
        scene.apply_overrides(&sets)?;
        prepared = prepared.reload_settings(&scene)?;
    }
    let patches = if scene.technique == "patches" {
        let pb = progress::spinner("building patches");
        let p = load_patches(&scene, &prepared);
        pb.finish_and_clear();
        let p = p?;
        if let (true, None, Some(b)) = (auto_frame, &prepared.hair, p.mesh.bounds()) {
            frame_bounds(&mut scene, b.min, b.max);
            scene.apply_overrides(&args.sets)?;
        }
        Some(p)
    } else {
        None
    };
    let size = [scene.output.width, scene.output.height];

    let ctx = GpuContext::headless()?;
    if scene.technique == "satf" {
        return super::render_satf::run(&ctx, &scene, &prepared, size, &args.output, args.json);
    }
    if let Some(p) = &patches {
        return run_patches(&ctx, &args, &scene, &prepared, p, size);
    }
    if args.frames.is_some() || args.animate.is_some() {
        let seq = super::animate::Sequence {
            frames: args.frames,
            animate: args.animate.as_deref(),
            json: args.json,
        };
        return super::animate::run(&ctx, seq, &args.output, &scene, &prepared, size);
    }
    let pb = rendering_spinner(&ctx, size);
    let result = if args.exact_oit {
        super::exact_oit::render(&ctx, &scene, &prepared, size)
    } else {
        render_frame(&ctx, &scene, &prepared, size)
    };
    pb.finish_and_clear();
    let (image, stats) = result?;
    save(&image, &args.output)?;

    let (strands, segments) = hair_counts(&prepared);
    let report = report(&ctx, &scene, &args.output, strands, segments, &stats);
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!(
            "wrote {} ({}x{}, {} strands, {} segments) on {} ({})",
            report.output,
            size[0],
            size[1],
            strands,
            segments,
            report.adapter.name,
            report.adapter.backend
        );
        match stats.gpu.as_ref().map(|g| &g.timings) {
            Some(t @ Timings::Passes(_)) => {
                println!("{t}; frame {:.3} ms", t.total_ms().unwrap_or(0.0))
            }
            _ => println!("GPU timestamps: not supported by this device"),
        }
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
    }
    Ok(())
}

/// Render one frame of a prepared scene offscreen and read it back.
pub(crate) fn render_frame(
    ctx: &GpuContext,
    scene: &Scene,
    prepared: &PreparedScene,
    size: [u32; 2],
) -> Result<(tress_render::LinearImage, FrameStats)> {
    let (_, targets, stats) = draw_frame(ctx, scene, prepared, size)?;
    let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
    Ok((image, stats))
}

/// Draw one frame of a prepared scene offscreen; the renderer (with its PPLL lists) and the
/// targets are returned for reading back.
pub(crate) fn draw_frame(
    ctx: &GpuContext,
    scene: &Scene,
    prepared: &PreparedScene,
    size: [u32; 2],
) -> Result<(Renderer, OffscreenTargets, FrameStats)> {
    let mut renderer = super::animate::renderer(ctx, scene, prepared)?;
    let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
    let hair = prepared
        .hair
        .as_ref()
        .map(|h| renderer.upload_hair(ctx, h))
        .transpose()?;
    let head = upload_head(ctx, prepared)?;
    let inputs = frame_inputs(
        PreparedScene::camera(scene, size),
        prepared,
        hair.as_ref(),
        head.as_ref(),
    );
    // In the default `Wait` mode the renderer itself repeats a frame that dropped fragments with
    // a grown PPLL pool (up to its cap), so one call gives the best frame the budget allows.
    let stats = renderer.render(ctx, &targets.targets(), &inputs)?;
    Ok((renderer, targets, stats))
}

/// Constant ambient light added to every technique's shading (linear RGB per channel).
pub(crate) use tress_render::session::AMBIENT;

/// The inputs of a strand, volume or hybrid frame of the prepared scene seen by `camera`.
pub(crate) fn frame_inputs<'a>(
    camera: tress_render::Camera,
    prepared: &'a PreparedScene,
    hair: Option<&'a tress_render::StrandGeometry>,
    head: Option<&'a HeadGeometry>,
) -> FrameInputs<'a> {
    FrameInputs {
        camera,
        lights: &prepared.lights,
        ambient: Vec3::splat(AMBIENT),
        material: prepared.material,
        hair,
        head,
        clear: prepared.clear_color(),
    }
}

/// The spinner shown while a frame of `size` renders.
pub(crate) fn rendering_spinner(ctx: &GpuContext, size: [u32; 2]) -> indicatif::ProgressBar {
    progress::spinner(format!(
        "rendering {}x{} on {}",
        size[0], size[1], ctx.adapter_info.name
    ))
}

pub(crate) fn report(
    ctx: &GpuContext,
    scene: &Scene,
    output: &Path,
    strands: usize,
    segments: usize,
    stats: &FrameStats,
) -> Report {
    let timings = stats.gpu.as_ref().map(|g| &g.timings);
    let frame_gpu_ms = match timings {
        Some(Timings::Passes(p)) => Some(p.iter().map(|t| t.ms).sum()),
        _ => None,
    };
    let ppll = stats.gpu.as_ref().map(|g| &g.ppll);
    Report {
        ppll: Ppll {
            capacity: stats.ppll_capacity,
            used: ppll.map_or(0, |p| p.used),
            dropped: ppll.map_or(0, |p| p.dropped),
            bytes: stats.ppll_bytes,
        },
        volume: super::animate::volume_report(stats),
        oit: OitReport::from_stats(stats),
        ..Report::new(
            ctx,
            scene,
            stats.size,
            (strands, segments),
            output,
            passes(timings),
            frame_gpu_ms,
        )
    }
}

/// `run` for the `patches` technique: render, write, report.
fn run_patches(
    ctx: &GpuContext,
    args: &Args,
    scene: &Scene,
    prepared: &PreparedScene,
    patches: &PatchScene,
    size: [u32; 2],
) -> Result<()> {
    let pb = rendering_spinner(ctx, size);
    let result = render_patch_frame(ctx, scene, prepared, patches, size);
    pb.finish_and_clear();
    let (image, stats) = result?;
    save(&image, &args.output)?;
    let passes = passes(stats.timings.as_ref());
    let frame_gpu_ms = (!passes.is_empty()).then(|| passes.iter().map(|p| p.gpu_ms).sum());
    let report = Report {
        patches: Some(PatchReport {
            scheme: stats.scheme.name().to_string(),
            source: patches.source.name().to_string(),
            triangles: stats.triangles,
            components: patches.mesh.component_count(),
            ao_bake_s: patches.ao_bake_seconds,
        }),
        ..Report::new(
            ctx,
            scene,
            size,
            hair_counts(prepared),
            &args.output,
            passes,
            frame_gpu_ms,
        )
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    println!(
        "wrote {} ({}x{}, {} triangles in {} patches from {}, {}) on {} ({})",
        report.output,
        size[0],
        size[1],
        stats.triangles,
        patches.mesh.component_count(),
        patches.source.name(),
        stats.scheme,
        report.adapter.name,
        report.adapter.backend
    );
    match &stats.timings {
        Some(t @ Timings::Passes(_)) => {
            println!("{t}; frame {:.3} ms", t.total_ms().unwrap_or(0.0))
        }
        _ => println!("GPU timestamps: not supported by this device"),
    }
    Ok(())
}

/// Render one frame of a prepared scene's patches offscreen and read it back.
pub(crate) fn render_patch_frame(
    ctx: &GpuContext,
    scene: &Scene,
    prepared: &PreparedScene,
    patches: &PatchScene,
    size: [u32; 2],
) -> Result<(tress_render::LinearImage, PatchFrameStats)> {
    let settings = tress_render::scene_setup::patch_settings(scene)?;
    let mut renderer = if patches.textures_from_files {
        PatchRenderer::with_textures(
            ctx,
            TargetFormats::default(),
            settings,
            patches.textures.clone(),
        )?
    } else {
        PatchRenderer::new(ctx, TargetFormats::default(), settings)?
    };
    let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
    let geometry = renderer.upload_patches(ctx, &patches.mesh, patches.sort_center)?;
    let head = upload_head(ctx, prepared)?;
    let inputs = PatchFrameInputs {
        camera: PreparedScene::camera(scene, size),
        lights: &prepared.lights,
        ambient: Vec3::splat(AMBIENT),
        head_color: prepared.material.head_color,
        patches: Some(&geometry),
        head: head.as_ref(),
        clear: prepared.clear_color(),
    };
    let stats = renderer.render(ctx, &targets.targets(), &inputs)?;
    let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
    Ok((image, stats))
}

/// Check that `path` names an image `render` can write (`.png` or `.exr`, any case).
fn check_output(path: &Path) -> Result<()> {
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
