//! `tress compare [INPUT...] -o OUT.png [--width W --height H] [--set key=value]... [--json]
//! [--transition alpha|dither] [--sweep N --far-factor F --repeat R --csv OUT.csv]`
//!
//! The split image of Jansson et al. 2019, Figure 1: the strand rasterizer on the left third, the
//! volume raymarcher on the right third, and the level-of-detail transition between them across
//! the middle third (alpha-blended by default, or dithered). Both halves are full renders of the
//! same scene and camera; the mean FLIP between them (over the frame and over the hair alone),
//! the share of the frame the hair covers and both renderers' GPU times are reported.
//!
//! `--sweep N` moves the camera away along its view line in `N` geometric steps from the scene's
//! distance to `F` times it (default 12) and writes one split image per distance
//! (`OUT-0000.png`, ...) and, with `--csv`, one row per distance: the quality and speed figures
//! of the paper's §4 (Figures 7 and 8). Timings are means over `R` frames (default 3) after one
//! warm-up frame; on a CPU Vulkan (lavapipe) they are CPU times.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use glam::UVec2;
use serde::Serialize;
use tress_render::gpu::linear_to_srgb;
use tress_render::hybrid::dither_threshold;
use tress_render::scene_setup::PreparedScene;
use tress_render::session::{FrameDetail, Session, TechniqueKind};
use tress_render::{COLOR_FORMAT, Camera, GpuContext, LinearImage, OffscreenTargets, read_texture};
use tress_trace::{DisplayImage, metrics};

use super::animate::numbered;
use super::open::open_session;
use super::render::{apply_options, base_scene};
use super::report::{VolumeReport, check_output, save, volume_report};
use crate::progress;

/// Arguments of `tress compare`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A scene file (`.toml`), or hair files (framed automatically); nothing: the built-in demo.
    inputs: Vec<PathBuf>,
    /// Output split image (`.png` or `.exr`); with `--sweep`, numbered per distance.
    #[arg(short, long)]
    output: PathBuf,
    /// Image width in pixels (default: the scene's).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long)]
    height: Option<u32>,
    /// Override any scene or technique setting, as for `render` (e.g. `volume.steps=256`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print exactly one JSON object.
    #[arg(long)]
    json: bool,
    /// The middle band's transition: `alpha` or `dither`.
    #[arg(long, default_value = "alpha")]
    transition: String,
    /// Render at N distances, from the scene's to `--far-factor` times it.
    #[arg(long, value_name = "N")]
    sweep: Option<u32>,
    /// The farthest distance of a sweep, as a multiple of the scene's camera distance.
    #[arg(long, default_value_t = 12.0)]
    far_factor: f32,
    /// Frames timed per renderer and distance (after one warm-up frame).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
    /// Write the sweep's figures as CSV.
    #[arg(long, value_name = "OUT.csv")]
    csv: Option<PathBuf>,
}

/// One renderer's part of a comparison.
#[derive(Serialize, Clone, Debug)]
struct Side {
    /// Mean GPU time of a frame (sum of its passes), when timestamps exist.
    gpu_ms: Option<f64>,
    /// The volume, for the raymarcher.
    #[serde(skip_serializing_if = "Option::is_none")]
    volume: Option<VolumeReport>,
}

/// The figures at one camera distance.
#[derive(Serialize, Clone, Debug)]
struct Row {
    /// Eye-to-target distance in world units.
    distance: f32,
    /// Share of the frame the hair covers, in percent.
    coverage_pct: f64,
    /// Mean FLIP between the strand and the volume render over the whole frame.
    flip: f64,
    /// Mean FLIP over the pixels the hair covers.
    flip_hair: f64,
    strands: Side,
    volume: Side,
    /// The split image written.
    output: String,
}

#[derive(Serialize)]
struct Report {
    width: u32,
    height: u32,
    strands: usize,
    segments: usize,
    adapter: String,
    rows: Vec<Row>,
}

/// Render the session's frame from `camera` with `technique`: one warm-up frame, then `repeat`
/// timed ones; the last image.
fn timed(
    ctx: &GpuContext,
    session: &mut Session,
    targets: &OffscreenTargets,
    camera: &Camera,
    technique: TechniqueKind,
    repeat: u32,
) -> Result<(LinearImage, Side)> {
    session.set_technique(ctx, technique.name())?;
    let mut frame = session.render(ctx, &targets.targets(), camera, None)?;
    let mut total = Some(0.0);
    for _ in 0..repeat {
        frame = session.render(ctx, &targets.targets(), camera, None)?;
        let ms = frame.timings.as_ref().and_then(|t| t.total_ms());
        total = total.zip(ms).map(|(a, b)| a + b);
    }
    let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
    let volume = match &frame.detail {
        FrameDetail::Strands(stats) => volume_report(stats),
        _ => None,
    };
    Ok((
        image,
        Side {
            gpu_ms: total.map(|t| t / f64::from(repeat)),
            volume,
        },
    ))
}

/// The display encoding of an opaque linear image (for FLIP).
fn display(image: &LinearImage) -> DisplayImage {
    DisplayImage {
        width: image.width,
        height: image.height,
        pixels: image
            .pixels
            .iter()
            .map(|p| [p[0], p[1], p[2]].map(linear_to_srgb))
            .collect(),
    }
}

/// The split image: strands left, volume right, the transition across the middle third (the
/// renderer's dither thresholds for the dithered one).
fn split(strands: &LinearImage, volume: &LinearImage, dither: bool) -> LinearImage {
    let w = strands.width as f32;
    let mut out = strands.clone();
    for (i, p) in out.pixels.iter_mut().enumerate() {
        let (x, y) = (i as u32 % strands.width, i as u32 / strands.width);
        let f = ((x as f32 + 0.5 - w / 3.0) / (w / 3.0)).clamp(0.0, 1.0);
        let v = volume.pixels[i];
        *p = if dither {
            if f > dither_threshold(UVec2::new(x, y)) {
                v
            } else {
                *p
            }
        } else {
            [0, 1, 2, 3].map(|k| p[k] + (v[k] - p[k]) * f)
        };
    }
    out
}

fn differs(a: [f32; 4], b: [f32; 4]) -> bool {
    a.iter()
        .zip(&b)
        .take(3)
        .any(|(x, y)| (x - y).abs() > 1.0 / 512.0)
}

pub(crate) fn run(args: Args) -> Result<()> {
    let dither = match args.transition.as_str() {
        "alpha" => false,
        "dither" => true,
        t => bail!("unknown --transition `{t}` (expected alpha or dither)"),
    };
    if !(args.far_factor.is_finite() && args.far_factor >= 1.0) {
        bail!("--far-factor must be at least 1, got {}", args.far_factor);
    }
    let steps = args.sweep.unwrap_or(1);
    if !(1..=64).contains(&steps) {
        bail!("--sweep must be in 1..=64, got {steps}");
    }
    if !(1..=1000).contains(&args.repeat) {
        bail!("--repeat must be in 1..=1000, got {}", args.repeat);
    }
    if args.csv.is_some() && args.sweep.is_none() {
        bail!("--csv needs --sweep N");
    }
    check_output(&args.output)?;
    let (mut scene, auto_frame) = base_scene(&args.inputs)?;
    apply_options(
        &mut scene,
        Some("strands"),
        args.width,
        args.height,
        &args.sets,
    )?;
    let ctx = GpuContext::headless()?;
    let pb = progress::spinner("loading the scene");
    let session = open_session(&ctx, &scene, auto_frame, args.sets.clone(), None);
    pb.finish_and_clear();
    let mut session = session?;
    if session.prepared().objects.is_empty() {
        bail!("the scene has no hair to compare");
    }
    let (strands, segments) = session.prepared().hair_counts();
    let scene = session.scene().clone();
    let size = [scene.output.width, scene.output.height];
    let targets = OffscreenTargets::new(&ctx, size, COLOR_FORMAT)?;

    let (eye, target) = (scene.camera.eye, scene.camera.target);
    let mut rows = Vec::new();
    for i in 0..steps {
        let t = if steps == 1 {
            0.0
        } else {
            i as f32 / (steps - 1) as f32
        };
        let factor = args.far_factor.powf(t);
        let mut s = scene.clone();
        s.camera.eye = target + (eye - target) * factor;
        s.camera.far = s.camera.far.max(scene.camera.far * factor);
        let camera = PreparedScene::camera(&s, size);
        let pb = progress::spinner(format!(
            "distance {}/{steps}: rendering {}x{} on {}",
            i + 1,
            size[0],
            size[1],
            ctx.adapter_info.name
        ));
        let result = (|| -> Result<_> {
            let (s_img, s_side) = timed(
                &ctx,
                &mut session,
                &targets,
                &camera,
                TechniqueKind::Strands,
                args.repeat,
            )?;
            let (v_img, v_side) = timed(
                &ctx,
                &mut session,
                &targets,
                &camera,
                TechniqueKind::Volume,
                args.repeat,
            )?;
            session.set_technique(&ctx, "strands")?;
            session.set_hair_visible(false);
            let bare = session.render(&ctx, &targets.targets(), &camera, None);
            session.set_hair_visible(true);
            bare?;
            let bare = read_texture(&ctx, &targets.color)?;
            Ok((s_img, s_side, v_img, v_side, bare))
        })();
        pb.finish_and_clear();
        let (s_img, s_side, v_img, v_side, bare) = result?;
        let out = if args.sweep.is_some() {
            numbered(&args.output, i)
        } else {
            args.output.clone()
        };
        save(&split(&s_img, &v_img, dither), &out)?;
        let cmp = metrics::compare(&display(&s_img), &display(&v_img))?;
        let covered: Vec<bool> = (0..bare.pixels.len())
            .map(|k| {
                differs(s_img.pixels[k], bare.pixels[k]) || differs(v_img.pixels[k], bare.pixels[k])
            })
            .collect();
        let n = covered.iter().filter(|c| **c).count();
        let flip_hair = cmp.masked_flip(&covered);
        rows.push(Row {
            distance: (s.camera.eye - target).length(),
            coverage_pct: 100.0 * n as f64 / covered.len() as f64,
            flip: cmp.scores.flip,
            flip_hair,
            strands: s_side,
            volume: v_side,
            output: out.display().to_string(),
        });
    }
    if let Some(path) = &args.csv {
        std::fs::write(path, csv(&rows)).with_context(|| format!("{}", path.display()))?;
    }
    let report = Report {
        width: size[0],
        height: size[1],
        strands,
        segments,
        adapter: ctx.adapter_info.name.clone(),
        rows,
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    for r in &report.rows {
        let ms = |s: &Side| {
            s.gpu_ms
                .map_or("untimed".to_string(), |m| format!("{m:.2} ms"))
        };
        println!(
            "wrote {}: distance {:.1}, hair {:.2}% of the frame, mean FLIP {:.4} (hair {:.4}), \
             strands {}, volume {}",
            r.output,
            r.distance,
            r.coverage_pct,
            r.flip,
            r.flip_hair,
            ms(&r.strands),
            ms(&r.volume)
        );
    }
    Ok(())
}

/// The sweep as CSV, one row per distance.
fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "distance,coverage_pct,flip,flip_hair,strands_ms,volume_ms,voxelize_ms,strands_over_volume\n",
    );
    let f = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
    for r in rows {
        let voxelize = r.volume.volume.as_ref().and_then(|v| v.voxelize_ms);
        let ratio = r.strands.gpu_ms.zip(r.volume.gpu_ms).map(|(s, v)| s / v);
        let _ = writeln!(
            out,
            "{:.3},{:.4},{:.5},{:.5},{},{},{},{}",
            r.distance,
            r.coverage_pct,
            r.flip,
            r.flip_hair,
            f(r.strands.gpu_ms),
            f(r.volume.gpu_ms),
            f(voxelize),
            f(ratio)
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, color: [f32; 4]) -> LinearImage {
        LinearImage {
            width: w,
            height: 4,
            pixels: vec![color; (w * 4) as usize],
        }
    }

    #[test]
    fn split_is_strands_left_volume_right_and_a_ramp_between() {
        let (s, v) = (
            image(30, [1.0, 0.0, 0.0, 1.0]),
            image(30, [0.0, 0.0, 1.0, 1.0]),
        );
        let out = split(&s, &v, false);
        assert_eq!(out.pixels[0], s.pixels[0]);
        assert_eq!(out.pixels[29], v.pixels[0]);
        let mid = out.pixels[15];
        assert!(
            (mid[0] - 0.5).abs() < 0.06 && (mid[2] - 0.5).abs() < 0.06,
            "{mid:?}"
        );
        let d = split(&s, &v, true);
        assert!(
            d.pixels
                .iter()
                .all(|p| *p == s.pixels[0] || *p == v.pixels[0])
        );
        assert_eq!(d.pixels[0], s.pixels[0]);
        assert_eq!(d.pixels[29], v.pixels[0]);
    }

    #[test]
    fn csv_has_a_header_and_a_row_per_distance() {
        let side = Side {
            gpu_ms: Some(2.0),
            volume: None,
        };
        let row = Row {
            distance: 10.0,
            coverage_pct: 1.5,
            flip: 0.01,
            flip_hair: 0.2,
            strands: side.clone(),
            volume: Side {
                gpu_ms: Some(1.0),
                volume: Some(VolumeReport {
                    resolution: 64,
                    voxelize_ms: Some(0.25),
                    bytes: 1,
                }),
            },
            output: "x.png".into(),
        };
        let text = csv(&[row.clone(), row]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("distance,coverage_pct,flip"));
        assert_eq!(
            lines[1],
            "10.000,1.5000,0.01000,0.20000,2.0000,1.0000,0.2500,2.0000"
        );
    }
}
