//! The cost of loaded rule sets against the base engine (`rgc bench
//! --rule-sets`): each set's compression time as a ratio to the base
//! engine's on the same graph in the same repetition, on the reference
//! systems of gamma 23 and 98; the work behind it (tasks, searches, merges);
//! and the time to load, verify and compile each set.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use super::measure::one_thread;
use crate::contacts;
use crate::engine::{self, CompiledRule, Engine, RuleSet, Work};
use crate::graph::ContactGraph;
use crate::math::stats::median;
use crate::rods::{RodParams, RodSystem};
use crate::{Error, Result, rule_file};

/// The systems rule sets are timed on: (gamma, density, box side).
pub const RULE_SYSTEMS: [(f64, f64, f64); 2] = [(23.0, 40.0, 10.0), (98.0, 190.0, 10.0)];

/// A named rule set: its files.
#[derive(Clone, Debug, Serialize)]
pub struct RuleSetFiles {
    pub name: String,
    pub files: Vec<PathBuf>,
}

impl std::str::FromStr for RuleSetFiles {
    type Err = Error;

    /// `NAME=FILE[,FILE...]`.
    fn from_str(s: &str) -> Result<Self> {
        let (name, files) = s.split_once('=').ok_or_else(|| {
            Error::Parameter(format!("rule set {s:?} is not NAME=FILE[,FILE...]"))
        })?;
        let files: Vec<PathBuf> = files
            .split(',')
            .filter(|f| !f.is_empty())
            .map(PathBuf::from)
            .collect();
        if name.is_empty() || name == "base" || files.is_empty() {
            return Err(Error::Parameter(format!(
                "rule set {s:?} needs a name other than base and at least one file"
            )));
        }
        Ok(RuleSetFiles {
            name: name.to_string(),
            files,
        })
    }
}

/// The default rule sets, from the project's motif directory `dir`: the
/// 138 extended rules (rods-6, rods-8, mixed-4), those with rods-9 and
/// rods-10 where both files exist (and with mixed-5 too where it exists),
/// and the mined rules.
pub fn default_rule_sets(dir: &Path) -> Vec<RuleSetFiles> {
    let set = |name: &str, files: &[&str]| RuleSetFiles {
        name: name.to_string(),
        files: files.iter().map(|f| dir.join(f)).collect(),
    };
    let mut sets = vec![set(
        "extended",
        &["rods-6.json", "rods-8.json", "mixed-4.json"],
    )];
    let exists = |f: &str| dir.join(f).is_file();
    if exists("rods-9.json") && exists("rods-10.json") {
        let rods = [
            "rods-6.json",
            "rods-8.json",
            "rods-9.json",
            "rods-10.json",
            "mixed-4.json",
        ];
        sets.push(set("rods-10+mixed-4", &rods));
        if exists("mixed-5.json") {
            let all: Vec<&str> = rods.iter().copied().chain(["mixed-5.json"]).collect();
            sets.push(set("rods-10+mixed-5", &all));
        }
    }
    sets.push(set("mined", &["mined.json"]));
    sets
}

/// A rule set loaded, with the time it took.
pub struct LoadedSet {
    pub files: RuleSetFiles,
    pub rules: Vec<CompiledRule>,
    /// Reading the files and verifying every rule (exact rank).
    pub seconds_verify: f64,
    /// Compiling the rules for matching and building the rule set's
    /// catalog, which every compression with it shares.
    pub seconds_compile: f64,
}

/// Loads, verifies and compiles one rule set, timing each part; every file must exist.
pub fn load_set(files: &RuleSetFiles) -> Result<LoadedSet> {
    if let Some(missing) = files.files.iter().find(|p| !p.is_file()) {
        return Err(Error::Parameter(format!(
            "rule file {} of rule set {} not found",
            missing.display(),
            files.name
        )));
    }
    let t = Instant::now();
    let rules = rule_file::load_rules(&files.files)?;
    let seconds_verify = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let rules: Vec<CompiledRule> = rules.iter().map(CompiledRule::new).collect();
    engine::prepare(&rules);
    let seconds_compile = t.elapsed().as_secs_f64();
    Ok(LoadedSet {
        files: files.clone(),
        rules,
        seconds_verify,
        seconds_compile,
    })
}

/// One rule set's load.
#[derive(Clone, Debug, Serialize)]
pub struct LoadRow {
    pub name: String,
    pub files: Vec<PathBuf>,
    pub n_rules: usize,
    pub n_rods_only: usize,
    pub seconds_verify: f64,
    pub seconds_compile: f64,
    pub seconds_total: f64,
}

/// One rule set (or the base engine) on one system, medians over the repetitions.
#[derive(Clone, Debug, Serialize)]
pub struct SetRow {
    pub gamma: f64,
    pub density: f64,
    pub box_len: f64,
    /// `base` for the base engine alone.
    pub name: String,
    pub n_rules: usize,
    pub seconds: f64,
    /// The median over repetitions of its time over the base engine's on
    /// the same graph in the same repetition (1 for the base engine).
    pub ratio_to_base: f64,
    /// What one compression did (medians over the repetitions).
    pub rod_tasks: f64,
    pub pair_tasks: f64,
    pub attempts: f64,
    pub merges: f64,
    pub rule_merges: f64,
    /// Seconds spent matching loaded rules (and keeping their index), in
    /// a second run of each repetition with a clock around that work.
    pub seconds_rules: f64,
    /// The rest of that timed run over the base engine's own timed run:
    /// the base engine's work with these rules, relative to without them,
    /// the median over repetitions. It grows with the merges the rules
    /// make: the price of the extra rigidity they find, not of matching.
    pub base_work_ratio: f64,
}

/// Everything `rgc bench --rule-sets` measures in one run.
#[derive(Clone, Debug, Serialize)]
pub struct RulesReport {
    pub repeat: usize,
    pub loads: Vec<LoadRow>,
    pub rows: Vec<SetRow>,
}

/// Times the base engine and every set on each of [`RULE_SYSTEMS`],
/// `repeat` times (repetition `k` on the systems of seed `k`), on one
/// thread. Within a repetition the engines run one after another on the
/// same graph, the first one shifting by one each repetition, so a change
/// of load biases them alike and the ratios hold.
pub fn run(repeat: usize, sets: &[LoadedSet]) -> RulesReport {
    one_thread(|| {
        let engines: Vec<(&str, Engine)> = std::iter::once(("base", Engine::base(RuleSet::Sound)))
            .chain(sets.iter().map(|s| {
                (
                    s.files.name.as_str(),
                    Engine::with_rules(RuleSet::Sound, &s.rules),
                )
            }))
            .collect();
        let mut rows = Vec::new();
        let mut samples: Vec<Vec<Vec<(f64, f64, Work)>>> =
            vec![vec![Vec::new(); engines.len()]; RULE_SYSTEMS.len()];
        for k in 0..repeat.max(1) {
            for (s, &(gamma, density, box_len)) in RULE_SYSTEMS.iter().enumerate() {
                let params = RodParams::new(gamma, box_len, density).expect("a reference system");
                let system = RodSystem::generate(params, k as u64);
                let graph = ContactGraph::from_contacts(system.len(), &contacts::detect(&system));
                for i in 0..engines.len() {
                    let e = (i + k) % engines.len();
                    let engine = &engines[e].1;
                    let t = Instant::now();
                    std::hint::black_box(engine.compress_measured(&graph, k as u64, false));
                    let seconds = t.elapsed().as_secs_f64();
                    // Again with the clock on loaded rules, for the split.
                    let t = Instant::now();
                    let (_, work) = engine.compress_measured(&graph, k as u64, true);
                    let timed = t.elapsed().as_secs_f64();
                    samples[s][e].push((seconds, timed, work));
                }
            }
        }
        for (s, &(gamma, density, box_len)) in RULE_SYSTEMS.iter().enumerate() {
            for (e, (name, engine)) in engines.iter().enumerate() {
                let t = &samples[s][e];
                let med = |f: &dyn Fn(&(f64, f64, Work)) -> f64| {
                    median(&mut t.iter().map(f).collect::<Vec<_>>())
                };
                let base = &samples[s][0];
                let mut ratios: Vec<f64> = t.iter().zip(base).map(|(a, b)| a.0 / b.0).collect();
                let mut base_work: Vec<f64> = t
                    .iter()
                    .zip(base)
                    .map(|(a, b)| (a.1 - a.2.rule_nanos as f64 * 1e-9) / b.1)
                    .collect();
                rows.push(SetRow {
                    gamma,
                    density,
                    box_len,
                    name: name.to_string(),
                    n_rules: engine.extra.len(),
                    seconds: med(&|x| x.0),
                    ratio_to_base: median(&mut ratios),
                    rod_tasks: med(&|x| x.2.rod_tasks as f64),
                    pair_tasks: med(&|x| x.2.pair_tasks as f64),
                    attempts: med(&|x| x.2.attempts as f64),
                    merges: med(&|x| x.2.merges as f64),
                    rule_merges: med(&|x| x.2.rule_merges as f64),
                    seconds_rules: med(&|x| x.2.rule_nanos as f64 * 1e-9),
                    base_work_ratio: median(&mut base_work),
                });
            }
        }
        let loads = sets
            .iter()
            .map(|s| LoadRow {
                name: s.files.name.clone(),
                files: s.files.files.clone(),
                n_rules: s.rules.len(),
                n_rods_only: s.rules.iter().filter(|r| r.rods_only()).count(),
                seconds_verify: s.seconds_verify,
                seconds_compile: s.seconds_compile,
                seconds_total: s.seconds_verify + s.seconds_compile,
            })
            .collect();
        RulesReport {
            repeat: repeat.max(1),
            loads,
            rows,
        }
    })
}
