//! `tress cards IN... -o OUT.obj [--cards N] [--segments N] [--bake-ao] [--textures DIR] [--json]`
//!
//! Strand assets to hair cards (Scheuermann 2004's polygon patches): neighbouring strands grouped
//! into ribbons by `tress_hair::patches::PatchMesh::from_strands`, written as an OBJ file that
//! `tress render --technique patches` and `tress bake-ao` read.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use serde::Serialize;
use tress_hair::patches::{AoParams, CardParams, HairTextures, PatchMesh, TextureParams, bake_ao};
use tress_render::patches::save_textures_png;

use crate::progress;

/// Arguments of `tress cards`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Hair files (`.hair`, `.tfx`, USD, `.abc`, `.data`, `.bin`), merged.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Output OBJ file.
    #[arg(short, long)]
    output: PathBuf,
    /// Number of cards (groups of neighbouring strands).
    #[arg(long, default_value_t = CardParams::default().cards)]
    cards: u32,
    /// Quads along each card.
    #[arg(long, default_value_t = CardParams::default().segments)]
    segments: u32,
    /// Card width in standard deviations of the group's spread, times 2.
    #[arg(long, default_value_t = CardParams::default().width_scale)]
    width_scale: f32,
    /// Narrowest card (world units).
    #[arg(long, default_value_t = CardParams::default().min_width)]
    min_width: f32,
    /// k-means rounds of the grouping.
    #[arg(long, default_value_t = CardParams::default().iterations)]
    iterations: u32,
    /// Seed of the grouping.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Also bake ambient occlusion into the cards (against the cards themselves).
    #[arg(long)]
    bake_ao: bool,
    /// AO rays per hemisphere and vertex (with --bake-ao).
    #[arg(long, default_value_t = AoParams::default().rays)]
    rays: u32,
    /// Also write the four procedural textures as PNG files into this folder.
    #[arg(long, value_name = "DIR")]
    textures: Option<PathBuf>,
    /// Print exactly one JSON object describing the result.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Report {
    output: String,
    strands: usize,
    cards: usize,
    vertices: usize,
    triangles: usize,
    seconds: f64,
    ao_bake_s: Option<f64>,
    textures: Vec<String>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    if !args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
    {
        bail!("{}: the output must end in .obj", args.output.display());
    }
    if args.inputs.contains(&args.output) {
        bail!("{}: output would overwrite an input", args.output.display());
    }
    let params = CardParams {
        cards: args.cards,
        segments: args.segments,
        width_scale: args.width_scale,
        min_width: args.min_width,
        iterations: args.iterations,
        seed: args.seed,
    };
    params.validate()?;
    let pb = progress::spinner("reading");
    let hair = tress_hair::formats::read_paths(&args.inputs);
    pb.finish_and_clear();
    let hair = hair?;
    let pb = progress::spinner(format!(
        "grouping {} strands into {} cards",
        hair.strand_count(),
        args.cards
    ));
    let start = Instant::now();
    let mesh = PatchMesh::from_strands(&hair, &params);
    pb.finish_and_clear();
    let mut mesh = mesh?;
    let seconds = start.elapsed().as_secs_f64();
    let ao_bake_s = if args.bake_ao {
        let ao = AoParams {
            rays: args.rays,
            ..AoParams::default()
        };
        let pb = progress::spinner(format!("baking AO ({} rays)", args.rays));
        let start = Instant::now();
        let r = bake_ao(&mut mesh, None, &ao);
        pb.finish_and_clear();
        r?;
        Some(start.elapsed().as_secs_f64())
    } else {
        None
    };
    mesh.write_obj(&args.output)?;
    let mut textures = Vec::new();
    if let Some(dir) = &args.textures {
        std::fs::create_dir_all(dir)?;
        let t = HairTextures::generate(&TextureParams::default())?;
        textures = save_textures_png(&t, dir)?
            .iter()
            .map(|p| p.display().to_string())
            .collect();
    }
    let report = Report {
        output: args.output.display().to_string(),
        strands: hair.strand_count(),
        cards: mesh.component_count(),
        vertices: mesh.vertex_count(),
        triangles: mesh.triangle_count(),
        seconds,
        ao_bake_s,
        textures,
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        eprintln!(
            "wrote {}: {} cards from {} strands, {} vertices, {} triangles ({:.2} s{})",
            report.output,
            report.cards,
            report.strands,
            report.vertices,
            report.triangles,
            seconds,
            ao_bake_s.map_or(String::new(), |s| format!(", AO {s:.2} s"))
        );
        for t in &report.textures {
            eprintln!("wrote {t}");
        }
    }
    Ok(())
}
