//! Strand voxelization, the CPU reference of `tress-render`'s `volume/voxelize.wgsl` and
//! `volume/volume_resolve.wgsl` (Jansson et al. 2019 §3.3, "Strand Voxelization").
//!
//! The hair is turned into two volumes over a grid fitted to its bounding box: a *density* volume
//! (how many strands pass through each voxel) and a *tangent* volume (their mean direction).
//!
//! # Grid
//!
//! [`VoxelGrid::fit`] puts a `res³` grid of cubic voxels around the hair's axis-aligned bounding
//! box: the longest side spans `res - 2 · GRID_PAD` voxels and the box is centred, so at least
//! [`GRID_PAD`] empty voxels surround the hair on every side (trilinear sampling and central
//! differences at the hair's edge then read empty voxels instead of clamping into hair). World
//! positions map to voxel coordinates by `(p - origin) · scale`; voxel `(i, j, k)` covers
//! `[i, i + 1) × [j, j + 1) × [k, k + 1)` and its index is `i + res · (j + res · k)`.
//!
//! # Exactness
//!
//! Positions are converted once to fixed point, [`SUBVOXEL`] steps per voxel
//! ([`VoxelGrid::fixed_point`]: one subtraction and one multiplication, both correctly rounded in
//! IEEE arithmetic and in Vulkan), and everything after that is integer arithmetic. So the GPU
//! voxelizer and this reference agree *exactly* on which voxels every sample lands in, given the
//! same grid; the test `tests/volume_voxelize.rs` of `tress-render` checks it.
//!
//! # Modes
//!
//! - [`VoxelizeMode::Vertices`], the paper's: every strand vertex adds one to the counter of the
//!   voxel it falls in. Segments longer than a voxel leave gaps (§4.2), which the paper covers
//!   with a reconstruction filter; here that is a box filter of radius
//!   `reconstruction_radius` in the resolve ([`resolve`]), scaled by the mean segment length in
//!   voxels so that one vertex stands for the strand length it represents and the density keeps
//!   the unit of the segments mode (strand length per voxel, in voxel edges).
//! - [`VoxelizeMode::Segments`]: every segment is sampled at voxel frequency — the remedy §4.2
//!   suggests. A segment `len` voxels long gets `floor(len)` samples plus one more with
//!   probability `frac(len)` (a fixed hash of the segment index decides, so the result is
//!   deterministic), spaced evenly at the midpoints of equal sub-intervals. The expected number of
//!   samples in a voxel is then exactly the strand length inside it in voxel edges: a strand
//!   crossing a voxel counts about once, whatever the segment length, and no voxel on a strand's
//!   path is skipped when segments are long.
//!
//! # Tangents and capacity
//!
//! Each sample's unit tangent is quantized from `[-1, 1]` to `[0, 255]` per channel
//! ([`quantize_tangent`]) and summed; the resolve divides the sums by the count and de-quantizes
//! ([`dequantize_tangent`]) to the mean tangent (§3.3, Figure 4). Counters hold at most
//! `cap` strands per voxel (the paper's 8-bit counter: 255): a sample that finds its voxel's
//! counter at or above the cap is *dropped* (its tangent is not added) and counted (design rule 8).
//! The 16-bit tangent sums cannot overflow below that cap.

use glam::{IVec3, UVec3, Vec3};

use crate::highlights::{HighlightView, highlight_texel, quantize_highlight, segment_highlights};

/// Empty voxels kept around the hair's bounding box on its longest side.
pub const GRID_PAD: u32 = 2;
/// Fixed-point steps per voxel edge.
pub const SUBVOXEL: u32 = 16;
/// log2 of [`SUBVOXEL`].
pub const SUBVOXEL_BITS: u32 = 4;
/// Smallest grid resolution.
pub const MIN_RESOLUTION: u32 = 8;
/// Largest grid resolution (keeps the fixed-point arithmetic inside 32 bits).
pub const MAX_RESOLUTION: u32 = 1024;
/// Largest per-voxel counter capacity (the tangent sums are 16 bits per channel).
pub const MAX_CAPACITY: u32 = 255;
/// Quantization levels of a tangent channel.
pub const TANGENT_LEVELS: f32 = 255.0;

/// How strands are deposited into the grid (module docs: Modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VoxelizeMode {
    /// One count per vertex (Jansson §3.3), gaps covered by the resolve's reconstruction filter.
    Vertices,
    /// Every segment sampled at voxel frequency (the remedy Jansson §4.2 suggests).
    #[default]
    Segments,
}

/// A `res³` grid of cubic voxels (module docs: Grid).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelGrid {
    /// World position of the corner of voxel `(0, 0, 0)`.
    pub origin: Vec3,
    /// Voxels per world unit.
    pub scale: f32,
    /// World length of a voxel edge.
    pub voxel_size: f32,
    /// The hair's bounding box, minimum corner.
    pub bounds_min: Vec3,
    /// The hair's bounding box, maximum corner.
    pub bounds_max: Vec3,
    /// Voxels per axis.
    pub res: u32,
}

impl VoxelGrid {
    /// The grid around the box `[bounds_min, bounds_max]` (module docs: Grid). The WGSL twin is
    /// `fit` in `volume/volume_bounds.wgsl`; the operations are the same, in the same order.
    pub fn fit(bounds_min: Vec3, bounds_max: Vec3, res: u32) -> VoxelGrid {
        let extent = bounds_max - bounds_min;
        let longest = extent.x.max(extent.y).max(extent.z.max(1e-6));
        let inner = (res - 2 * GRID_PAD) as f32;
        let voxel_size = longest / inner;
        let scale = inner / longest;
        let center = (bounds_min + bounds_max) * 0.5;
        let origin = center - Vec3::splat(voxel_size * (res as f32 * 0.5));
        VoxelGrid {
            origin,
            scale,
            voxel_size,
            bounds_min,
            bounds_max,
            res,
        }
    }

    /// Number of voxels, `res³`.
    pub fn voxel_count(&self) -> usize {
        (self.res as usize).pow(3)
    }

    /// Continuous voxel coordinates of a world point.
    pub fn voxel_from_world(&self, p: Vec3) -> Vec3 {
        (p - self.origin) * self.scale
    }

    /// Fixed-point voxel coordinates of a world point, [`SUBVOXEL`] steps per voxel, clamped to
    /// the grid.
    pub fn fixed_point(&self, p: Vec3) -> UVec3 {
        let f = (p - self.origin) * (self.scale * SUBVOXEL as f32);
        let hi = (self.res * SUBVOXEL - 1) as f32;
        let c = |x: f32| x.floor().clamp(0.0, hi) as u32;
        UVec3::new(c(f.x), c(f.y), c(f.z))
    }

    /// Linear index of a voxel, `x + res · (y + res · z)`.
    pub fn index(&self, v: UVec3) -> usize {
        let r = self.res as usize;
        v.x as usize + r * (v.y as usize + r * v.z as usize)
    }
}

/// A well-mixed 32-bit hash (PCG output permutation); WGSL twin `voxel_hash`.
pub fn voxel_hash(x: u32) -> u32 {
    let h = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let h = ((h >> ((h >> 28) + 4)) ^ h).wrapping_mul(277_803_737);
    (h >> 22) ^ h
}

/// `floor(sqrt(x))` exactly, from a float estimate corrected in integers, for `x < 65535²` (the
/// voxelizer's squared lengths stay below `3 · (1024 · 16)²`); WGSL twin `isqrt`.
pub fn isqrt(x: u32) -> u32 {
    let mut r = (x as f32).sqrt() as u32;
    while r > 0 && r * r > x {
        r -= 1;
    }
    while (r + 1) * (r + 1) <= x {
        r += 1;
    }
    r
}

/// A unit tangent quantized from `[-1, 1]` to `[0, 255]` per channel, `floor(x · 255 + 0.5)` of
/// `x = saturate(t / 2 + 1/2)`; WGSL twin `quantize_tangent`.
pub fn quantize_tangent(t: Vec3) -> UVec3 {
    let q = |c: f32| ((c * 0.5 + 0.5).clamp(0.0, 1.0) * TANGENT_LEVELS + 0.5).floor() as u32;
    UVec3::new(q(t.x), q(t.y), q(t.z))
}

/// The mean tangent from quantized sums over `count` samples: `(sum / count) / 255 · 2 - 1`
/// (Jansson §3.3); zero for `count = 0`. WGSL twin `dequantize_tangent`.
pub fn dequantize_tangent(sum: Vec3, count: f32) -> Vec3 {
    if count <= 0.0 {
        return Vec3::ZERO;
    }
    sum / count / TANGENT_LEVELS * 2.0 - Vec3::ONE
}

/// The texel byte that holds a zero tangent component (`encode_texel`).
pub const TEXEL_TANGENT_ZERO: f32 = 128.0;
/// Texel levels per unit of tangent (`encode_texel`).
pub const TEXEL_TANGENT_SCALE: f32 = 127.0;
/// The most counts a texel holds.
pub const TEXEL_MAX_COUNT: u32 = 255;

/// The volume texture's texel of a voxel (`rgba8unorm`, 4 bytes; WGSL twin `encode_texel`): rgb
/// the mean tangent `t` as `u = t / |t|^(2/3)` (so `|u| = |t|^(1/3)`), each channel
/// `128 + floor(127 u + 1/2)` (zero exact), a the count clamped to 255. A short mean tangent
/// (spread directions, the faded tips of fur) keeps its direction to about a degree, where a
/// linear 8-bit store turned it by about ten and streaked the fur's highlights. The raymarcher
/// decodes the eight texels around a point ([`decode_texel`]) and filters the values.
pub fn encode_texel(tangent: Vec3, count: u32) -> [u8; 4] {
    let len = tangent.length();
    let u = if len > 0.0 {
        tangent * len.max(1e-30).powf(-2.0 / 3.0)
    } else {
        Vec3::ZERO
    };
    let t = |c: f32| {
        (TEXEL_TANGENT_ZERO + (c.clamp(-1.0, 1.0) * TEXEL_TANGENT_SCALE + 0.5).floor()) as u8
    };
    [t(u.x), t(u.y), t(u.z), count.min(TEXEL_MAX_COUNT) as u8]
}

/// A texel as the mean tangent and the density, the count times `density_unit` (WGSL twin
/// `decode_texel`, which gets the texel normalized). A texel without strands has no tangent,
/// whatever its rgb: the resolve writes zero bytes outside the hair's box, as does a new texture.
pub fn decode_texel(bytes: [u8; 4], density_unit: f32) -> (Vec3, f32) {
    if bytes[3] == 0 {
        return (Vec3::ZERO, 0.0);
    }
    let u = |b: u8| (f32::from(b) - TEXEL_TANGENT_ZERO) / TEXEL_TANGENT_SCALE;
    let u = Vec3::new(u(bytes[0]), u(bytes[1]), u(bytes[2]));
    (u * u.length_squared(), f32::from(bytes[3]) * density_unit)
}

/// Unit direction of a segment, `(0, 1, 0)` for a degenerate one (as `strand.wgsl`).
pub fn segment_tangent(p0: Vec3, p1: Vec3) -> Vec3 {
    let d = p1 - p0;
    let len = d.length();
    if len > 1e-20 { d / len } else { Vec3::Y }
}

/// The fixed-point sample positions of segment number `segment` from `q0` to `q1` in the
/// segments mode (module docs: Modes); WGSL twin `segment_sample_count` / `segment_sample`.
pub fn segment_samples(q0: UVec3, q1: UVec3, segment: u32) -> impl Iterator<Item = UVec3> {
    let n = segment_sample_count(q0, q1, segment);
    let (a, d) = (q0.as_ivec3(), q1.as_ivec3() - q0.as_ivec3());
    (0..n).map(move |k| segment_sample(a, d, k, n))
}

/// How many samples a segment gets: `floor(len) + (frac(len) > hash)`, `len` in voxels at
/// [`SUBVOXEL`] precision.
pub fn segment_sample_count(q0: UVec3, q1: UVec3, segment: u32) -> u32 {
    let d = q1.as_ivec3() - q0.as_ivec3();
    let d2 = (d.x * d.x + d.y * d.y + d.z * d.z) as u32;
    let len = isqrt(d2);
    let mut n = len >> SUBVOXEL_BITS;
    if (len & (SUBVOXEL - 1)) > (voxel_hash(segment) & (SUBVOXEL - 1)) {
        n += 1;
    }
    n
}

/// Sample `k` of `n`: `a + d · (2k + 1) / 2n` in integers (the point lies between the ends, so
/// the numerator is non-negative and the division floors).
pub fn segment_sample(a: IVec3, d: IVec3, k: u32, n: u32) -> UVec3 {
    let two_n = 2 * n as i32;
    let num = a * two_n + d * (2 * k as i32 + 1);
    (num / two_n).as_uvec3()
}

/// Raw counters of a voxelization (what the GPU's storage buffers hold before the resolve).
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelCounts {
    /// The grid.
    pub grid: VoxelGrid,
    /// Samples that reached each voxel (including dropped ones), `res³`.
    pub counts: Vec<u32>,
    /// Per voxel: quantized tangent sums of the accepted samples.
    pub tangent_sums: Vec<UVec3>,
    /// Per voxel: the accepted samples' quantized highlight sums, a light each
    /// ([`crate::highlights`]; zero without a [`HighlightView`]).
    pub highlight_sums: Vec<[u32; 4]>,
    /// Per voxel: the accepted samples' quantized tip fades, summed
    /// ([`crate::highlights::quantize_highlight`] of the fade: 255 a sample without fade).
    pub fade_sums: Vec<u32>,
    /// Samples deposited in all (accepted and dropped).
    pub deposits: u64,
    /// Samples dropped because their voxel's counter was at the capacity.
    pub dropped: u64,
}

impl VoxelCounts {
    fn new(grid: VoxelGrid) -> Self {
        let n = grid.voxel_count();
        VoxelCounts {
            grid,
            counts: vec![0; n],
            tangent_sums: vec![UVec3::ZERO; n],
            highlight_sums: vec![[0; 4]; n],
            fade_sums: vec![0; n],
            deposits: 0,
            dropped: 0,
        }
    }

    fn deposit(&mut self, q: UVec3, tangent: UVec3, (highlights, fade): ([u32; 4], u32), cap: u32) {
        let i = self.grid.index(q >> SUBVOXEL_BITS);
        let old = self.counts[i];
        self.counts[i] += 1;
        self.deposits += 1;
        if old >= cap {
            self.dropped += 1;
        } else {
            self.tangent_sums[i] += tangent;
            self.fade_sums[i] += fade;
            for (sum, h) in self.highlight_sums[i].iter_mut().zip(highlights) {
                *sum += h;
            }
        }
    }

    /// The counter of voxel `v` clamped to `cap` (what the resolve reads).
    pub fn clamped(&self, i: usize, cap: u32) -> u32 {
        self.counts[i].min(cap)
    }
}

/// The segments of strands given by `strand_offsets` (start of each strand, then the vertex
/// count): `(first vertex, strand)` pairs in order, as the renderer uploads them.
pub fn strand_segments(strand_offsets: &[u32]) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    for (s, w) in strand_offsets.windows(2).enumerate() {
        out.extend((w[0]..w[1].saturating_sub(1)).map(|v| [v, s as u32]));
    }
    out
}

/// The strands' tip fade of a segment: its mean vertex thickness over `reference` (the
/// thickness that fades nothing), saturated; WGSL twin in `volume/voxelize.wgsl`.
pub fn segment_fade(t0: f32, t1: f32, reference: f32) -> f32 {
    crate::saturate(0.5 * (t0 + t1) / reference)
}

/// Voxelize strands into `grid` (module docs). `segments` are `(first vertex, strand)` pairs
/// ([`strand_segments`]); `cap` is the per-voxel capacity, `1..=MAX_CAPACITY`. With `fade`
/// (per-vertex thickness and the thickness that fades nothing) each sample's tangent is weighed
/// by its segment's [`segment_fade`] before quantization, so a voxel's mean tangent has the length
/// of its strands' mean opacity fade (times their coherence): what the raymarcher weighs the
/// density with.
pub fn voxelize(
    positions: &[Vec3],
    segments: &[[u32; 2]],
    grid: &VoxelGrid,
    mode: VoxelizeMode,
    cap: u32,
    fade: Option<(&[f32], f32)>,
) -> VoxelCounts {
    voxelize_lit(positions, segments, grid, mode, cap, fade, None)
}

/// [`voxelize`], also summing every accepted sample's quantized highlights for `view`
/// ([`crate::highlights::segment_highlights`] of its segment) when one is given.
pub fn voxelize_lit(
    positions: &[Vec3],
    segments: &[[u32; 2]],
    grid: &VoxelGrid,
    mode: VoxelizeMode,
    cap: u32,
    fade: Option<(&[f32], f32)>,
    view: Option<&HighlightView>,
) -> VoxelCounts {
    let mut out = VoxelCounts::new(*grid);
    for (s, seg) in segments.iter().enumerate() {
        let (v0, v1) = (seg[0] as usize, seg[0] as usize + 1);
        let (p0, p1) = (positions[v0], positions[v1]);
        let w = fade.map_or(1.0, |(t, r)| segment_fade(t[v0], t[v1], r));
        let t = segment_tangent(p0, p1);
        let tq = quantize_tangent(t * w);
        let hq = (
            view.map_or([0; 4], |v| segment_highlights(v, p0, p1, t, w)),
            quantize_highlight(w),
        );
        let (q0, q1) = (grid.fixed_point(p0), grid.fixed_point(p1));
        match mode {
            VoxelizeMode::Segments => {
                for q in segment_samples(q0, q1, s as u32) {
                    out.deposit(q, tq, hq, cap);
                }
            }
            VoxelizeMode::Vertices => {
                out.deposit(q0, tq, hq, cap);
                let last = segments
                    .get(s + 1)
                    .is_none_or(|next| next[1] != seg[1] || next[0] != seg[0] + 1);
                if last {
                    out.deposit(q1, tq, hq, cap);
                }
            }
        }
    }
    out
}

/// What the resolve writes per voxel: the mean tangent (not normalized) and the density.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VoxelValue {
    /// De-quantized mean tangent.
    pub tangent: Vec3,
    /// Strand density (strand length in the voxel, in voxel edges).
    pub density: f32,
    /// The clamped counts summed over the filter's box (the voxel's count without a filter).
    pub count: u32,
    /// The highlight texel: each light's fade-weighted mean quantized highlight over the box
    /// ([`crate::highlights::highlight_texel`]).
    pub highlights: [u8; 4],
}

impl VoxelValue {
    /// The texel the resolve writes ([`encode_texel`]).
    pub fn texel(&self) -> [u8; 4] {
        encode_texel(self.tangent, self.count)
    }
}

/// The resolve of one voxel (WGSL `volume_resolve.wgsl`): with `radius = 0` the clamped count
/// times `weight` and the mean tangent of the voxel; with `radius > 0` the reconstruction filter,
/// the mean clamped count over the `(2r + 1)³` box (voxels outside the grid count as empty) times
/// `weight`, and the tangent sums of the box divided by its counts.
pub fn resolve(counts: &VoxelCounts, v: UVec3, radius: u32, weight: f32, cap: u32) -> VoxelValue {
    let g = &counts.grid;
    let r = radius as i32;
    let mut c = 0u32;
    let mut sum = UVec3::ZERO;
    let mut lit = [0u32; 4];
    let mut fades = 0u32;
    for dz in -r..=r {
        for dy in -r..=r {
            for dx in -r..=r {
                let n = v.as_ivec3() + IVec3::new(dx, dy, dz);
                if n.cmplt(IVec3::ZERO).any() || n.cmpge(IVec3::splat(g.res as i32)).any() {
                    continue;
                }
                let i = g.index(n.as_uvec3());
                c += counts.clamped(i, cap);
                sum += counts.tangent_sums[i];
                fades += counts.fade_sums[i];
                for (l, h) in lit.iter_mut().zip(counts.highlight_sums[i]) {
                    *l += h;
                }
            }
        }
    }
    let side = (2 * radius + 1) as f32;
    VoxelValue {
        tangent: dequantize_tangent(sum.as_vec3(), c as f32),
        density: c as f32 / (side * side * side) * weight,
        count: c,
        highlights: lit.map(|l| highlight_texel(l, fades)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> VoxelGrid {
        VoxelGrid::fit(Vec3::ZERO, Vec3::new(12.0, 6.0, 3.0), 16)
    }

    #[test]
    fn texels_keep_short_tangents_direction_and_the_count() {
        // Directions spread over the sphere, lengths from a faded tip's to a coherent voxel's.
        let mut worst_angle = [0.0f32; 3];
        for (k, len) in [0.05f32, 0.2, 1.0].into_iter().enumerate() {
            for i in 0..500 {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / 500.0;
                let phi = 2.399_963_3 * i as f32;
                let r = (1.0 - z * z).sqrt();
                let t = Vec3::new(r * phi.cos(), r * phi.sin(), z) * len;
                let (back, density) = decode_texel(encode_texel(t, 7), 0.5);
                assert_eq!(density, 3.5);
                let angle = back
                    .normalize()
                    .dot(t.normalize())
                    .min(1.0)
                    .acos()
                    .to_degrees();
                worst_angle[k] = worst_angle[k].max(angle);
                assert!(
                    (back.length() / len - 1.0).abs() < 0.06,
                    "{t}: {back} ({len})"
                );
            }
        }
        // About a degree at a twentieth of a unit tangent, where a linear 8-bit store of the
        // same tangent turns it by up to 7.8 degrees (half a level of 2/255 a channel).
        assert!(worst_angle[0] < 1.3, "{worst_angle:?}");
        assert!(worst_angle[2] < 0.4, "{worst_angle:?}");
        // Zero is exact; the count clamps at 255; a texel without strands has no tangent.
        assert_eq!(encode_texel(Vec3::ZERO, 0), [128, 128, 128, 0]);
        assert_eq!(encode_texel(Vec3::X, 300)[3], 255);
        assert_eq!(decode_texel([0, 0, 0, 0], 1.0), (Vec3::ZERO, 0.0));
        assert_eq!(
            decode_texel(encode_texel(Vec3::ZERO, 3), 1.0),
            (Vec3::ZERO, 3.0)
        );
    }

    #[test]
    fn fit_pads_and_centres_the_box() {
        let g = grid();
        assert!((g.voxel_size - 1.0).abs() < 1e-6 && (g.scale - 1.0).abs() < 1e-6);
        let lo = g.voxel_from_world(g.bounds_min);
        let hi = g.voxel_from_world(g.bounds_max);
        assert!((lo.x - GRID_PAD as f32).abs() < 1e-5, "{lo}");
        assert!((hi.x - (16 - GRID_PAD) as f32).abs() < 1e-5, "{hi}");
        // Shorter axes are centred.
        assert!(((lo.y + hi.y) * 0.5 - 8.0).abs() < 1e-5);
        // A point maps into the grid; outside points clamp.
        assert_eq!(g.fixed_point(Vec3::new(0.0, 0.0, 0.0)).x, 2 * SUBVOXEL);
        assert_eq!(g.fixed_point(Vec3::splat(-100.0)), UVec3::ZERO);
        assert_eq!(
            g.fixed_point(Vec3::splat(100.0)),
            UVec3::splat(16 * SUBVOXEL - 1)
        );
        // A degenerate box still makes a valid grid.
        let p = VoxelGrid::fit(Vec3::ONE, Vec3::ONE, 16);
        assert!(p.scale.is_finite() && p.scale > 0.0);
    }

    #[test]
    fn isqrt_is_exact() {
        for x in (0..5000).chain([
            805_306_368,
            805_306_367,
            65_534 * 65_534,
            65_535 * 65_535 - 1,
        ]) {
            let r = isqrt(x) as u64;
            assert!(r * r <= x as u64 && (r + 1) * (r + 1) > x as u64, "{x}");
        }
    }

    #[test]
    fn tangent_quantization_round_trips_within_half_a_level() {
        for t in [
            Vec3::X,
            Vec3::NEG_Y,
            Vec3::new(0.6, -0.8, 0.0),
            Vec3::splat(0.577_350_3),
        ] {
            let q = quantize_tangent(t);
            let back = dequantize_tangent(q.as_vec3(), 1.0);
            assert!(
                (back - t).abs().max_element() <= 1.0 / TANGENT_LEVELS + 1e-6,
                "{t} {back}"
            );
        }
        assert_eq!(quantize_tangent(Vec3::NEG_ONE), UVec3::ZERO);
        assert_eq!(quantize_tangent(Vec3::ONE), UVec3::splat(255));
        assert_eq!(dequantize_tangent(Vec3::ONE, 0.0), Vec3::ZERO);
        // The mean of two opposite-ish quantized tangents is their average.
        let s = (quantize_tangent(Vec3::X) + quantize_tangent(Vec3::Y)).as_vec3();
        let m = dequantize_tangent(s, 2.0);
        assert!(
            (m - Vec3::new(0.5, 0.5, 0.0)).abs().max_element() < 0.01,
            "{m}"
        );
    }

    #[test]
    fn segment_samples_are_about_one_per_voxel_and_on_the_segment() {
        let g = VoxelGrid::fit(Vec3::ZERO, Vec3::splat(60.0), 64);
        let (p0, p1) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(40.0, 30.0, 7.5));
        let (q0, q1) = (g.fixed_point(p0), g.fixed_point(p1));
        let len = g.voxel_from_world(p1).distance(g.voxel_from_world(p0));
        let mut total = 0.0;
        for seg in 0..64 {
            let samples: Vec<UVec3> = segment_samples(q0, q1, seg).collect();
            let n = samples.len() as f32;
            assert!(n == len.floor() || n == len.floor() + 1.0, "{n} for {len}");
            total += n;
            for q in samples {
                // On the segment, within the fixed-point rounding.
                let x = q.as_vec3() / SUBVOXEL as f32;
                let (a, b) = (g.voxel_from_world(p0), g.voxel_from_world(p1));
                let t = ((x - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                assert!((a + (b - a) * t).distance(x) < 0.2, "{x}");
            }
        }
        // Stochastic rounding: the mean count is the length.
        assert!(
            (total / 64.0 - len).abs() < 0.25,
            "{} vs {len}",
            total / 64.0
        );
    }

    #[test]
    fn segments_mode_counts_strand_length_whatever_the_segment_length() {
        // One straight strand along x through the grid, cut into segments of 0.3 to 5 voxels:
        // each voxel it crosses counts about once.
        let g = VoxelGrid::fit(Vec3::ZERO, Vec3::new(28.0, 1.0, 1.0), 32);
        for seg_len in [0.3f32, 1.0, 2.5, 5.0] {
            let n = (28.0 / seg_len) as usize;
            let positions: Vec<Vec3> = (0..=n)
                .map(|i| Vec3::new(i as f32 * seg_len, 0.5, 0.5))
                .collect();
            let segments = strand_segments(&[0, positions.len() as u32]);
            let c = voxelize(&positions, &segments, &g, VoxelizeMode::Segments, 255, None);
            let total: u32 = c.counts.iter().sum();
            let length = n as f32 * seg_len * g.scale;
            assert!(
                (total as f32 - length).abs() <= 0.15 * length + 2.0,
                "{seg_len}: {total} samples for {length} voxels"
            );
            assert_eq!(c.dropped, 0);
            assert_eq!(c.deposits, u64::from(total));
        }
    }

    #[test]
    fn the_tip_fade_weighs_the_mean_tangent() {
        // One straight strand along x tapering from thickness 1 to 0.1: the mean tangent of
        // each voxel it crosses points along x with the length of the fade there.
        let g = VoxelGrid::fit(Vec3::ZERO, Vec3::new(28.0, 1.0, 1.0), 32);
        let n = 28;
        let positions: Vec<Vec3> = (0..=n).map(|i| Vec3::new(i as f32, 0.5, 0.5)).collect();
        let thickness: Vec<f32> = (0..=n).map(|i| 1.0 - 0.9 * i as f32 / n as f32).collect();
        let segments = strand_segments(&[0, positions.len() as u32]);
        let faded = voxelize(
            &positions,
            &segments,
            &g,
            VoxelizeMode::Segments,
            255,
            Some((&thickness, 1.0)),
        );
        let plain = voxelize(&positions, &segments, &g, VoxelizeMode::Segments, 255, None);
        assert_eq!(
            faded.counts, plain.counts,
            "the fade leaves the density alone"
        );
        let mut checked = 0;
        for (i, &c) in faded.counts.iter().enumerate() {
            if c == 0 {
                continue;
            }
            let t = dequantize_tangent(faded.tangent_sums[i].as_vec3(), c as f32);
            let x = (i as u32 % g.res) as f32 + 0.5;
            let fade = 1.0 - 0.9 * (x / g.scale + g.origin.x) / n as f32;
            // Samples of a voxel span about one segment: the fade within 0.05 of the centre's,
            // plus a quantization level.
            assert!(
                (t.length() - fade).abs() < 0.06,
                "voxel {i}: {} vs {fade}",
                t.length()
            );
            assert!(t.normalize().x > 0.99);
            checked += 1;
        }
        assert!(checked > 20, "{checked}");
        assert_eq!(segment_fade(0.5, 0.7, 1.0), 0.6);
        assert_eq!(segment_fade(2.0, 2.0, 1.0), 1.0);
    }

    #[test]
    fn vertices_mode_leaves_gaps_that_the_filter_covers() {
        let g = VoxelGrid::fit(Vec3::ZERO, Vec3::new(28.0, 1.0, 1.0), 32);
        let positions: Vec<Vec3> = (0..=9)
            .map(|i| Vec3::new(i as f32 * 3.0, 0.5, 0.5))
            .collect();
        let segments = strand_segments(&[0, 10]);
        let c = voxelize(&positions, &segments, &g, VoxelizeMode::Vertices, 255, None);
        assert_eq!(c.deposits, 10);
        let q = |x: f32| g.fixed_point(Vec3::new(x, 0.5, 0.5)) >> SUBVOXEL_BITS;
        // Between two vertices the voxels are empty...
        assert_eq!(c.counts[g.index(q(4.5))], 0);
        // ...the radius-1 filter weighted by the segment length (3 voxels) fills them.
        let weight = 3.0 * g.scale;
        let v = resolve(&c, q(4.5), 1, weight, 255);
        assert!(v.density > 0.0, "{v:?}");
        assert!((v.tangent - Vec3::X).length() < 0.01, "{v:?}");
        // The filter keeps the mass: summed density along the strand ≈ its length in voxels.
        let mut total = 0.0;
        for z in 0..32 {
            for y in 0..32 {
                for x in 0..32 {
                    total += resolve(&c, UVec3::new(x, y, z), 1, weight, 255).density;
                }
            }
        }
        assert!((total - 30.0).abs() < 1e-3, "{total}");
    }

    #[test]
    fn capacity_drops_and_counts_what_overflows() {
        let g = VoxelGrid::fit(Vec3::ZERO, Vec3::ONE, 8);
        // 40 vertices in one voxel, capacity 16.
        let positions = vec![Vec3::splat(0.5); 40];
        let segments = strand_segments(&[0, 40]);
        let c = voxelize(&positions, &segments, &g, VoxelizeMode::Vertices, 16, None);
        assert_eq!((c.deposits, c.dropped), (40, 24));
        let i = g.index(g.fixed_point(Vec3::splat(0.5)) >> SUBVOXEL_BITS);
        assert_eq!((c.counts[i], c.clamped(i, 16)), (40, 16));
        // Only accepted samples carry tangents: the mean stays a unit-range vector.
        let v = resolve(
            &c,
            UVec3::from_array([i as u32 % 8, (i as u32 / 8) % 8, i as u32 / 64]),
            0,
            1.0,
            16,
        );
        assert_eq!(v.density, 16.0);
        assert!(v.tangent.abs().max_element() <= 1.0);
    }

    #[test]
    fn segments_never_cross_strands() {
        assert_eq!(strand_segments(&[0, 2, 3, 6]), vec![[0, 0], [3, 2], [4, 2]]);
    }
}
