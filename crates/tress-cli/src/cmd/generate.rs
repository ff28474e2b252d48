//! `tress generate STYLE -o OUT [--strands N] [--vertices N] [--seed S] [...]`

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use tress_hair::generate::{self, Style};

use crate::progress;

/// Arguments of `tress generate`. Unset parameters take the style's defaults.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Style: straight, wavy, curly, ponytail or fur.
    style: Style,
    /// Output file; `.hair` or `.tfx` chooses the format.
    #[arg(short, long)]
    output: PathBuf,
    /// Number of strands.
    #[arg(long)]
    strands: Option<u32>,
    /// Vertices per strand.
    #[arg(long)]
    vertices: Option<u32>,
    /// Strand length (world units).
    #[arg(long)]
    length: Option<f32>,
    /// Curl (helix) radius for curly hair, wave amplitude for wavy hair.
    #[arg(long)]
    curl_radius: Option<f32>,
    /// Curls or waves per unit length.
    #[arg(long)]
    curl_frequency: Option<f32>,
    /// Pull of strands toward clump centres (0 = none, 1 = full).
    #[arg(long)]
    clumping: Option<f32>,
    /// Random jitter growing toward the tip (world units).
    #[arg(long)]
    noise: Option<f32>,
    /// Root thickness (world units), tapering to the tip.
    #[arg(long)]
    thickness: Option<f32>,
    /// Random seed (same seed, same hair).
    #[arg(long)]
    seed: Option<u64>,
    /// Also write the head (or body) mesh the hair grows from as OBJ.
    #[arg(long, value_name = "OBJ")]
    head: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let mut p = args.style.default_params();
    macro_rules! set {
        ($($f:ident),*) => { $( if let Some(v) = args.$f { p.$f = v; } )* };
    }
    set!(
        strands,
        vertices,
        length,
        curl_radius,
        curl_frequency,
        clumping,
        noise,
        thickness,
        seed
    );
    // Check the output format before spending time generating.
    tress_hair::formats::Format::from_path(&args.output)?;
    let start = Instant::now();
    let pb = progress::spinner(format!("generating {} ({} strands)", args.style, p.strands));
    let hair = generate::generate(args.style, &p);
    pb.finish_and_clear();
    let hair = hair?;
    let gen_ms = start.elapsed().as_secs_f64() * 1e3;
    tress_hair::formats::write_path(&args.output, &hair)?;
    if let Some(obj) = &args.head {
        let mesh = generate::shape_for(args.style).mesh(&generate::head_for(args.style), 48);
        std::fs::write(obj, mesh.to_obj()).with_context(|| format!("{}", obj.display()))?;
    }
    eprintln!(
        "wrote {}: {} strands, {} vertices (generated in {gen_ms:.0} ms)",
        args.output.display(),
        hair.strand_count(),
        hair.vertex_count()
    );
    Ok(())
}
