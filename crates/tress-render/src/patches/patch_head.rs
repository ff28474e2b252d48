//! The patch technique's head: `patch_head.wgsl` drawn by the shared [`HeadPass`].

use crate::head::HeadPass;
use crate::{GpuContext, RenderError};

/// The head drawn first, with depth writes (`Less`), so the patch passes' depth test rejects the
/// hair behind it: two-sided Lambert plus ambient, unshadowed (the patches' self-shadowing is
/// their baked AO), over the patch technique's view and lights groups.
pub(crate) fn patch_head(
    ctx: &GpuContext,
    view_layout: &wgpu::BindGroupLayout,
    lights_layout: &wgpu::BindGroupLayout,
    color_format: wgpu::TextureFormat,
) -> Result<HeadPass, RenderError> {
    HeadPass::with_shader(
        ctx,
        ["patches/patch_head.wgsl", "patches/head"],
        [view_layout, lights_layout],
        color_format,
    )
}
