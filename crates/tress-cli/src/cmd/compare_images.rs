//! `tress compare-images A B [--json] [--heatmap OUT.png] [--mask MASK.png]`: mean FLIP, RMSE
//! and SSIM of image B (the test) against image A (the reference), see `tress_trace::metrics`;
//! with a mask, also the mean FLIP over the pixels it marks (e.g. the hair's).

use std::path::PathBuf;

use anyhow::{Result, bail};
use tress_trace::{DisplayImage, ImageKind, metrics};

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
}

pub(crate) fn run(args: Args) -> Result<()> {
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
    let report = Report {
        scores: s,
        flip_masked: mask.as_ref().map(|m| comparison.masked_flip(m)),
        mask_pixels: mask.as_ref().map(|m| m.iter().filter(|&&x| x).count()),
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
    }
    Ok(())
}
