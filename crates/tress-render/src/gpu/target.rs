//! Render targets: the caller's views ([`Targets`]) and an offscreen pair for headless rendering
//! ([`OffscreenTargets`]).

use crate::{Camera, GpuContext, RenderError};

/// Default color format of offscreen targets: linear half floats. Hair is many thin, partly
/// transparent layers blended together, so blending in linear space with more than 8 bits per
/// channel avoids banding in dark hair; readback converts to 8-bit sRGB for PNG and keeps full
/// precision for EXR. Applications may render into any blendable color format instead (for
/// example an `Rgba8UnormSrgb` or `Bgra8UnormSrgb` swapchain view): pass it in [`TargetFormats`].
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Depth format the renderer needs: 32-bit float, depth 0 near and 1 far, cleared to 1, compared
/// with `Less`. The strand passes read it as a texture, so caller depth textures need
/// `TEXTURE_BINDING` usage besides `RENDER_ATTACHMENT`.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The formats the renderer's pipelines are built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormats {
    /// Color attachment format (must be blendable and renderable).
    pub color: wgpu::TextureFormat,
}

impl Default for TargetFormats {
    fn default() -> Self {
        TargetFormats {
            color: COLOR_FORMAT,
        }
    }
}

/// Caller-provided views the renderer draws into. Both must have the same size; the depth
/// texture must be [`DEPTH_FORMAT`] with `RENDER_ATTACHMENT | TEXTURE_BINDING` usage.
#[derive(Clone, Copy, Debug)]
pub struct Targets<'a> {
    /// Color view (format as given to the renderer).
    pub color: &'a wgpu::TextureView,
    /// Depth view.
    pub depth: &'a wgpu::TextureView,
}

/// Load operations of a frame's first pass: clear to `clear` (and depth to 1), or keep what the
/// targets hold when the frame draws over the caller's content.
pub(crate) fn clear_loads(
    clear: Option<wgpu::Color>,
) -> (wgpu::LoadOp<wgpu::Color>, wgpu::LoadOp<f32>) {
    match clear {
        Some(c) => (wgpu::LoadOp::Clear(c), wgpu::LoadOp::Clear(1.0)),
        None => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
    }
}

impl Targets<'_> {
    /// A render pass over both targets with the given load operations, storing both.
    pub(crate) fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &str,
        (color_load, depth_load): (wgpu::LoadOp<wgpu::Color>, wgpu::LoadOp<f32>),
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: self.color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: color_load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: depth_load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// What every renderer checks first in a frame: the targets (see [`Targets::validate`]), a
    /// valid camera whose viewport is the targets' size, and at most [`crate::MAX_LIGHTS`] lights.
    /// Returns the size in pixels.
    pub(crate) fn validate_view(
        &self,
        formats: TargetFormats,
        camera: &Camera,
        lights: usize,
    ) -> Result<[u32; 2], RenderError> {
        let size = self.validate(formats)?;
        camera.validate()?;
        if camera.viewport != size {
            return Err(RenderError::Target(format!(
                "camera viewport {:?} differs from the target size {size:?}",
                camera.viewport
            )));
        }
        crate::inputs::check_light_count(lights)?;
        Ok(size)
    }

    /// Check formats, usages and sizes; returns the size in pixels.
    pub fn validate(&self, formats: TargetFormats) -> Result<[u32; 2], RenderError> {
        let color = self.color.texture();
        let depth = self.depth.texture();
        if color.format() != formats.color {
            return Err(RenderError::Target(format!(
                "color target is {:?} but the renderer was built for {:?}",
                color.format(),
                formats.color
            )));
        }
        if !color
            .usage()
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        {
            return Err(RenderError::Target(
                "color target lacks RENDER_ATTACHMENT usage".into(),
            ));
        }
        if depth.format() != DEPTH_FORMAT {
            return Err(RenderError::Target(format!(
                "depth target is {:?}, expected {DEPTH_FORMAT:?}",
                depth.format()
            )));
        }
        let need = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        if !depth.usage().contains(need) {
            return Err(RenderError::Target(
                "depth target needs RENDER_ATTACHMENT | TEXTURE_BINDING usage".into(),
            ));
        }
        if color.sample_count() != 1 || depth.sample_count() != 1 {
            return Err(RenderError::Target(
                "multisampled targets are not supported".into(),
            ));
        }
        let size = [color.width(), color.height()];
        if size != [depth.width(), depth.height()] {
            return Err(RenderError::Target(format!(
                "color is {}x{} but depth is {}x{}",
                size[0],
                size[1],
                depth.width(),
                depth.height()
            )));
        }
        Ok(size)
    }
}

/// An offscreen color + depth pair for headless rendering and readback.
#[derive(Debug)]
pub struct OffscreenTargets {
    /// Color texture (`COPY_SRC` so it can be read back).
    pub color: wgpu::Texture,
    /// Depth texture.
    pub depth: wgpu::Texture,
    /// View of `color`.
    pub color_view: wgpu::TextureView,
    /// View of `depth`.
    pub depth_view: wgpu::TextureView,
}

impl OffscreenTargets {
    /// Create targets of `size` pixels in `format` (use [`COLOR_FORMAT`] unless you need another).
    pub fn new(
        ctx: &GpuContext,
        size: [u32; 2],
        format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let max = ctx.caps.max_texture_2d;
        if size[0] == 0 || size[1] == 0 || size[0] > max || size[1] > max {
            return Err(RenderError::Invalid(format!(
                "target size {}x{} is outside 1..={max}",
                size[0], size[1]
            )));
        }
        let extent = wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        };
        ctx.scoped("creating offscreen targets", || {
            let color = ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("frame/offscreen/color"),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            let depth = ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("frame/offscreen/depth"),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            let color_view = color.create_view(&Default::default());
            let depth_view = depth.create_view(&Default::default());
            OffscreenTargets {
                color,
                depth,
                color_view,
                depth_view,
            }
        })
    }

    /// The views as [`Targets`].
    pub fn targets(&self) -> Targets<'_> {
        Targets {
            color: &self.color_view,
            depth: &self.depth_view,
        }
    }

    /// Size in pixels.
    pub fn size(&self) -> [u32; 2] {
        [self.color.width(), self.color.height()]
    }
}

/// A view of a new 2D texture of `size` and `format` that passes render into and later passes
/// read (`RENDER_ATTACHMENT | TEXTURE_BINDING`): the screen-sized intermediate layers.
pub(crate) fn screen_layer(
    ctx: &GpuContext,
    label: &str,
    size: [u32; 2],
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    ctx.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size[0],
                height: size[1],
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}
