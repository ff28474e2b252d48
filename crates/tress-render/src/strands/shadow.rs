//! [`ShadowMap`], owner of `shadow.wgsl`.

use crate::bind::Layouts;
use crate::gpu::DEPTH_FORMAT;
use crate::gpu::light_maps::{LightCameras, layer_views, per_light_texture};
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::gpu::types::CameraUniform;
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::strands::StrandGeometry;
use crate::{GpuContext, MAX_LIGHTS, RenderError, shaders};

/// One ADSM depth map per light (a layer of one array texture): the nearest hair or head depth
/// seen from the light (Jansson 2019 §3.4).
#[derive(Debug)]
pub struct ShadowMap {
    strand_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    head_pipeline: wgpu::RenderPipeline,
    size: u32,
    layers: Vec<wgpu::TextureView>,
    cameras: LightCameras,
}

/// What the shadow maps are drawn from.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShadowCasters<'a> {
    /// Every head of hair the rasterizer draws this frame.
    pub(crate) hair: &'a [&'a StrandGeometry],
    pub(crate) head: Option<&'a HeadGeometry>,
    /// Strand width in shadow-map texels (`shadow_width_px`).
    pub(crate) width_px: f32,
}

impl ShadowMap {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        params: &wgpu::Buffer,
        size: u32,
    ) -> Result<Self, RenderError> {
        if size == 0 || size > ctx.caps.max_texture_2d {
            return Err(RenderError::Invalid(format!(
                "shadow map size {size} is outside 1..={}",
                ctx.caps.max_texture_2d
            )));
        }
        let module = shaders::create_module(ctx, "strands/shadow.wgsl", "strands/shadow/shader")?;
        ctx.scoped("creating the shadow maps", || {
            let strand_layout = pipeline_layout(
                ctx,
                "strands/shadow/strand-layout",
                &[Some(&layouts.view), None, Some(&layouts.strands)],
            );
            let head_layout =
                pipeline_layout(ctx, "strands/shadow/head-layout", &[Some(&layouts.view)]);
            let pipeline = |label,
                            layout,
                            vertex_entry,
                            buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                            topology| {
                RasterPipeline {
                    vertex_entry,
                    buffers,
                    primitive: wgpu::PrimitiveState {
                        topology,
                        ..Default::default()
                    },
                    depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                    fragment_entry: None,
                    ..RasterPipeline::new(label, layout, &module)
                }
                .create(ctx)
            };
            let triangles = wgpu::PrimitiveTopology::TriangleList;
            let strand_pipeline = pipeline(
                "strands/shadow/strand-pipeline",
                &strand_layout,
                "vs_strand",
                &[],
                triangles,
            );
            let line_pipeline = pipeline(
                "strands/shadow/line-pipeline",
                &strand_layout,
                "vs_strand_line",
                &[],
                wgpu::PrimitiveTopology::LineList,
            );
            let head_pipeline = pipeline(
                "strands/shadow/head-pipeline",
                &head_layout,
                "vs_head",
                &[Some(HEAD_VERTEX_LAYOUT)],
                triangles,
            );
            let texture = per_light_texture(ctx, "strands/shadow/maps", size, DEPTH_FORMAT);
            let layers = layer_views(&texture, |i| Some(format!("strands/shadow/map-{i}")));
            let cameras = LightCameras::new(ctx, "strands/shadow", "view", &layouts.view, params);
            ShadowMap {
                strand_pipeline,
                line_pipeline,
                head_pipeline,
                size,
                layers,
                cameras,
            }
        })
    }

    /// Edge length in texels.
    pub fn size(&self) -> u32 {
        self.size
    }

    /// Bytes of the depth maps (one layer per possible light).
    pub fn bytes(&self) -> u64 {
        self.layers
            .first()
            .map_or(0, |v| crate::gpu::texture_bytes(v.texture()))
    }

    /// The per-light depth views (bound in the lighting group).
    pub(crate) fn layer_views(&self) -> &[wgpu::TextureView] {
        &self.layers
    }

    /// Record one depth pass per light camera (`light_cameras.len() <= MAX_LIGHTS`). The first
    /// pass writes the begin timestamp and the last the end timestamp of `timer_name`. Strands
    /// are drawn as one-texel lines when `width_px <= 1` (the default), else as ribbons
    /// `width_px` texels wide.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &crate::gpu::GpuTimer,
        light_cameras: &[CameraUniform],
        casters: ShadowCasters<'_>,
    ) {
        let ShadowCasters {
            hair,
            head,
            width_px,
        } = casters;
        let n = light_cameras.len().min(MAX_LIGHTS);
        for (i, cam) in light_cameras.iter().take(n).enumerate() {
            let camera = self.cameras.set(ctx, i, cam);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("strands/shadow/pass"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.layers[i],
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render_writes("strands/shadow", i == 0, i + 1 == n),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, camera, &[]);
            if let Some(head) = head {
                pass.set_pipeline(&self.head_pipeline);
                head.draw(&mut pass);
            }
            for hair in hair.iter().filter(|h| h.segment_count() > 0) {
                pass.set_bind_group(2, &hair.bind_group, &[]);
                if width_px <= 1.0 {
                    pass.set_pipeline(&self.line_pipeline);
                    pass.draw(0..hair.segment_count() * 2, 0..1);
                } else {
                    pass.set_pipeline(&self.strand_pipeline);
                    pass.draw(0..hair.segment_count() * 6, 0..1);
                }
            }
        }
    }
}
