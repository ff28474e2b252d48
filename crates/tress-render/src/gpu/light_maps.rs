//! What the shadow-map passes (the strands' ADSM maps, SATF's maps between clusters) allocate per
//! light: an array texture with one layer per light, its per-layer views, and a camera uniform
//! with its bind group per light.

use crate::bind::bind_group;
use crate::gpu::types::CameraUniform;
use crate::gpu::uniform_buffer;
use crate::{GpuContext, MAX_LIGHTS};

/// A `size`² texture of `format` with one array layer per possible light, drawn into and then
/// sampled.
pub(crate) fn per_light_texture(
    ctx: &GpuContext,
    label: &str,
    size: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: MAX_LIGHTS as u32,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// One 2D view per array layer of `texture`, labelled `label(layer)`.
pub(crate) fn layer_views(
    texture: &wgpu::Texture,
    label: impl Fn(u32) -> Option<String>,
) -> Vec<wgpu::TextureView> {
    (0..texture.depth_or_array_layers())
        .map(|i| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: label(i).as_deref(),
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: i,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect()
}

/// One camera uniform per possible light (`{prefix}/camera-{i}`), each bound with the pass's
/// `params` uniform in a bind group of `layout` (`{prefix}/{group}-{i}`; camera at binding 0,
/// params at 1).
#[derive(Debug)]
pub(crate) struct LightCameras(Vec<(wgpu::Buffer, wgpu::BindGroup)>);

impl LightCameras {
    pub(crate) fn new(
        ctx: &GpuContext,
        prefix: &str,
        group: &str,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
    ) -> Self {
        LightCameras(
            (0..MAX_LIGHTS)
                .map(|i| {
                    let camera = uniform_buffer(
                        ctx,
                        &format!("{prefix}/camera-{i}"),
                        &CameraUniform::default(),
                    );
                    let bind = bind_group(
                        ctx,
                        &format!("{prefix}/{group}-{i}"),
                        layout,
                        &[
                            (0, camera.as_entire_binding()),
                            (1, params.as_entire_binding()),
                        ],
                    );
                    (camera, bind)
                })
                .collect(),
        )
    }

    /// Write light `i`'s camera; returns the bind group that holds it.
    pub(crate) fn set(
        &self,
        ctx: &GpuContext,
        i: usize,
        camera: &CameraUniform,
    ) -> &wgpu::BindGroup {
        let (buffer, bind) = &self.0[i];
        ctx.queue
            .write_buffer(buffer, 0, bytemuck::bytes_of(camera));
        bind
    }
}
