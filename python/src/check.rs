//! The exact verdict on one contact pattern.

use pyo3::prelude::*;
use rgc::graph::io::parse_graph6;
use rgc::pattern::Pattern;

use crate::{error, interrupt};

/// The exact rigidity verdict of the rods-only contact pattern given as
/// graph6 text (the same as `rgc check --graph6`), as JSON text: `rigid`,
/// `dof`, `class` ('rigid', 'flexible', 'component-dependent' or
/// 'undecided') and the realization components.
#[pyfunction]
#[pyo3(signature = (graph6, seed=None), text_signature = "(graph6, seed=1)")]
pub fn check_graph6(
    py: Python<'_>,
    graph6: &str,
    seed: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let seed = crate::seed(seed)?;
    let g = parse_graph6(graph6.trim()).map_err(error)?;
    let p = Pattern::from_graph(&g).map_err(error)?;
    let v = interrupt::run(py, move || rgc::rigidity::check_exact(&p, seed))?.map_err(error)?;
    serde_json::to_string(&v).map_err(crate::value_error)
}
