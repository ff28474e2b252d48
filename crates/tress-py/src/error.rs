//! Errors as Python exceptions: `tress.HairError` for files, `ValueError` for arguments.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::{PyErr, create_exception};

create_exception!(
    tress,
    HairError,
    pyo3::exceptions::PyException,
    "A hair or mesh file could not be read or written; the message is the line the `tress` \
     command prints: the file, then the problem."
);

/// A file's error: `tress.HairError` with the error's one line, or `ValueError` for a bad
/// parameter.
pub(crate) fn file_error(e: tress_hair::HairError) -> PyErr {
    match e {
        tress_hair::HairError::Parameter(msg) => PyValueError::new_err(msg),
        other => HairError::new_err(one_line(&other)),
    }
}

/// An error in arrays the caller gave (wrong lengths, offsets out of order): `ValueError`.
pub(crate) fn value_error(e: tress_hair::HairError) -> PyErr {
    PyValueError::new_err(one_line(&e))
}

/// A rendering error: `ValueError` for invalid settings or inputs, `RuntimeError` otherwise.
pub(crate) fn render_error(e: tress_render::RenderError) -> PyErr {
    match e {
        tress_render::RenderError::Invalid(msg) => PyValueError::new_err(msg),
        tress_render::RenderError::Hair(h) => file_error(h),
        other => PyRuntimeError::new_err(one_line(&other)),
    }
}

/// An error and its sources on one line, as the `tress` command prints it (a source already in
/// the message is not repeated).
pub(crate) fn one_line(e: &(dyn std::error::Error + 'static)) -> String {
    let mut line = String::new();
    let mut cause = Some(e);
    while let Some(c) = cause {
        let text = c.to_string();
        if !line.contains(&text) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&text);
        }
        cause = c.source();
    }
    line.replace('\n', " ")
}
