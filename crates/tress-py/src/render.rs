//! The renderer: one GPU device, reused by every call; frames come back as arrays shaped
//! (views, H, W, C).

use glam::{Mat4, Vec3};
use numpy::ndarray::Array4;
use numpy::{IntoPyArray, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tress_render::maps::MapRenderer;
use tress_render::scene_setup::{PreparedHair, hair_material};
use tress_render::session::{Session, SessionOptions, technique_kind};
use tress_render::{
    COLOR_FORMAT, Camera, GpuContext, OffscreenTargets, TargetFormats, TechniqueKind, TriMesh,
    read_texture,
};

use crate::arrays::HairIn;
use crate::error::{render_error, value_error};

/// How to install a Vulkan driver, for the error when there is no adapter.
const NO_ADAPTER: &str = "no GPU adapter for tress: install a Vulkan driver (on Debian or \
    Ubuntu without a GPU: `apt-get install mesa-vulkan-drivers` gives lavapipe, a CPU Vulkan \
    driver; with a GPU, its vendor's driver)";

/// A renderer over one GPU device (the first Vulkan adapter, or `WGPU_ADAPTER_NAME`).
#[pyclass(module = "tress._tress", name = "Renderer", frozen)]
pub(crate) struct Renderer {
    ctx: GpuContext,
}

/// One view: world-to-view and clip-from-view matrices, row-major (4, 4) float32.
pub(crate) type View<'py> = (PyReadonlyArray2<'py, f32>, PyReadonlyArray2<'py, f32>);

/// A (4, 4) row-major array as a matrix.
pub(crate) fn mat4(a: &PyReadonlyArray2<'_, f32>, name: &str) -> PyResult<Mat4> {
    if a.shape() != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (4, 4), got {:?}",
            a.shape()
        )));
    }
    let s = a
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name} must be C-contiguous")))?;
    let mut cols = [0f32; 16];
    cols.copy_from_slice(s);
    Ok(Mat4::from_cols_array(&cols).transpose())
}

/// A head given as (vertices (V, 3) float32, faces (F, 3) uint32), as a mesh.
pub(crate) fn head_mesh(
    (v, f): (PyReadonlyArray2<'_, f32>, PyReadonlyArray2<'_, u32>),
) -> PyResult<TriMesh> {
    if v.shape()[1] != 3 || f.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "head must be (vertices (V, 3), faces (F, 3)), got {:?} and {:?}",
            v.shape(),
            f.shape()
        )));
    }
    let positions = v
        .as_slice()
        .map_err(|_| PyValueError::new_err("head vertices must be C-contiguous"))?
        .chunks_exact(3)
        .map(Vec3::from_slice)
        .collect();
    let indices = f
        .as_slice()
        .map_err(|_| PyValueError::new_err("head faces must be C-contiguous"))?
        .to_vec();
    TriMesh::from_triangles(positions, indices).map_err(value_error)
}

/// What a render call gathers over its views, flat and in view order.
#[derive(Default)]
struct Frames {
    rgb: Vec<f32>,
    alpha: Vec<f32>,
    strand_id: Vec<i32>,
    direction: Vec<f32>,
    depth: Vec<f32>,
    head: Vec<bool>,
}

impl Renderer {
    /// The shaded frames (`rgb`, `alpha`) of every camera through one [`Session`].
    #[allow(clippy::too_many_arguments)]
    fn shade(
        &self,
        asset: tress_hair::HairAsset,
        head: Option<TriMesh>,
        kind: TechniqueKind,
        technique: String,
        settings: Vec<String>,
        background: (f32, f32, f32),
        cameras: &[Camera],
        frames: &mut Frames,
    ) -> PyResult<()> {
        let [width, height] = cameras[0].viewport;
        let mut scene = tress_scene::Scene::default();
        scene.technique = technique;
        scene.background = Vec3::from(background);
        scene.output.width = width;
        scene.output.height = height;
        let material = hair_material(&tress_scene::Material::default()).map_err(render_error)?;
        let hair = PreparedHair {
            asset,
            material,
            technique: kind,
        };
        let options = SessionOptions {
            overrides: settings,
            ..SessionOptions::default()
        };
        let mut session = Session::with_hair(
            &self.ctx,
            TargetFormats::default(),
            scene,
            vec![hair],
            head,
            options,
        )
        .map_err(render_error)?;
        session.set_transparent_background(true);
        let targets = OffscreenTargets::new(&self.ctx, [width, height], COLOR_FORMAT)
            .map_err(render_error)?;
        for camera in cameras {
            session
                .render(&self.ctx, &targets.targets(), camera, None)
                .map_err(render_error)?;
            let image = read_texture(&self.ctx, &targets.color).map_err(render_error)?;
            for p in &image.pixels {
                frames.rgb.extend_from_slice(&p[..3]);
                frames.alpha.push(p[3]);
            }
        }
        Ok(())
    }
}

#[pymethods]
impl Renderer {
    /// Open the device; `RuntimeError` saying how to install a driver when there is none.
    #[new]
    fn new(py: Python<'_>) -> PyResult<Self> {
        let ctx = py
            .detach(GpuContext::headless)
            .map_err(|e| PyRuntimeError::new_err(format!("{NO_ADAPTER} ({e})")))?;
        Ok(Renderer { ctx })
    }

    /// The adapter's name and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
    #[getter]
    fn adapter(&self) -> String {
        format!(
            "{} ({:?})",
            self.ctx.adapter_info.name, self.ctx.adapter_info.backend
        )
    }

    /// Render `hair` from each of `views` at `width` × `height` with `technique`; the head is
    /// None or (vertices (V, 3) float32, faces (F, 3) uint32); `settings` are scene
    /// `key=value` overrides. With `shaded`: `rgb` (linear float32, over the background) and
    /// `alpha` (coverage of hair and head), shaped (views, H, W, 3) and (views, H, W, 1). With
    /// `geometry`: `strand_id` (int32, −1 empty, −2 head), `direction` (float32 (dx, dy) in
    /// pixels, y down), `depth` (float32, inf where empty) and `head` (bool).
    #[pyo3(signature = (hair, views, width, height, technique = "strands", head = None,
        settings = Vec::new(), background = (0.0, 0.0, 0.0), shaded = true, geometry = false))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        hair: HairIn<'py>,
        views: Vec<View<'py>>,
        width: u32,
        height: u32,
        technique: &str,
        head: Option<(PyReadonlyArray2<'py, f32>, PyReadonlyArray2<'py, u32>)>,
        settings: Vec<String>,
        background: (f32, f32, f32),
        shaded: bool,
        geometry: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kind = technique_kind(technique).map_err(render_error)?;
        if matches!(kind, TechniqueKind::Satf) {
            return Err(PyValueError::new_err(
                "technique \"satf\" needs a baked database and is not offered from Python; \
                 use strands, volume, hybrid, auto or patches",
            ));
        }
        let vecs = hair.read()?;
        let cameras = views
            .iter()
            .map(|(v, p)| {
                let camera = Camera {
                    view_from_world: mat4(v, "view")?,
                    clip_from_view: mat4(p, "projection")?,
                    viewport: [width, height],
                };
                camera.validate().map_err(render_error)?;
                Ok(camera)
            })
            .collect::<PyResult<Vec<_>>>()?;
        let head = head.map(head_mesh).transpose()?;
        let technique = technique.to_owned();
        let (w, h, n) = (width as usize, height as usize, cameras.len());
        if n == 0 {
            return Err(PyValueError::new_err("render needs at least one view"));
        }
        let frames = py.detach(|| -> PyResult<Frames> {
            let asset = vecs.into_asset()?;
            let mut frames = Frames::default();
            if geometry {
                let maps =
                    MapRenderer::new(&self.ctx, &asset, head.as_ref()).map_err(render_error)?;
                for camera in &cameras {
                    let m = maps.render(&self.ctx, camera).map_err(render_error)?;
                    frames.strand_id.extend_from_slice(&m.strand_id);
                    frames.direction.extend(m.direction.iter().flatten());
                    frames.depth.extend_from_slice(&m.depth);
                    frames.head.extend(m.head.iter().copied());
                }
            }
            if shaded {
                self.shade(
                    asset,
                    head,
                    kind,
                    technique,
                    settings,
                    background,
                    &cameras,
                    &mut frames,
                )?;
            }
            Ok(frames)
        })?;
        let d = PyDict::new(py);
        let array = |c: usize, v: Vec<f32>| {
            Array4::from_shape_vec((n, h, w, c), v)
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))
        };
        if shaded {
            d.set_item("rgb", array(3, frames.rgb)?.into_pyarray(py))?;
            d.set_item("alpha", array(1, frames.alpha)?.into_pyarray(py))?;
        }
        if geometry {
            let ids = Array4::from_shape_vec((n, h, w, 1), frames.strand_id)
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            let heads = Array4::from_shape_vec((n, h, w, 1), frames.head)
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            d.set_item("strand_id", ids.into_pyarray(py))?;
            d.set_item("direction", array(2, frames.direction)?.into_pyarray(py))?;
            d.set_item("depth", array(1, frames.depth)?.into_pyarray(py))?;
            d.set_item("head", heads.into_pyarray(py))?;
        }
        Ok(d)
    }
}
