//! `tress render --exact-oit`: the strand frame as exact sorted compositing would draw it, a
//! reference for the OIT's error (`tress compare-images REF TEST`). The frame is drawn with the
//! paper's PPLL, its pool allowed to hold every fragment; the lists are read back and each
//! pixel's k-buffer composite is replaced by every fragment sorted by depth and blended in order
//! (`PpllFragments::sort_exactly`).

use anyhow::{Context, Result, bail};
use tress_render::scene_setup::PreparedScene;
use tress_render::strands::OitKind;
use tress_render::{FrameStats, GpuContext, LinearImage, read_texture};
use tress_scene::Scene;
/// Settings `--exact-oit` puts before the command line's `--set`s: the PPLL, with a pool cap as
/// large as the device's bindings allow.
pub(crate) const SETS: [&str; 2] = ["strands.oit=\"ppll\"", "strands.ppll_max_mib=4096"];

/// Render the exact reference of a strand frame.
pub(crate) fn render(
    ctx: &GpuContext,
    scene: &Scene,
    prepared: &PreparedScene,
    size: [u32; 2],
) -> Result<(LinearImage, FrameStats)> {
    if scene.technique != "strands" {
        bail!(
            "--exact-oit composites strand fragments: it needs technique `strands`, not `{}`",
            scene.technique
        );
    }
    let (renderer, targets, stats) = super::render::draw_frame(ctx, scene, prepared, size)?;
    match stats.gpu.as_ref().and_then(|g| g.oit) {
        Some(o) if o.kind == OitKind::Ppll && o.lost == 0 => {}
        Some(o) if o.kind == OitKind::Ppll => bail!(
            "--exact-oit: the PPLL pool could not hold the frame ({} of {} fragments lost); \
             render a smaller image or raise strands.ppll_max_mib",
            o.lost,
            o.fragments
        ),
        _ => bail!("--exact-oit: the frame was not drawn with the PPLL"),
    }
    let mut image = read_texture(ctx, &targets.color).context("reading the frame back")?;
    let fragments = renderer
        .ppll_fragments(ctx)?
        .context("--exact-oit: the renderer kept no PPLL lists")?;
    fragments.sort_exactly(&mut image, prepared.strands.k as usize);
    Ok((image, stats))
}
