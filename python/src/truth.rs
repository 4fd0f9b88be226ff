//! The exact truth of a rod system: per-rod cluster labels.

use numpy::ndarray::Array1;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use rgc::rods::RodSystem;
use rgc::spanning::Criterion;
use rgc::truth::{Truth, TruthOptions};

use crate::compress::{check_memory, criterion};
use crate::system::PyRods;
use crate::{count, interrupt, pythonic, value_error};

/// Rigid clusters of the exact truth and the degrees of freedom.
#[pyclass(name = "Truth", module = "rgc", frozen)]
pub struct PyTruth {
    pub cluster_idx: Vec<i64>,
    pub clusters: Vec<Vec<u32>>,
    /// Internal degrees of freedom, or None when undecided.
    #[pyo3(get)]
    pub dof: Option<usize>,
    /// Whether a rigid cluster spans (None when undecided).
    #[pyo3(get)]
    pub spanning: Option<bool>,
    /// 'exact', 'float' or 'undecided'.
    #[pyo3(get)]
    pub method: String,
    /// Why truth is undecided (or how a float answer was reached).
    #[pyo3(get)]
    pub reason: Option<String>,
    /// Whether truth stopped before work that would pass `memory_limit`
    /// (it is then undecided).
    #[pyo3(get)]
    pub memory_refused: bool,
    /// The whole answer as `rgc truth --json` prints it, as JSON text.
    #[pyo3(get)]
    pub report: String,
    /// How many strains of the box the rods resist (6: a solid, 0: a
    /// fluid), over the strains of the periodic axes; None where unknown
    /// (`strain_reason` says why).
    #[pyo3(get)]
    pub strain_rank: Option<u8>,
    /// The coordinate strains resisted alone, by name ('xx' ... 'xy').
    #[pyo3(get)]
    pub strains_resisted: Vec<String>,
    /// The strains considered: those of the periodic axes.
    #[pyo3(get)]
    pub strains_considered: Vec<String>,
    /// Why the strain rank is unknown, if it is.
    #[pyo3(get)]
    pub strain_reason: Option<String>,
}

#[pymethods]
impl PyTruth {
    /// Per rod, the index of the largest rigid cluster holding it
    /// (clusters largest first; a hinge rod lies in several), or -1:
    /// int64, shape (N,).
    #[getter]
    fn cluster_idx<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        Array1::from(self.cluster_idx.clone()).into_pyarray(py)
    }

    /// Each cluster's rods: a list of int64 arrays, largest first.
    #[getter]
    fn clusters<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<i64>>> {
        self.clusters
            .iter()
            .map(|c| Array1::from_iter(c.iter().map(|&r| i64::from(r))).into_pyarray(py))
            .collect()
    }

    /// Whether truth could not decide.
    #[getter]
    fn undecided(&self) -> bool {
        self.method == "undecided"
    }

    /// What `pickle` rebuilds the answer from.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let state = (
            self.cluster_idx.clone(),
            self.clusters.clone(),
            self.dof,
            self.spanning,
            self.method.clone(),
            self.reason.clone(),
            self.memory_refused,
            self.report.clone(),
            (
                self.strain_rank,
                self.strains_resisted.clone(),
                self.strains_considered.clone(),
                self.strain_reason.clone(),
            ),
        );
        crate::pickle::reduce(py, "_truth", state)
    }

    fn __repr__(&self) -> String {
        let dof = self.dof.map_or("None".to_string(), |d| d.to_string());
        let strain = self
            .strain_rank
            .map_or("None".to_string(), |r| r.to_string());
        format!(
            "Truth(method={:?}, dof={dof}, clusters={}, strain_rank={strain})",
            self.method,
            self.clusters.len()
        )
    }
}

/// Contacts and truth of `system`: the library's whole work for `truth`.
pub(crate) fn of_rods(
    system: &RodSystem,
    criterion: Criterion,
    seed: u64,
    memory_limit: Option<u64>,
) -> Truth {
    let network = rgc::network::Network::detect(system.clone());
    let opts = TruthOptions {
        memory_limit,
        ..TruthOptions::seeded(seed)
    };
    rgc::truth::of_system(network.view(), criterion, opts)
}

/// The exact generic rigidity of `rods` (the same answer as `rgc truth`
/// with that seed): degrees of freedom, rigid clusters and spanning under
/// 'wrap', 'faces' or 'solid' (all six strains of the box resisted). `memory_limit` in bytes (positive) refuses a system
/// whose elimination would pass it; an undecided answer comes back as it
/// is here (`rgc.truth` raises `UndecidedError` for it unless asked not to).
#[pyfunction]
#[pyo3(
    signature = (rods, criterion="wrap", seed=None, memory_limit=None),
    text_signature = "(rods, criterion='wrap', seed=1, memory_limit=None)"
)]
pub fn truth(
    py: Python<'_>,
    rods: &PyRods,
    criterion: &str,
    seed: Option<&Bound<'_, PyAny>>,
    memory_limit: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyTruth> {
    let seed = crate::seed(seed)?;
    let criterion = self::criterion(criterion, true)?;
    let memory_limit = match memory_limit {
        Some(m) => Some(count(m, "memory_limit (bytes)", 1, u64::MAX)?),
        None => None,
    };
    check_memory(rods, memory_limit)?;
    let system = rods.system.clone();
    let t = interrupt::run(py, move || of_rods(&system, criterion, seed, memory_limit))?;
    let mut cluster_idx = vec![-1i64; rods.system.len()];
    for (k, c) in t.clusters.iter().enumerate().rev() {
        for &r in &c.rods {
            cluster_idx[r as usize] = k as i64;
        }
    }
    let strains = t.strains.clone().expect("truth reports its strains");
    let names = |v: &[rgc::truth::Strain]| v.iter().map(ToString::to_string).collect();
    Ok(PyTruth {
        strain_rank: strains.rank,
        strains_resisted: names(&strains.resisted),
        strains_considered: names(&strains.considered),
        strain_reason: strains.reason.as_deref().map(pythonic),
        cluster_idx,
        clusters: t.clusters.iter().map(|c| c.rods.clone()).collect(),
        dof: t.outcome.dof(),
        spanning: t.spanning,
        method: t.outcome.decision().to_string(),
        reason: t.outcome.reason().map(pythonic),
        memory_refused: t.outcome.refused().is_some(),
        report: serde_json::to_string(&t).map_err(value_error)?,
    })
}
