//! `tress compare-images A B [--json] [--heatmap OUT.png]`: mean FLIP, RMSE and SSIM of image B
//! (the test) against image A (the reference), see `tress_trace::metrics`.

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
    let s = comparison.scores;
    if args.json {
        println!("{}", serde_json::to_string(&s)?);
    } else {
        println!(
            "FLIP {:.5}  RMSE {:.5}  SSIM {:.5}  ({}x{})",
            s.flip, s.rmse, s.ssim, comparison.width, comparison.height
        );
    }
    Ok(())
}
