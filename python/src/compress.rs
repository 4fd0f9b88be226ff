//! 3D-RGC compression of a rod system: per-rod body labels.

use numpy::ndarray::Array1;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rgc::engine::RuleSet;
use rgc::rods::file::Loaded;
use rgc::sample::{self, Rods, SampleOptions};
use rgc::spanning::Criterion;

use crate::system::PyRods;
use crate::{count, error, interrupt, value_error};

/// A criterion by name; 'solid' only where the exact truth answers
/// (`solid`), since a compression's bodies cannot say which strains the
/// rods resist.
pub(crate) fn criterion(name: &str, solid: bool) -> PyResult<Criterion> {
    match name {
        "wrap" => Ok(Criterion::Wrap),
        "faces" => Ok(Criterion::Faces),
        "solid" if solid => Ok(Criterion::Solid),
        "solid" => Err(value_error(
            "criterion 'solid' needs the exact truth (rgc.truth), not a compression",
        )),
        _ if solid => Err(value_error(format!(
            "criterion must be 'wrap', 'faces' or 'solid', got {name:?}"
        ))),
        _ => Err(value_error(format!(
            "criterion must be 'wrap' or 'faces', got {name:?}"
        ))),
    }
}

fn rules(name: &str) -> PyResult<RuleSet> {
    match name {
        "sound" => Ok(RuleSet::Sound),
        "paper" => Ok(RuleSet::Paper),
        "certified" => Ok(RuleSet::Certified),
        _ => Err(value_error(format!(
            "rules must be 'sound', 'paper' or 'certified', got {name:?}"
        ))),
    }
}

/// The bodies of one compression run (the first that spans, else the one
/// with the largest body, as `rgc sample` reports).
#[pyclass(name = "Compression", module = "rgc", frozen)]
pub struct PyCompression {
    pub body_idx: Vec<i64>,
    pub spans: Vec<bool>,
    #[pyo3(get)]
    pub spanning: bool,
    #[pyo3(get)]
    pub runs_spanning: usize,
    #[pyo3(get)]
    pub run: usize,
    /// The report `rgc sample --json` prints, as JSON text.
    #[pyo3(get)]
    pub report: String,
}

#[pymethods]
impl PyCompression {
    /// Per rod, the index of its body (bodies largest first), or -1: int64, shape (N,).
    #[getter]
    fn body_idx<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        Array1::from(self.body_idx.clone()).into_pyarray(py)
    }

    /// Per body, whether it spans under the criterion: bool, shape (B,).
    #[getter]
    fn spans<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        Array1::from(self.spans.clone()).into_pyarray(py)
    }

    /// What `pickle` rebuilds the compression from.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let state = (
            self.body_idx.clone(),
            self.spans.clone(),
            self.spanning,
            self.runs_spanning,
            self.run,
            self.report.clone(),
        );
        crate::pickle::reduce(py, "_compression", state)
    }

    fn __repr__(&self) -> String {
        format!(
            "Compression({} bodies, spanning={})",
            self.spans.len(),
            if self.spanning { "True" } else { "False" }
        )
    }
}

/// These rods as `rgc sample` reads them from a file.
fn read(rods: &PyRods) -> Rods {
    Rods::Read {
        path: "<python>".into(),
        loaded: Loaded {
            system: (*rods.system).clone(),
            cut: rods.cut,
            wrapped: 0,
            lines: (1..=rods.system.len()).collect(),
            ids: None,
        },
    }
}

/// Refuses, as `rgc sample` and `rgc truth` do, rods whose contacts and
/// compression are estimated to need more memory than `limit` bytes (none:
/// what the process has available): a `MemoryError` before the work.
pub(crate) fn check_memory(rods: &PyRods, limit: Option<u64>) -> PyResult<()> {
    read(rods).check_memory(limit).map_err(error)
}

/// What `rgc sample` would be given for these rods (read, not generated).
pub(crate) fn options(
    rods: &PyRods,
    rules: RuleSet,
    runs: usize,
    seed: u64,
    criterion: Criterion,
) -> SampleOptions {
    SampleOptions {
        rods: read(rods),
        seed,
        runs,
        rules,
        criterion,
        truth: false,
    }
}

/// Compresses the contact graph of `rods` with 3D-RGC: `runs` runs (1 to
/// 100,000, the command line's cap) in random motif orders from `seed`
/// (the same runs as `rgc sample` with that seed), rules 'sound', 'paper'
/// or 'certified', spanning under 'wrap' or 'faces'.
#[pyfunction]
#[pyo3(
    signature = (rods, rules="sound", runs=None, seed=None, criterion="wrap"),
    text_signature = "(rods, rules='sound', runs=1, seed=1, criterion='wrap')"
)]
pub fn compress(
    py: Python<'_>,
    rods: &PyRods,
    rules: &str,
    runs: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    criterion: &str,
) -> PyResult<PyCompression> {
    let seed = crate::seed(seed)?;
    let runs = match runs {
        Some(r) => count(r, "runs", 1, rgc::engine::MAX_RUNS)? as usize,
        None => 1,
    };
    let opts = options(
        rods,
        self::rules(rules)?,
        runs,
        seed,
        self::criterion(criterion, false)?,
    );
    opts.check_memory(None).map_err(error)?;
    let criterion = opts.criterion;
    let (s, reported) = interrupt::run(py, move || {
        let s = sample::sample(&opts)?;
        let reported = s.reported_bodies(criterion);
        Ok::<_, rgc::Error>((s, reported))
    })?
    .map_err(error)?;
    let mut body_idx = vec![-1i64; s.system.len()];
    for (k, b) in reported.bodies.iter().enumerate() {
        for &r in &b.rods {
            body_idx[r as usize] = k as i64;
        }
    }
    Ok(PyCompression {
        body_idx,
        spans: reported.bodies.iter().map(|b| b.spans).collect(),
        spanning: s.report.rigid_spanning,
        runs_spanning: s.report.runs_spanning,
        run: reported.run,
        report: serde_json::to_string(&s.report).map_err(value_error)?,
    })
}
