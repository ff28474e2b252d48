//! [`ShadowMap`], owner of `shadow.wgsl`.

use wgpu::util::DeviceExt;

use crate::bind::Layouts;
use crate::gpu::DEPTH_FORMAT;
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
    head_pipeline: wgpu::RenderPipeline,
    size: u32,
    layers: Vec<wgpu::TextureView>,
    cameras: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
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
            let pipeline =
                |label, layout, vertex_entry, buffers: &[Option<wgpu::VertexBufferLayout<'_>>]| {
                    RasterPipeline {
                        vertex_entry,
                        buffers,
                        depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                        fragment_entry: None,
                        ..RasterPipeline::new(label, layout, &module)
                    }
                    .create(ctx)
                };
            let strand_pipeline = pipeline(
                "strands/shadow/strand-pipeline",
                &strand_layout,
                "vs_strand",
                &[],
            );
            let head_pipeline = pipeline(
                "strands/shadow/head-pipeline",
                &head_layout,
                "vs_head",
                &[Some(HEAD_VERTEX_LAYOUT)],
            );
            let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("strands/shadow/maps"),
                size: wgpu::Extent3d {
                    width: size,
                    height: size,
                    depth_or_array_layers: MAX_LIGHTS as u32,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            let layers = (0..MAX_LIGHTS as u32)
                .map(|i| {
                    texture.create_view(&wgpu::TextureViewDescriptor {
                        label: Some(&format!("strands/shadow/map-{i}")),
                        dimension: Some(wgpu::TextureViewDimension::D2),
                        base_array_layer: i,
                        array_layer_count: Some(1),
                        ..Default::default()
                    })
                })
                .collect();
            let cameras = (0..MAX_LIGHTS)
                .map(|i| {
                    let buffer = ctx
                        .device
                        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                            label: Some(&format!("strands/shadow/camera-{i}")),
                            contents: bytemuck::bytes_of(&CameraUniform::default()),
                            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        });
                    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some(&format!("strands/shadow/view-{i}")),
                        layout: &layouts.view,
                        entries: &[
                            wgpu::BindGroupEntry {
                                binding: 0,
                                resource: buffer.as_entire_binding(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 1,
                                resource: params.as_entire_binding(),
                            },
                        ],
                    });
                    (buffer, group)
                })
                .collect();
            ShadowMap {
                strand_pipeline,
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
    /// pass writes the begin timestamp and the last the end timestamp of `timer_name`.
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut crate::gpu::GpuTimer,
        light_cameras: &[CameraUniform],
        hair: Option<&StrandGeometry>,
        head: Option<&HeadGeometry>,
    ) {
        let n = light_cameras.len().min(MAX_LIGHTS);
        for (i, cam) in light_cameras.iter().take(n).enumerate() {
            ctx.queue
                .write_buffer(&self.cameras[i].0, 0, bytemuck::bytes_of(cam));
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
            pass.set_bind_group(0, &self.cameras[i].1, &[]);
            if let Some(head) = head {
                pass.set_pipeline(&self.head_pipeline);
                head.draw(&mut pass);
            }
            if let Some(hair) = hair.filter(|h| h.segment_count() > 0) {
                pass.set_pipeline(&self.strand_pipeline);
                pass.set_bind_group(2, &hair.bind_group, &[]);
                pass.draw(0..hair.segment_count() * 6, 0..1);
            }
        }
    }
}
