//! What loading rule sets costs before the engine can use them: reading the
//! files, verifying every rule by exact rank (in parallel over the rules,
//! on every thread: what a run pays) and compiling each for the engine.

use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use crate::engine::CompiledRule;
use crate::math::stats::median;
use crate::{Error, Result, rule_file};

/// The rule sets whose loading is timed, by name, with their files in the
/// project's motif directory: the rods-only sets to 10 rods with the mixed
/// ones to 4 components (the engine's target of 1,569 rules), the mixed
/// motifs of 5 components, and every extended set at once.
pub const LOAD_SETS: [(&str, &[&str]); 3] = [
    (
        "rods<=10+mixed<=4",
        &[
            "rods-6.json",
            "rods-8.json",
            "mixed-4.json",
            "rods-9.json",
            "rods-10.json",
        ],
    ),
    ("mixed-5", &["mixed-5.json"]),
    (
        "all extended",
        &[
            "rods-6.json",
            "rods-8.json",
            "mixed-4.json",
            "rods-9.json",
            "rods-10.json",
            "mixed-5.json",
        ],
    ),
];

/// The cost of loading one rule set (medians over the repetitions).
#[derive(Clone, Debug, Serialize)]
pub struct RuleLoadRow {
    pub name: String,
    pub files: Vec<String>,
    /// Rules loaded (repeats dropped).
    pub rules: usize,
    /// Reading, parsing and verifying every rule.
    pub seconds_load: f64,
    /// [`CompiledRule::new`] for every rule.
    pub seconds_compile: f64,
    /// Both, measured together per repetition.
    pub seconds: f64,
}

/// The rule sets' loading costs, on `threads` threads.
#[derive(Clone, Debug, Serialize)]
pub struct RuleLoadReport {
    pub threads: usize,
    pub repeat: usize,
    pub sets: Vec<RuleLoadRow>,
}

/// Times loading each of [`LOAD_SETS`] from `dir` `repeat` times, on the
/// current thread pool; every file must exist.
pub fn run_rule_load(dir: &Path, repeat: usize) -> Result<RuleLoadReport> {
    let mut sets = Vec::new();
    for (name, files) in LOAD_SETS {
        let paths: Vec<_> = files.iter().map(|f| dir.join(f)).collect();
        if let Some(missing) = paths.iter().find(|p| !p.is_file()) {
            return Err(Error::Parameter(format!(
                "rule file {} not found (--motifs names the directory of the project's rule files)",
                missing.display()
            )));
        }
        let (mut load, mut compile, mut both, mut rules) = (vec![], vec![], vec![], 0);
        for _ in 0..repeat {
            let t = Instant::now();
            let loaded = rule_file::load_rules(&paths)?;
            let loaded_at = t.elapsed().as_secs_f64();
            let compiled: Vec<CompiledRule> = loaded.iter().map(CompiledRule::new).collect();
            let total = t.elapsed().as_secs_f64();
            rules = compiled.len();
            load.push(loaded_at);
            compile.push(total - loaded_at);
            both.push(total);
        }
        sets.push(RuleLoadRow {
            name: name.to_string(),
            files: files.iter().map(|f| f.to_string()).collect(),
            rules,
            seconds_load: median(&mut load),
            seconds_compile: median(&mut compile),
            seconds: median(&mut both),
        });
    }
    Ok(RuleLoadReport {
        threads: rayon::current_num_threads(),
        repeat,
        sets,
    })
}
