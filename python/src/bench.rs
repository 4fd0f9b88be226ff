//! The reference for the module's overhead: the library's own time for the
//! work `truth` and `compress` do, measured inside Rust with no arrays
//! converted.

use std::time::Instant;

use pyo3::prelude::*;
use rgc::engine::RuleSet;
use rgc::graph::ContactGraph;
use rgc::rods::file::Loaded;
use rgc::sample::{self, Rods, SampleOptions};
use rgc::spanning::Criterion;
use rgc::truth::TruthOptions;

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
            let contacts = rgc::contacts::detect(system);
            let graph = ContactGraph::from_contacts(system.len(), &contacts);
            let t = rgc::truth::of_system(
                system,
                &contacts,
                &graph,
                Criterion::Wrap,
                TruthOptions::seeded(seed),
            );
            std::hint::black_box(t);
            start.elapsed().as_secs_f64()
        })),
        "compress" => {
            let opts = SampleOptions {
                rods: Rods::Read {
                    path: "<python>".into(),
                    loaded: Loaded {
                        system: system.clone(),
                        cut: rods.cut,
                        lines: (1..=system.len()).collect(),
                    },
                },
                seed,
                runs: 1,
                rules: RuleSet::Sound,
                criterion: Criterion::Wrap,
                truth: false,
            };
            py.detach(|| {
                let start = Instant::now();
                let s = sample::sample(&opts)?;
                std::hint::black_box(s.reported_bodies(Criterion::Wrap));
                Ok(start.elapsed().as_secs_f64())
            })
            .map_err(|e: rgc::Error| value_error(e))
        }
        _ => Err(value_error(format!(
            "what must be 'truth' or 'compress', got {what:?}"
        ))),
    }
}
