//! `tress bake-ao [IN.obj] -o OUT.obj [--rays N] [--max-distance D] [--sides S]
//! [--patch-opacity A] [--seed S] [--head-obj HEAD.obj | --generated-head] [--json]`
//!
//! Per-vertex ambient occlusion of a patch mesh (Scheuermann 2004, sketch "Ambient occlusion"),
//! baked by `tress_hair::patches::bake_ao` (rays against the patches and the head through a
//! BVH, on all cores) and stored in the OBJ's vertex colors. Without an input it bakes the
//! generated layered patch head (`tress_hair::patches::generate_patches` with its defaults) on
//! the generated head.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use serde::Serialize;
use tress_hair::generate::{Head, TriMesh};
use tress_hair::patches::{AoParams, PatchMesh, PatchParams, bake_ao, generate_patches};
use tress_render::patches::scene::parse_sides;

use crate::progress;

/// Arguments of `tress bake-ao`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// A patch OBJ file; none: the generated layered patch head.
    input: Option<PathBuf>,
    /// Output OBJ file (AO in the vertex colors).
    #[arg(short, long)]
    output: PathBuf,
    /// Rays per hemisphere and vertex.
    #[arg(long, default_value_t = AoParams::default().rays)]
    rays: u32,
    /// Occluders farther than this (world units) do not count.
    #[arg(long, default_value_t = AoParams::default().max_distance)]
    max_distance: f32,
    /// Which hemispheres of a two-sided patch count: max, mean or front.
    #[arg(long, default_value = "max")]
    sides: String,
    /// Light a patch stops where a ray crosses it, in [0, 1].
    #[arg(long, default_value_t = AoParams::default().patch_opacity)]
    patch_opacity: f32,
    /// Seed of the ray directions.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// A head mesh that occludes too (OBJ, glTF `.gltf`/`.glb` or USD `Mesh` prims).
    #[arg(long, conflicts_with = "generated_head")]
    head_obj: Option<PathBuf>,
    /// The default generated head occludes too (always on without an input).
    #[arg(long)]
    generated_head: bool,
    /// Print exactly one JSON object describing the bake.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Report {
    output: String,
    source: String,
    vertices: usize,
    triangles: usize,
    patches: usize,
    head_triangles: usize,
    rays: u32,
    seconds: f64,
    mean_ao: f64,
    min_ao: f32,
}

pub(crate) fn run(args: Args) -> Result<()> {
    if !args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
    {
        bail!("{}: the output must end in .obj", args.output.display());
    }
    let params = AoParams {
        rays: args.rays,
        max_distance: args.max_distance,
        seed: args.seed,
        sides: parse_sides(&args.sides)?,
        patch_opacity: args.patch_opacity,
    };
    params.validate()?;
    let (mut mesh, source) = match &args.input {
        Some(path) => (PatchMesh::read_obj(path)?, path.display().to_string()),
        None => {
            let pb = progress::spinner("generating the layered patch head");
            let m = generate_patches(&PatchParams::default());
            pb.finish_and_clear();
            (m?, "generated".to_string())
        }
    };
    let head: Option<TriMesh> = match (&args.head_obj, args.generated_head || args.input.is_none())
    {
        (Some(path), _) => Some(tress_hair::formats::read_mesh(path)?),
        (None, true) => Some(Head::default().mesh(64)),
        (None, false) => None,
    };
    let pb = progress::spinner(format!(
        "baking AO: {} vertices x {} rays",
        mesh.vertex_count(),
        args.rays
    ));
    let start = Instant::now();
    let r = bake_ao(&mut mesh, head.as_ref(), &params);
    let seconds = start.elapsed().as_secs_f64();
    pb.finish_and_clear();
    r?;
    mesh.write_obj(&args.output)?;
    let ao = mesh.ao();
    let report = Report {
        output: args.output.display().to_string(),
        source,
        vertices: mesh.vertex_count(),
        triangles: mesh.triangle_count(),
        patches: mesh.component_count(),
        head_triangles: head.as_ref().map_or(0, |h| h.triangle_count()),
        rays: args.rays,
        seconds,
        mean_ao: ao.iter().map(|&a| f64::from(a)).sum::<f64>() / ao.len().max(1) as f64,
        min_ao: ao.iter().copied().fold(1.0, f32::min),
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        eprintln!(
            "wrote {}: AO of {} vertices ({} patches, {} head triangles) with {} rays in {:.2} s; \
             mean {:.3}, min {:.3}",
            report.output,
            report.vertices,
            report.patches,
            report.head_triangles,
            report.rays,
            seconds,
            report.mean_ao,
            report.min_ao
        );
    }
    Ok(())
}
