//! `tress view [INPUT...] [--technique T] [--width W --height H] [--set key=value]...
//! [--frames N] [--screenshot OUT.png]`: the interactive viewer (`tress_viewer`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use tress_viewer::ViewerOptions;

use super::open::satf_loader;

/// Arguments of `tress view`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A scene file (`.toml`), or hair files (`.hair`, `.tfx`, USD, `.abc`, `.data`, `.bin`; merged, framed automatically),
    /// or one hair-card OBJ file. Nothing opens the built-in demo scene.
    inputs: Vec<PathBuf>,
    /// Technique to start with (default: the scene's, else `strands`); T cycles them.
    #[arg(long)]
    technique: Option<String>,
    /// Window width in pixels.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Window height in pixels.
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Override any scene or technique setting by its dotted name, e.g. `strands.k=8`;
    /// applied to every file opened in the viewer. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Render N frames, then exit (prints what they measured).
    #[arg(long, value_name = "N")]
    frames: Option<u32>,
    /// Save the last frame as this PNG before exiting.
    #[arg(long, value_name = "OUT.png")]
    screenshot: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let report = tress_viewer::run(ViewerOptions {
        inputs: args.inputs,
        size: [args.width, args.height],
        technique: args.technique,
        overrides: args.sets,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        satf_database: Some(satf_loader(None)),
    })
    .context("view")?;
    println!("tress view: {report}");
    if let Some(p) = args.screenshot {
        println!("tress view: saved {}", p.display());
    }
    Ok(())
}
