//! The extension module `tress._tress` of the Python package `tress` (python/tress): hair files
//! into numpy arrays and back, the generators, resampling and follow hairs, and a renderer whose
//! frames come back as arrays. A thin layer over tress-hair and tress-render: no file or
//! rendering logic of its own. Every call that reads, writes or renders releases the GIL.

use pyo3::prelude::*;

mod arrays;
mod error;
mod hair;
mod render;

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
    Ok(())
}
