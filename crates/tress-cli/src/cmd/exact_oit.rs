//! `tress render --exact-oit`: the strand frame as exact sorted compositing would draw it, a
//! reference for the OIT's error (`tress compare-images REF TEST`). The frame is drawn with the
//! paper's PPLL, its pool allowed to hold every fragment; the lists are read back and each
//! pixel's k-buffer composite is replaced by every fragment sorted by depth and blended in order
//! (`PpllFragments::sort_exactly`).

use anyhow::{Result, bail};
use tress_render::session::{FrameDetail, Session, SessionFrame, TechniqueKind};
use tress_render::strands::OitKind;
use tress_render::{GpuContext, LinearImage};

/// Settings `--exact-oit` puts before the command line's `--set`s: the PPLL, with a pool cap as
/// large as the device's bindings allow.
pub(crate) const SETS: [&str; 2] = ["strands.oit=\"ppll\"", "strands.ppll_max_mib=4096"];

/// Render the exact reference of the session's strand frame at `size`.
pub(crate) fn render(
    ctx: &GpuContext,
    session: &mut Session,
    size: [u32; 2],
) -> Result<(LinearImage, SessionFrame)> {
    if session.technique_kind() != TechniqueKind::Strands {
        bail!(
            "--exact-oit composites strand fragments: it needs technique `strands`, not `{}`",
            session.technique()
        );
    }
    let (mut image, frame) = super::render::render_frame(ctx, session, size)?;
    let oit = match &frame.detail {
        FrameDetail::Strands(stats) => stats.gpu.as_ref().and_then(|g| g.oit),
        _ => None,
    };
    match oit {
        Some(o) if o.kind == OitKind::Ppll && o.lost == 0 => {}
        Some(o) if o.kind == OitKind::Ppll => bail!(
            "--exact-oit: the PPLL pool could not hold the frame ({} of {} fragments lost); \
             render a smaller image or raise strands.ppll_max_mib",
            o.lost,
            o.fragments
        ),
        _ => bail!("--exact-oit: the frame was not drawn with the PPLL"),
    }
    if !session.sort_exactly(ctx, &mut image)? {
        bail!("--exact-oit: the renderer kept no PPLL lists");
    }
    Ok((image, frame))
}
