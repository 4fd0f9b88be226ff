//! The integration tests: one binary, one module per concern.

mod bench;
mod bench_truth;
mod charts;
mod cli;
mod contacts;
mod defects;
mod engine;
mod enumerate;
mod fallback;
mod float;
mod fss;
mod graphio;
mod layers;
mod mine;
mod planes;
mod projection;
mod rank;
mod rigidity;
mod rulefiles;
mod rules;
mod sample;
mod spanning;
mod stability;
mod threshold;
mod truth;

use std::path::PathBuf;

/// An empty scratch directory of one test: the process id and the test's
/// own name, so tests running in parallel never share (or delete) a folder.
pub fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rgc-it-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
