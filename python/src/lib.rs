//! rgc from Python: rod systems, their contacts, 3D-RGC compression and the
//! exact truth, with numpy arrays in and out.
//!
//! The library does the work; this crate only converts. Long work runs on a
//! thread of its own while the calling thread waits with the interpreter
//! released and answers Ctrl-C (`interrupt`); library errors are
//! `MemoryError`s where memory is the problem and `ValueError`s otherwise,
//! with the library's one-line message; every array is typed (float64
//! coordinates, int64 labels).

mod bench;
mod check;
mod compress;
mod contacts;
mod interrupt;
mod moduli;
mod pickle;
mod system;
mod truth;

use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;

/// Bad input as a `ValueError` with its one-line message.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A library error as Python sees it: `MemoryError` for work refused for
/// its memory, `ValueError` for everything else (what the CLI exits 2 on).
pub(crate) fn error(e: rgc::Error) -> PyErr {
    match e {
        rgc::Error::Memory(_) => PyMemoryError::new_err(pythonic(&e.to_string())),
        _ => value_error(e),
    }
}

/// A library message with the command line's flag named as Python's argument.
pub(crate) fn pythonic(message: &str) -> String {
    message.replace("(--memory-limit)", "(memory_limit)")
}

/// How Python writes `obj`, for a message.
pub(crate) fn repr(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map_or_else(|_| "?".into(), |r| r.to_string())
}

/// A count argument (`runs`, `memory_limit`) from `lo` to `hi`, or a
/// `ValueError` naming it: a negative, fractional or huge number would
/// otherwise be an unnamed `OverflowError` or `TypeError`.
pub(crate) fn count(obj: &Bound<'_, PyAny>, name: &str, lo: u64, hi: u64) -> PyResult<u64> {
    let bad = || {
        let got = obj.repr().map_or_else(|_| "?".into(), |r| r.to_string());
        value_error(format!(
            "{name} must be an integer from {lo} to {hi}, got {got}"
        ))
    };
    if obj.is_instance_of::<pyo3::types::PyBool>() {
        return Err(bad());
    }
    let v: u64 = obj.extract().map_err(|_| bad())?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(bad())
    }
}

/// A seed (default 1) from 0 to 2^64 - 1, or a `ValueError` naming it.
pub(crate) fn seed(obj: Option<&Bound<'_, PyAny>>) -> PyResult<u64> {
    obj.map_or(Ok(1), |s| count(s, "seed", 0, u64::MAX))
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
    m.add_function(wrap_pyfunction!(moduli::moduli, m)?)?;
    m.add_function(wrap_pyfunction!(check::check_graph6, m)?)?;
    m.add_function(wrap_pyfunction!(bench::library_seconds, m)?)?;
    pickle::register(m)?;
    m.add("MAX_RUNS", rgc::engine::MAX_RUNS)?;
    Ok(())
}
