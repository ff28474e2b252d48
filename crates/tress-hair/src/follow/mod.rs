//! Follow hairs: `count` followers for every guide strand, so a few thousand guides (what
//! TressFX files and grooming tools store) become a full head of hair. Two modes:
//!
//! - [`FollowMode::Interpolate`] (default), as grooming tools do: a follower's root lies in a
//!   triangle of three neighbouring guide roots on the scalp, and its shape is the blend of those
//!   three guides with the root's barycentric weights. The coat is even *between* guides.
//! - [`FollowMode::Offset`], TressFX's: a follower is a copy of its guide moved by a random
//!   offset on the scalp that grows from the root to the tip by the tip-separation factor, so
//!   followers fan out around their guide:
//!   `follower[i] = guide[i] + offset * (1 + tip_separation * i / (n - 1))`.
//!
//! Distances come from the asset, not from a fixed number of world units: the **root spacing**
//! is the median distance from a guide's root to the nearest other guide's root, and the root
//! radius defaults to [`DEFAULT_RADIUS_FACTOR`] of it ([`FollowRadius::Spacing`]); an explicit
//! radius in world units is [`FollowRadius::World`]. A 0.3-unit radius (TressFX's sample value,
//! tress's old default) suits guides 0.47 units apart but throws followers 30 cm around a head
//! modelled in metres with guides 3.5 mm apart.
//!
//! # Implementation
//!
//! **Roots and scalp.** The guides' roots go into a k-d tree (`crate::kdtree`); each root's
//! nearest other root gives the spacing, its 12 nearest neighbours the scalp's plane there (the
//! least-squares plane's normal, turned toward the guide's root tangent). Where the neighbours
//! are collinear (a single row of guides) or too few, the root tangent stands in for the normal,
//! as in TressFX.
//!
//! **Offset mode.** Each guide's `count` root offsets lie in the scalp's tangent plane at its
//! root (TressFX uses the plane across the root tangent, which for hair lying flat on the scalp
//! puts followers' roots inside the head or in the air), within the root radius, spread as a
//! sunflower spiral turned by a random angle and jittered: stratified instead of independent
//! uniform samples, so a guide's followers do not clump. The default radius, 0.7 of the spacing,
//! makes neighbouring guides' disks overlap just enough to leave no gap between them.
//!
//! **Interpolated mode.** The guides' roots are triangulated on the scalp. A head, a mohawk, a
//! bear's body have no single flat parameterization, so each root triangulates its own
//! neighbourhood: its 12 nearest roots projected onto its scalp plane, a Delaunay triangulation
//! of those 13 points (Bowyer–Watson), and the triangles that have the root as a corner (its
//! fan). Where the scalp is smooth at the guides' spacing, neighbouring roots find the same
//! triangles (the Delaunay triangles of a point set are a property of the points, and four
//! co-circular roots, as on a regular grid, pick the diagonal through their lowest-numbered root
//! whatever the projection), so the fans merge into one consistent triangulation. Triangles
//! whose longest edge exceeds 3 times the local spacing (they would bridge a parting, a gap or
//! a concave border) or that are slivers are dropped, so followers stay where guides are. Each
//! guide shares its `count` followers out over its fan in proportion to area, greedily toward
//! each triangle's expected count; each triangle's points are a fixed evenly spread pattern
//! (Lloyd's algorithm in a triangle whose corners, the guides, are occupied), placed with a
//! random corner permutation and a small jitter. A follower's vertex `i` is
//! `Σ w_j guide_j(i / (n - 1))` with `w` its barycentric weights and each guide sampled at the
//! same fraction of its vertices (linear between vertices), then moved across the hair by a
//! random offset within `root_radius * tip_separation * i / (n - 1)`: followers stray from the
//! blend toward the tip, none at the root. A guide that is the corner of no triangle (isolated,
//! a single row) gets offset followers instead; [`FollowReport::offset_guides`] counts them.
//! Blending guides whose shapes differ much (curls of different phase, the two sides of a
//! parting that no dropped triangle separates) averages them: the offset mode keeps each guide's
//! shape.
//!
//! Both modes put the guide first, then its followers, each follower with its guide's vertex
//! count, per-vertex attributes and strand UV. Everything random comes from per-guide (and
//! per-triangle) streams of the seed, so the output does not depend on thread scheduling.

mod interpolate;
mod pattern;
mod roots;
#[cfg(test)]
mod tests;

use std::fmt;
use std::str::FromStr;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::rng::Rng;
use crate::{HairAsset, HairError};
use roots::Roots;

/// The default root radius, as a fraction of the guides' root spacing.
pub const DEFAULT_RADIUS_FACTOR: f32 = 0.7;

/// How followers are made (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FollowMode {
    /// Blend the three guides whose roots surround the follower's root (default).
    #[default]
    Interpolate,
    /// Copy the guide, offset on the scalp and fanning out toward the tip (TressFX).
    Offset,
}

impl FollowMode {
    /// `"interpolate"` or `"offset"`.
    pub fn name(self) -> &'static str {
        match self {
            FollowMode::Interpolate => "interpolate",
            FollowMode::Offset => "offset",
        }
    }
}

impl fmt::Display for FollowMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FollowMode {
    type Err = HairError;
    fn from_str(s: &str) -> Result<Self, HairError> {
        match s {
            "interpolate" => Ok(FollowMode::Interpolate),
            "offset" => Ok(FollowMode::Offset),
            _ => Err(HairError::Parameter(format!(
                "follow mode must be \"interpolate\" or \"offset\", got \"{s}\""
            ))),
        }
    }
}

/// The root radius of follow hairs: in world units, or relative to the guides' root spacing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FollowRadius {
    /// World units.
    World(f32),
    /// This many times the guides' root spacing (the median distance from a root to the
    /// nearest other root).
    Spacing(f32),
}

impl Default for FollowRadius {
    fn default() -> Self {
        FollowRadius::Spacing(DEFAULT_RADIUS_FACTOR)
    }
}

impl FromStr for FollowRadius {
    type Err = HairError;
    /// `"0.25"`: world units; `"0.6x"`: 0.6 times the root spacing.
    fn from_str(s: &str) -> Result<Self, HairError> {
        let bad = || {
            HairError::Parameter(format!(
                "follow radius must be a number of world units (0.25) or a multiple of the root \
                 spacing (0.6x), got \"{s}\""
            ))
        };
        let (number, relative) = match s.trim().strip_suffix(['x', 'X']) {
            Some(n) => (n, true),
            None => (s.trim(), false),
        };
        let x: f32 = number.trim().parse().map_err(|_| bad())?;
        if !(x.is_finite() && x >= 0.0) {
            return Err(bad());
        }
        Ok(if relative {
            FollowRadius::Spacing(x)
        } else {
            FollowRadius::World(x)
        })
    }
}

impl fmt::Display for FollowRadius {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FollowRadius::World(r) => write!(f, "{r}"),
            FollowRadius::Spacing(k) => write!(f, "{k}x"),
        }
    }
}

/// Parameters of follow-hair generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowParams {
    /// Followers per guide (`strands = guides * (count + 1)`).
    pub count: u32,
    /// How followers are made. Default [`FollowMode::Interpolate`].
    pub mode: FollowMode,
    /// Offset mode: the largest root offset from the guide. Interpolated mode: the scale of the
    /// followers' stray toward the tip. Default 0.7 × the root spacing.
    pub root_radius: FollowRadius,
    /// Offset mode: how much farther apart the tips are than the roots (0: parallel followers).
    /// Interpolated mode: the tip strays up to `root_radius * tip_separation` from the blend.
    /// Default 1.
    pub tip_separation: f32,
    /// Random seed; the same seed gives the same followers.
    pub seed: u64,
}

impl Default for FollowParams {
    fn default() -> Self {
        FollowParams {
            count: 0,
            mode: FollowMode::default(),
            root_radius: FollowRadius::default(),
            tip_separation: 1.0,
            seed: 0,
        }
    }
}

/// What a follow-hair generation derived from the guides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowReport {
    /// The guides' root spacing: the median distance from a root to the nearest other root
    /// (`None` when no two roots are apart).
    pub root_spacing: Option<f32>,
    /// The root radius used, in world units.
    pub root_radius: f32,
    /// Interpolated mode: guides that are the corner of no triangle and got offset followers.
    pub offset_guides: usize,
}

impl HairAsset {
    /// The asset with `params.count` followers after each guide strand (see the module docs).
    pub fn with_follow_hairs(&self, params: &FollowParams) -> Result<HairAsset, HairError> {
        self.follow_hairs(params).map(|(asset, _)| asset)
    }

    /// [`HairAsset::with_follow_hairs`], with what it derived from the guides.
    pub fn follow_hairs(
        &self,
        params: &FollowParams,
    ) -> Result<(HairAsset, FollowReport), HairError> {
        let valid = |x: f32| x.is_finite() && x >= 0.0;
        let radius_ok = match params.root_radius {
            FollowRadius::World(r) | FollowRadius::Spacing(r) => valid(r),
        };
        if !radius_ok || !valid(params.tip_separation) {
            return Err(HairError::Parameter(
                "follow-hair radius and tip separation must be finite and non-negative".into(),
            ));
        }
        let per_guide = params.count as usize + 1;
        let strands = self.strand_count().checked_mul(per_guide);
        let vertices = self.vertex_count().checked_mul(per_guide);
        let (Some(strands), Some(vertices)) = (strands, vertices) else {
            return Err(HairError::Parameter("too many follow hairs".into()));
        };
        if vertices > u32::MAX as usize {
            return Err(HairError::Parameter(format!(
                "{} followers per guide would make {vertices} vertices (more than 2^32)",
                params.count
            )));
        }
        let root_points: Vec<Vec3> = (0..self.strand_count())
            .map(|g| self.strand(g)[0])
            .collect();
        let tangents = self.tangents();
        let up: Vec<Vec3> = (0..self.strand_count())
            .map(|g| tangents[self.strand_range(g).start])
            .collect();
        let roots = Roots::new(&root_points, &up);
        let root_spacing = roots.median_spacing();
        let root_radius = match params.root_radius {
            FollowRadius::World(r) => r,
            FollowRadius::Spacing(k) => {
                k * root_spacing.ok_or_else(|| {
                    HairError::Parameter(
                        "the guides' roots have no spacing to derive a follow-hair radius from \
                         (fewer than two distinct roots); give the radius in world units"
                            .into(),
                    )
                })?
            }
        };
        let mut report = FollowReport {
            root_spacing,
            root_radius,
            offset_guides: 0,
        };
        if params.count == 0 {
            return Ok((self.clone(), report));
        }
        let blends = match params.mode {
            FollowMode::Interpolate => interpolate::plan(&roots, params.count, params.seed),
            FollowMode::Offset => vec![None; self.strand_count()],
        };
        report.offset_guides = match params.mode {
            FollowMode::Interpolate => blends.iter().filter(|b| b.is_none()).count(),
            FollowMode::Offset => 0,
        };
        let chunks: Vec<Vec<Vec3>> = (0..self.strand_count())
            .into_par_iter()
            .map(|g| {
                let normal = roots.normals[g]
                    .or_else(|| up[g].try_normalize())
                    .unwrap_or(Vec3::Y);
                let mut rng = Rng::stream(params.seed, g as u64);
                let guide = self.strand(g);
                let mut out = Vec::with_capacity(guide.len() * per_guide);
                out.extend_from_slice(guide);
                let (u, v) = normal.any_orthonormal_pair();
                let across = |d: Vec2| (u * d.x + v * d.y) * root_radius;
                let fraction = |i: usize| i as f32 / (guide.len().max(2) - 1) as f32;
                match &blends[g] {
                    Some(followers) => {
                        for b in followers {
                            let stray = across(rng.in_disk()) * params.tip_separation;
                            let [s0, s1, s2] = b.guides.map(|j| self.strand(j as usize));
                            let w = b.weights;
                            if s0.len() == guide.len()
                                && s1.len() == guide.len()
                                && s2.len() == guide.len()
                            {
                                // The usual case, guides of one vertex count: vertex by vertex.
                                out.extend((0..guide.len()).map(|i| {
                                    s0[i] * w.x + s1[i] * w.y + s2[i] * w.z + stray * fraction(i)
                                }));
                            } else {
                                out.extend((0..guide.len()).map(|i| {
                                    let f = fraction(i);
                                    sample(s0, f) * w.x
                                        + sample(s1, f) * w.y
                                        + sample(s2, f) * w.z
                                        + stray * f
                                }));
                            }
                        }
                    }
                    None => {
                        for d in pattern::disk(params.count as usize, &mut rng) {
                            let offset = across(d);
                            out.extend(guide.iter().enumerate().map(|(i, &p)| {
                                p + offset * (1.0 + params.tip_separation * fraction(i))
                            }));
                        }
                    }
                }
                out
            })
            .collect();
        let counts: Vec<u32> = (0..self.strand_count())
            .flat_map(|g| std::iter::repeat_n(self.strand(g).len() as u32, per_guide))
            .collect();
        debug_assert_eq!(counts.len(), strands);
        let mut out = HairAsset::from_counts(chunks.concat(), &counts)?;
        let repeat_vertex = |a: &[f32]| -> Vec<f32> { repeat_strands(self, a, per_guide) };
        if let Some(t) = self.thickness() {
            out = out.with_thickness(repeat_vertex(t))?;
        }
        if let Some(t) = self.transparency() {
            out = out.with_transparency(repeat_vertex(t))?;
        }
        if let Some(c) = self.color() {
            out = out.with_color(repeat_strands(self, c, per_guide))?;
        }
        if let Some(uv) = self.strand_uv() {
            out = out.with_strand_uv(
                uv.iter()
                    .flat_map(|&x| std::iter::repeat_n(x, per_guide))
                    .collect(),
            )?;
        }
        Ok((out, report))
    }
}

/// The point at fraction `f` of a strand's vertices, linear between vertices.
fn sample(strand: &[Vec3], f: f32) -> Vec3 {
    let x = f.clamp(0.0, 1.0) * (strand.len() - 1) as f32;
    let i = (x.floor() as usize).min(strand.len().saturating_sub(2));
    match strand.get(i + 1) {
        Some(&next) => strand[i].lerp(next, x - i as f32),
        None => strand[i],
    }
}

/// Repeat each strand's slice of a per-vertex array `per_guide` times.
fn repeat_strands<T: Copy>(asset: &HairAsset, values: &[T], per_guide: usize) -> Vec<T> {
    let mut out = Vec::with_capacity(values.len() * per_guide);
    for s in 0..asset.strand_count() {
        let slice = &values[asset.strand_range(s)];
        for _ in 0..per_guide {
            out.extend_from_slice(slice);
        }
    }
    out
}
