//! `tress render --technique satf`: the SATF technique (Xu et al. 2006) through the CLI.
//!
//! The database is `satf.database` (baked there on first use), or a file in the cache folder
//! named by the bake settings ([`super::satf_bake::database_for_render`]); the clusters are
//! fitted to the scene's hair or generated on its head (`satf.clusters`, see
//! `tress_render::satf::scene`). The frame is rendered twice and the second is reported, so the
//! timings exclude first-use costs; `--json` adds a `satf` object with the hierarchy's counts
//! (Table 1's C#, L#, S#, H#), the strands the cluster fit left out (`skipped_strands`, also
//! printed as a warning), the CPU preparation times and the GPU milliseconds of Table 1's
//! stages (`stages_ms`: index calculation, map construction, texture mapping, lighting,
//! shadowing) beside the keys every technique reports.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use glam::Vec3;
use serde::Serialize;
use tress_render::satf::scene::{load_clusters, satf_settings};
use tress_render::{
    COLOR_FORMAT, GpuContext, OffscreenTargets, PreparedScene, SatfDatabase, SatfFrameInputs,
    SatfGeometry, SatfRenderer, TargetFormats, Timings, read_texture,
};
use tress_scene::Scene;

use super::render::{AMBIENT, Report, hair_counts, passes, rendering_spinner, save, upload_head};
use super::satf_bake::database_for_render;
use crate::progress;

/// The `satf` part of the report.
#[derive(Serialize)]
pub(crate) struct SatfReport {
    database: String,
    database_samples: u32,
    cluster_source: &'static str,
    clusters: u32,
    macro_clusters: usize,
    layers: u32,
    cluster_strands: usize,
    /// Strands of the scene's hair in no cluster, by reason (`too_short`, `degenerate`).
    skipped_strands: Skipped,
    hsvs: u32,
    uniform_hsvs: u32,
    interpolated_hsvs: u32,
    atlas: [u32; 2],
    /// `timestamps` (GPU) or `wall_clock` (each stage submitted alone, CPU clock).
    stage_timing: &'static str,
    clusters_cpu_ms: f64,
    features_cpu_ms: f64,
    /// GPU milliseconds of Table 1's stages (null without timestamps).
    stages_ms: Stages,
}

/// Strands the cluster fit left out, by reason.
#[derive(Serialize)]
struct Skipped {
    total: usize,
    too_short: usize,
    degenerate: usize,
}

#[derive(Serialize)]
struct Stages {
    index_calculation: Option<f64>,
    map_construction: Option<f64>,
    texture_mapping: Option<f64>,
    lighting: Option<f64>,
    shadowing: Option<f64>,
}

/// Render `scene` with the SATF technique into `output` (`.png` or `.exr`, checked by the
/// caller) and report on stdout.
pub(crate) fn run(
    ctx: &GpuContext,
    scene: &Scene,
    prepared: &PreparedScene,
    size: [u32; 2],
    output: &Path,
    json: bool,
) -> Result<()> {
    let satf = satf_settings(scene)?;
    let (cpu_db, db_path) =
        database_for_render(satf.database.as_deref(), &satf.bake, satf.bake_explicit)?;
    let pb = progress::spinner("building SATF clusters");
    let start = Instant::now();
    let volume = load_clusters(scene, &satf, prepared.hair.as_ref());
    pb.finish_and_clear();
    let volume = volume?;
    let clusters_cpu_ms = start.elapsed().as_secs_f64() * 1e3;

    let pb = rendering_spinner(ctx, size);
    let result = (|| -> Result<_> {
        let db = SatfDatabase::new(ctx, &cpu_db)?;
        let geometry = SatfGeometry::new(ctx, &volume, &db, &satf.settings)?;
        let mut renderer = SatfRenderer::new(ctx, TargetFormats::default(), satf.settings)?;
        let head = upload_head(ctx, prepared)?;
        let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
        let inputs = SatfFrameInputs {
            camera: PreparedScene::camera(scene, size),
            lights: &prepared.lights,
            ambient: Vec3::splat(AMBIENT),
            head_color: prepared.material.head_color,
            clusters: Some(&geometry),
            database: &db,
            head: head.as_ref(),
            clear: prepared.clear_color(),
        };
        // The first frame warms up; the second is the one reported.
        renderer.render(ctx, &targets.targets(), &inputs)?;
        let stats = renderer.render(ctx, &targets.targets(), &inputs)?;
        let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
        Ok((image, stats, geometry.features_ms(), geometry.atlas_size()))
    })();
    pb.finish_and_clear();
    let (image, stats, features_cpu_ms, atlas) = result?;
    save(&image, output)?;

    let [i, c, m, l, s] = stats.table1_ms().map(|(_, ms)| ms);
    let counts = volume.stats(&satf.settings.sampling);
    let r = SatfReport {
        database: db_path.display().to_string(),
        database_samples: cpu_db.sample_count() as u32,
        cluster_source: match satf.clusters {
            tress_render::satf::scene::ClusterSource::Fit(_) => "fit",
            tress_render::satf::scene::ClusterSource::Generate(_) => "generate",
        },
        clusters: stats.clusters,
        macro_clusters: counts.macro_clusters,
        layers: stats.layers,
        cluster_strands: counts.strands,
        skipped_strands: Skipped {
            total: counts.skipped.total(),
            too_short: counts.skipped.too_short,
            degenerate: counts.skipped.degenerate,
        },
        hsvs: stats.hsvs,
        uniform_hsvs: stats.uniform_hsvs,
        interpolated_hsvs: stats.interpolated_hsvs,
        atlas,
        stage_timing: match satf.settings.stage_timing {
            tress_render::satf::StageTiming::Timestamps => "timestamps",
            tress_render::satf::StageTiming::WallClock => "wall_clock",
        },
        clusters_cpu_ms,
        features_cpu_ms,
        stages_ms: Stages {
            index_calculation: i,
            map_construction: c,
            texture_mapping: m,
            lighting: l,
            shadowing: s,
        },
    };
    let report = Report::new(
        ctx,
        scene,
        size,
        hair_counts(prepared),
        output,
        passes(Some(&stats.timings)),
        stats.timings.total_ms(),
    );
    if counts.skipped.total() > 0 {
        eprintln!(
            "tress: satf: {} of the hair's strands are in no cluster ({} too short to have a \
             direction, {} degenerate)",
            counts.skipped.total(),
            counts.skipped.too_short,
            counts.skipped.degenerate
        );
    }
    if json {
        let report = Report {
            satf: Some(r),
            ..report
        };
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    println!(
        "wrote {} ({}x{}, {} clusters, {} layers, {} HSVs ({} uniform), {} strands) on {} ({})",
        report.output,
        size[0],
        size[1],
        r.clusters,
        r.layers,
        r.hsvs,
        r.uniform_hsvs,
        r.cluster_strands,
        report.adapter.name,
        report.adapter.backend
    );
    match &stats.timings {
        t @ Timings::Passes(_) => println!("{t}; frame {:.3} ms", t.total_ms().unwrap_or(0.0)),
        Timings::NotSupported => println!("GPU timestamps: not supported by this device"),
    }
    println!(
        "CPU: clusters {clusters_cpu_ms:.0} ms, sector features {features_cpu_ms:.0} ms; database {} ({} samples)",
        r.database, r.database_samples
    );
    Ok(())
}
