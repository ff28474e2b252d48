//! `tress convert IN... OUT [--follow N [--follow-mode M] [--follow-radius R|Kx]] [--seed S]`

use std::path::PathBuf;

use anyhow::{Result, bail};
use tress_hair::{FollowMode, FollowParams, FollowRadius};

use crate::progress;

/// Arguments of `tress convert`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Input files, then the output file (the last path). Inputs are merged (any format tress
    /// reads); the output format follows its extension: `.hair`, `.tfx`, `.usda`, `.usdc`, `.usd`
    /// or `.data`.
    #[arg(required = true, num_args = 2.., value_name = "IN... OUT")]
    paths: Vec<PathBuf>,
    /// Give every strand N follow hairs: strands = inputs × (N + 1).
    #[arg(long, default_value_t = 0)]
    follow: u32,
    /// How follow hairs are made: `interpolate` (blend the three guides whose roots surround
    /// the follower's, so the coat is even between guides) or `offset` (TressFX: copies of the
    /// guide, offset on the scalp and fanning out toward the tip).
    #[arg(long, default_value = "interpolate", value_parser = parse_mode)]
    follow_mode: FollowMode,
    /// Follow-hair root radius: world units (`0.25`) or a multiple of the guides' root spacing,
    /// the median distance from a root to the nearest other root (`0.6x`). Offset mode: the
    /// largest root offset; interpolate: the scale of the followers' stray toward the tip.
    #[arg(long, default_value_t = FollowParams::default().root_radius, value_parser = parse_radius)]
    follow_radius: FollowRadius,
    /// Offset mode: how much farther apart follow-hair tips are than their roots; interpolate:
    /// how far (in root radii) the tips stray from the blend.
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
        ..tress_hair::formats::ReadOptions::default()
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
            mode: args.follow_mode,
            root_radius: args.follow_radius,
            tip_separation: args.tip_separation,
            seed: args.seed,
        };
        let out = hair.follow_hairs(&params);
        pb.finish_and_clear();
        let (followed, report) = out?;
        hair = followed;
        let spacing = report
            .root_spacing
            .map_or_else(|| "none".to_owned(), |s| format!("{s:.4}"));
        eprintln!(
            "follow hairs: {} × {}, guides' root spacing {spacing} (median), radius {:.4}",
            args.follow_mode.name(),
            args.follow,
            report.root_radius
        );
        if report.offset_guides > 0 {
            eprintln!(
                "follow hairs: {} guides are the corner of no triangle of guides (isolated or in a \
                 single row); their followers are offset",
                report.offset_guides
            );
        }
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

fn parse_mode(s: &str) -> Result<FollowMode, String> {
    s.parse().map_err(|e: tress_hair::HairError| e.to_string())
}

fn parse_radius(s: &str) -> Result<FollowRadius, String> {
    s.parse().map_err(|e: tress_hair::HairError| e.to_string())
}
