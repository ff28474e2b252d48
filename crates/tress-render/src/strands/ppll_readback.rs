//! Reading the PPLL's lists back after a frame ([`crate::Renderer::ppll_fragments`]): every
//! fragment the build pass stored, per pixel, for CPU composites that check or replace the
//! k-buffer resolve (the exact sorted composite of a whole frame, `tress render --exact-oit`).

use glam::Vec3;
use tress_shading::{StrandFragment, resolve_k_buffer};

use crate::gpu::types::PpllNode;
use crate::gpu::{LinearImage, read_whole_buffer};
use crate::strands::ppll::PpllPool;
use crate::{GpuContext, RenderError};

/// A frame's PPLL fragments: pixel `p` (row-major, `size[0]` wide) holds
/// `fragments[offsets[p]..offsets[p + 1]]`, in list order (last drawn first).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PpllFragments {
    /// The target's size.
    pub size: [u32; 2],
    /// `size[0] * size[1] + 1` offsets into `fragments`.
    pub offsets: Vec<usize>,
    /// Every stored fragment, colors decoded from RGB9E5.
    pub fragments: Vec<StrandFragment>,
}

impl PpllFragments {
    /// The fragments of pixel `(x, y)`.
    pub fn pixel(&self, x: u32, y: u32) -> &[StrandFragment] {
        let p = y as usize * self.size[0] as usize + x as usize;
        &self.fragments[self.offsets[p]..self.offsets[p + 1]]
    }

    /// Turn `image`, the frame the PPLL's k-buffer resolve drew with these fragments (`k` of
    /// them sorted), into the frame exact sorted compositing draws: each pixel gets
    /// `frame - kbuffer + sorted`, the k-buffer's composite over black
    /// ([`resolve_k_buffer`], the resolve's CPU twin) replaced by every fragment blended in
    /// depth order. The two have the same total opacity, so what lies under the hair (head,
    /// background) stays as the GPU drew it.
    pub fn sort_exactly(&self, image: &mut LinearImage, k: usize) {
        for y in 0..image.height.min(self.size[1]) {
            for x in 0..image.width.min(self.size[0]) {
                let f = self.pixel(x, y);
                if f.is_empty() {
                    continue;
                }
                let drawn = resolve_k_buffer(f, k, Vec3::ZERO);
                let sorted = resolve_k_buffer(f, f.len(), Vec3::ZERO);
                let p = &mut image.pixels[(y * image.width + x) as usize];
                for c in 0..3 {
                    p[c] = (p[c] + sorted[c] - drawn[c]).max(0.0);
                }
            }
        }
    }
}

/// `unpack_rgb9e5` of `common/ppll.wgsl`.
pub fn unpack_rgb9e5(v: u32) -> glam::Vec3 {
    let scale = 2f32.powi((v >> 27) as i32 - 24);
    glam::Vec3::new(
        (v & 511) as f32,
        ((v >> 9) & 511) as f32,
        ((v >> 18) & 511) as f32,
    ) * scale
}

/// Every stored fragment of `pool`'s last frame. A list that points outside the nodes or runs
/// longer than the pool (a damaged pool) is an error, never a hang.
pub(crate) fn read_fragments(
    ctx: &GpuContext,
    pool: &PpllPool,
) -> Result<PpllFragments, RenderError> {
    let heads: Vec<u32> = bytemuck::pod_collect_to_vec(&read_whole_buffer(
        ctx,
        &pool.heads,
        "strands/ppll/readback",
    )?);
    let mut nodes: Vec<PpllNode> = Vec::new();
    for chunk in &pool.nodes {
        let bytes = read_whole_buffer(ctx, chunk, "strands/ppll/readback")?;
        nodes.extend(bytemuck::pod_collect_to_vec::<u8, PpllNode>(&bytes));
    }
    // Chunk c holds nodes c * nodes_per_chunk.. and every chunk but the last in use is full, so
    // the chunks one after another are the node array (a chunk past the capacity holds one
    // unused node, past every index).
    nodes.truncate(pool.capacity as usize);
    let pixels = pool.size[0] as usize * pool.size[1] as usize;
    let mut out = PpllFragments {
        size: pool.size,
        offsets: Vec::with_capacity(pixels + 1),
        fragments: Vec::new(),
    };
    for &head in heads.iter().take(pixels) {
        out.offsets.push(out.fragments.len());
        let (mut next, mut walked) = (head, 0usize);
        while next != 0 {
            let n = nodes
                .get(next as usize - 1)
                .filter(|_| walked < nodes.len())
                .ok_or_else(|| RenderError::Readback("a damaged PPLL list".into()))?;
            out.fragments.push(StrandFragment {
                color: unpack_rgb9e5(n.color),
                alpha: n.alpha,
                depth: n.depth,
            });
            next = n.next;
            walked += 1;
        }
    }
    out.offsets.push(out.fragments.len());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frag(c: [f32; 3], alpha: f32, depth: f32) -> StrandFragment {
        StrandFragment {
            color: Vec3::from(c),
            alpha,
            depth,
        }
    }

    #[test]
    fn a_pixel_gets_the_sorted_composite_over_what_lay_under_it() {
        // One pixel, three fragments; the "GPU" frame is the k = 1 resolve over a background.
        let bg = Vec3::new(0.2, 0.3, 0.4);
        let f = vec![
            frag([1.0, 0.0, 0.0], 0.5, 0.3),
            frag([0.0, 1.0, 0.0], 0.4, 0.1),
            frag([0.0, 0.0, 1.0], 0.6, 0.2),
        ];
        let drawn = resolve_k_buffer(&f, 1, bg);
        let mut image = LinearImage {
            width: 1,
            height: 1,
            pixels: vec![[drawn.x, drawn.y, drawn.z, 1.0]],
        };
        let fragments = PpllFragments {
            size: [1, 1],
            offsets: vec![0, 3],
            fragments: f.clone(),
        };
        fragments.sort_exactly(&mut image, 1);
        // Independent: back to front over the background, farthest first.
        let want = [f[0], f[2], f[1]]
            .iter()
            .fold(bg, |dst, x| x.alpha * x.color + (1.0 - x.alpha) * dst);
        let got = Vec3::from_slice(&image.pixels[0][..3]);
        assert!((got - want).abs().max_element() < 1e-5, "{got} vs {want}");
        assert!((drawn - want).abs().max_element() > 0.01, "k = 1 differs");
    }

    #[test]
    fn rgb9e5_unpacks_like_the_shader() {
        // exponent 15 + 9 = 24 -> scale 1: mantissas are the values.
        let v = 3 | (200 << 9) | (511 << 18) | (24 << 27);
        assert_eq!(unpack_rgb9e5(v), Vec3::new(3.0, 200.0, 511.0));
        assert_eq!(unpack_rgb9e5(256 | (16 << 27)), Vec3::new(1.0, 0.0, 0.0));
    }
}
