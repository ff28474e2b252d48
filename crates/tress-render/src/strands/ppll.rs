//! The PPLL buffers: per-pixel heads, the node pool and its counters, with the pool's sizing
//! policy (initial size, cap, growth after a frame that dropped fragments).

use crate::gpu::types::{PpllCounters, PpllNode};
use crate::{GpuContext, RenderError};

/// Bytes per PPLL node.
pub const NODE_BYTES: u64 = std::mem::size_of::<PpllNode>() as u64;

/// Growth factor applied to the nodes requested by a frame that overflowed.
const GROWTH: f64 = 1.25;

/// PPLL occupancy and memory of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PpllStats {
    /// Node capacity of the pool.
    pub capacity: u32,
    /// Nodes written (`min(requested, capacity)`).
    pub used: u32,
    /// Fragments that asked for a node (including those dropped).
    pub requested: u32,
    /// Fragments dropped because the pool was full.
    pub dropped: u32,
    /// Bytes of the node pool.
    pub node_bytes: u64,
    /// Bytes of the per-pixel head buffer.
    pub head_bytes: u64,
}

impl PpllStats {
    /// From the counters read back and the pool's size.
    pub(crate) fn from_counters(c: PpllCounters, capacity: u32, head_bytes: u64) -> Self {
        PpllStats {
            capacity,
            used: c.requested.min(capacity),
            requested: c.requested,
            dropped: c.dropped,
            node_bytes: u64::from(capacity) * NODE_BYTES,
            head_bytes,
        }
    }
}

/// The node capacity for a target of `pixels`: `nodes_per_pixel * pixels`, at least one node, at
/// most `cap_nodes`.
pub(crate) fn initial_capacity(pixels: u64, nodes_per_pixel: f32, cap_nodes: u32) -> u32 {
    let want = (pixels as f64 * f64::from(nodes_per_pixel)).ceil();
    (want.min(f64::from(cap_nodes)) as u32).max(1)
}

/// The capacity after a frame that requested `requested` nodes with `capacity`: grown when it
/// overflowed, else unchanged.
pub(crate) fn grown_capacity(capacity: u32, requested: u32, cap_nodes: u32) -> u32 {
    if requested <= capacity {
        return capacity;
    }
    let want = (f64::from(requested) * GROWTH)
        .ceil()
        .min(f64::from(cap_nodes)) as u32;
    want.max(capacity)
}

/// Storage buffers the node pool may span (`NODE_CHUNKS` in `common/ppll_pool.wgsl`): with
/// lavapipe's 128 MiB bindings, a pool of up to 512 MiB (33.5M nodes).
pub const NODE_CHUNKS: usize = 4;

/// The PPLL buffers of one target size.
#[derive(Debug)]
pub(crate) struct PpllPool {
    pub(crate) heads: wgpu::Buffer,
    /// [`NODE_CHUNKS`] buffers; chunk `c` holds nodes `c * nodes_per_chunk ..`. Chunks the
    /// capacity does not reach are one-node placeholders (every binding must exist).
    pub(crate) nodes: Vec<wgpu::Buffer>,
    pub(crate) counters: wgpu::Buffer,
    pub(crate) size: [u32; 2],
    pub(crate) capacity: u32,
    pub(crate) nodes_per_chunk: u32,
}

impl PpllPool {
    /// Nodes one storage binding of the device holds.
    pub(crate) fn nodes_per_chunk(ctx: &GpuContext) -> u32 {
        let binding = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        (binding / NODE_BYTES).clamp(1, u64::from(u32::MAX - 1)) as u32
    }

    /// Largest node count allowed by the settings' cap and the device ([`NODE_CHUNKS`]
    /// bindings of the device's largest storage binding).
    pub(crate) fn cap_nodes(ctx: &GpuContext, max_bytes: u64) -> u32 {
        let device = u64::from(Self::nodes_per_chunk(ctx)) * NODE_CHUNKS as u64;
        (max_bytes / NODE_BYTES)
            .min(device)
            .min(u64::from(u32::MAX - 1)) as u32
    }

    pub(crate) fn head_bytes(size: [u32; 2]) -> u64 {
        u64::from(size[0]) * u64::from(size[1]) * 4
    }

    /// Bytes of the nodes and heads.
    pub(crate) fn bytes(&self) -> u64 {
        u64::from(self.capacity) * NODE_BYTES + Self::head_bytes(self.size)
    }

    pub(crate) fn new(
        ctx: &GpuContext,
        size: [u32; 2],
        capacity: u32,
    ) -> Result<Self, RenderError> {
        let head_bytes = Self::head_bytes(size);
        let limit = ctx.caps.max_storage_binding.min(ctx.caps.max_buffer_size);
        if head_bytes > limit {
            return Err(RenderError::Limit {
                what: format!("the PPLL head buffer of a {}x{} target", size[0], size[1]),
                needed: head_bytes,
                limit,
            });
        }
        let capacity = capacity.max(1);
        let per_chunk = Self::nodes_per_chunk(ctx);
        let chunks = capacity.div_ceil(per_chunk) as usize;
        if chunks > NODE_CHUNKS {
            return Err(RenderError::Limit {
                what: format!("the PPLL node pool ({NODE_CHUNKS} storage bindings)"),
                needed: u64::from(capacity) * NODE_BYTES,
                limit: u64::from(per_chunk) * NODE_CHUNKS as u64 * NODE_BYTES,
            });
        }
        ctx.scoped("allocating the PPLL", || {
            let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
            // COPY_SRC: `Renderer::ppll_fragments` reads the lists back.
            let storage = storage | wgpu::BufferUsages::COPY_SRC;
            let buffer = |label: &str, size: u64, usage| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let nodes = (0..NODE_CHUNKS as u32)
                .map(|c| {
                    let first = c.saturating_mul(per_chunk);
                    let count = capacity.saturating_sub(first).min(per_chunk).max(1);
                    buffer(
                        &format!("strands/ppll/nodes-{c}"),
                        u64::from(count) * NODE_BYTES,
                        storage,
                    )
                })
                .collect();
            PpllPool {
                heads: buffer("strands/ppll/heads", head_bytes, storage),
                nodes,
                counters: buffer(
                    "strands/ppll/counters",
                    std::mem::size_of::<PpllCounters>() as u64,
                    storage | wgpu::BufferUsages::COPY_SRC,
                ),
                size,
                capacity,
                nodes_per_chunk: per_chunk,
            }
        })
    }

    /// The pool's bindings 0..=5 of `common/ppll_pool.wgsl` (heads, counters, node chunks).
    pub(crate) fn entries(&self) -> Vec<(u32, wgpu::BindingResource<'_>)> {
        let mut e = vec![
            (0, self.heads.as_entire_binding()),
            (1, self.counters.as_entire_binding()),
        ];
        e.extend(
            self.nodes
                .iter()
                .enumerate()
                .map(|(c, b)| (2 + c as u32, b.as_entire_binding())),
        );
        e
    }

    /// Reset heads to empty lists and the counters to zero (start of the build pass).
    pub(crate) fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.heads, 0, None);
        encoder.clear_buffer(&self.counters, 0, None);
    }
}

/// The layout entries of `common/ppll_pool.wgsl`'s bindings, visible to the fragment stage.
pub(crate) fn pool_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    (0..2 + NODE_CHUNKS as u32)
        .map(|b| crate::bind::storage(b, wgpu::ShaderStages::FRAGMENT, false))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capacity_policy() {
        assert_eq!(initial_capacity(100, 8.0, 1000), 800);
        assert_eq!(initial_capacity(1000, 8.0, 1000), 1000);
        assert_eq!(initial_capacity(0, 8.0, 1000), 1);
        assert_eq!(grown_capacity(800, 700, 10_000), 800);
        assert_eq!(grown_capacity(800, 1000, 10_000), 1250);
        assert_eq!(grown_capacity(800, 1000, 900), 900);
        assert_eq!(grown_capacity(800, 1000, 500), 800);
    }

    #[test]
    fn stats_clamp_used_to_capacity() {
        let c = PpllCounters {
            requested: 120,
            dropped: 20,
            tail: 0,
            _pad1: 0,
        };
        let s = PpllStats::from_counters(c, 100, 64);
        assert_eq!((s.used, s.dropped, s.node_bytes), (100, 20, 1600));
    }
}
