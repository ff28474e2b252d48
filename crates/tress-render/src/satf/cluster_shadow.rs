//! [`ClusterShadow`], owner of `cluster_shadow.wgsl` (Table 1, "shadowing", with
//! [`super::SMaps`]).

use super::SatfGeometry;
use super::passes::{Slot, layout};
use crate::gpu::DEPTH_FORMAT;
use crate::gpu::light_maps::{LightCameras, layer_views, per_light_texture};
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::gpu::types::CameraUniform;
use crate::head::{HEAD_VERTEX_LAYOUT, HeadGeometry};
use crate::{GpuContext, MAX_LIGHTS, RenderError, shaders};

/// The layer mesh vertex layout (`SatfVertex`, locations 0 to 5).
pub(crate) const SATF_VERTEX_LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 48,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Float32, 4 => Float32x3, 5 => Uint32
    ],
};

/// The per-light shadow maps between clusters: depth and the id of the nearest cluster (index +
/// 1) or the head, one array layer per light.
#[derive(Debug)]
pub(crate) struct ShadowTargets {
    pub(crate) size: u32,
    depth_layers: Vec<wgpu::TextureView>,
    id_layers: Vec<wgpu::TextureView>,
    pub(crate) depth_array: wgpu::TextureView,
    pub(crate) ids_array: wgpu::TextureView,
}

impl ShadowTargets {
    /// Bytes of the depth and id maps.
    pub(crate) fn bytes(&self) -> u64 {
        crate::gpu::texture_bytes(self.depth_array.texture())
            + crate::gpu::texture_bytes(self.ids_array.texture())
    }

    pub(crate) fn new(ctx: &GpuContext, size: u32) -> Result<Self, RenderError> {
        if size == 0 || size > ctx.caps.max_texture_2d {
            return Err(RenderError::Invalid(format!(
                "satf.shadow_map_size {size} is outside 1..={}",
                ctx.caps.max_texture_2d
            )));
        }
        ctx.scoped("creating the SATF shadow maps", || {
            let make = |name: &str, format| {
                per_light_texture(ctx, &format!("satf/cluster_shadow/{name}"), size, format)
            };
            let depth = make("depth", DEPTH_FORMAT);
            let ids = make("ids", wgpu::TextureFormat::R32Uint);
            let layers = |t: &wgpu::Texture| layer_views(t, |_| None);
            let array = |t: &wgpu::Texture| {
                t.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                })
            };
            ShadowTargets {
                size,
                depth_layers: layers(&depth),
                id_layers: layers(&ids),
                depth_array: array(&depth),
                ids_array: array(&ids),
            }
        })
    }
}

/// Rasterizes the outermost layer of every cluster and the head from each light (the shadow map
/// that replaces the paper's shadow volumes between clusters, §6.4).
#[derive(Debug)]
pub struct ClusterShadow {
    layer_pipeline: wgpu::RenderPipeline,
    head_pipeline: wgpu::RenderPipeline,
    cameras: LightCameras,
}

impl ClusterShadow {
    pub(crate) fn new(ctx: &GpuContext, params: &wgpu::Buffer) -> Result<Self, RenderError> {
        let module = shaders::create_module(
            ctx,
            "satf/cluster_shadow.wgsl",
            "satf/cluster_shadow/shader",
        )?;
        ctx.scoped("creating the SATF cluster shadow pipelines", || {
            let group_layout = layout(
                ctx,
                "satf/cluster_shadow/layout",
                wgpu::ShaderStages::VERTEX,
                &[(0, Slot::Uniform), (1, Slot::Uniform)],
            );
            let pl = pipeline_layout(
                ctx,
                "satf/cluster_shadow/pipeline-layout",
                &[Some(&group_layout)],
            );
            let pipeline = |label: &str, entry: &str, buffer: wgpu::VertexBufferLayout<'static>| {
                RasterPipeline {
                    vertex_entry: entry,
                    buffers: &[Some(buffer)],
                    depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                    targets: &[Some(wgpu::TextureFormat::R32Uint.into())],
                    ..RasterPipeline::new(label, &pl, &module)
                }
                .create(ctx)
            };
            let layer_pipeline = pipeline(
                "satf/cluster_shadow/layer-pipeline",
                "vs_layer",
                SATF_VERTEX_LAYOUT,
            );
            let head_pipeline = pipeline(
                "satf/cluster_shadow/head-pipeline",
                "vs_head",
                HEAD_VERTEX_LAYOUT,
            );
            let cameras = LightCameras::new(
                ctx,
                "satf/cluster_shadow",
                "bind-group",
                &group_layout,
                params,
            );
            ClusterShadow {
                layer_pipeline,
                head_pipeline,
                cameras,
            }
        })
    }

    /// Record one pass per light camera (at most [`MAX_LIGHTS`]). `timestamps(i, n)` gives the
    /// timestamp writes of pass `i` of `n`.
    #[expect(clippy::too_many_arguments, reason = "the pass's inputs, one each")]
    pub(crate) fn encode<'t>(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ShadowTargets,
        light_cameras: &[CameraUniform],
        geometry: Option<&SatfGeometry>,
        head: Option<&HeadGeometry>,
        mut timestamps: impl FnMut(usize, usize) -> Option<wgpu::RenderPassTimestampWrites<'t>>,
    ) {
        let n = light_cameras.len().min(MAX_LIGHTS);
        for (i, cam) in light_cameras.iter().take(n).enumerate() {
            let camera = self.cameras.set(ctx, i, cam);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("satf/cluster_shadow/pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &targets.id_layers[i],
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth_layers[i],
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timestamps(i, n),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, camera, &[]);
            if let Some(head) = head {
                pass.set_pipeline(&self.head_pipeline);
                head.draw(&mut pass);
            }
            if let Some(g) = geometry.filter(|g| g.layout.clusters > 0) {
                let l = &g.layout;
                pass.set_pipeline(&self.layer_pipeline);
                pass.set_vertex_buffer(0, g.vertices.slice(..));
                pass.set_index_buffer(g.indices.slice(..), wgpu::IndexFormat::Uint32);
                for c in 0..l.clusters {
                    let tile = c * l.layers + l.layers - 1;
                    let base = (tile * l.vertices_per_tile()) as i32;
                    pass.draw_indexed(0..l.indices_per_tile(), base, 0..1);
                }
            }
        }
    }
}
