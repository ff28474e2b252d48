//! [`PpllBuild`], owner of `ppll_build.wgsl`.

use crate::bind::{Layouts, bind_group, bind_group_layout, depth_texture};
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::strands::PpllPool;
use crate::strands::oit::OitPart;
use crate::strands::ppll::{NODE_CHUNKS, pool_layout_entries};
use crate::{GpuContext, RenderError, shaders};

/// Binding of the head's depth in `ppll_build.wgsl` (after the pool's).
const HEAD_DEPTH: u32 = 2 + NODE_CHUNKS as u32;

/// The PPLL build pass: strands are shaded and their fragments inserted into per-pixel lists.
#[derive(Debug)]
pub struct PpllBuild {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// What the build pass reads and writes in a frame.
pub(crate) struct PpllBuildInputs<'a> {
    /// The heads of hair, each drawn with its own groups into the one pool.
    pub(crate) parts: &'a [OitPart<'a>],
    pub(crate) pool: &'a PpllPool,
    /// The head's depth: read-only attachment (early rejection) and texture (exact test).
    pub(crate) depth: &'a wgpu::TextureView,
}

impl PpllBuild {
    pub(crate) fn new(ctx: &GpuContext, layouts: &Layouts) -> Result<Self, RenderError> {
        let module =
            shaders::create_module(ctx, "strands/ppll_build.wgsl", "strands/ppll_build/shader")?;
        ctx.scoped("creating the PPLL build pipeline", || {
            let mut entries = pool_layout_entries();
            entries.push(depth_texture(HEAD_DEPTH, wgpu::ShaderStages::FRAGMENT));
            let layout = bind_group_layout(ctx, "strands/ppll_build/layout", &entries);
            let pipeline_layout = pipeline_layout(
                ctx,
                "strands/ppll_build/pipeline-layout",
                &[
                    Some(&layouts.view),
                    Some(&layouts.lighting),
                    Some(&layouts.strands),
                    Some(&layout),
                ],
            );
            let pipeline = RasterPipeline {
                depth_stencil: Some(depth_test(false, wgpu::CompareFunction::Less)),
                ..RasterPipeline::new("strands/ppll_build/pipeline", &pipeline_layout, &module)
            }
            .create(ctx);
            PpllBuild { pipeline, layout }
        })
    }

    /// Record the pass: clear the lists, then draw every part's segments' quads.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &PpllBuildInputs<'_>,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        inputs.pool.clear(encoder);
        let mut entries = inputs.pool.entries();
        entries.push((HEAD_DEPTH, wgpu::BindingResource::TextureView(inputs.depth)));
        let group = bind_group(ctx, "strands/ppll_build/bind-group", &self.layout, &entries);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("strands/ppll_build/pass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: inputs.depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(3, &group, &[]);
        for part in inputs.parts {
            pass.set_bind_group(0, part.view, &[]);
            pass.set_bind_group(1, part.lighting, &[]);
            pass.set_bind_group(2, &part.geometry.bind_group, &[]);
            pass.draw(0..part.geometry.segment_count() * 6, 0..1);
        }
    }
}
