//! Hair–hair interaction on a grid (Petrovic et al. 2005): every simulated vertex splats its
//! weight and velocity onto the grid's nodes; friction pulls each vertex's velocity towards the
//! hair's mean velocity around it, and a push down the gradient of the density above the rest
//! pose's densest node keeps the hair's volume: hair may move anywhere, but never pack tighter
//! than it was packed at rest (so nothing is pushed at rest).
//!
//! The grid lives in the head's space (it moves with the head), over the rest hair's bounds
//! padded by the longest strand, `hair_grid` nodes along its longest axis. Sums are fixed-point
//! integers ([`WEIGHT_ONE`], [`VELOCITY_ONE`]), as the GPU's `atomicAdd` on `i32` needs, so they do
//! not depend on the order vertices are added in: the CPU twin and every GPU run get the same
//! sums. Velocities are in cells a substep, clamped to ±[`MAX_CELLS`].

use glam::{IVec3, UVec3, Vec3};

/// Fixed-point scale of a vertex's weight (a trilinear weight of 1).
pub const WEIGHT_ONE: f32 = 256.0;
/// Fixed-point scale of a weighted velocity component (cells a substep).
pub const VELOCITY_ONE: f32 = 4096.0;
/// Largest velocity splatted, in cells a substep.
pub const MAX_CELLS: f32 = 4.0;
/// Largest volume push a substep, in cells.
pub const MAX_PUSH_CELLS: f32 = 0.5;

/// The grid's placement and sums.
#[derive(Clone, Debug, PartialEq)]
pub struct HairGrid {
    /// Node (0, 0, 0), head space.
    pub origin: Vec3,
    /// Node spacing.
    pub cell: f32,
    /// Nodes along x, y, z.
    pub dims: UVec3,
    /// Weight a node (fixed point).
    pub density: Vec<i32>,
    /// Weighted velocity a node, x y z interleaved (fixed point).
    pub momentum: Vec<i32>,
    /// The rest pose's largest weight a node (at least [`WEIGHT_ONE`]): denser is excess, and
    /// the excess is measured in it.
    pub rest_peak: f32,
}

/// The 8 nodes around a grid-space point and their trilinear weights.
pub fn corners(g: Vec3, dims: UVec3) -> [(usize, f32); 8] {
    let max = (dims - UVec3::ONE).as_vec3();
    let g = g.clamp(Vec3::ZERO, max);
    let base = g.floor().min(max - Vec3::ONE).max(Vec3::ZERO);
    let f = g - base;
    let b = base.as_ivec3();
    std::array::from_fn(|k| {
        let k = k as i32;
        let o = IVec3::new(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        let w = (if o.x == 1 { f.x } else { 1.0 - f.x })
            * (if o.y == 1 { f.y } else { 1.0 - f.y })
            * (if o.z == 1 { f.z } else { 1.0 - f.z });
        let c = (b + o).as_uvec3();
        ((c.x + dims.x * (c.y + dims.y * c.z)) as usize, w)
    })
}

impl HairGrid {
    /// A grid over `lo`–`hi` (head space) with `nodes` nodes along the longest axis.
    pub fn new(lo: Vec3, hi: Vec3, nodes: u32) -> HairGrid {
        let cell = (hi - lo).max_element().max(1e-6) / (nodes.max(2) - 1) as f32;
        let dims = ((hi - lo) / cell).ceil().as_uvec3() + UVec3::ONE;
        let dims = dims.max(UVec3::splat(2));
        let n = (dims.x * dims.y * dims.z) as usize;
        HairGrid {
            origin: lo,
            cell,
            dims,
            density: vec![0; n],
            momentum: vec![0; 3 * n],
            rest_peak: WEIGHT_ONE,
        }
    }

    /// Grid-space coordinates of a head-space point.
    pub fn to_grid(&self, p: Vec3) -> Vec3 {
        (p - self.origin) / self.cell
    }

    /// Clear the sums.
    pub fn clear(&mut self) {
        self.density.fill(0);
        self.momentum.fill(0);
    }

    /// Add a vertex at `p` (head space) moving `velocity_cells` (cells a substep).
    pub fn splat(&mut self, p: Vec3, velocity_cells: Vec3) {
        let v = velocity_cells.clamp(Vec3::splat(-MAX_CELLS), Vec3::splat(MAX_CELLS));
        for (i, w) in corners(self.to_grid(p), self.dims) {
            // Ties to even, as WGSL's round.
            self.density[i] += (w * WEIGHT_ONE).round_ties_even() as i32;
            for a in 0..3 {
                self.momentum[3 * i + a] += (w * v[a] * VELOCITY_ONE).round_ties_even() as i32;
            }
        }
    }

    /// Take the current sums as the rest pose's (their densest node).
    pub fn keep_as_rest(&mut self) {
        self.rest_peak = self
            .density
            .iter()
            .copied()
            .max()
            .map_or(WEIGHT_ONE, |m| (m as f32).max(WEIGHT_ONE));
    }

    /// The hair's mean velocity at `p` (cells a substep; zero where there is no hair).
    pub fn velocity(&self, p: Vec3) -> Vec3 {
        let (mut rho, mut m) = (0.0f32, Vec3::ZERO);
        for (i, w) in corners(self.to_grid(p), self.dims) {
            rho += w * self.density[i] as f32;
            m += w * Vec3::new(
                self.momentum[3 * i] as f32,
                self.momentum[3 * i + 1] as f32,
                self.momentum[3 * i + 2] as f32,
            );
        }
        if rho <= 0.0 {
            return Vec3::ZERO;
        }
        m / rho * (WEIGHT_ONE / VELOCITY_ONE)
    }

    /// The density above the rest peak at node `c`, relative to the rest peak.
    fn excess(&self, c: IVec3) -> f32 {
        let c = c
            .clamp(IVec3::ZERO, self.dims.as_ivec3() - IVec3::ONE)
            .as_uvec3();
        let i = (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize;
        (self.density[i] as f32 - self.rest_peak).max(0.0) / self.rest_peak
    }

    /// The gradient (per cell) of the excess density at `p`: central differences of the nodes
    /// around it, trilinearly blended.
    pub fn excess_gradient(&self, p: Vec3) -> Vec3 {
        let g = self.to_grid(p);
        let mut grad = Vec3::ZERO;
        for (i, w) in corners(g, self.dims) {
            if w == 0.0 {
                continue;
            }
            let i = i as u32;
            let c = IVec3::new(
                (i % self.dims.x) as i32,
                ((i / self.dims.x) % self.dims.y) as i32,
                (i / (self.dims.x * self.dims.y)) as i32,
            );
            let d = |o: IVec3| 0.5 * (self.excess(c + o) - self.excess(c - o));
            grad += w * Vec3::new(d(IVec3::X), d(IVec3::Y), d(IVec3::Z));
        }
        grad
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splatted_velocity_reads_back_and_sums_do_not_depend_on_order() {
        let mut a = HairGrid::new(Vec3::ZERO, Vec3::splat(10.0), 11);
        let points: Vec<(Vec3, Vec3)> = (0..50)
            .map(|i| {
                let f = i as f32;
                (
                    Vec3::new(3.0 + 0.07 * f, 4.0 + 0.03 * f, 5.0 - 0.05 * f),
                    Vec3::new(0.5, -0.25, 0.125),
                )
            })
            .collect();
        for (p, v) in &points {
            a.splat(*p, *v);
        }
        let mut b = a.clone();
        b.clear();
        for (p, v) in points.iter().rev() {
            b.splat(*p, *v);
        }
        assert_eq!(a, b);
        let v = a.velocity(Vec3::new(4.0, 4.5, 4.0));
        assert!((v - Vec3::new(0.5, -0.25, 0.125)).length() < 2e-3, "{v}");
        assert_eq!(a.velocity(Vec3::splat(9.5)), Vec3::ZERO);
        // At rest there is no excess; hair packed tighter than at rest pushes away.
        a.keep_as_rest();
        assert_eq!(a.excess_gradient(Vec3::new(4.0, 4.5, 4.0)), Vec3::ZERO);
        for _ in 0..200 {
            a.splat(Vec3::new(5.0, 5.0, 5.0), Vec3::ZERO);
        }
        let g = a.excess_gradient(Vec3::new(5.6, 5.0, 5.0));
        assert!(g.x < 0.0, "{g}");
    }
}
