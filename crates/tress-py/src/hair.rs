//! Hair in and out: read and write every format tress knows, the generators, resampling and
//! follow hairs. Each releases the GIL while it works.

use std::path::PathBuf;

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tress_hair::formats::{self, ReadOptions};
use tress_hair::generate::{self as generators, Style, StyleParams};
use tress_hair::{FollowMode, FollowParams, FollowRadius};

use crate::arrays::{HairIn, asset_dict};
use crate::error::{file_error, value_error};

/// Read hair files (merged in order, each by its extension) at animation frame `frame`; every
/// Bézier or B-spline span is cut into `cubic_segments` segments. Returns a dict of arrays.
#[pyfunction]
#[pyo3(signature = (paths, frame = 0, cubic_segments = 4))]
pub(crate) fn load<'py>(
    py: Python<'py>,
    paths: Vec<PathBuf>,
    frame: u32,
    cubic_segments: u32,
) -> PyResult<Bound<'py, PyDict>> {
    let options = ReadOptions {
        cubic_segments,
        frame,
    };
    let asset = py
        .detach(|| formats::load_paths(&paths, &options))
        .map_err(file_error)?
        .0;
    asset_dict(py, asset)
}

/// Write hair to `path`, its format chosen by the extension.
#[pyfunction]
pub(crate) fn save(py: Python<'_>, path: PathBuf, hair: HairIn<'_>) -> PyResult<()> {
    let vecs = hair.read()?;
    py.detach(|| {
        let asset = vecs.into_asset()?;
        formats::write_path(&path, &asset).map_err(file_error)
    })
}

/// The generator styles, in the CLI's order.
#[pyfunction]
pub(crate) fn styles() -> Vec<&'static str> {
    Style::ALL.iter().map(|s| s.name()).collect()
}

/// A generated groom: the style's own parameters where an argument is None.
#[pyfunction]
#[pyo3(signature = (style, strands = None, vertices = None, length = None, seed = None,
    curl_radius = None, curl_frequency = None, clumping = None, noise = None, thickness = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn generate<'py>(
    py: Python<'py>,
    style: &str,
    strands: Option<u32>,
    vertices: Option<u32>,
    length: Option<f32>,
    seed: Option<u64>,
    curl_radius: Option<f32>,
    curl_frequency: Option<f32>,
    clumping: Option<f32>,
    noise: Option<f32>,
    thickness: Option<f32>,
) -> PyResult<Bound<'py, PyDict>> {
    let style: Style = style.parse().map_err(file_error)?;
    let d = style.default_params();
    let params = StyleParams {
        strands: strands.unwrap_or(d.strands),
        vertices: vertices.unwrap_or(d.vertices),
        length: length.unwrap_or(d.length),
        curl_radius: curl_radius.unwrap_or(d.curl_radius),
        curl_frequency: curl_frequency.unwrap_or(d.curl_frequency),
        clumping: clumping.unwrap_or(d.clumping),
        noise: noise.unwrap_or(d.noise),
        seed: seed.unwrap_or(d.seed),
        thickness: thickness.unwrap_or(d.thickness),
    };
    let asset = py
        .detach(|| generators::generate(style, &params))
        .map_err(file_error)?;
    asset_dict(py, asset)
}

/// Every strand resampled to `n` vertices, by arc length (`by="arclength"`) or to segments of
/// about `segment_length` (`by="length"`, `n` ignored).
#[pyfunction]
#[pyo3(signature = (hair, n = 0, by = "arclength", segment_length = 0.0))]
pub(crate) fn resample<'py>(
    py: Python<'py>,
    hair: HairIn<'py>,
    n: u32,
    by: &str,
    segment_length: f32,
) -> PyResult<Bound<'py, PyDict>> {
    let vecs = hair.read()?;
    let by = by.to_owned();
    let asset = py.detach(|| {
        let asset = vecs.into_asset()?;
        match by.as_str() {
            "arclength" => asset.resample_count(n).map_err(value_error),
            "length" => asset.resample_length(segment_length).map_err(value_error),
            other => Err(PyValueError::new_err(format!(
                "by must be \"arclength\" or \"length\", got {other:?}"
            ))),
        }
    })?;
    asset_dict(py, asset)
}

/// The guides with `count` follow hairs after each (`mode` "interpolate" or "offset"; `radius`
/// in times the roots' spacing).
#[pyfunction]
#[pyo3(signature = (hair, count, mode = "interpolate", radius = 0.7, tip_separation = 1.0, seed = 0))]
pub(crate) fn follow<'py>(
    py: Python<'py>,
    hair: HairIn<'py>,
    count: u32,
    mode: &str,
    radius: f32,
    tip_separation: f32,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = match mode {
        "interpolate" => FollowMode::Interpolate,
        "offset" => FollowMode::Offset,
        other => {
            return Err(PyValueError::new_err(format!(
                "mode must be \"interpolate\" or \"offset\", got {other:?}"
            )));
        }
    };
    let params = FollowParams {
        count,
        mode,
        root_radius: FollowRadius::Spacing(radius),
        tip_separation,
        seed,
    };
    let vecs = hair.read()?;
    let asset = py.detach(|| {
        vecs.into_asset()?
            .with_follow_hairs(&params)
            .map_err(value_error)
    })?;
    asset_dict(py, asset)
}

/// A mesh as numpy arrays: vertices (V, 3) float32 and faces (F, 3) int32.
type MeshArrays<'py> = (
    Bound<'py, numpy::PyArray2<f32>>,
    Bound<'py, numpy::PyArray2<i32>>,
);

/// The generated head the styles grow from (the body for `fur`), as (vertices (V, 3) float32,
/// faces (F, 3) int32).
#[pyfunction]
#[pyo3(signature = (style = "straight"))]
pub(crate) fn generated_head<'py>(py: Python<'py>, style: &str) -> PyResult<MeshArrays<'py>> {
    let style: Style = style.parse().map_err(file_error)?;
    let mesh = generators::shape_for(style).mesh(&generators::head_for(style), 64);
    let v: Vec<f32> = mesh.positions.iter().flat_map(|p| p.to_array()).collect();
    let f: Vec<i32> = mesh.indices.iter().map(|&i| i as i32).collect();
    let vn = mesh.positions.len();
    let fnum = mesh.indices.len() / 3;
    let v = Array2::from_shape_vec((vn, 3), v).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let f =
        Array2::from_shape_vec((fnum, 3), f).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((v.into_pyarray(py), f.into_pyarray(py)))
}
