//! Contacts as arrays: pairs, points, axis parameters and image offsets.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rgc::contacts::Contact;

use crate::interrupt;
use crate::system::{PyBox, PyRods};

/// The contacts of a rod system, one row each, with the box its rods were
/// given in (whose frame the points come out in).
#[pyclass(name = "Contacts", module = "rgc", frozen)]
pub struct PyContacts {
    pub contacts: Vec<Contact>,
    pub n_rods: usize,
    pub r#box: PyBox,
}

fn rows<T: Copy + numpy::Element, const K: usize>(
    contacts: &[Contact],
    f: impl Fn(&Contact) -> [T; K],
) -> Array2<T> {
    let flat: Vec<T> = contacts.iter().flat_map(f).collect();
    Array2::from_shape_vec((contacts.len(), K), flat).expect("K values per contact")
}

#[pymethods]
impl PyContacts {
    fn __len__(&self) -> usize {
        self.contacts.len()
    }

    /// The two rods of each contact, first < second: int64, shape (M, 2).
    #[getter]
    fn pairs<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        rows(&self.contacts, |c| c.rods.map(i64::from)).into_pyarray(py)
    }

    /// Contact points, wrapped into the box along periodic axes, in the
    /// box's frame (`[-L/2, L/2)` if centred): float64, shape (M, 3).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(&self.contacts, |c| self.r#box.to_frame(c.point.into())).into_pyarray(py)
    }

    /// Arc length from each rod's centre to its closest point: float64, shape (M, 2).
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(&self.contacts, |c| c.params).into_pyarray(py)
    }

    /// The periodic image of the second rod that touches the first, in box
    /// sides per axis: int64, shape (M, 3).
    #[getter]
    fn shifts<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        rows(&self.contacts, |c| c.shift.map(i64::from)).into_pyarray(py)
    }

    /// Rods of the system the contacts belong to.
    #[getter]
    fn n_rods(&self) -> usize {
        self.n_rods
    }

    /// What `pickle` rebuilds the contacts from (points in rgc's frame, so
    /// the round trip is exact).
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let state = (
            self.pairs(py),
            self.params(py),
            rows(&self.contacts, |c| [c.point.x, c.point.y, c.point.z]).into_pyarray(py),
            self.shifts(py),
            self.n_rods,
            self.r#box.clone(),
        );
        crate::pickle::reduce(py, "_contacts", state)
    }

    fn __repr__(&self) -> String {
        format!(
            "Contacts({} contacts between {} rods)",
            self.contacts.len(),
            self.n_rods
        )
    }
}

/// Every contact of `rods` (cores closer than the sum of the radii),
/// periodic images included.
#[pyfunction]
pub fn contacts(py: Python<'_>, rods: &PyRods) -> PyResult<PyContacts> {
    crate::compress::check_memory(rods, None)?;
    let system = rods.system.clone();
    Ok(PyContacts {
        contacts: interrupt::run(py, move || rgc::contacts::detect(&system))?,
        n_rods: rods.system.len(),
        r#box: rods.r#box(),
    })
}
