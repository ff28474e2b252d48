//! Curves as DCC tools store them (USD `BasisCurves` / `NurbsCurves`, Alembic `ICurves`) turned
//! into strands: linear curves as they are, cubic and NURBS curves tessellated.
//!
//! # Tessellation rule
//!
//! Every span of a cubic curve, and every knot span of positive length of a NURBS curve, is cut
//! into [`ReadOptions::cubic_segments`] equal parameter steps (default 4); spans share their end
//! vertices, so a curve of `s` spans becomes `s × segments + 1` vertices (a periodic curve ends
//! where it starts). The test fixtures' scripts (`tests/data/curve_eval.py`) state the same rule
//! independently.
//!
//! Cubic bases are those of the USD `BasisCurves` documentation (row vector `[t³ t² t 1]` times
//! the basis matrix times four control points):
//!
//! | basis | spans of `n` vertices: non-periodic / pinned / periodic |
//! | --- | --- |
//! | Bézier (vstep 3) | `(n − 1) / 3` (needs `n = 3k + 1`) / same / `n / 3` |
//! | B-spline, Catmull-Rom (vstep 1) | `n − 3` / `n − 1` / `n` |
//!
//! `pinned` adds the phantom points `2 P₀ − P₁` and `2 Pₙ₋₁ − Pₙ₋₂`, so the curve reaches its end
//! vertices. Hermite and power bases are refused. NURBS curves are evaluated as rational
//! B-splines (weights optional) with the Cox–de Boor recursion over the curve's domain
//! `[knots[order − 1], knots[n]]`; USD's `ranges` are not applied.
//!
//! # Primvars
//!
//! Widths (diameters → thickness), colors and opacities (→ transparency `1 − opacity`) are
//! per curve set with an interpolation:
//! `constant` (one value), `uniform` (one per curve), `varying` (one per span end; per vertex
//! on linear curves), `vertex` (one per control vertex, interpolated with the curve's own basis).
//! When the declared interpolation does not match the number of values, the interpolation that
//! does is used; when none does, the file is refused. Widths are scaled by the world transform's
//! scale (the cube root of its 3×3 determinant).

mod stencils;

use glam::{DMat4, Vec2, Vec3};

use crate::{HairAsset, HairError};
use stencils::Stencils;

/// Settings of the readers of curve formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadOptions {
    /// Segments each cubic span (and NURBS knot span) is cut into: 1 to [`MAX_CUBIC_SEGMENTS`].
    pub cubic_segments: u32,
    /// The frame of an animated file to read: the `frame`-th time sample of USD `points` and
    /// the `frame`-th sample of Alembic `P` (0: the first; past the last: the last). Other
    /// attributes and transforms are read at their first sample; a still file reads the same
    /// at every frame.
    pub frame: u32,
}

/// The most segments per span [`ReadOptions::cubic_segments`] accepts.
pub const MAX_CUBIC_SEGMENTS: u32 = 64;

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            cubic_segments: 4,
            frame: 0,
        }
    }
}

impl ReadOptions {
    /// Check the settings' ranges.
    pub fn validate(&self) -> Result<(), HairError> {
        if (1..=MAX_CUBIC_SEGMENTS).contains(&self.cubic_segments) {
            Ok(())
        } else {
            Err(HairError::Parameter(format!(
                "cubic_segments must be 1 to {MAX_CUBIC_SEGMENTS}, not {}",
                self.cubic_segments
            )))
        }
    }
}

/// How a primvar's values map onto the curves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interp {
    Constant,
    Uniform,
    Varying,
    Vertex,
}

/// A per-curve-set attribute with its interpolation (`None`: infer from the count).
#[derive(Clone, Debug)]
pub(crate) struct Primvar<T> {
    pub(crate) interp: Option<Interp>,
    pub(crate) values: Vec<T>,
}

/// Cubic bases tress tessellates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CubicBasis {
    Bezier,
    Bspline,
    CatmullRom,
}

/// End conditions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Wrap {
    NonPeriodic,
    Pinned,
    Periodic,
}

/// What the control vertices describe.
#[derive(Clone, Debug)]
pub(crate) enum Shape {
    Linear,
    Cubic(CubicBasis, Wrap),
    /// Per-curve order, all knot vectors back to back, optional per-vertex weights.
    Nurbs {
        orders: Vec<u32>,
        knots: Vec<f64>,
        weights: Option<Vec<f64>>,
    },
}

/// One set of curves from a file (a USD prim, an Alembic object), in object space.
#[derive(Clone, Debug)]
pub(crate) struct CurveSet {
    /// Prim or object path, for messages.
    pub(crate) name: String,
    pub(crate) positions: Vec<Vec3>,
    pub(crate) counts: Vec<u32>,
    pub(crate) shape: Shape,
    pub(crate) widths: Option<Primvar<f32>>,
    pub(crate) colors: Option<Primvar<Vec3>>,
    /// Opacity (1 − transparency).
    pub(crate) opacity: Option<Primvar<f32>>,
    /// One UV per curve.
    pub(crate) strand_uv: Option<Vec<Vec2>>,
    /// Curves to leave out (Alembic guides), one flag per curve.
    pub(crate) skip: Option<Vec<bool>>,
    /// Object to world.
    pub(crate) world: DMat4,
}

fn invalid(name: &str, curve: usize, reason: impl std::fmt::Display) -> HairError {
    HairError::Invalid(format!("{name}: curve {curve}: {reason}"))
}

/// Values that can be blended with weights.
trait Blend: Copy {
    const ZERO: Self;
    fn add_scaled(self, other: Self, w: f32) -> Self;
}

impl Blend for f32 {
    const ZERO: f32 = 0.0;
    fn add_scaled(self, other: f32, w: f32) -> f32 {
        self + other * w
    }
}

impl Blend for Vec3 {
    const ZERO: Vec3 = Vec3::ZERO;
    fn add_scaled(self, other: Vec3, w: f32) -> Vec3 {
        self + other * w
    }
}

/// A primvar resolved against the curve set: its interpolation and where each curve's values start.
struct Resolved<'a, T> {
    interp: Interp,
    values: &'a [T],
}

fn resolve<'a, T>(
    name: &str,
    what: &str,
    p: &'a Primvar<T>,
    curves: usize,
    vertices: usize,
    varying: usize,
) -> Result<Resolved<'a, T>, HairError> {
    let n = p.values.len();
    let fits = |i: Interp| match i {
        Interp::Constant => n == 1,
        Interp::Uniform => n == curves,
        Interp::Vertex => n == vertices,
        Interp::Varying => n == varying,
    };
    let interp = p
        .interp
        .filter(|&i| fits(i))
        .or_else(|| {
            [
                Interp::Vertex,
                Interp::Varying,
                Interp::Uniform,
                Interp::Constant,
            ]
            .into_iter()
            .find(|&i| fits(i))
        })
        .ok_or_else(|| {
            HairError::Invalid(format!(
                "{name}: {what} has {n} values, which fit neither 1, {curves} curves, {vertices} \
                 vertices nor {varying} span ends"
            ))
        })?;
    Ok(Resolved {
        interp,
        values: &p.values,
    })
}

impl CurveSet {
    /// Tessellate into an asset in world space; `None` when every curve is skipped.
    pub(crate) fn into_asset(self, options: &ReadOptions) -> Result<Option<HairAsset>, HairError> {
        options.validate()?;
        let name = self.name.as_str();
        let total: u64 = self.counts.iter().map(|&c| u64::from(c)).sum();
        if total != self.positions.len() as u64 {
            return Err(HairError::Invalid(format!(
                "{name}: the vertex counts add up to {total} but there are {} points",
                self.positions.len()
            )));
        }
        let curves = self.counts.len();
        let segments = options.cubic_segments;
        if let Some(s) = &self.skip
            && s.len() != curves
        {
            return Err(HairError::Invalid(format!(
                "{name}: {} guide flags for {curves} curves",
                s.len()
            )));
        }
        if let Some(uv) = &self.strand_uv
            && uv.len() != curves
        {
            return Err(HairError::Invalid(format!(
                "{name}: {} root UVs for {curves} curves",
                uv.len()
            )));
        }
        if matches!(self.shape, Shape::Linear) && self.keeps_every_curve() {
            // The asset checks the points, in the same order.
            return self.into_whole_linear();
        }
        if let Some(i) = crate::asset::first_failing(&self.positions, Vec3::is_finite) {
            return Err(HairError::Invalid(format!(
                "{name}: point {i} is not finite"
            )));
        }
        // Stencils per curve, and the number of span ends (the varying count).
        let mut plans: Vec<(usize, usize, Stencils)> =
            Vec::with_capacity(if matches!(self.shape, Shape::Linear) {
                0
            } else {
                curves
            });
        let mut varying = 0usize;
        let linear = matches!(self.shape, Shape::Linear);
        if linear {
            varying = self.positions.len();
        } else {
            let mut start = 0usize;
            let mut knot_at = 0usize;
            for (i, &c) in self.counts.iter().enumerate() {
                let n = c as usize;
                let mut st = Stencils::default();
                st.clear();
                match &self.shape {
                    Shape::Linear => {}
                    Shape::Cubic(basis, wrap) => {
                        st.cubic(*basis, *wrap, n, segments)
                            .map_err(|e| invalid(name, i, e))?;
                        varying += st.spans as usize + usize::from(*wrap != Wrap::Periodic);
                    }
                    Shape::Nurbs { orders, knots, .. } => {
                        let order =
                            *orders.get(i).ok_or_else(|| invalid(name, i, "no order"))? as usize;
                        let k = knots
                            .get(knot_at..knot_at + n + order)
                            .ok_or_else(|| invalid(name, i, "the knot vector is too short"))?;
                        knot_at += n + order;
                        st.nurbs(n, order, k, segments)
                            .map_err(|e| invalid(name, i, e))?;
                        varying += st.spans as usize + 1;
                    }
                }
                plans.push((start, n, st));
                start += n;
            }
        }
        let widths = self
            .widths
            .as_ref()
            .map(|p| resolve(name, "widths", p, curves, self.positions.len(), varying))
            .transpose()?;
        let colors = self
            .colors
            .as_ref()
            .map(|p| resolve(name, "colors", p, curves, self.positions.len(), varying))
            .transpose()?;
        let opacity = self
            .opacity
            .as_ref()
            .map(|p| resolve(name, "opacity", p, curves, self.positions.len(), varying))
            .transpose()?;
        let weights = match &self.shape {
            Shape::Nurbs {
                weights: Some(w), ..
            } if w.len() == self.positions.len() => Some(w.as_slice()),
            Shape::Nurbs {
                weights: Some(w), ..
            } if !w.is_empty() => {
                return Err(HairError::Invalid(format!(
                    "{name}: {} point weights for {} points",
                    w.len(),
                    self.positions.len()
                )));
            }
            _ => None,
        };
        let skip = |i: usize| self.skip.as_ref().is_some_and(|s| s[i]);

        let mut positions = Vec::with_capacity(if linear { self.positions.len() } else { 0 });
        let mut counts = Vec::with_capacity(curves);
        let mut thickness = widths
            .as_ref()
            .map(|_| Vec::with_capacity(positions.capacity()));
        let mut color = colors
            .as_ref()
            .map(|_| Vec::with_capacity(positions.capacity()));
        let mut alpha = opacity
            .as_ref()
            .map(|_| Vec::with_capacity(positions.capacity()));
        let mut uvs = self.strand_uv.as_ref().map(|_| Vec::with_capacity(curves));
        let mut start = 0usize;
        let mut varying_at = 0usize;
        for i in 0..curves {
            let n = self.counts[i] as usize;
            let span_ends = if linear {
                n
            } else {
                let st = &plans[i].2;
                st.spans as usize
                    + usize::from(!matches!(self.shape, Shape::Cubic(_, Wrap::Periodic)))
            };
            let range = start..start + n;
            let vrange = varying_at..varying_at + span_ends;
            start += n;
            varying_at += span_ends;
            if skip(i) || n == 0 {
                continue;
            }
            let before = positions.len();
            if linear {
                positions.extend_from_slice(&self.positions[range.clone()]);
            } else {
                let st = &plans[i].2;
                for s in &st.samples {
                    let taps = &st.taps[s.start as usize..(s.start + s.len) as usize];
                    let (mut p, mut wsum) = (Vec3::ZERO, 0.0f32);
                    for &(j, w) in taps {
                        let w = w * weights.map_or(1.0, |ws| ws[range.start + j as usize] as f32);
                        p += self.positions[range.start + j as usize] * w;
                        wsum += w;
                    }
                    positions.push(if weights.is_some() && wsum != 0.0 {
                        p / wsum
                    } else {
                        p
                    });
                }
            }
            let out = positions.len() - before;
            counts.push(out as u32);
            let plan = plans.get(i).map(|p| &p.2);
            if let (Some(t), Some(r)) = (thickness.as_mut(), widths.as_ref()) {
                expand(t, r, i, range.clone(), vrange.clone(), out, plan);
            }
            if let (Some(c), Some(r)) = (color.as_mut(), colors.as_ref()) {
                expand(c, r, i, range.clone(), vrange.clone(), out, plan);
            }
            if let (Some(a), Some(r)) = (alpha.as_mut(), opacity.as_ref()) {
                expand(a, r, i, range.clone(), vrange.clone(), out, plan);
            }
            if let (Some(u), Some(src)) = (uvs.as_mut(), self.strand_uv.as_ref()) {
                u.push(src[i]);
            }
        }
        if counts.is_empty() {
            return Ok(None);
        }
        let strands = Strands {
            positions,
            counts,
            thickness,
            color,
            opacity: alpha,
            strand_uv: uvs,
        };
        strands.into_asset(name, self.world).map(Some)
    }

    /// Whether every curve becomes a strand: none is skipped and none is empty.
    fn keeps_every_curve(&self) -> bool {
        self.counts.iter().all(|&c| c > 0) && self.skip.as_ref().is_none_or(|s| !s.contains(&true))
    }

    /// Linear curves that all become strands: the arrays move into the asset as they are instead
    /// of being copied curve by curve (the counts, points and widths were checked by the caller).
    fn into_whole_linear(self) -> Result<Option<HairAsset>, HairError> {
        if self.counts.is_empty() {
            return Ok(None);
        }
        let name = self.name.as_str();
        let counts = &self.counts;
        let strands = Strands {
            thickness: per_vertex(name, "widths", self.widths, counts, self.positions.len())?,
            color: per_vertex(name, "colors", self.colors, counts, self.positions.len())?,
            opacity: per_vertex(name, "opacity", self.opacity, counts, self.positions.len())?,
            strand_uv: self.strand_uv,
            positions: self.positions,
            counts: self.counts,
        };
        strands.into_asset(&self.name, self.world).map(Some)
    }
}

/// A primvar of linear curves as one value per vertex; values that are already per vertex
/// (vertex or varying) move.
fn per_vertex<T: Copy>(
    name: &str,
    what: &str,
    p: Option<Primvar<T>>,
    counts: &[u32],
    vertices: usize,
) -> Result<Option<Vec<T>>, HairError> {
    let Some(p) = p else {
        return Ok(None);
    };
    let interp = resolve(name, what, &p, counts.len(), vertices, vertices)?.interp;
    Ok(Some(match interp {
        Interp::Vertex | Interp::Varying => p.values,
        Interp::Constant => vec![p.values[0]; vertices],
        Interp::Uniform => counts
            .iter()
            .zip(&p.values)
            .flat_map(|(&c, &v)| std::iter::repeat_n(v, c as usize))
            .collect(),
    }))
}

/// The output strands of a curve set in object space, each array per vertex (UVs per strand).
struct Strands {
    positions: Vec<Vec3>,
    counts: Vec<u32>,
    thickness: Option<Vec<f32>>,
    color: Option<Vec<Vec3>>,
    /// Opacity (1 − transparency).
    opacity: Option<Vec<f32>>,
    strand_uv: Option<Vec<Vec2>>,
}

impl Strands {
    /// The asset in world space: points transformed, widths scaled by the transform's scale
    /// (and clamped at 0), opacity turned into transparency.
    fn into_asset(self, name: &str, world: DMat4) -> Result<HairAsset, HairError> {
        let mut positions = self.positions;
        if world != DMat4::IDENTITY {
            let m = world.as_mat4();
            for p in &mut positions {
                *p = m.transform_point3(*p);
            }
        }
        let named = |e: HairError| match e {
            HairError::Invalid(reason) => HairError::Invalid(format!("{name}: {reason}")),
            other => other,
        };
        let mut asset = HairAsset::from_counts(positions, &self.counts).map_err(named)?;
        if let Some(mut t) = self.thickness {
            let det = world.determinant().abs().cbrt() as f32;
            let width_scale = if det.is_finite() { det } else { 1.0 };
            for w in &mut t {
                *w = (*w * width_scale).max(0.0);
            }
            asset = asset.with_thickness(t).map_err(named)?;
        }
        if let Some(c) = self.color {
            asset = asset.with_color(c).map_err(named)?;
        }
        if let Some(a) = self.opacity {
            let t = a.into_iter().map(|o| 1.0 - o).collect();
            asset = asset.with_transparency(t).map_err(named)?;
        }
        if let Some(u) = self.strand_uv {
            asset = asset.with_strand_uv(u).map_err(named)?;
        }
        Ok(asset)
    }
}

/// Append curve `i`'s `out` per-vertex values of a primvar.
fn expand<T: Blend>(
    dst: &mut Vec<T>,
    p: &Resolved<'_, T>,
    i: usize,
    vertices: std::ops::Range<usize>,
    span_ends: std::ops::Range<usize>,
    out: usize,
    plan: Option<&Stencils>,
) {
    match (p.interp, plan) {
        (Interp::Constant, _) => dst.extend(std::iter::repeat_n(p.values[0], out)),
        (Interp::Uniform, _) => dst.extend(std::iter::repeat_n(p.values[i], out)),
        (Interp::Vertex, None) | (Interp::Varying, None) => {
            let src = if p.interp == Interp::Vertex {
                vertices
            } else {
                span_ends
            };
            dst.extend_from_slice(&p.values[src]);
        }
        (Interp::Vertex, Some(st)) => {
            let base = &p.values[vertices];
            dst.extend(st.samples.iter().map(|s| {
                st.taps[s.start as usize..(s.start + s.len) as usize]
                    .iter()
                    .fold(T::ZERO, |acc, &(j, w)| acc.add_scaled(base[j as usize], w))
            }));
        }
        (Interp::Varying, Some(st)) => {
            let ends = &p.values[span_ends];
            let count = ends.len();
            dst.extend(st.samples.iter().map(|s| {
                let a = ends[(s.span as usize).min(count - 1)];
                let b = ends[(s.span as usize + 1) % count];
                a.add_scaled(a, -s.t).add_scaled(b, s.t)
            }));
        }
    }
}
