//! `tress info FILE... [--json]`

use std::path::PathBuf;

use anyhow::Result;
use serde::Serialize;
use tress_hair::HairAsset;

use crate::progress;

/// Arguments of `tress info`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Hair files (`.hair`, `.tfx`); several are merged into one asset.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print exactly one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// What `info` reports; also its JSON schema.
#[derive(Serialize, Debug)]
pub(crate) struct Info {
    files: Vec<String>,
    strands: usize,
    vertices: usize,
    segments: usize,
    bbox_min: [f32; 3],
    bbox_max: [f32; 3],
    vertices_per_strand_min: u32,
    vertices_per_strand_max: u32,
    strand_length_min: f32,
    strand_length_max: f32,
    strand_length_mean: f32,
    has_thickness: bool,
    has_transparency: bool,
    has_color: bool,
    has_strand_uv: bool,
}

impl Info {
    pub(crate) fn of(files: &[PathBuf], h: &HairAsset) -> Info {
        let b = h.bounds();
        let (vmin, vmax) = h.vertices_per_strand_range();
        let len = h.length_stats();
        Info {
            files: files.iter().map(|p| p.display().to_string()).collect(),
            strands: h.strand_count(),
            vertices: h.vertex_count(),
            segments: h.segment_count(),
            bbox_min: b.min.to_array(),
            bbox_max: b.max.to_array(),
            vertices_per_strand_min: vmin,
            vertices_per_strand_max: vmax,
            strand_length_min: len.min,
            strand_length_max: len.max,
            strand_length_mean: len.mean,
            has_thickness: h.thickness().is_some(),
            has_transparency: h.transparency().is_some(),
            has_color: h.color().is_some(),
            has_strand_uv: h.strand_uv().is_some(),
        }
    }
}

pub(crate) fn run(args: Args) -> Result<()> {
    let pb = progress::spinner("reading");
    let hair = tress_hair::formats::read_paths(&args.files);
    pb.finish_and_clear();
    let info = Info::of(&args.files, &hair?);
    if args.json {
        println!("{}", serde_json::to_string(&info)?);
    } else {
        let yes = |b: bool| if b { "yes" } else { "no" };
        println!("files:               {}", info.files.join(", "));
        println!("strands:             {}", info.strands);
        println!("vertices:            {}", info.vertices);
        println!("segments:            {}", info.segments);
        println!(
            "vertices per strand: {}..{}",
            info.vertices_per_strand_min, info.vertices_per_strand_max
        );
        println!(
            "strand length:       {:.4} .. {:.4} (mean {:.4})",
            info.strand_length_min, info.strand_length_max, info.strand_length_mean
        );
        println!("bounds min:          {:?}", info.bbox_min);
        println!("bounds max:          {:?}", info.bbox_max);
        println!(
            "attributes:          thickness {}, transparency {}, color {}, strand UV {}",
            yes(info.has_thickness),
            yes(info.has_transparency),
            yes(info.has_color),
            yes(info.has_strand_uv)
        );
    }
    Ok(())
}
