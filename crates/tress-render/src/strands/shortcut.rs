//! The ShortCut buffers (`common/shortcut.wgsl`): per pixel `k` layers of depth keys (with a
//! claimed fragment's alpha) and `k - 1` of colors, the fragment counter, the tail's
//! transmittance target and its weighted color target. Their size is fixed by the target and
//! `k`, never by the hair: at 1280x720, 3.5 MiB a key layer and a color layer, 1.76 MiB of
//! transmittance and 7.0 MiB of tail color: 54.5 MiB at k = 7 and 61.5 MiB at k = 8 (the
//! default).

use crate::bind::{depth_texture, storage, texture_2d};
use crate::gpu::screen_layer;
use crate::gpu::types::PpllCounters;
use crate::{GpuContext, RenderError};

/// Largest ShortCut `k` (`MAX_SHORTCUT_K` in `common/shortcut.wgsl`).
pub const MAX_SHORTCUT_K: u32 = 16;

/// Format of the tail's transmittance target (multiplied into with `dst * (1 - src)`).
pub(crate) const TRANSMITTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// Format of the tail's weighted color target (`Σ w · color`, `Σ w`, added into).
pub(crate) const TAIL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Binding of the head's depth (depth and shade passes) in `common/shortcut.wgsl`'s group.
pub(crate) const HEAD_DEPTH: u32 = 3;
/// Binding of the transmittance texture (resolve pass).
pub(crate) const TRANSMITTANCE: u32 = 4;
/// Binding of the tail's weighted color (resolve pass).
pub(crate) const TAIL: u32 = 6;

/// Bytes ShortCut needs for a target of `size` with `k` layers: 4 bytes a key layer and a
/// color layer a pixel (`k` keys, `k - 1` colors: the k-th nearest opens the tail), 2 of
/// transmittance and 8 of tail color a pixel (plus 16 bytes of counters).
pub fn shortcut_bytes(size: [u32; 2], k: u32) -> u64 {
    let pixels = u64::from(size[0]) * u64::from(size[1]);
    let k = k.clamp(1, MAX_SHORTCUT_K);
    key_bytes(pixels, k)
        + color_bytes(pixels, k)
        + pixels * target_texel_bytes()
        + std::mem::size_of::<PpllCounters>() as u64
}

/// Bytes of `k` key layers of `pixels`.
fn key_bytes(pixels: u64, k: u32) -> u64 {
    pixels * 4 * u64::from(k)
}

/// Bytes of the `k - 1` color layers of `pixels` (one word when there are none: a binding is
/// never empty).
fn color_bytes(pixels: u64, k: u32) -> u64 {
    (pixels * 4 * u64::from(k - 1)).max(4)
}

/// Bytes a pixel of the transmittance and tail targets take.
fn target_texel_bytes() -> u64 {
    [TRANSMITTANCE_FORMAT, TAIL_FORMAT]
        .iter()
        .map(|f| u64::from(f.block_copy_size(None).unwrap_or(0)))
        .sum()
}

/// The layout of the depth and shade passes' group 3: keys, colors, counters, head depth.
pub(crate) fn raster_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    vec![
        storage(0, fragment, false),
        storage(1, fragment, false),
        storage(2, fragment, false),
        depth_texture(HEAD_DEPTH, fragment),
    ]
}

/// The layout of the resolve pass's group 3: keys, colors, transmittance, tail color.
pub(crate) fn resolve_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    vec![
        storage(0, fragment, false),
        storage(1, fragment, false),
        texture_2d(TRANSMITTANCE, fragment),
        texture_2d(TAIL, fragment),
    ]
}

/// ShortCut's per-target buffers.
#[derive(Debug)]
pub(crate) struct ShortcutBuffers {
    pub(crate) keys: wgpu::Buffer,
    pub(crate) colors: wgpu::Buffer,
    pub(crate) counters: wgpu::Buffer,
    pub(crate) transmittance: wgpu::TextureView,
    /// The tail's weighted color: `Σ w · color` in rgb, `Σ w` in alpha.
    pub(crate) tail: wgpu::TextureView,
    pub(crate) size: [u32; 2],
    pub(crate) k: u32,
}

impl ShortcutBuffers {
    pub(crate) fn new(ctx: &GpuContext, size: [u32; 2], k: u32) -> Result<Self, RenderError> {
        let k = k.clamp(1, MAX_SHORTCUT_K);
        let pixels = u64::from(size[0]) * u64::from(size[1]);
        let layer_bytes = key_bytes(pixels, k);
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        if layer_bytes > limit {
            return Err(RenderError::Limit {
                what: format!(
                    "ShortCut's {k} layers of a {}x{} target (lower strands.shortcut_k)",
                    size[0], size[1]
                ),
                needed: layer_bytes,
                limit,
            });
        }
        ctx.scoped("allocating the ShortCut buffers", || {
            let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
            let buffer = |label: &str, size: u64, usage| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let texture = |label: &str, format| screen_layer(ctx, label, size, format);
            ShortcutBuffers {
                keys: buffer("strands/shortcut/keys", layer_bytes, storage),
                colors: buffer("strands/shortcut/colors", color_bytes(pixels, k), storage),
                counters: buffer(
                    "strands/shortcut/counters",
                    std::mem::size_of::<PpllCounters>() as u64,
                    storage | wgpu::BufferUsages::COPY_SRC,
                ),
                transmittance: texture("strands/shortcut/transmittance", TRANSMITTANCE_FORMAT),
                tail: texture("strands/shortcut/tail", TAIL_FORMAT),
                size,
                k,
            }
        })
    }

    /// Bytes of the layers, the tail targets and the counters, as
    /// allocated (the figure `shortcut_bytes` predicts).
    pub(crate) fn bytes(&self) -> u64 {
        let buffers = [&self.keys, &self.colors, &self.counters];
        let pixels = u64::from(self.size[0]) * u64::from(self.size[1]);
        buffers.iter().map(|b| b.size()).sum::<u64>() + pixels * target_texel_bytes()
    }

    /// Empty every layer and zero the counters (start of the depth pass).
    pub(crate) fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.keys, 0, None);
        encoder.clear_buffer(&self.counters, 0, None);
    }

    /// Group 3 of the depth and shade passes.
    pub(crate) fn raster_group(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        head_depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        crate::bind::bind_group(
            ctx,
            "strands/shortcut/raster-bind-group",
            layout,
            &[
                (0, self.keys.as_entire_binding()),
                (1, self.colors.as_entire_binding()),
                (2, self.counters.as_entire_binding()),
                (HEAD_DEPTH, wgpu::BindingResource::TextureView(head_depth)),
            ],
        )
    }

    /// Group 3 of the resolve pass.
    pub(crate) fn resolve_group(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
    ) -> wgpu::BindGroup {
        crate::bind::bind_group(
            ctx,
            "strands/shortcut/resolve-bind-group",
            layout,
            &[
                (0, self.keys.as_entire_binding()),
                (1, self.colors.as_entire_binding()),
                (
                    TRANSMITTANCE,
                    wgpu::BindingResource::TextureView(&self.transmittance),
                ),
                (TAIL, wgpu::BindingResource::TextureView(&self.tail)),
            ],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_is_fixed_by_the_screen_and_k_within_64_mib_at_720p() {
        let mib = |k| shortcut_bytes([1280, 720], k) as f64 / f64::from(1 << 20);
        for k in 4..=8 {
            assert!(mib(k) <= 64.0, "k = {k}: {} MiB", mib(k));
        }
        assert!(mib(4) < mib(8));
        // Per pixel: 8 keys and 7 colors (4 bytes each), an R16Float transmittance (2) and an
        // Rgba16Float tail (8); 16 bytes of counters.
        assert_eq!(
            shortcut_bytes([1280, 720], 8),
            1280 * 720 * (8 * 4 + 7 * 4 + 2 + 8) + 16
        );
        // k = 1: one key layer and no color layer (a one-word binding).
        assert_eq!(shortcut_bytes([2, 2], 1), 4 * (4 + 10) + 4 + 16);
    }
}
