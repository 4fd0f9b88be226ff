//! The reference for the module's overhead: the library's own time for the
//! work `truth` and `compress` do, measured inside Rust with no arrays
//! converted.

use std::time::Instant;

use pyo3::prelude::*;
use rgc::engine::RuleSet;
use rgc::sample;
use rgc::spanning::Criterion;

use crate::system::PyRods;
use crate::value_error;

/// Seconds the library takes for `what` ('truth' or 'compress', with the
/// module's defaults and `seed`) on `rods`, the interpreter released.
#[pyfunction]
#[pyo3(signature = (rods, what, seed=1))]
pub fn library_seconds(py: Python<'_>, rods: &PyRods, what: &str, seed: u64) -> PyResult<f64> {
    let system = &rods.system;
    match what {
        "truth" => Ok(py.detach(|| {
            let start = Instant::now();
            std::hint::black_box(crate::truth::of_rods(system, Criterion::Wrap, seed, None));
            start.elapsed().as_secs_f64()
        })),
        "compress" => {
            let opts = crate::compress::options(rods, RuleSet::Sound, 1, seed, Criterion::Wrap);
            py.detach(|| {
                let start = Instant::now();
                let s = sample::sample(&opts)?;
                std::hint::black_box(s.reported_bodies(Criterion::Wrap));
                Ok(start.elapsed().as_secs_f64())
            })
            .map_err(crate::error)
        }
        _ => Err(value_error(format!(
            "what must be 'truth' or 'compress', got {what:?}"
        ))),
    }
}
