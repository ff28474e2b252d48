//! `tress info FILE... [--json]`

use std::path::PathBuf;

use anyhow::Result;
use serde::Serialize;
use tress_hair::HairAsset;
use tress_hair::formats::{Details, Format, ReadOptions};

use crate::progress;

/// Arguments of `tress info`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Hair files (`.hair`, `.tfx`, `.usda`/`.usdc`/`.usdz`/`.usd`, `.abc`, `.data`, `.bin`);
    /// several are merged into one asset.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Segments per span when cubic or NURBS curves (USD, Alembic) are tessellated (1 to 64).
    #[arg(long, default_value_t = ReadOptions::default().cubic_segments)]
    cubic_segments: u32,
    /// Print exactly one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// What `info` reports; also its JSON schema.
#[derive(Serialize, Debug)]
pub(crate) struct Info {
    files: Vec<String>,
    /// Per file: its format and what the read found.
    sources: Vec<Source>,
    /// Frames of an animated cache (the most over the files; 1 when all are still).
    frames: u32,
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

/// One input file of `info`: its format, the USD prims or Alembic objects read, the USD meshes
/// found, and the strands left out.
#[derive(Serialize, Debug)]
pub(crate) struct Source {
    file: String,
    format: &'static str,
    objects: Vec<String>,
    meshes: Vec<String>,
    guides_skipped: usize,
    single_vertex_skipped: usize,
    /// Frames of an animated cache (1: a still file).
    frames: u32,
    /// Their rate where the file says (`null` otherwise).
    fps: Option<f64>,
}

impl Source {
    fn of(file: &std::path::Path, format: Format, d: &Details) -> Source {
        Source {
            file: file.display().to_string(),
            format: format.name(),
            objects: d.objects.clone(),
            meshes: d.meshes.clone(),
            guides_skipped: d.guides_skipped,
            single_vertex_skipped: d.single_vertex_skipped,
            frames: d.frames,
            fps: d.fps,
        }
    }
}

impl Info {
    pub(crate) fn of(files: &[PathBuf], h: &HairAsset) -> Info {
        let b = h.bounds();
        let (vmin, vmax) = h.vertices_per_strand_range();
        let len = h.length_stats();
        Info {
            files: files.iter().map(|p| p.display().to_string()).collect(),
            sources: Vec::new(),
            frames: 1,
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
    let options = ReadOptions {
        cubic_segments: args.cubic_segments,
        ..ReadOptions::default()
    };
    let read = tress_hair::formats::load_paths(&args.files, &options);
    pb.finish_and_clear();
    let (hair, found) = read?;
    let mut info = Info::of(&args.files, &hair);
    info.sources = args
        .files
        .iter()
        .zip(&found)
        .map(|(p, (format, details))| Source::of(p, *format, details))
        .collect();
    info.frames = info.sources.iter().map(|s| s.frames).max().unwrap_or(1);
    if args.json {
        println!("{}", serde_json::to_string(&info)?);
    } else {
        let yes = |b: bool| if b { "yes" } else { "no" };
        println!("files:               {}", info.files.join(", "));
        for s in &info.sources {
            println!("format:              {} ({})", s.format, s.file);
            if !s.objects.is_empty() {
                println!("  curves read:       {}", s.objects.join(", "));
            }
            if !s.meshes.is_empty() {
                println!("  meshes (head):     {}", s.meshes.join(", "));
            }
            if s.guides_skipped > 0 {
                println!("  guides skipped:    {}", s.guides_skipped);
            }
            if s.single_vertex_skipped > 0 {
                println!("  1-vertex strands skipped: {}", s.single_vertex_skipped);
            }
            if s.frames > 1 {
                let rate = s
                    .fps
                    .map(|f| format!(" at {} fps", rate(f)))
                    .unwrap_or_default();
                println!(
                    "  frames:            {}{rate} (an animated cache)",
                    s.frames
                );
            }
        }
        println!("frames:              {}", info.frames);
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

/// A frame rate as people write it: whole rates without decimals (24), others with three
/// (29.970).
fn rate(fps: f64) -> String {
    if (fps - fps.round()).abs() < 1e-6 {
        format!("{fps:.0}")
    } else {
        format!("{fps:.3}")
    }
}
