//! Strands into voxel volumes as single-view hair reconstruction trains on (NeuralHDHair's
//! 96 × 128 × 128 occupancy and orientation fields): an exact segment walk on the CPU.
//!
//! `tress_shading::voxelize` (the CPU twin of the GPU voxelizer) does not fit: its grid is a
//! cube fitted to the hair, its segment samples are stochastic and its tangents quantized and
//! directed. This walks every segment through an axis-aligned grid of any shape and bounds
//! (Amanatides and Woo's traversal), so each voxel a segment passes through is found and the
//! segment's length inside it is exact.
//!
//! Layout: arrays indexed `[d, h, w]` with `d` along world z, `h` along world y and `w` along
//! world x, each increasing with the world coordinate; voxel `[d, h, w]` covers
//! `min + (w, h, d) · size` to `min + (w + 1, h + 1, d + 1) · size`, `size = (max - min) /
//! (W, H, D)`.

use glam::{DVec3, Vec3};
use numpy::IntoPyArray;
use numpy::ndarray::{Array3, Array4};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::HairIn;

/// Largest voxel count per axis.
const MAX_RESOLUTION: usize = 2048;

/// A grid: `res` = (W, H, D) voxels along (x, y, z) over `[min, max]`.
struct Grid {
    min: DVec3,
    size: DVec3,
    res: [usize; 3],
}

/// What the walk accumulates per voxel.
struct Volumes {
    /// World length of strand inside each voxel.
    density: Vec<f32>,
    /// Sum of sign-normalised unit tangents times their length in the voxel.
    tangent: Vec<DVec3>,
}

/// The tangent's sign chosen so that it points down (`t.y < 0`), or if horizontal towards +z,
/// or if also along x towards +x: one of `t` and `-t` for every direction.
fn sign_normalised(t: DVec3) -> DVec3 {
    let key = if t.y != 0.0 {
        -t.y
    } else if t.z != 0.0 {
        t.z
    } else {
        t.x
    };
    if key < 0.0 { -t } else { t }
}

impl Grid {
    fn index(&self, v: [usize; 3]) -> usize {
        (v[2] * self.res[1] + v[1]) * self.res[0] + v[0]
    }

    /// Walk the segment `a`–`b` (world) through the grid, adding its length and tangent to
    /// every voxel it passes through.
    fn walk(&self, a: DVec3, b: DVec3, out: &mut Volumes) {
        let length = (b - a).length();
        if length == 0.0 {
            return;
        }
        let t = sign_normalised((b - a) / length);
        let (p, q) = ((a - self.min) / self.size, (b - self.min) / self.size);
        let d = q - p;
        let res = DVec3::new(self.res[0] as f64, self.res[1] as f64, self.res[2] as f64);
        // Clip the parameter range to the grid's box (Liang and Barsky).
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for k in 0..3 {
            if d[k] == 0.0 {
                if p[k] < 0.0 || p[k] >= res[k] {
                    return;
                }
            } else {
                let (u, v) = ((0.0 - p[k]) / d[k], (res[k] - p[k]) / d[k]);
                t0 = t0.max(u.min(v));
                t1 = t1.min(u.max(v));
            }
        }
        if t0 >= t1 {
            return;
        }
        let start = p + d * t0;
        let mut voxel = [0usize; 3];
        let mut step = [0isize; 3];
        let mut t_max = [f64::INFINITY; 3];
        let mut t_delta = [f64::INFINITY; 3];
        for k in 0..3 {
            // The voxel the walk starts in: the one the segment enters (towards its direction).
            let mut c = start[k].floor();
            if d[k] < 0.0 && start[k] == c {
                c -= 1.0;
            }
            voxel[k] = c.clamp(0.0, res[k] - 1.0) as usize;
            if d[k] > 0.0 {
                step[k] = 1;
                t_max[k] = (voxel[k] as f64 + 1.0 - p[k]) / d[k];
                t_delta[k] = 1.0 / d[k];
            } else if d[k] < 0.0 {
                step[k] = -1;
                t_max[k] = (voxel[k] as f64 - p[k]) / d[k];
                t_delta[k] = -1.0 / d[k];
            }
        }
        let mut t_here = t0;
        loop {
            let k = (0..3)
                .min_by(|&i, &j| t_max[i].total_cmp(&t_max[j]))
                .unwrap_or(0);
            let t_next = t_max[k].min(t1);
            let inside = (t_next - t_here) * length;
            if inside > 0.0 {
                let i = self.index(voxel);
                out.density[i] += inside as f32;
                out.tangent[i] += t * inside;
            }
            if t_max[k] >= t1 {
                break;
            }
            t_here = t_next;
            let next = voxel[k] as isize + step[k];
            if next < 0 || next >= self.res[k] as isize {
                break;
            }
            voxel[k] = next as usize;
            t_max[k] += t_delta[k];
        }
    }
}

/// Voxelize `hair` into a `resolution` = (D, H, W) grid over `bounds` ((min xyz, max xyz);
/// default: the hair's bounding box grown by one voxel on every side). Returns a dict:
/// `occupancy` (D, H, W) bool (a strand passes through the voxel), `density` (D, H, W)
/// float32 (strand length inside the voxel, world units), `orientation` (D, H, W, 3) float32
/// (the length-weighted mean of the sign-normalised unit tangents, normalised; zero where
/// empty) and `bounds` ((3,), (3,)) the grid's box. See the module docs for the layout.
#[pyfunction]
#[pyo3(signature = (hair, resolution, bounds = None))]
pub(crate) fn voxelize<'py>(
    py: Python<'py>,
    hair: HairIn<'py>,
    resolution: (usize, usize, usize),
    bounds: Option<([f32; 3], [f32; 3])>,
) -> PyResult<Bound<'py, PyDict>> {
    let (nd, nh, nw) = resolution;
    for (n, axis) in [(nd, "D"), (nh, "H"), (nw, "W")] {
        if !(3..=MAX_RESOLUTION).contains(&n) {
            return Err(PyValueError::new_err(format!(
                "resolution: {axis} must lie in 3..={MAX_RESOLUTION}, got {resolution:?}"
            )));
        }
    }
    let res = [nw, nh, nd];
    let vecs = hair.read()?;
    let (grid, volumes) = py.detach(|| -> PyResult<(Grid, Volumes)> {
        let asset = vecs.into_asset()?;
        let (min, max) = match bounds {
            Some((lo, hi)) => {
                let (lo, hi) = (Vec3::from(lo).as_dvec3(), Vec3::from(hi).as_dvec3());
                if !(lo.is_finite() && hi.is_finite() && lo.cmplt(hi).all()) {
                    return Err(PyValueError::new_err(format!(
                        "bounds: need finite min < max on every axis, got {lo} and {hi}"
                    )));
                }
                (lo, hi)
            }
            None => {
                let b = asset.bounds();
                let (lo, hi) = (b.min.as_dvec3(), b.max.as_dvec3());
                let extent = hi - lo;
                // A flat axis (strands in a plane) gets a thousandth of the largest extent.
                let floor = (extent.max_element() * 1e-3).max(1e-6);
                let extent = extent.max(DVec3::splat(floor));
                let centre = (lo + hi) * 0.5;
                let n = DVec3::new(nw as f64, nh as f64, nd as f64);
                // Padded by one voxel: the box spans n - 2 voxels, centred.
                let half = extent * 0.5 * n / (n - 2.0);
                (centre - half, centre + half)
            }
        };
        let n = DVec3::new(nw as f64, nh as f64, nd as f64);
        let grid = Grid {
            min,
            size: (max - min) / n,
            res,
        };
        let count = nw * nh * nd;
        let mut volumes = Volumes {
            density: vec![0.0; count],
            tangent: vec![DVec3::ZERO; count],
        };
        let positions = asset.positions();
        for w in asset.strand_offsets().windows(2) {
            for v in w[0] as usize..(w[1] as usize).saturating_sub(1) {
                grid.walk(
                    positions[v].as_dvec3(),
                    positions[v + 1].as_dvec3(),
                    &mut volumes,
                );
            }
        }
        Ok((grid, volumes))
    })?;
    let shape = (nd, nh, nw);
    let err = |e: numpy::ndarray::ShapeError| PyRuntimeError::new_err(e.to_string());
    let occupancy: Vec<bool> = volumes.density.iter().map(|&l| l > 0.0).collect();
    let orientation: Vec<f32> = volumes
        .tangent
        .iter()
        .flat_map(|t| t.normalize_or_zero().as_vec3().to_array())
        .collect();
    let d = PyDict::new(py);
    d.set_item(
        "occupancy",
        Array3::from_shape_vec(shape, occupancy)
            .map_err(err)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "density",
        Array3::from_shape_vec(shape, volumes.density)
            .map_err(err)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "orientation",
        Array4::from_shape_vec((nd, nh, nw, 3), orientation)
            .map_err(err)?
            .into_pyarray(py),
    )?;
    let max = grid.min + grid.size * DVec3::new(nw as f64, nh as f64, nd as f64);
    d.set_item(
        "bounds",
        (grid.min.as_vec3().to_array(), max.as_vec3().to_array()),
    )?;
    Ok(d)
}
