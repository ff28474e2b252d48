//! Geometry maps of hair, the images hair-reconstruction research trains on: per pixel the
//! nearest strand's index, its projected direction and the view depth, and the head's
//! silhouette. Strands are drawn as 1-pixel lines and the head as triangles into integer and
//! float targets with a depth test, so each pixel holds the nearest surface's values
//! ([`MapRenderer`], shader `maps/maps.wgsl`). [`segment_direction`] is the CPU twin of the
//! shader's projected direction.

use glam::{Mat4, Vec2, Vec3, Vec4};
use tress_hair::HairAsset;
use wgpu::util::DeviceExt;

use crate::bind::{bind_group, bind_group_layout, storage, uniform};
use crate::gpu::pipeline::{RasterPipeline, depth_test, pipeline_layout};
use crate::gpu::read_texture_bytes;
use crate::{Camera, DEPTH_FORMAT, GpuContext, RenderError, TriMesh, shaders};

/// Bytes of one segment in the shader's storage buffer (two `vec4<f32>`).
const SEGMENT_BYTES: u64 = 32;
/// The strand index the maps hold where the head is nearest.
pub const HEAD_ID: i32 = -2;
/// The strand index the maps hold where nothing was drawn.
pub const EMPTY_ID: i32 = -1;

/// The camera uniform of `maps.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MapCamera {
    clip_from_world: [f32; 16],
    view_z: [f32; 4],
    viewport: [f32; 2],
    _pad: [f32; 2],
}

/// One frame's geometry maps, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryMaps {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The nearest strand's index, [`HEAD_ID`] where the head is nearer, [`EMPTY_ID`] where
    /// nothing is.
    pub strand_id: Vec<i32>,
    /// The nearest strand segment's direction in pixels (x right, y down), unit length, root to
    /// tip; zero where no strand is nearest.
    pub direction: Vec<[f32; 2]>,
    /// The nearest surface's depth along the view direction (positive in front); infinite
    /// where nothing is.
    pub depth: Vec<f32>,
    /// Whether the head covers the pixel (behind hair or not).
    pub head: Vec<bool>,
}

/// The unit direction, in pixels (x right, y down), of segment `a`→`b` projected by
/// `clip_from_world` into a `viewport`-sized image; zero when an end is behind the eye or the
/// segment projects to a point. The CPU twin of `vs_strand` in `maps.wgsl`.
pub fn segment_direction(clip_from_world: Mat4, viewport: [f32; 2], a: Vec3, b: Vec3) -> Vec2 {
    let to_pixels = |c: Vec4| {
        let ndc = c.truncate().truncate() / c.w;
        Vec2::new(
            (ndc.x + 1.0) * 0.5 * viewport[0],
            (1.0 - ndc.y) * 0.5 * viewport[1],
        )
    };
    let ca = clip_from_world * a.extend(1.0);
    let cb = clip_from_world * b.extend(1.0);
    if ca.w <= 1e-6 || cb.w <= 1e-6 {
        return Vec2::ZERO;
    }
    let d = to_pixels(cb) - to_pixels(ca);
    let len = d.length();
    if len > 1e-12 { d / len } else { Vec2::ZERO }
}

/// One draw's worth of segments (storage buffers are bound in chunks the device allows).
struct Chunk {
    group: wgpu::BindGroup,
    segments: u32,
}

/// Hair and head uploaded for geometry maps; render any number of cameras.
pub struct MapRenderer {
    strands: wgpu::RenderPipeline,
    head_pipeline: wgpu::RenderPipeline,
    chunks: Vec<Chunk>,
    head_group: wgpu::BindGroup,
    head_indices: Option<(wgpu::Buffer, u32)>,
    camera: wgpu::Buffer,
}

impl std::fmt::Debug for MapRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MapRenderer")
            .field("chunks", &self.chunks.len())
            .finish()
    }
}

/// The targets' formats: strand index, (direction, depth), head coverage.
const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Sint;
const DATA_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const HEAD_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

impl MapRenderer {
    /// Upload `hair`'s segments (strand index in each) and the `head` mesh.
    pub fn new(
        ctx: &GpuContext,
        hair: &HairAsset,
        head: Option<&TriMesh>,
    ) -> Result<MapRenderer, RenderError> {
        if let Some(h) = head {
            crate::head::validate(h)?;
        }
        if hair.strand_count() > i32::MAX as usize {
            return Err(RenderError::Invalid(
                "geometry maps index at most 2^31 strands".into(),
            ));
        }
        let mut data: Vec<[f32; 4]> = Vec::with_capacity(hair.segment_count() * 2);
        for (i, strand) in hair.strands().enumerate() {
            let id = f32::from_bits(i as u32);
            for w in strand.windows(2) {
                data.push([w[0].x, w[0].y, w[0].z, id]);
                data.push([w[1].x, w[1].y, w[1].z, 0.0]);
            }
        }
        let limit = ctx.device.limits().max_storage_buffer_binding_size;
        let per_chunk = (limit / SEGMENT_BYTES).clamp(1, 1 << 24) as usize;
        let layout = bind_group_layout(
            ctx,
            "maps/group",
            &[
                uniform(0, wgpu::ShaderStages::VERTEX),
                storage(1, wgpu::ShaderStages::VERTEX, true),
                storage(2, wgpu::ShaderStages::VERTEX, true),
            ],
        );
        let camera = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("maps/camera"),
            size: std::mem::size_of::<MapCamera>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let init = |label: &str, contents: &[u8], usage| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        let storage_usage = wgpu::BufferUsages::STORAGE;
        let head_points: Vec<[f32; 4]> = match head {
            Some(h) => h
                .positions
                .iter()
                .map(|p| p.extend(0.0).to_array())
                .collect(),
            None => vec![[0.0; 4]],
        };
        let head_buffer = init(
            "maps/head",
            bytemuck::cast_slice(&head_points),
            storage_usage,
        );
        let group = |segments: &wgpu::Buffer| {
            bind_group(
                ctx,
                "maps/group",
                &layout,
                &[
                    (0, camera.as_entire_binding()),
                    (1, segments.as_entire_binding()),
                    (2, head_buffer.as_entire_binding()),
                ],
            )
        };
        let chunks = data
            .chunks(per_chunk * 2)
            .map(|c| {
                let buffer = init("maps/segments", bytemuck::cast_slice(c), storage_usage);
                Chunk {
                    group: group(&buffer),
                    segments: (c.len() / 2) as u32,
                }
            })
            .collect::<Vec<_>>();
        let dummy = init(
            "maps/segments",
            bytemuck::cast_slice(&[[0f32; 4]; 2]),
            storage_usage,
        );
        let head_group = group(&dummy);
        let head_indices = head.map(|h| {
            (
                init(
                    "maps/head_indices",
                    bytemuck::cast_slice(&h.indices),
                    wgpu::BufferUsages::INDEX,
                ),
                h.indices.len() as u32,
            )
        });
        let module = shaders::create_module(ctx, "maps/maps.wgsl", "maps/shader")?;
        let pl = pipeline_layout(ctx, "maps/layout", &[Some(&layout)]);
        let target = |format, write_mask| {
            Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask,
            })
        };
        let all = wgpu::ColorWrites::ALL;
        let strand_targets = [
            target(ID_FORMAT, all),
            target(DATA_FORMAT, all),
            target(HEAD_FORMAT, wgpu::ColorWrites::empty()),
        ];
        let head_targets = [
            target(ID_FORMAT, all),
            target(DATA_FORMAT, all),
            target(HEAD_FORMAT, all),
        ];
        let (strands, head_pipeline) = ctx.scoped("creating the maps pipelines", || {
            let strands = RasterPipeline {
                vertex_entry: "vs_strand",
                fragment_entry: Some("fs_maps"),
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::LineList,
                    ..Default::default()
                },
                depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                targets: &strand_targets,
                ..RasterPipeline::new("maps/strands", &pl, &module)
            }
            .create(ctx);
            let head = RasterPipeline {
                vertex_entry: "vs_head",
                fragment_entry: Some("fs_maps"),
                depth_stencil: Some(depth_test(true, wgpu::CompareFunction::Less)),
                targets: &head_targets,
                ..RasterPipeline::new("maps/head", &pl, &module)
            }
            .create(ctx);
            (strands, head)
        })?;
        Ok(MapRenderer {
            strands,
            head_pipeline,
            chunks,
            head_group,
            head_indices,
            camera,
        })
    }

    /// The maps seen by `camera` (its viewport is the maps' size).
    pub fn render(&self, ctx: &GpuContext, camera: &Camera) -> Result<GeometryMaps, RenderError> {
        camera.validate()?;
        let [width, height] = camera.viewport;
        let max = ctx.caps.max_texture_2d;
        if width > max || height > max {
            return Err(RenderError::Invalid(format!(
                "maps of {width}x{height} exceed the device's {max} pixels"
            )));
        }
        let view_z = camera.view_from_world.row(2);
        let uniform = MapCamera {
            clip_from_world: camera.clip_from_world().to_cols_array(),
            view_z: view_z.to_array(),
            viewport: [width as f32, height as f32],
            _pad: [0.0; 2],
        };
        ctx.queue
            .write_buffer(&self.camera, 0, bytemuck::bytes_of(&uniform));
        let extent = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label, format| {
            ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let (id, data, head, depth) = ctx.scoped("creating the maps targets", || {
            (
                texture("maps/id", ID_FORMAT),
                texture("maps/data", DATA_FORMAT),
                texture("maps/head", HEAD_FORMAT),
                texture("maps/depth", DEPTH_FORMAT),
            )
        })?;
        let views = [&id, &data, &head].map(|t| t.create_view(&Default::default()));
        let depth_view = depth.create_view(&Default::default());
        let clears = [
            wgpu::Color {
                r: f64::from(EMPTY_ID),
                ..wgpu::Color::TRANSPARENT
            },
            wgpu::Color::TRANSPARENT,
            wgpu::Color::TRANSPARENT,
        ];
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("maps/encoder"),
            });
        {
            let attachments: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = views
                .iter()
                .zip(clears)
                .map(|(view, clear)| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                })
                .collect();
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("maps/pass"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if let Some((indices, count)) = &self.head_indices {
                pass.set_pipeline(&self.head_pipeline);
                pass.set_bind_group(0, &self.head_group, &[]);
                pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*count, 0, 0..1);
            }
            pass.set_pipeline(&self.strands);
            for chunk in &self.chunks {
                pass.set_bind_group(0, &chunk.group, &[]);
                pass.draw(0..chunk.segments * 2, 0..1);
            }
        }
        ctx.queue.submit([enc.finish()]);
        let ids: Vec<i32> = bytemuck::pod_collect_to_vec(&read_texture_bytes(ctx, &id, 4)?);
        let values: Vec<[f32; 4]> =
            bytemuck::pod_collect_to_vec(&read_texture_bytes(ctx, &data, 16)?);
        let heads = read_texture_bytes(ctx, &head, 1)?;
        let depth = ids
            .iter()
            .zip(&values)
            .map(|(&i, v)| if i == EMPTY_ID { f32::INFINITY } else { v[2] })
            .collect();
        Ok(GeometryMaps {
            width,
            height,
            direction: values.iter().map(|v| [v[0], v[1]]).collect(),
            depth,
            strand_id: ids,
            head: heads.iter().map(|&h| h > 127).collect(),
        })
    }
}
