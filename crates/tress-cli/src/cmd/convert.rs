//! `tress convert IN... OUT [--follow N] [--seed S]`

use std::path::PathBuf;

use anyhow::{Result, bail};
use tress_hair::FollowParams;

use crate::progress;

/// Arguments of `tress convert`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Input files, then the output file (the last path). Inputs are merged (any format tress
    /// reads); the output format follows its extension: `.hair`, `.tfx`, `.usda`, `.usdc`, `.usd`
    /// or `.data`.
    #[arg(required = true, num_args = 2.., value_name = "IN... OUT")]
    paths: Vec<PathBuf>,
    /// Give every strand N follow hairs (TressFX style): strands = inputs × (N + 1).
    #[arg(long, default_value_t = 0)]
    follow: u32,
    /// Largest root offset of a follow hair from its guide (world units).
    #[arg(long, default_value_t = FollowParams::default().root_radius)]
    follow_radius: f32,
    /// How much farther apart follow-hair tips are than their roots.
    #[arg(long, default_value_t = FollowParams::default().tip_separation)]
    tip_separation: f32,
    /// Resample every strand to this many vertices.
    #[arg(long)]
    resample: Option<u32>,
    /// Keep this fraction of the strands (deterministic for the seed).
    #[arg(long)]
    strand_ratio: Option<f32>,
    /// Segments per span when cubic or NURBS curves (USD, Alembic) are tessellated (1 to 64).
    #[arg(long, default_value_t = tress_hair::formats::ReadOptions::default().cubic_segments)]
    cubic_segments: u32,
    /// Random seed for follow hairs and strand subsets.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let Some((output, inputs)) = args.paths.split_last() else {
        bail!("convert needs at least one input and one output");
    };
    let format = tress_hair::formats::Format::from_path(output)?;
    if !format.is_writable() {
        bail!(
            "{}: tress does not write {}; it writes .hair, .tfx, .usda, .usdc, .usd and .data",
            output.display(),
            format.name()
        );
    }
    if inputs.contains(output) {
        bail!("{}: output would overwrite an input", output.display());
    }
    let pb = progress::spinner("reading");
    let options = tress_hair::formats::ReadOptions {
        cubic_segments: args.cubic_segments,
    };
    let hair = tress_hair::formats::load_paths(inputs, &options);
    pb.finish_and_clear();
    let mut hair = hair?.0;
    if let Some(ratio) = args.strand_ratio {
        hair = hair.subset(ratio, args.seed)?;
    }
    if args.follow > 0 {
        let pb = progress::spinner(format!("adding {} follow hairs per strand", args.follow));
        let params = FollowParams {
            count: args.follow,
            root_radius: args.follow_radius,
            tip_separation: args.tip_separation,
            seed: args.seed,
        };
        let out = hair.with_follow_hairs(&params);
        pb.finish_and_clear();
        hair = out?;
    }
    if let Some(n) = args.resample {
        hair = hair.resample_count(n)?;
    }
    tress_hair::formats::write_path(output, &hair)?;
    eprintln!(
        "wrote {}: {} strands, {} vertices",
        output.display(),
        hair.strand_count(),
        hair.vertex_count()
    );
    Ok(())
}
