//! The CPU reference path tracer (`tress-trace`, what `tress reference` runs) over arrays: any
//! camera given as matrices, frames back as (views, H, W, 3) float32 linear RGB. No GPU.

use glam::Vec3;
use numpy::ndarray::Array4;
use numpy::{IntoPyArray, PyArray4, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use tress_scene::{HairSpec, Scene};
use tress_trace::{SceneGeometry, TraceError, TraceSettings, Tracer, ViewCamera};

use crate::arrays::HairIn;
use crate::error::one_line;
use crate::render::{View, head_mesh, mat4};

/// The `[hair.material]` keys of the physically based fibre (Chiang et al. 2016) that `fiber`
/// may set, and the strand diameter.
pub(crate) const FIBER_KEYS: [&str; 9] = [
    "eumelanin",
    "pheomelanin",
    "sigma_a",
    "target_color",
    "beta_m",
    "beta_n",
    "alpha_deg",
    "eta",
    "thickness",
];

/// `strands.shading` values the tracer offers from Python.
const SHADINGS: [&str; 2] = ["kajiya-kay", "marschner"];

/// A tracer error as a `ValueError` (settings, scene keys and inputs are the caller's).
fn trace_error(e: TraceError) -> PyErr {
    PyValueError::new_err(one_line(&e))
}

/// The scene the tracer reads: `tress render`'s defaults (lights, `[strands]`), the given
/// `shading`, background and `key=value` overrides, and one hair entry carrying the material
/// with the `fiber` keys. The hair entry's `files` is a placeholder: the geometry comes from
/// the arrays.
fn scene(
    shading: &str,
    fiber: &[(String, String)],
    overrides: &[String],
    background: (f32, f32, f32),
) -> PyResult<Scene> {
    if !SHADINGS.contains(&shading) {
        return Err(PyValueError::new_err(format!(
            "unknown shading {shading:?}; valid: {}",
            SHADINGS.join(", ")
        )));
    }
    let mut scene = Scene::default();
    scene.background = Vec3::from(background);
    scene.hair.push(HairSpec {
        files: vec!["(arrays)".into()],
        ..HairSpec::default()
    });
    scene
        .strands
        .insert("shading".into(), toml::Value::String(shading.into()));
    for (key, value) in fiber {
        if !FIBER_KEYS.contains(&key.as_str()) {
            return Err(PyValueError::new_err(format!(
                "unknown fiber key {key:?}; valid: {}",
                FIBER_KEYS.join(", ")
            )));
        }
        scene
            .apply_override(&format!("hair.0.material.{key}={value}"))
            .map_err(|e| PyValueError::new_err(format!("fiber: {}", one_line(&e))))?;
    }
    scene
        .apply_overrides(overrides)
        .map_err(|e| PyValueError::new_err(one_line(&e)))?;
    Ok(scene)
}

/// Path-trace `hair` from each of `views` at `width` × `height`: `spp` samples per pixel,
/// `shading` `kajiya-kay` or `marschner` (Chiang et al. 2016's fibres, the `fiber` keys
/// [`FIBER_KEYS`] as `(key, TOML value)` pairs), the head None or (vertices (V, 3) float32,
/// faces (F, 3) uint32). `settings` are `key=value` overrides: `trace.NAME` ones set the
/// tracer (`tress_trace::SETTING_NAMES`), the others the scene. Returns (views, H, W, 3)
/// float32 linear RGB over `background`; the same `seed` gives the same frames.
#[pyfunction]
#[pyo3(signature = (hair, views, width, height, spp = 16, shading = "marschner",
    fiber = Vec::new(), head = None, settings = Vec::new(), background = (0.0, 0.0, 0.0),
    seed = 0))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn path_trace<'py>(
    py: Python<'py>,
    hair: HairIn<'py>,
    views: Vec<View<'py>>,
    width: u32,
    height: u32,
    spp: u32,
    shading: &str,
    fiber: Vec<(String, String)>,
    head: Option<(PyReadonlyArray2<'py, f32>, PyReadonlyArray2<'py, u32>)>,
    settings: Vec<String>,
    background: (f32, f32, f32),
    seed: u64,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    if views.is_empty() {
        return Err(PyValueError::new_err("path_trace needs at least one view"));
    }
    if width == 0 || height == 0 {
        return Err(PyValueError::new_err(format!(
            "width and height must be at least 1, got {width} x {height}"
        )));
    }
    let mut trace = TraceSettings::default();
    let mut scene_sets = Vec::new();
    let mut ao_radius_given = false;
    for set in &settings {
        match set.strip_prefix("trace.") {
            Some(rest) => {
                let (name, value) = rest.split_once('=').ok_or_else(|| {
                    PyValueError::new_err(format!("setting {set:?}: expected trace.NAME=VALUE"))
                })?;
                ao_radius_given |= name.trim() == "ao_radius";
                trace.set(name.trim(), value).map_err(trace_error)?;
            }
            None => scene_sets.push(set.clone()),
        }
    }
    trace.set("spp", &spp.to_string()).map_err(trace_error)?;
    trace.seed = seed;
    let scene = scene(shading, &fiber, &scene_sets, background)?;
    let cameras = views
        .iter()
        .map(|(v, p)| {
            Ok(ViewCamera {
                view_from_world: mat4(v, "view")?,
                clip_from_view: mat4(p, "projection")?,
                width,
                height,
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let head = head.map(head_mesh).transpose()?;
    let vecs = hair.read()?;
    let pixels = py.detach(|| -> PyResult<Vec<f32>> {
        let hair = vecs.into_asset()?;
        // The AO radius is in world units: scaled to the hair's unit as `tress reference` does.
        if !ao_radius_given && trace.ao_radius.is_finite() {
            let b = hair.bounds();
            trace.ao_radius *= tress_render::scene_setup::unit_scale(b.min, b.max);
        }
        let geometry = SceneGeometry {
            hair: Some(hair),
            head,
        };
        let mut pixels = Vec::with_capacity(cameras.len() * (width * height * 3) as usize);
        for camera in &cameras {
            let tracer =
                Tracer::with_camera(&scene, &geometry, &trace, camera).map_err(trace_error)?;
            let image = tracer.render(&|_| {}).image;
            pixels.extend(image.pixels.iter().flat_map(|p| p.to_array()));
        }
        Ok(pixels)
    })?;
    let (n, h, w) = (cameras.len(), height as usize, width as usize);
    let frames = Array4::from_shape_vec((n, h, w, 3), pixels)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(frames.into_pyarray(py))
}
