//! rgc from Python: rod systems, their contacts, 3D-RGC compression and the
//! exact truth, with numpy arrays in and out.
//!
//! The library does the work; this crate only converts. Long work runs with
//! the interpreter released, errors are `ValueError`s with the library's
//! one-line message, and every array is typed (float64 coordinates, int64
//! labels).

mod bench;
mod check;
mod compress;
mod contacts;
mod system;
mod truth;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A library error as the `ValueError` the command line would print.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

#[pymodule]
fn _rgc(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<system::PyBox>()?;
    m.add_class::<system::PyRods>()?;
    m.add_class::<contacts::PyContacts>()?;
    m.add_class::<compress::PyCompression>()?;
    m.add_class::<truth::PyTruth>()?;
    m.add_function(wrap_pyfunction!(system::generate, m)?)?;
    m.add_function(wrap_pyfunction!(contacts::contacts, m)?)?;
    m.add_function(wrap_pyfunction!(compress::compress, m)?)?;
    m.add_function(wrap_pyfunction!(truth::truth, m)?)?;
    m.add_function(wrap_pyfunction!(check::check_graph6, m)?)?;
    m.add_function(wrap_pyfunction!(bench::library_seconds, m)?)?;
    Ok(())
}
