//! The hair asset: strands of connected vertices stored as a structure of arrays.

use std::ops::Range;

use glam::{Vec2, Vec3};

use crate::HairError;

/// The index of the first value `ok` refuses. Blocks of values are checked without an early exit
/// per value, which the compiler vectorizes (the common case: every value passes); only a block
/// holding a refused value is searched value by value.
pub(crate) fn first_failing<T: Copy>(values: &[T], ok: impl Fn(T) -> bool) -> Option<usize> {
    const BLOCK: usize = 1024;
    values.chunks(BLOCK).enumerate().find_map(|(b, block)| {
        if block.iter().fold(true, |all, &v| all & ok(v)) {
            None
        } else {
            block.iter().position(|&v| !ok(v)).map(|i| b * BLOCK + i)
        }
    })
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (the identity of [`Aabb::union`] and [`Aabb::grow`]).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The smallest box holding `self` and `p`.
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The box around a set of points; `None` for an empty set.
    pub fn from_points(points: &[Vec3]) -> Option<Self> {
        let first = *points.first()?;
        let (min, max) = points
            .iter()
            .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        Some(Aabb { min, max })
    }

    /// Centre of the box.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Edge lengths of the box.
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }
}

/// Strand length statistics (world units, summed over segments).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthStats {
    /// Shortest strand.
    pub min: f32,
    /// Longest strand.
    pub max: f32,
    /// Mean strand length.
    pub mean: f32,
    /// Sum of all strand lengths.
    pub total: f32,
}

/// A [`HairAsset`] taken apart by [`HairAsset::into_parts`] (its fields, moved out).
#[derive(Clone, Debug, PartialEq)]
pub struct HairParts {
    /// Vertex positions, strand after strand.
    pub positions: Vec<Vec3>,
    /// Where each strand starts in `positions`, and the vertex count at the end.
    pub strand_offsets: Vec<u32>,
    /// Per-vertex strand diameter.
    pub thickness: Option<Vec<f32>>,
    /// Per-vertex transparency (0 opaque).
    pub transparency: Option<Vec<f32>>,
    /// Per-vertex linear RGB color.
    pub color: Option<Vec<Vec3>>,
    /// Per-strand UV.
    pub strand_uv: Option<Vec<Vec2>>,
}

/// A hair asset: a set of strands, each a polyline from root to tip.
///
/// Stored as a structure of arrays: one `positions` array for all vertices, and per-strand vertex
/// ranges given by `strand_offsets` (`offsets[i]..offsets[i + 1]` are the vertices of strand `i`),
/// so strands may have different vertex counts. Optional per-vertex thickness, transparency and
/// color arrays have one entry per vertex; optional strand UVs one entry per strand.
///
/// Invariants (checked by every constructor): at least one strand, every strand has at least one
/// vertex, all positions and attributes are finite, attribute arrays have the right lengths.
#[derive(Clone, Debug, PartialEq)]
pub struct HairAsset {
    positions: Vec<Vec3>,
    strand_offsets: Vec<u32>,
    thickness: Option<Vec<f32>>,
    transparency: Option<Vec<f32>>,
    color: Option<Vec<Vec3>>,
    strand_uv: Option<Vec<Vec2>>,
}

impl HairAsset {
    /// The asset taken apart without copies: positions, strand offsets (`strand_count + 1`,
    /// starting at 0) and the optional thickness, transparency, color and strand UVs.
    pub fn into_parts(self) -> HairParts {
        HairParts {
            positions: self.positions,
            strand_offsets: self.strand_offsets,
            thickness: self.thickness,
            transparency: self.transparency,
            color: self.color,
            strand_uv: self.strand_uv,
        }
    }

    /// An asset from positions and the vertex count of each strand.
    pub fn from_counts(positions: Vec<Vec3>, vertex_counts: &[u32]) -> Result<Self, HairError> {
        let mut offsets = Vec::with_capacity(vertex_counts.len() + 1);
        let mut acc: u64 = 0;
        offsets.push(0);
        for &c in vertex_counts {
            acc += u64::from(c);
            let off = u32::try_from(acc)
                .map_err(|_| HairError::Invalid("more than 2^32 vertices".into()))?;
            offsets.push(off);
        }
        Self::from_offsets(positions, offsets)
    }

    /// An asset from positions and strand offsets (`strands + 1` entries, starting at 0, ending at
    /// the vertex count, non-decreasing with every strand non-empty).
    pub fn from_offsets(positions: Vec<Vec3>, strand_offsets: Vec<u32>) -> Result<Self, HairError> {
        if strand_offsets.len() < 2 {
            return Err(HairError::Invalid("the asset has no strands".into()));
        }
        if strand_offsets[0] != 0 {
            return Err(HairError::Invalid("strand offsets must start at 0".into()));
        }
        if let Some(i) = strand_offsets.windows(2).position(|w| w[1] <= w[0]) {
            return Err(HairError::Invalid(format!("strand {i} has no vertices")));
        }
        let last = *strand_offsets.last().unwrap_or(&0) as usize;
        if last != positions.len() {
            return Err(HairError::Invalid(format!(
                "strands hold {last} vertices but {} positions were given",
                positions.len()
            )));
        }
        if let Some(i) = first_failing(&positions, Vec3::is_finite) {
            return Err(HairError::Invalid(format!(
                "vertex {i} has a non-finite position"
            )));
        }
        Ok(HairAsset {
            positions,
            strand_offsets,
            thickness: None,
            transparency: None,
            color: None,
            strand_uv: None,
        })
    }

    /// Attach per-vertex thickness (strand diameter in world units, finite and non-negative).
    pub fn with_thickness(mut self, thickness: Vec<f32>) -> Result<Self, HairError> {
        check_per_vertex("thickness", thickness.len(), self.vertex_count())?;
        if let Some(i) = first_failing(&thickness, |t| t.is_finite() && t >= 0.0) {
            return Err(HairError::Invalid(format!(
                "thickness of vertex {i} is negative or not finite"
            )));
        }
        self.thickness = Some(thickness);
        Ok(self)
    }

    /// Attach per-vertex transparency (0 = opaque, 1 = invisible).
    pub fn with_transparency(mut self, transparency: Vec<f32>) -> Result<Self, HairError> {
        check_per_vertex("transparency", transparency.len(), self.vertex_count())?;
        if let Some(i) = first_failing(&transparency, f32::is_finite) {
            return Err(HairError::Invalid(format!(
                "transparency of vertex {i} is not finite"
            )));
        }
        self.transparency = Some(transparency);
        Ok(self)
    }

    /// Attach per-vertex linear RGB color.
    pub fn with_color(mut self, color: Vec<Vec3>) -> Result<Self, HairError> {
        check_per_vertex("color", color.len(), self.vertex_count())?;
        if let Some(i) = first_failing(&color, Vec3::is_finite) {
            return Err(HairError::Invalid(format!(
                "color of vertex {i} is not finite"
            )));
        }
        self.color = Some(color);
        Ok(self)
    }

    /// Attach a UV per strand (e.g. the scalp texture coordinate of its root).
    pub fn with_strand_uv(mut self, uv: Vec<Vec2>) -> Result<Self, HairError> {
        if uv.len() != self.strand_count() {
            return Err(HairError::Invalid(format!(
                "strand UV array has {} entries for {} strands",
                uv.len(),
                self.strand_count()
            )));
        }
        if let Some(i) = first_failing(&uv, Vec2::is_finite) {
            return Err(HairError::Invalid(format!(
                "UV of strand {i} is not finite"
            )));
        }
        self.strand_uv = Some(uv);
        Ok(self)
    }

    /// Drop the optional arrays that are present (builder helpers for operations).
    pub fn without_attributes(mut self) -> Self {
        self.thickness = None;
        self.transparency = None;
        self.color = None;
        self.strand_uv = None;
        self
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.strand_offsets.len() - 1
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of line segments (each strand of `n` vertices has `n - 1`).
    pub fn segment_count(&self) -> usize {
        self.vertex_count() - self.strand_count()
    }

    /// All vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Mutable access to positions (the strand structure cannot change through it).
    /// Callers must keep positions finite.
    pub fn positions_mut(&mut self) -> &mut [Vec3] {
        &mut self.positions
    }

    /// Strand offsets: `strands + 1` entries.
    pub fn strand_offsets(&self) -> &[u32] {
        &self.strand_offsets
    }

    /// Vertex index range of strand `i`. Panics if `i >= strand_count()`.
    pub fn strand_range(&self, i: usize) -> Range<usize> {
        self.strand_offsets[i] as usize..self.strand_offsets[i + 1] as usize
    }

    /// Vertices of strand `i`. Panics if `i >= strand_count()`.
    pub fn strand(&self, i: usize) -> &[Vec3] {
        &self.positions[self.strand_range(i)]
    }

    /// Iterator over the strands' vertex slices.
    pub fn strands(&self) -> impl ExactSizeIterator<Item = &[Vec3]> + '_ {
        self.strand_offsets
            .windows(2)
            .map(|w| &self.positions[w[0] as usize..w[1] as usize])
    }

    /// Vertex count of each strand.
    pub fn vertex_counts(&self) -> impl ExactSizeIterator<Item = u32> + '_ {
        self.strand_offsets.windows(2).map(|w| w[1] - w[0])
    }

    /// Smallest and largest vertex count over the strands.
    pub fn vertices_per_strand_range(&self) -> (u32, u32) {
        self.vertex_counts()
            .fold((u32::MAX, 0), |(lo, hi), c| (lo.min(c), hi.max(c)))
    }

    /// Per-vertex thickness, if present.
    pub fn thickness(&self) -> Option<&[f32]> {
        self.thickness.as_deref()
    }

    /// Per-vertex transparency, if present.
    pub fn transparency(&self) -> Option<&[f32]> {
        self.transparency.as_deref()
    }

    /// Per-vertex color, if present.
    pub fn color(&self) -> Option<&[Vec3]> {
        self.color.as_deref()
    }

    /// Per-strand UV, if present.
    pub fn strand_uv(&self) -> Option<&[Vec2]> {
        self.strand_uv.as_deref()
    }

    /// Bounding box of all vertices.
    pub fn bounds(&self) -> Aabb {
        // The invariants guarantee at least one vertex.
        Aabb::from_points(&self.positions).unwrap_or(Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        })
    }

    /// Per-vertex unit tangents pointing from root to tip: the direction of the segment leaving
    /// the vertex, and for the tip the segment arriving at it. Single-vertex strands and
    /// zero-length segments get the last valid direction of their strand, or +Y.
    pub fn tangents(&self) -> Vec<Vec3> {
        let mut out = vec![Vec3::Y; self.positions.len()];
        for w in self.strand_offsets.windows(2) {
            let (a, b) = (w[0] as usize, w[1] as usize);
            let strand = &self.positions[a..b];
            let mut last = Vec3::Y;
            for (i, t_out) in out[a..b].iter_mut().enumerate() {
                let d = if i + 1 < strand.len() {
                    strand[i + 1] - strand[i]
                } else if i > 0 {
                    strand[i] - strand[i - 1]
                } else {
                    Vec3::ZERO
                };
                if let Some(t) = d.try_normalize() {
                    last = t;
                }
                *t_out = last;
            }
        }
        out
    }

    /// Length of each strand (sum of its segment lengths).
    pub fn strand_lengths(&self) -> Vec<f32> {
        self.strands()
            .map(|s| s.windows(2).map(|p| p[0].distance(p[1])).sum())
            .collect()
    }

    /// Strand length statistics.
    pub fn length_stats(&self) -> LengthStats {
        let lengths = self.strand_lengths();
        let total: f32 = lengths.iter().sum();
        let (min, max) = lengths
            .iter()
            .fold((f32::INFINITY, 0.0f32), |(lo, hi), &l| {
                (lo.min(l), hi.max(l))
            });
        LengthStats {
            min,
            max,
            mean: total / lengths.len() as f32,
            total,
        }
    }
}

fn check_per_vertex(name: &str, len: usize, vertices: usize) -> Result<(), HairError> {
    if len == vertices {
        Ok(())
    } else {
        Err(HairError::Invalid(format!(
            "{name} array has {len} entries for {vertices} vertices"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_failing_finds_the_first_refused_value_in_any_block() {
        let ok = |v: f32| v.is_finite();
        assert_eq!(first_failing(&[] as &[f32], ok), None);
        for n in [1, 1023, 1024, 1025, 5000] {
            let mut v = vec![1.0f32; n];
            assert_eq!(first_failing(&v, ok), None);
            for bad in [0, n / 2, n - 1] {
                v[bad] = f32::NAN;
                v[n - 1] = f32::INFINITY;
                assert_eq!(first_failing(&v, ok), Some(bad), "n {n}, bad {bad}");
                v.fill(1.0);
            }
        }
    }

    fn two_strands() -> HairAsset {
        let p = vec![
            Vec3::ZERO,
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        HairAsset::from_counts(p, &[3, 2]).unwrap()
    }

    #[test]
    fn counts_and_ranges() {
        let h = two_strands();
        assert_eq!(h.strand_count(), 2);
        assert_eq!(h.vertex_count(), 5);
        assert_eq!(h.segment_count(), 3);
        assert_eq!(h.strand(1), &[Vec3::X, Vec3::new(2.0, 0.0, 0.0)]);
        assert_eq!(h.vertices_per_strand_range(), (2, 3));
    }

    #[test]
    fn tangents_point_root_to_tip() {
        let t = two_strands().tangents();
        assert_eq!(t, vec![Vec3::Y, Vec3::Y, Vec3::Y, Vec3::X, Vec3::X]);
    }

    #[test]
    fn bounds_and_lengths() {
        let h = two_strands();
        let b = h.bounds();
        assert_eq!(b.min, Vec3::ZERO);
        assert_eq!(b.max, Vec3::new(2.0, 3.0, 0.0));
        let s = h.length_stats();
        assert_eq!((s.min, s.max, s.total), (1.0, 3.0, 4.0));
        assert_eq!(s.mean, 2.0);
    }

    #[test]
    fn constructors_reject_bad_input() {
        assert!(HairAsset::from_counts(vec![], &[]).is_err());
        assert!(HairAsset::from_counts(vec![Vec3::ZERO], &[0, 1]).is_err());
        assert!(HairAsset::from_counts(vec![Vec3::ZERO], &[2]).is_err());
        assert!(HairAsset::from_counts(vec![Vec3::NAN], &[1]).is_err());
        let h = two_strands();
        assert!(h.clone().with_thickness(vec![1.0; 4]).is_err());
        assert!(h.clone().with_thickness(vec![-1.0; 5]).is_err());
        assert!(h.clone().with_strand_uv(vec![Vec2::ZERO; 3]).is_err());
        assert!(h.with_color(vec![Vec3::ONE; 5]).is_ok());
    }
}
