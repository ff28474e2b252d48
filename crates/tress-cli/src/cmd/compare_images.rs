//! `tress compare-images A B [--json] [--heatmap OUT.png] [--mask MASK.png]`: mean FLIP, RMSE
//! and SSIM of image B (the test) against image A (the reference), see `tress_trace::metrics`;
//! with a mask, also the mean FLIP over the pixels it marks (e.g. the hair's). Beside them, the
//! scores at a matched scale ([`tress_trace::matched`]: both images box-filtered in linear
//! light by `--scale`, default 3), the mean linear colour over the mask and its ratio to the
//! reference's, and with `--floor`, the reference's own seed-to-seed figure at that scale.

use std::path::PathBuf;

use anyhow::{Result, bail};
use tress_trace::{DisplayImage, ImageKind, matched, metrics};

/// Arguments of `tress compare-images`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// The reference image (`.png` or `.exr`).
    reference: PathBuf,
    /// The test image, of the same size.
    test: PathBuf,
    /// Print exactly one JSON object with the keys `flip`, `rmse` and `ssim`.
    #[arg(long)]
    json: bool,
    /// Write FLIP's per-pixel error as a magma heat map (`.png`).
    #[arg(long, value_name = "OUT.png")]
    heatmap: Option<PathBuf>,
    /// Also report the mean FLIP over the pixels where this image (same size) is not black
    /// (`flip_masked`, and their count `mask_pixels`, in the JSON).
    #[arg(long, value_name = "MASK.png")]
    mask: Option<PathBuf>,
    /// The matched scale's box factor: both images are averaged over `N × N` blocks in linear
    /// light before the `matched` scores (1: pixel scale).
    #[arg(long, value_name = "N", default_value_t = tress_trace::matched::DEFAULT_SCALE)]
    scale: u32,
    /// The reference traced again with another seed: its matched-scale FLIP against the
    /// reference is reported as `floor`, the noise no test image can be expected to beat.
    #[arg(long, value_name = "SECOND.png")]
    floor: Option<PathBuf>,
}

/// The scores, and the masked FLIP when a mask was given.
#[derive(serde::Serialize)]
struct Report {
    #[serde(flatten)]
    scores: metrics::Scores,
    #[serde(skip_serializing_if = "Option::is_none")]
    flip_masked: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mask_pixels: Option<usize>,
    /// The scores at the matched scale.
    matched: matched::MatchedScore,
    /// The reference's second seed against the reference, at the matched scale.
    #[serde(skip_serializing_if = "Option::is_none")]
    floor: Option<matched::MatchedScore>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    if !(1..=64).contains(&args.scale) {
        bail!("--scale must lie in 1..=64, got {}", args.scale);
    }
    if let Some(path) = &args.heatmap
        && ImageKind::from_path(path)? != ImageKind::Png
    {
        bail!("{}: the heat map must end in .png", path.display());
    }
    let reference = DisplayImage::read(&args.reference)?;
    let test = DisplayImage::read(&args.test)?;
    let comparison = metrics::compare(&reference, &test)?;
    if let Some(path) = &args.heatmap {
        comparison.save_heatmap(path)?;
    }
    let mask = match &args.mask {
        Some(path) => {
            let m = DisplayImage::read(path)?;
            if (m.width, m.height) != (comparison.width, comparison.height) {
                bail!(
                    "{}: the mask is {}x{}, the images {}x{}",
                    path.display(),
                    m.width,
                    m.height,
                    comparison.width,
                    comparison.height
                );
            }
            Some(
                m.pixels
                    .iter()
                    .map(|p| p.iter().any(|&c| c > 0.0))
                    .collect::<Vec<bool>>(),
            )
        }
        None => None,
    };
    let s = comparison.scores;
    let linear_reference = matched::to_linear(&reference);
    let at_scale = |test: &DisplayImage| {
        matched::compare(
            &linear_reference,
            &matched::to_linear(test),
            mask.as_deref(),
            args.scale,
        )
    };
    let floor = match &args.floor {
        Some(path) => {
            let second = DisplayImage::read(path)?;
            Some(at_scale(&second).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?)
        }
        None => None,
    };
    let report = Report {
        scores: s,
        flip_masked: mask.as_ref().map(|m| comparison.masked_flip(m)),
        mask_pixels: mask.as_ref().map(|m| m.iter().filter(|&&x| x).count()),
        matched: at_scale(&test)?,
        floor,
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!(
            "FLIP {:.5}  RMSE {:.5}  SSIM {:.5}  ({}x{})",
            s.flip, s.rmse, s.ssim, comparison.width, comparison.height
        );
        if let (Some(f), Some(n)) = (report.flip_masked, report.mask_pixels) {
            println!("FLIP over the mask {f:.5}  ({n} pixels)");
        }
        print_matched("", &report.matched);
        if let Some(floor) = &report.floor {
            print_matched("the reference's second seed: ", floor);
        }
    }
    Ok(())
}

/// The matched-scale lines of the text report.
fn print_matched(prefix: &str, m: &matched::MatchedScore) {
    let masked = m
        .flip_masked
        .map_or_else(String::new, |f| format!(", over the mask {f:.5}"));
    println!("{prefix}at scale {}: FLIP {:.5}{masked}", m.scale, m.flip);
    if let (Some(r), Some(t), Some(q)) = (m.mean_reference, m.mean_test, m.color_ratio) {
        println!(
            "{prefix}mean linear colour ({:.4}, {:.4}, {:.4}) against the reference's \
             ({:.4}, {:.4}, {:.4}): ratio ({:.3}, {:.3}, {:.3})",
            t[0], t[1], t[2], r[0], r[1], r[2], q[0], q[1], q[2]
        );
    }
}
