//! [`HeadPass`], owner of `head_pass.wgsl` (and, built with another shader, the patch
//! technique's head), and `HeadPipeline`, the head pipeline every technique draws its head with.

use crate::bind::Layouts;
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::gpu::{Targets, clear_loads};
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::{GpuContext, RenderError, shaders};

/// Draws the opaque head mesh with depth writes, Lambert-lit: with ADSM shadows
/// (`head_pass.wgsl`, the strands, volume and hybrid), or unshadowed (`patch_head.wgsl`).
#[derive(Debug)]
pub struct HeadPass {
    pipeline: HeadPipeline,
    /// The render pass's label.
    label: String,
}

impl HeadPass {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let groups = [&layouts.view, &layouts.lighting];
        Self::with_shader(
            ctx,
            ["head/head_pass.wgsl", "head/head_pass"],
            groups,
            color_format,
        )
    }

    /// The head drawn by `shader` (`[path, label prefix]`), its groups 0 and 1 laid out as
    /// `groups`.
    pub(crate) fn with_shader(
        ctx: &GpuContext,
        [path, label]: [&'static str; 2],
        groups: [&wgpu::BindGroupLayout; 2],
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module = shaders::create_module(ctx, path, &format!("{label}/shader"))?;
        let pipeline = ctx.scoped("creating a head pipeline", || {
            let layout = pipeline_layout(
                ctx,
                &format!("{label}/layout"),
                &[Some(groups[0]), Some(groups[1])],
            );
            HeadPipeline::new(
                ctx,
                &format!("{label}/pipeline"),
                &module,
                &layout,
                color_format,
            )
        })?;
        Ok(HeadPass {
            pipeline,
            label: format!("{label}/pass"),
        })
    }

    /// The frame's head pass (see [`HeadPipeline::encode`]) with groups 0 and 1.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets<'_>,
        clear: Option<wgpu::Color>,
        writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        groups: [&wgpu::BindGroup; 2],
        head: Option<&HeadGeometry>,
    ) {
        let pass = HeadPassInfo {
            label: &self.label,
            clear,
            writes,
        };
        self.pipeline.encode(encoder, targets, pass, &groups, head);
    }
}

/// How a frame's head pass begins: its label, whether it clears the targets first, and its
/// timestamp writes.
pub(crate) struct HeadPassInfo<'a> {
    pub(crate) label: &'a str,
    pub(crate) clear: Option<wgpu::Color>,
    pub(crate) writes: Option<wgpu::RenderPassTimestampWrites<'a>>,
}

/// The opaque head of every technique: `vs_main` and `fs_main` of the technique's head shader
/// over [`HEAD_VERTEX_LAYOUT`], depth written with `Less`, one color target without blending. The
/// techniques' heads differ only in their shader's lighting, and so in their bind groups.
#[derive(Debug)]
pub(crate) struct HeadPipeline(wgpu::RenderPipeline);

impl HeadPipeline {
    pub(crate) fn new(
        ctx: &GpuContext,
        label: &str,
        module: &wgpu::ShaderModule,
        layout: &wgpu::PipelineLayout,
        color_format: wgpu::TextureFormat,
    ) -> Self {
        HeadPipeline(
            RasterPipeline {
                buffers: &[Some(HEAD_VERTEX_LAYOUT)],
                depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                targets: &[Some(color_format.into())],
                ..RasterPipeline::new(label, layout, module)
            }
            .create(ctx),
        )
    }

    /// Every technique's head pass: the frame's first pass over the targets, clearing them
    /// when `info.clear` is set, then the head (if any) drawn with `groups` bound from 0.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets<'_>,
        info: HeadPassInfo<'_>,
        groups: &[&wgpu::BindGroup],
        head: Option<&HeadGeometry>,
    ) {
        let mut pass =
            targets.begin_pass(encoder, info.label, clear_loads(info.clear), info.writes);
        if let Some(head) = head {
            for (i, g) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, *g, &[]);
            }
            pass.set_pipeline(&self.0);
            head.draw(&mut pass);
        }
    }
}
