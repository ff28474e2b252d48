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

use anyhow::{Context, Result};
use tress_render::session::{FrameDetail, Session};
use tress_render::{COLOR_FORMAT, GpuContext, OffscreenTargets, read_texture};

use super::open::DatabaseFile;
use super::render::rendering_spinner;
use super::report::{Report, SatfReport, save, timings_line};

/// Render the session's scene with the SATF technique (current) into `output` (`.png` or
/// `.exr`, checked by the caller) and report on stdout; `database` names the file the session's
/// database came from.
pub(crate) fn run(
    ctx: &GpuContext,
    session: &mut Session,
    output: &Path,
    json: bool,
    database: &DatabaseFile,
) -> Result<()> {
    let size = [session.scene().output.width, session.scene().output.height];
    let pb = rendering_spinner(ctx, size);
    let result = (|| -> Result<_> {
        let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
        let camera = session.camera(size);
        // The first frame warms up; the second is the one reported.
        session.render(ctx, &targets.targets(), &camera, None)?;
        let frame = session.render(ctx, &targets.targets(), &camera, None)?;
        let image = read_texture(ctx, &targets.color).context("reading the frame back")?;
        Ok((image, frame))
    })();
    pb.finish_and_clear();
    let (image, frame) = result?;
    save(&image, output)?;

    let (FrameDetail::Satf(stats), Some(info)) = (&frame.detail, session.satf()) else {
        anyhow::bail!("the frame was not drawn with the satf technique");
    };
    let db_path = database.path().unwrap_or_default();
    let r = SatfReport::new(info, stats, &db_path);
    let report = Report::new(ctx, session, &frame, output);
    if r.skipped_strands.total > 0 {
        eprintln!(
            "tress: satf: {} of the hair's strands are in no cluster ({} too short to have a \
             direction, {} degenerate)",
            r.skipped_strands.total, r.skipped_strands.too_short, r.skipped_strands.degenerate
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
    println!("{}", timings_line(Some(&stats.timings)));
    println!(
        "CPU: clusters {:.0} ms, sector features {:.0} ms; database {} ({} samples)",
        r.clusters_cpu_ms, r.features_cpu_ms, r.database, r.database_samples
    );
    Ok(())
}
