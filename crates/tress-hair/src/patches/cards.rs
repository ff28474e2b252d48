//! Hair cards from strands: neighbouring strands grouped into ribbons (the backing of
//! `tress cards`).
//!
//! 1. Every strand is resampled to `segments + 1` points evenly spaced by arc length.
//! 2. Strands are grouped by k-means (Lloyd's algorithm, `iterations` rounds) on a 9-dimensional
//!    point per strand: its root, middle and tip. Grouping on the whole path rather than the root
//!    alone keeps strands that start together but part ways in different cards. The `cards`
//!    initial centres are distinct strands picked by a shuffle seeded with `seed`; groups that
//!    end up empty make no card.
//! 3. Each group becomes one ribbon of `segments` quads. Its centre line is the mean of its
//!    members' resampled points, row by row. Its cross direction at each row is the main axis of
//!    the members' spread around the centre in the plane perpendicular to the centre line (the
//!    major eigenvector of their covariance in that plane, smoothed over ±2 rows); where the
//!    spread is nearly round (eigenvalues within 10% of their sum) the previous row's direction
//!    is kept, and the sign always agrees with it, so the ribbon neither spins nor flips. Its
//!    width is `width_scale × 2σ`, σ the standard deviation along that axis, and at least
//!    `min_width`. A lone strand, or a group without spread, lies flat: its cross direction is
//!    perpendicular to the strand and to the direction away from the roots' centroid.
//! 4. Normals `across × tangent` are made to point away from the roots' centroid (for head hair,
//!    away from the head), flipping a whole ribbon at a time.
//!
//! UVs: `u` 0 to 1 across, `v` 0 at the root row to 1 at the tip row.

use glam::{Mat3, Vec2, Vec3};
use rayon::prelude::*;

use super::PatchMesh;
use crate::rng::Rng;
use crate::{HairAsset, HairError};

/// Largest accepted card or segment count.
const MAX_COUNT: u32 = 1 << 20;
/// Rows on either side whose spread is averaged into a row's cross direction.
const SMOOTH: usize = 2;

/// Settings of [`PatchMesh::from_strands`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CardParams {
    /// Number of cards (groups); at most the strand count is used. Default 400.
    pub cards: u32,
    /// Quads along each card (at least 1). Default 16.
    pub segments: u32,
    /// Card width in standard deviations of the group's spread, times 2 (2: the card covers
    /// ±2σ). Finite and non-negative. Default 2.
    pub width_scale: f32,
    /// Smallest card width (world units, finite and positive). Default 0.2.
    pub min_width: f32,
    /// k-means rounds. Default 8.
    pub iterations: u32,
    /// Seed of the k-means start. Default 0.
    pub seed: u64,
}

impl Default for CardParams {
    fn default() -> Self {
        CardParams {
            cards: 400,
            segments: 16,
            width_scale: 2.0,
            min_width: 0.2,
            iterations: 8,
            seed: 0,
        }
    }
}

impl CardParams {
    /// Check the parameters (ranges as documented; counts at most 2^20).
    pub fn validate(&self) -> Result<(), HairError> {
        if !(1..=MAX_COUNT).contains(&self.cards) || !(1..=MAX_COUNT).contains(&self.segments) {
            return Err(HairError::Parameter(format!(
                "cards and segments must lie in 1..={MAX_COUNT}, got {} and {}",
                self.cards, self.segments
            )));
        }
        if self.iterations > 1000 {
            return Err(HairError::Parameter(format!(
                "k-means iterations must be at most 1000, got {}",
                self.iterations
            )));
        }
        if !(self.width_scale.is_finite() && self.width_scale >= 0.0) {
            return Err(HairError::Parameter(format!(
                "card width scale must be finite and non-negative, got {}",
                self.width_scale
            )));
        }
        if !(self.min_width.is_finite() && self.min_width > 0.0) {
            return Err(HairError::Parameter(format!(
                "card minimum width must be finite and positive, got {}",
                self.min_width
            )));
        }
        Ok(())
    }
}

impl PatchMesh {
    /// Hair cards that follow groups of neighbouring strands of `asset` (see the [module docs](self)). Each non-empty group is one component, in group order.
    pub fn from_strands(asset: &HairAsset, params: &CardParams) -> Result<PatchMesh, HairError> {
        params.validate()?;
        let rows = params.segments as usize + 1;
        let resampled = asset.resample_count(rows as u32)?;
        let points = resampled.positions();
        let strands = asset.strand_count();
        let feature = |s: usize| -> [Vec3; 3] {
            let p = &points[s * rows..(s + 1) * rows];
            [p[0], p[rows / 2], p[rows - 1]]
        };
        let features: Vec<[Vec3; 3]> = (0..strands).into_par_iter().map(feature).collect();
        let group = kmeans(&features, params);
        let k = group.iter().map(|&g| g as usize + 1).max().unwrap_or(0);
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); k];
        for (s, &g) in group.iter().enumerate() {
            members[g as usize].push(s as u32);
        }
        members.retain(|m| !m.is_empty());
        let centroid = features.iter().map(|f| f[0]).sum::<Vec3>() / strands as f32;

        let ribbons: Vec<[Vec<Vec3>; 3]> = members
            .par_iter()
            .map(|m| ribbon(points, rows, m, centroid, params))
            .collect();
        let n = ribbons.len() * 2 * rows;
        let (mut positions, mut normals, mut tangents) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        let mut uvs = Vec::with_capacity(n);
        let mut indices = Vec::with_capacity(ribbons.len() * 6 * params.segments as usize);
        for [p, nrm, t] in ribbons {
            let base = positions.len() as u32;
            positions.extend(p);
            normals.extend(nrm);
            tangents.extend(t);
            for r in 0..rows {
                let v = r as f32 / (rows - 1) as f32;
                uvs.extend([Vec2::new(0.0, v), Vec2::new(1.0, v)]);
            }
            for r in 0..params.segments {
                let (l0, r0) = (base + 2 * r, base + 2 * r + 1);
                let (l1, r1) = (l0 + 2, r0 + 2);
                indices.extend_from_slice(&[l0, r0, l1, r0, r1, l1]);
            }
        }
        PatchMesh::new(positions, normals, tangents, uvs, indices)
    }
}

/// k-means on the strands' features: the group of each strand.
fn kmeans(features: &[[Vec3; 3]], params: &CardParams) -> Vec<u32> {
    let n = features.len();
    let k = (params.cards as usize).min(n);
    // A partial Fisher-Yates shuffle picks k distinct strands as the first centres.
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut rng = Rng::new(params.seed);
    for i in 0..k {
        let j = i + rng.below((n - i) as u64) as usize;
        order.swap(i, j);
    }
    let mut centres: Vec<[Vec3; 3]> = order[..k].iter().map(|&s| features[s as usize]).collect();
    let mut group = vec![0u32; n];
    for round in 0..=params.iterations {
        group.par_iter_mut().zip(features).for_each(|(g, f)| {
            *g = nearest(&centres, f);
        });
        if round == params.iterations {
            break;
        }
        let mut sum = vec![[Vec3::ZERO; 3]; k];
        let mut count = vec![0u32; k];
        for (f, &g) in features.iter().zip(&group) {
            for (s, p) in sum[g as usize].iter_mut().zip(f) {
                *s += *p;
            }
            count[g as usize] += 1;
        }
        for ((c, s), &m) in centres.iter_mut().zip(&sum).zip(&count) {
            if m > 0 {
                *c = s.map(|p| p / m as f32);
            }
        }
    }
    group
}

/// The centre closest to `f` (squared distance summed over the three points).
fn nearest(centres: &[[Vec3; 3]], f: &[Vec3; 3]) -> u32 {
    let mut best = (f32::INFINITY, 0u32);
    for (i, c) in centres.iter().enumerate() {
        let mut d = c[0].distance_squared(f[0]);
        if d >= best.0 {
            continue;
        }
        d += c[1].distance_squared(f[1]);
        if d >= best.0 {
            continue;
        }
        d += c[2].distance_squared(f[2]);
        if d < best.0 {
            best = (d, i as u32);
        }
    }
    best.1
}

/// The main axis of the spread `cov` in the plane perpendicular to unit `t`, with the sign that
/// agrees with `prev`. Where the spread is nearly round (eigenvalues within 10%) or absent, `prev`
/// (projected into the plane) is kept, so the ribbon does not spin.
fn major_axis(cov: &Mat3, t: Vec3, prev: Vec3) -> Vec3 {
    let keep = (prev - t * prev.dot(t))
        .try_normalize()
        .unwrap_or_else(|| t.any_orthonormal_vector());
    let (b1, b2) = t.any_orthonormal_pair();
    // The 2×2 covariance in the plane's basis.
    let a = b1.dot(*cov * b1);
    let b = b1.dot(*cov * b2);
    let c = b2.dot(*cov * b2);
    let spread = (a - c).hypot(2.0 * b);
    if spread <= 0.1 * (a + c) || !spread.is_finite() || spread <= 0.0 {
        return keep;
    }
    let angle = 0.5 * (2.0 * b).atan2(a - c);
    let axis = b1 * angle.cos() + b2 * angle.sin();
    if axis.dot(keep) < 0.0 { -axis } else { axis }
}

/// One ribbon: positions, normals and tangents of its `rows` (left, right) vertex pairs.
fn ribbon(
    points: &[Vec3],
    rows: usize,
    members: &[u32],
    centroid: Vec3,
    params: &CardParams,
) -> [Vec<Vec3>; 3] {
    let m = members.len() as f32;
    let strand = |s: u32| &points[s as usize * rows..(s as usize + 1) * rows];
    let mut centre = vec![Vec3::ZERO; rows];
    for &s in members {
        for (c, p) in centre.iter_mut().zip(strand(s)) {
            *c += *p;
        }
    }
    centre.iter_mut().for_each(|c| *c /= m);
    let mut cov = vec![Mat3::ZERO; rows];
    for &s in members {
        for ((c, p), q) in cov.iter_mut().zip(strand(s)).zip(&centre) {
            let d = *p - *q;
            *c += Mat3::from_cols(d * d.x, d * d.y, d * d.z);
        }
    }
    cov.iter_mut().for_each(|c| *c *= 1.0 / m);

    // Segment directions; rows at zero-length segments take the nearest real direction,
    // preferring the one before them.
    let raw: Vec<Option<Vec3>> = (0..rows)
        .map(|r| {
            let (a, b) = if r + 1 < rows { (r, r + 1) } else { (r - 1, r) };
            (centre[b] - centre[a]).try_normalize()
        })
        .collect();
    let first = raw.iter().flatten().next().copied().unwrap_or(Vec3::NEG_Y);
    let mut last = first;
    let tangent: Vec<Vec3> = raw
        .iter()
        .map(|d| {
            last = d.unwrap_or(last);
            last
        })
        .collect();

    let mut across = vec![Vec3::X; rows];
    let mut prev = {
        let t = tangent[0];
        t.cross(centre[0] - centroid)
            .try_normalize()
            .unwrap_or_else(|| t.any_orthonormal_vector())
    };
    let mut widths = vec![params.min_width; rows];
    for r in 0..rows {
        let t = tangent[r];
        let lo = r.saturating_sub(SMOOTH);
        let hi = (r + SMOOTH).min(rows - 1);
        let smooth: Mat3 =
            cov[lo..=hi].iter().copied().sum::<Mat3>() * (1.0 / (hi - lo + 1) as f32);
        let a = major_axis(&smooth, t, prev);
        let sigma = a.dot(smooth * a).max(0.0).sqrt();
        widths[r] = (params.width_scale * 2.0 * sigma).max(params.min_width);
        across[r] = a;
        prev = a;
    }

    let outward: f32 = (0..rows)
        .map(|r| across[r].cross(tangent[r]).dot(centre[r] - centroid))
        .sum();
    if outward < 0.0 {
        across.iter_mut().for_each(|a| *a = -*a);
    }
    let mut positions = Vec::with_capacity(2 * rows);
    let mut normals = Vec::with_capacity(2 * rows);
    let mut tangents = Vec::with_capacity(2 * rows);
    for r in 0..rows {
        let half = across[r] * (0.5 * widths[r]);
        positions.extend([centre[r] - half, centre[r] + half]);
        let n = across[r].cross(tangent[r]).normalize_or(Vec3::Z);
        normals.extend([n, n]);
        tangents.extend([tangent[r], tangent[r]]);
    }
    [positions, normals, tangents]
}
