//! The GPU core: context and capability checks, render targets, readback to PNG/EXR, timestamp
//! queries, the GPU-visible struct types and the pipeline builders the passes share.

mod context;
pub(crate) mod light_maps;
pub(crate) mod pipeline;
mod readback;
mod target;
mod timer;
pub mod types;

pub use context::{
    ADAPTER_ENV, Capabilities, ContextOptions, GpuContext, MIN_STORAGE_BINDING_BYTES,
    MIN_STORAGE_BUFFERS_PER_STAGE, check_capabilities,
};
pub(crate) use readback::read_texture_bytes;
pub use readback::{
    LinearImage, f16_to_f32, linear_to_srgb, read_buffer, read_texture, read_whole_buffer,
    srgb_to_linear,
};
pub use target::{COLOR_FORMAT, DEPTH_FORMAT, OffscreenTargets, TargetFormats, Targets};
pub(crate) use target::{clear_loads, screen_layer};
pub(crate) use timer::{FrameEncoder, GpuTimer, TimerMode};
pub use timer::{PassTiming, Timings};

/// A uniform buffer holding `value`, writable by the queue.
pub(crate) fn uniform_buffer<T: bytemuck::Pod>(
    ctx: &GpuContext,
    label: &str,
    value: &T,
) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::bytes_of(value),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        })
}

/// Bytes a texture's texels take (every mip level and array layer; depth formats by their
/// depth aspect). The driver may pad; this is the logical size.
pub fn texture_bytes(t: &wgpu::Texture) -> u64 {
    let format = t.format();
    let texel = format
        .block_copy_size(None)
        .or_else(|| format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)))
        .unwrap_or(4);
    let texels: u64 = (0..t.mip_level_count())
        .map(|m| {
            let s = t.size().mip_level_size(m, t.dimension());
            u64::from(s.width) * u64::from(s.height) * u64::from(s.depth_or_array_layers)
        })
        .sum();
    texels * u64::from(texel)
}
