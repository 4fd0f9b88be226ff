//! The foundation benchmark: contact detection and one compression, single
//! threaded, on the reference systems of the paper's aspect ratios, and the
//! project's rule sets timed against the base engine on the same graphs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use super::measure::one_thread;
use crate::contacts;
use crate::engine::{self, CompiledRule, Engine, RuleSet};
use crate::graph::ContactGraph;
use crate::math::stats::median;
use crate::rods::{RodParams, RodSystem};
use crate::usage::peak_rss_mib;
use crate::{Error, Result, rule_file};

/// The reference systems: (gamma, density, box side).
pub const SYSTEMS: [(f64, f64, f64); 4] = [
    (23.0, 40.0, 5.0),
    (23.0, 40.0, 10.0),
    (23.0, 40.0, 15.0),
    (98.0, 190.0, 10.0),
];

/// Figures for one system (medians over the repetitions).
#[derive(Clone, Debug, Serialize)]
pub struct BenchRow {
    pub gamma: f64,
    pub density: f64,
    pub box_len: f64,
    pub n_rods: usize,
    pub n_contacts: usize,
    pub seconds_generate: f64,
    pub seconds_detect: f64,
    pub seconds_compress: f64,
    /// Detection alone, per rod.
    pub detect_ns_per_rod: f64,
    /// Detection plus one compression, per rod.
    pub ns_per_rod: f64,
    /// Peak resident memory of the process after the first repetition of
    /// this system (systems run smallest first), MiB.
    pub peak_rss_mib: f64,
    pub components: usize,
    pub largest_body_rods: usize,
}

/// Checks that `max_rods` leaves at least one reference system to run.
pub fn check_max_rods(max_rods: usize) -> Result<()> {
    let smallest = SYSTEMS
        .iter()
        .filter_map(|&(gamma, density, l)| RodParams::new(gamma, l, density).ok())
        .map(|p| p.n_rods())
        .min()
        .unwrap_or(0);
    if max_rods < smallest {
        return Err(Error::Parameter(format!(
            "--max-rods {max_rods} leaves no reference system to run (the smallest has {smallest} rods)"
        )));
    }
    Ok(())
}

/// The rule sets the benchmark times against the base engine, by name, with
/// their files in the project's motif directory.
pub const RULE_SETS: [(&str, &[&str]); 2] = [
    ("extended", &["rods-6.json", "rods-8.json", "mixed-4.json"]),
    ("mined", &["mined.json"]),
];

/// Loads and verifies the [`RULE_SETS`] from `dir`; every file must exist.
pub fn load_rule_sets(dir: &Path) -> Result<Vec<(&'static str, Vec<CompiledRule>)>> {
    RULE_SETS
        .iter()
        .map(|&(name, files)| {
            let paths: Vec<PathBuf> = files.iter().map(|f| dir.join(f)).collect();
            if let Some(missing) = paths.iter().find(|p| !p.is_file()) {
                return Err(Error::Parameter(format!(
                    "rule file {} not found (--motifs names the directory of the project's rule files; --no-rules times none)",
                    missing.display()
                )));
            }
            let rules = rule_file::load_rules(&paths)?;
            Ok((name, rules.iter().map(CompiledRule::new).collect()))
        })
        .collect()
}

/// A named set of loaded rules whose compression cost is set against the
/// base engine's on the same graphs.
pub struct RuleSetBench<'a> {
    pub name: String,
    pub rules: &'a [CompiledRule],
}

/// The cost of one rule set on the rules system (medians over repetitions).
#[derive(Clone, Debug, Serialize)]
pub struct RulesRow {
    pub name: String,
    pub n_rules: usize,
    pub seconds_compress: f64,
    /// Its compression time over the base engine's, the median of the
    /// ratios measured on the same graph in the same repetition.
    pub ratio_to_base: f64,
}

/// Everything the foundation benchmark measures in one run.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub systems: Vec<BenchRow>,
    /// Detection per rod at gamma 98 over gamma 23 (both L = 10), the
    /// median of the ratios of each repetition; `None` when either system
    /// was left out.
    pub detect_ratio_98_to_23: Option<f64>,
    /// The system the rule sets were timed on, `(gamma, density, box)`.
    pub rules_system: (f64, f64, f64),
    pub rules: Vec<RulesRow>,
}

/// The system on which rule sets are timed: gamma 23 at L = 10.
pub const RULES_SYSTEM: (f64, f64, f64) = (23.0, 40.0, 10.0);

/// Runs the systems up to `max_rods` rods in order of size, `repeat` times
/// each, on one thread, and times each rule set against the base engine on
/// [`RULES_SYSTEM`]. Repetitions are interleaved across systems, so a change
/// of load during the run biases every system alike and the ratios hold.
pub fn run(repeat: usize, max_rods: usize, sets: &[RuleSetBench]) -> BenchReport {
    one_thread(|| {
        let params: Vec<RodParams> = SYSTEMS
            .iter()
            .map(|&(gamma, density, box_len)| {
                RodParams::new(gamma, box_len, density).expect("valid reference system")
            })
            .filter(|p| p.n_rods() <= max_rods)
            .collect();
        let mut samples: Vec<Vec<Timed>> = vec![Vec::new(); params.len()];
        let mut rules: Vec<Vec<(f64, f64)>> = vec![Vec::new(); sets.len()];
        for k in 0..repeat.max(1) as u64 {
            for (p, out) in params.iter().zip(&mut samples) {
                out.push(time_once(*p, k));
            }
            if !sets.is_empty() {
                time_rules(k, sets, &mut rules);
            }
        }
        let systems: Vec<BenchRow> = params
            .iter()
            .zip(&mut samples)
            .map(|(p, s)| summarize(*p, s))
            .collect();
        let at = |gamma: f64| {
            params
                .iter()
                .position(|p| p.gamma == gamma && p.box_len == 10.0)
        };
        let detect_ratio_98_to_23 = at(98.0).zip(at(23.0)).map(|(a, b)| {
            let mut r: Vec<f64> = samples[a]
                .iter()
                .zip(&samples[b])
                .map(|(x, y)| x.detect_per_rod() / y.detect_per_rod())
                .collect();
            median(&mut r)
        });
        let rules = sets
            .iter()
            .zip(&mut rules)
            .map(|(set, t)| RulesRow {
                name: set.name.clone(),
                n_rules: set.rules.len(),
                seconds_compress: median(&mut t.iter().map(|x| x.0).collect::<Vec<_>>()),
                ratio_to_base: median(&mut t.iter().map(|x| x.0 / x.1).collect::<Vec<_>>()),
            })
            .collect();
        BenchReport {
            systems,
            detect_ratio_98_to_23,
            rules_system: RULES_SYSTEM,
            rules,
        }
    })
}

/// One repetition on one system.
#[derive(Clone)]
struct Timed {
    generate: f64,
    detect: f64,
    compress: f64,
    n_rods: usize,
    n_contacts: usize,
    components: usize,
    largest: usize,
    peak_rss_mib: f64,
}

impl Timed {
    fn detect_per_rod(&self) -> f64 {
        self.detect / self.n_rods.max(1) as f64
    }
}

fn time_once(params: RodParams, k: u64) -> Timed {
    let t = Instant::now();
    let system = RodSystem::generate(params, k);
    let generate = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let found = contacts::detect(&system);
    let graph = ContactGraph::from_contacts(system.len(), &found);
    let detect = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let c = engine::compress(&graph, RuleSet::Sound, k);
    Timed {
        generate,
        detect,
        compress: t.elapsed().as_secs_f64(),
        n_rods: system.len(),
        n_contacts: found.len(),
        components: c.components,
        largest: c.largest_rods(),
        peak_rss_mib: peak_rss_mib(),
    }
}

/// Times the base engine and then each rule set on repetition `k`'s graph,
/// pushing (set's seconds, base seconds) per set.
fn time_rules(k: u64, sets: &[RuleSetBench], out: &mut [Vec<(f64, f64)>]) {
    let (gamma, density, box_len) = RULES_SYSTEM;
    let params = RodParams::new(gamma, box_len, density).expect("valid rules system");
    let system = RodSystem::generate(params, k);
    let graph = ContactGraph::from_contacts(system.len(), &contacts::detect(&system));
    let time = |engine: Engine| {
        let t = Instant::now();
        std::hint::black_box(engine.compress(&graph, &[], k).expect("no declared bodies"));
        t.elapsed().as_secs_f64()
    };
    let base = time(Engine::base(RuleSet::Sound));
    for (set, o) in sets.iter().zip(out) {
        o.push((time(Engine::with_rules(RuleSet::Sound, set.rules)), base));
    }
}

fn summarize(params: RodParams, s: &[Timed]) -> BenchRow {
    let med = |f: fn(&Timed) -> f64| median(&mut s.iter().map(f).collect::<Vec<_>>());
    let (detect, compress) = (med(|t| t.detect), med(|t| t.compress));
    let last = s.last().expect("at least one repetition");
    BenchRow {
        gamma: params.gamma,
        density: params.density,
        box_len: params.box_len,
        n_rods: last.n_rods,
        n_contacts: last.n_contacts,
        seconds_generate: med(|t| t.generate),
        seconds_detect: detect,
        seconds_compress: compress,
        detect_ns_per_rod: detect * 1e9 / last.n_rods.max(1) as f64,
        ns_per_rod: (detect + compress) * 1e9 / last.n_rods.max(1) as f64,
        peak_rss_mib: s[0].peak_rss_mib,
        components: last.components,
        largest_body_rods: last.largest,
    }
}
