//! Hair between numpy arrays and [`HairAsset`]: CSR layout, `points` (P, 3) float32 and
//! `offsets` (N + 1,) int64. Arrays leave without copies where the layout allows (positions,
//! thickness, transparency and colors are moved into numpy); arrays that come in are read
//! once into a new asset.

use glam::{Vec2, Vec3};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tress_hair::{HairAsset, HairParts};

use crate::error::value_error;

/// Hair as the arrays Python gave: every array C-contiguous and of the right dtype (the
/// Python package converts); shapes are checked here.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct HairIn<'py> {
    /// (P, 3) float32 vertex positions.
    points: PyReadonlyArray2<'py, f32>,
    /// (N + 1,) int64 strand offsets.
    offsets: PyReadonlyArray1<'py, i64>,
    /// (P,) float32 diameters, or None.
    thickness: Option<PyReadonlyArray1<'py, f32>>,
    /// (P,) float32 transparency, or None.
    transparency: Option<PyReadonlyArray1<'py, f32>>,
    /// (P, 3) float32 linear RGB, or None.
    color: Option<PyReadonlyArray2<'py, f32>>,
    /// (N, 2) float32 strand UVs, or None.
    uv: Option<PyReadonlyArray2<'py, f32>>,
}

/// Hair read from `HairIn`: plain vectors, so that the GIL can be released while they become
/// an asset.
pub(crate) struct HairVecs {
    points: Vec<Vec3>,
    offsets: Vec<u32>,
    thickness: Option<Vec<f32>>,
    transparency: Option<Vec<f32>>,
    color: Option<Vec<Vec3>>,
    uv: Option<Vec<Vec2>>,
}

/// The rows of a (n, k) float32 array, checked to have `k` columns.
fn rows<const K: usize>(a: &PyReadonlyArray2<'_, f32>, name: &str) -> PyResult<Vec<[f32; K]>> {
    let shape = a.shape();
    if shape[1] != K {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (n, {K}), got {shape:?}"
        )));
    }
    let flat = a
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name} must be C-contiguous")))?;
    Ok(flat
        .chunks_exact(K)
        .map(|c| std::array::from_fn(|i| c[i]))
        .collect())
}

/// A 1-D float32 array as a vector.
fn values(a: &PyReadonlyArray1<'_, f32>, name: &str) -> PyResult<Vec<f32>> {
    a.as_slice()
        .map(<[f32]>::to_vec)
        .map_err(|_| PyValueError::new_err(format!("{name} must be C-contiguous")))
}

impl HairIn<'_> {
    /// The arrays copied out of numpy (with the GIL held).
    pub(crate) fn read(&self) -> PyResult<HairVecs> {
        let points: Vec<Vec3> = rows::<3>(&self.points, "points")?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let offsets = self
            .offsets
            .as_slice()
            .map_err(|_| PyValueError::new_err("offsets must be C-contiguous"))?
            .iter()
            .map(|&o| {
                u32::try_from(o).map_err(|_| {
                    PyValueError::new_err(format!("offsets must lie in [0, 2^32), got {o}"))
                })
            })
            .collect::<PyResult<Vec<u32>>>()?;
        Ok(HairVecs {
            points,
            offsets,
            thickness: self
                .thickness
                .as_ref()
                .map(|a| values(a, "thickness"))
                .transpose()?,
            transparency: self
                .transparency
                .as_ref()
                .map(|a| values(a, "transparency"))
                .transpose()?,
            color: self
                .color
                .as_ref()
                .map(|a| rows::<3>(a, "color").map(|v| v.into_iter().map(Vec3::from).collect()))
                .transpose()?,
            uv: self
                .uv
                .as_ref()
                .map(|a| rows::<2>(a, "uv").map(|v| v.into_iter().map(Vec2::from).collect()))
                .transpose()?,
        })
    }
}

impl HairVecs {
    /// The asset (checked: offsets from 0, increasing, ending at the vertex count; attribute
    /// lengths; finite values). Errors are `ValueError`s.
    pub(crate) fn into_asset(self) -> PyResult<HairAsset> {
        let mut asset = HairAsset::from_offsets(self.points, self.offsets).map_err(value_error)?;
        if let Some(t) = self.thickness {
            asset = asset.with_thickness(t).map_err(value_error)?;
        }
        if let Some(t) = self.transparency {
            asset = asset.with_transparency(t).map_err(value_error)?;
        }
        if let Some(c) = self.color {
            asset = asset.with_color(c).map_err(value_error)?;
        }
        if let Some(uv) = self.uv {
            asset = asset.with_strand_uv(uv).map_err(value_error)?;
        }
        Ok(asset)
    }
}

/// `n` rows of `K` floats moved into a (n, K) array without a copy where the allocation can
/// be reinterpreted (it always can for glam's vectors of f32).
fn matrix<'py, T: bytemuck::Pod, const K: usize>(
    py: Python<'py>,
    v: Vec<T>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let n = v.len();
    let flat: Vec<f32> = bytemuck::allocation::try_cast_vec(v)
        .unwrap_or_else(|(_, v)| bytemuck::cast_slice::<T, f32>(&v).to_vec());
    let a =
        Array2::from_shape_vec((n, K), flat).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// An asset as a dict of arrays: `points`, `offsets` and the attributes it has.
pub(crate) fn asset_dict(py: Python<'_>, asset: HairAsset) -> PyResult<Bound<'_, PyDict>> {
    let parts: HairParts = asset.into_parts();
    let d = PyDict::new(py);
    d.set_item("points", matrix::<Vec3, 3>(py, parts.positions)?)?;
    let offsets: Vec<i64> = parts.strand_offsets.iter().map(|&o| i64::from(o)).collect();
    d.set_item("offsets", Array1::from(offsets).into_pyarray(py))?;
    if let Some(t) = parts.thickness {
        d.set_item("thickness", Array1::from(t).into_pyarray(py))?;
    }
    if let Some(t) = parts.transparency {
        d.set_item("transparency", Array1::from(t).into_pyarray(py))?;
    }
    if let Some(c) = parts.color {
        d.set_item("color", matrix::<Vec3, 3>(py, c)?)?;
    }
    if let Some(uv) = parts.strand_uv {
        d.set_item("uv", matrix::<Vec2, 2>(py, uv)?)?;
    }
    Ok(d)
}
