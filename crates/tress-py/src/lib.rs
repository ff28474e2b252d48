//! The extension module `tress._tress` of the Python package `tress` (python/tress): hair files
//! into numpy arrays and back, the generators, resampling and follow hairs, and a renderer whose
//! frames come back as arrays, the CPU reference path tracer, and strands into voxel volumes.
//! A thin layer over tress-hair, tress-render and tress-trace: no file or rendering logic of its
//! own (the voxel walk of `voxel.rs` is the exception: no crate has one over an arbitrary grid).
//! Every call that reads, writes, renders, traces or voxelizes releases the GIL.

use pyo3::prelude::*;

mod arrays;
mod error;
mod hair;
mod render;
mod trace;
mod voxel;

/// The module: functions over plain arrays; the Python package wraps them in `Hair`, `Camera`
/// and `Renderer`.
#[pymodule]
fn _tress(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("HairError", m.py().get_type::<error::HairError>())?;
    m.add(
        "READS",
        tress_hair::formats::Format::ALL
            .map(|f| f.extension())
            .to_vec(),
    )?;
    m.add_function(wrap_pyfunction!(hair::load, m)?)?;
    m.add_function(wrap_pyfunction!(hair::save, m)?)?;
    m.add_function(wrap_pyfunction!(hair::generate, m)?)?;
    m.add_function(wrap_pyfunction!(hair::styles, m)?)?;
    m.add_function(wrap_pyfunction!(hair::resample, m)?)?;
    m.add_function(wrap_pyfunction!(hair::follow, m)?)?;
    m.add_function(wrap_pyfunction!(hair::generated_head, m)?)?;
    m.add_class::<render::Renderer>()?;
    m.add_function(wrap_pyfunction!(trace::path_trace, m)?)?;
    m.add_function(wrap_pyfunction!(voxel::voxelize, m)?)?;
    Ok(())
}
