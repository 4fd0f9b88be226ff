//! The elastic moduli of a rod system, as `rgc moduli --json` prints them.

use pyo3::prelude::*;

use rgc::moduli::{LSMR_ITERATIONS, MAX_LSMR_ITERATIONS, ModuliOptions, Solver, of_system};
use rgc::truth::TruthOptions;

use crate::compress::check_memory;
use crate::system::PyRods;
use crate::{count, interrupt, value_error};

/// The elastic tensor of `rods` (a spring `k` at every contact, rigid
/// rods), as the JSON text of `rgc moduli --json` with that seed,
/// solver (`auto`, `qr` or `lsmr`) and cap on LSMR's iterations per
/// strain; `rgc.moduli` reads it into arrays.
#[pyfunction]
#[pyo3(
    signature = (rods, k=1.0, seed=None, memory_limit=None, solver="auto", lsmr_iterations=None),
    text_signature = "(rods, k=1.0, seed=1, memory_limit=None, solver='auto', lsmr_iterations=10000)"
)]
pub fn moduli(
    py: Python<'_>,
    rods: &PyRods,
    k: f64,
    seed: Option<&Bound<'_, PyAny>>,
    memory_limit: Option<&Bound<'_, PyAny>>,
    solver: &str,
    lsmr_iterations: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let seed = crate::seed(seed)?;
    // Solver's own names, as its JSON spells them.
    let solver: Solver = serde_json::from_value(serde_json::Value::from(solver)).map_err(|_| {
        value_error(format!(
            "solver must be 'auto', 'qr' or 'lsmr', not {solver:?}"
        ))
    })?;
    let memory_limit = match memory_limit {
        Some(m) => Some(count(m, "memory_limit (bytes)", 1, u64::MAX)?),
        None => None,
    };
    let lsmr_iterations = match lsmr_iterations {
        Some(n) => count(n, "lsmr_iterations", 1, MAX_LSMR_ITERATIONS as u64)? as usize,
        None => LSMR_ITERATIONS,
    };
    check_memory(rods, memory_limit)?;
    let system = rods.system.clone();
    let opts = ModuliOptions {
        stiffness: k,
        truth: TruthOptions {
            memory_limit,
            ..TruthOptions::seeded(seed)
        },
        solver,
        lsmr_iterations,
    };
    let e = interrupt::run(py, move || {
        let network = rgc::network::Network::detect((*system).clone());
        of_system(network.view(), opts)
    })?
    .map_err(crate::error)?;
    serde_json::to_string(&e).map_err(value_error)
}
