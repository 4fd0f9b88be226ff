//! Pickling: each class hands `pickle` one of the functions below and its
//! state, and the function rebuilds it (checked again, as its constructor
//! would) in whatever process unpickles it, such as a multiprocessing pool.

use numpy::ndarray::ArrayView2;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rgc::contacts::Contact;
use rgc::rods::{Rod, RodSystem};

use crate::compress::PyCompression;
use crate::contacts::PyContacts;
use crate::system::{PyBox, PyRods, check_build};
use crate::truth::PyTruth;
use crate::{error, value_error};

/// `(rebuild, state)` for `__reduce__`: the module function `name` of
/// `rgc._rgc` and the arguments it takes.
pub fn reduce<'py>(
    py: Python<'py>,
    name: &str,
    state: impl IntoPyObject<'py, Target = PyTuple, Output = Bound<'py, PyTuple>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
    let rebuild = py.import("rgc._rgc")?.getattr(name)?;
    let state = state.into_pyobject(py).map_err(Into::into)?;
    Ok((rebuild, state))
}

/// Rods from their state in rgc's frame, checked again.
#[pyfunction]
fn _rods(
    r#box: &PyBox,
    centres: PyReadonlyArray2<'_, f64>,
    directions: PyReadonlyArray2<'_, f64>,
    lengths: PyReadonlyArray1<'_, f64>,
    radii: PyReadonlyArray1<'_, f64>,
    cut: usize,
) -> PyResult<PyRods> {
    let (centres, directions) = (centres.as_array(), directions.as_array());
    let (lengths, radii) = (lengths.as_array(), radii.as_array());
    let n = centres.nrows();
    if directions.nrows() != n || lengths.len() != n || radii.len() != n {
        return Err(value_error("pickled rods of different lengths"));
    }
    check_build(n)?;
    let rods = (0..n)
        .map(|i| {
            let v =
                |a: &ArrayView2<'_, f64>| nalgebra::Vector3::new(a[[i, 0]], a[[i, 1]], a[[i, 2]]);
            Rod::new(v(&centres), v(&directions), lengths[i], radii[i])
        })
        .collect();
    let system = RodSystem::new(r#box.domain, rods).map_err(error)?;
    Ok(PyRods::new(system, cut, r#box.centred))
}

/// Contacts from their state, points in rgc's frame.
#[pyfunction]
fn _contacts(
    pairs: PyReadonlyArray2<'_, i64>,
    params: PyReadonlyArray2<'_, f64>,
    points: PyReadonlyArray2<'_, f64>,
    shifts: PyReadonlyArray2<'_, i64>,
    n_rods: usize,
    r#box: &PyBox,
) -> PyResult<PyContacts> {
    let (pairs, params) = (pairs.as_array(), params.as_array());
    let (points, shifts) = (points.as_array(), shifts.as_array());
    let m = pairs.nrows();
    let shapes = [
        pairs.shape(),
        params.shape(),
        points.shape(),
        shifts.shape(),
    ];
    if shapes != [[m, 2], [m, 2], [m, 3], [m, 3]] {
        return Err(value_error("pickled contacts of different lengths"));
    }
    let contacts = (0..m)
        .map(|i| {
            let rod = |k: usize| {
                u32::try_from(pairs[[i, k]])
                    .ok()
                    .filter(|&r| (r as usize) < n_rods)
            };
            let shift = |k: usize| i32::try_from(shifts[[i, k]]).ok();
            Some(Contact {
                rods: [rod(0)?, rod(1)?],
                params: [params[[i, 0]], params[[i, 1]]],
                point: nalgebra::Vector3::new(points[[i, 0]], points[[i, 1]], points[[i, 2]]),
                shift: [shift(0)?, shift(1)?, shift(2)?],
            })
        })
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| value_error("pickled contacts name rods or images out of range"))?;
    Ok(PyContacts {
        contacts,
        n_rods,
        r#box: r#box.clone(),
    })
}

#[pyfunction]
fn _compression(
    body_idx: Vec<i64>,
    spans: Vec<bool>,
    spanning: bool,
    runs_spanning: usize,
    run: usize,
    report: String,
) -> PyCompression {
    PyCompression {
        body_idx,
        spans,
        spanning,
        runs_spanning,
        run,
        report,
    }
}

#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn _truth(
    cluster_idx: Vec<i64>,
    clusters: Vec<Vec<u32>>,
    dof: Option<usize>,
    spanning: Option<bool>,
    method: String,
    reason: Option<String>,
    memory_refused: bool,
    report: String,
    strains: (Option<u8>, Vec<String>, Vec<String>, Option<String>),
) -> PyTruth {
    let (strain_rank, strains_resisted, strains_considered, strain_reason) = strains;
    PyTruth {
        strain_rank,
        strains_resisted,
        strains_considered,
        strain_reason,
        cluster_idx,
        clusters,
        dof,
        spanning,
        method,
        reason,
        memory_refused,
        report,
    }
}

/// The rebuilding functions, as `rgc._rgc._rods` and so on.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_rods, m)?)?;
    m.add_function(wrap_pyfunction!(_contacts, m)?)?;
    m.add_function(wrap_pyfunction!(_compression, m)?)?;
    m.add_function(wrap_pyfunction!(_truth, m)?)?;
    Ok(())
}
