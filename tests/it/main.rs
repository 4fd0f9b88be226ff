//! The integration tests: one binary, one module per concern.

mod audits;
mod battery;
mod bench;
mod bench_truth;
mod charts;
mod cli;
mod contacts;
mod defects;
mod dumps;
mod engine;
mod ensembles;
mod enumerate;
mod fallback;
mod float;
mod fss;
mod graphio;
mod graphml;
mod horizon;
mod layers;
mod locality;
mod memory;
mod mine;
mod moduli;
mod planes;
mod projection;
mod rank;
mod render;
mod rigidity;
mod rodboxes;
mod rodfiles;
mod rulefiles;
mod rules;
mod sample;
mod spanning;
mod stability;
mod stamp;
mod stdin;
mod stiffening;
mod studies;
mod threshold;
mod truth;
mod truth_contract;
mod truth_draws;
mod truth_motions;
mod truth_strain;
mod truth_studies;
mod vtk;
mod workspaces;

use std::path::{Path, PathBuf};

/// An empty scratch directory of one test: the process id and the test's
/// own name, so tests running in parallel never share (or delete) a folder.
pub fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rgc-it-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A rod of unit length, for the tests that place rods by hand; [`cube`]
/// gives it its radius.
pub fn unit(center: nalgebra::Vector3<f64>, axis: nalgebra::Vector3<f64>) -> rgc::rods::Rod {
    rgc::rods::Rod::new(center, axis, 1.0, 0.0)
}

/// Unit rods with the radius of `params` in its periodic cube, taken as
/// they are: not checked, since some tests put centres outside the box on
/// purpose.
pub fn cube(params: rgc::rods::RodParams, rods: Vec<rgc::rods::Rod>) -> rgc::rods::RodSystem {
    let radius = params.radius();
    rgc::rods::RodSystem {
        domain: rgc::rods::Domain::cube(params.box_len),
        rods: rods
            .into_iter()
            .map(|r| rgc::rods::Rod::new(r.center, r.axis, 1.0, radius))
            .collect(),
    }
}

/// The CPU seconds of a study's first `n` sequences, summed from its
/// records as written (a record's wall time where it carries no CPU time):
/// what a variant reading those sequences must report. Sums, not an
/// ordering of them, since CPU comes in 10 ms ticks and a tiny sequence
/// may cost none.
pub fn cpu_of_first(study: &Path, n: u64) -> f64 {
    std::fs::read_to_string(study.join("records.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<rgc::threshold::sequence::Record>(l).unwrap())
        .filter(|r| r.index < n)
        .map(|r| r.cpu_seconds.unwrap_or(r.seconds))
        .sum()
}
