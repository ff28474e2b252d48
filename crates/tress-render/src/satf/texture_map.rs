//! [`TextureMap`], owner of `texture_map.wgsl` (Table 1, "texture mapping").

use super::SatfGeometry;
use super::cluster_shadow::SATF_VERTEX_LAYOUT;
use super::passes::{Slot, layout};
use crate::bind::bind_group;
use crate::gpu::Targets;
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout, premultiplied_over};
use crate::{GpuContext, RenderError, shaders};

/// Draws every layer mesh with its maps, shading by equation 13 and blending by equation 14:
/// per cluster, back to front, the back faces of layers `n−1 … 0` then the front faces of
/// `0 … n−1` (§6.5).
#[derive(Debug)]
pub struct TextureMap {
    layout: wgpu::BindGroupLayout,
    back: wgpu::RenderPipeline,
    front: wgpu::RenderPipeline,
}

impl TextureMap {
    pub(crate) fn new(
        ctx: &GpuContext,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let module =
            shaders::create_module(ctx, "satf/texture_map.wgsl", "satf/texture_map/shader")?;
        ctx.scoped("creating the SATF texture mapping pipelines", || {
            let layout = layout(
                ctx,
                "satf/texture_map/layout",
                wgpu::ShaderStages::VERTEX_FRAGMENT,
                &[
                    (0, Slot::Uniform),
                    (1, Slot::Uniform),
                    (2, Slot::Texture),
                    (3, Slot::Texture),
                    (4, Slot::Texture),
                ],
            );
            let pl = pipeline_layout(ctx, "satf/texture_map/pipeline-layout", &[Some(&layout)]);
            let pipeline = |label: &str, cull: wgpu::Face| {
                RasterPipeline {
                    buffers: &[Some(SATF_VERTEX_LAYOUT)],
                    primitive: wgpu::PrimitiveState {
                        cull_mode: Some(cull),
                        ..Default::default()
                    },
                    depth_stencil: Some(depth_test(false, wgpu::CompareFunction::Less)),
                    targets: &[Some(premultiplied_over(color_format))],
                    ..RasterPipeline::new(label, &pl, &module)
                }
                .create(ctx)
            };
            TextureMap {
                back: pipeline("satf/texture_map/back-pipeline", wgpu::Face::Front),
                front: pipeline("satf/texture_map/front-pipeline", wgpu::Face::Back),
                layout,
            }
        })
    }

    /// Record the pass: clusters in `order` (back to front), each back faces outer to inner,
    /// then front faces inner to outer.
    #[expect(clippy::too_many_arguments, reason = "the pass's inputs, one each")]
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        camera: &wgpu::Buffer,
        params: &wgpu::Buffer,
        geometry: &SatfGeometry,
        order: &[u32],
        targets: &Targets<'_>,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let a = &geometry.atlas;
        let bind = bind_group(
            ctx,
            "satf/texture_map/bind-group",
            &self.layout,
            &[
                (0, camera.as_entire_binding()),
                (1, params.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(&a.maps)),
                (3, wgpu::BindingResource::TextureView(&a.s_map)),
                (4, wgpu::BindingResource::TextureView(&a.l_map)),
            ],
        );
        let mut pass = targets.begin_pass(
            encoder,
            "satf/texture_map/pass",
            (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
            timestamps,
        );
        let l = &geometry.layout;
        if l.clusters == 0 {
            return;
        }
        pass.set_bind_group(0, &bind, &[]);
        pass.set_vertex_buffer(0, geometry.vertices.slice(..));
        pass.set_index_buffer(geometry.indices.slice(..), wgpu::IndexFormat::Uint32);
        let n = l.indices_per_tile();
        let base = |c: u32, layer: u32| ((c * l.layers + layer) * l.vertices_per_tile()) as i32;
        for &c in order.iter().filter(|&&c| c < l.clusters) {
            pass.set_pipeline(&self.back);
            for layer in (0..l.layers).rev() {
                pass.draw_indexed(0..n, base(c, layer), 0..1);
            }
            pass.set_pipeline(&self.front);
            for layer in 0..l.layers {
                pass.draw_indexed(0..n, base(c, layer), 0..1);
            }
        }
    }
}
