//! The foundation benchmark: contact detection and one compression, single
//! threaded, on the reference systems of the paper's aspect ratios; and the
//! truth benchmark: how the cost of exact whole-system rigidity grows with
//! the system, and so how large a box truth can decide.

use serde::{Deserialize, Serialize};
use std::time::Instant;

use crate::contacts;
use crate::engine::{self, CompiledRule, Engine, RuleSet};
use crate::graph::ContactGraph;
use crate::math::stats::{self, median};
use crate::progress::Progress;
use crate::rods::{RodParams, RodSystem};
use crate::spanning::Criterion;
use crate::truth::{self, TruthOptions};
use crate::usage::thread_cpu_seconds;
pub use crate::usage::{peak_rss_mib, reset_peak_rss};

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

/// Runs `f` on a pool of one thread: the figures are per core, whatever the
/// machine.
fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool")
        .install(f)
}

/// Checks that `max_rods` leaves at least one reference system to run.
pub fn check_max_rods(max_rods: usize) -> crate::Result<()> {
    let smallest = SYSTEMS
        .iter()
        .filter_map(|&(gamma, density, l)| RodParams::new(gamma, l, density).ok())
        .map(|p| p.n_rods())
        .min()
        .unwrap_or(0);
    if max_rods < smallest {
        return Err(crate::Error::Parameter(format!(
            "--max-rods {max_rods} leaves no reference system to run (the smallest has {smallest} rods)"
        )));
    }
    Ok(())
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

/// Aspect ratio of the truth benchmark's systems.
pub const TRUTH_GAMMA: f64 = 23.0;

/// Densities either side of truth's rigidity threshold at gamma 23, where
/// the rigid and flexible regions are both large and truth works hardest.
pub const TRUTH_DENSITIES: [f64; 2] = [34.0, 38.0];

/// The density of the reach: the denser, slower one.
pub const REACH_DENSITY: f64 = 38.0;

/// The largest box side a prediction considers.
pub const PREDICT_MAX_BOX: usize = 100;

/// What the truth benchmark runs: every density, box side and seed `1..=seeds`.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthPlan {
    pub densities: Vec<f64>,
    pub boxes: Vec<usize>,
    pub seeds: u64,
}

impl Default for TruthPlan {
    /// Boxes 3 to 7 and three seeds: about a minute on one core (box 8
    /// alone takes about 40 s per seed at density 38).
    fn default() -> Self {
        TruthPlan {
            densities: TRUTH_DENSITIES.to_vec(),
            boxes: (3..=7).collect(),
            seeds: 3,
        }
    }
}

impl TruthPlan {
    /// Checks every system of the plan before the first one runs.
    pub fn check(&self) -> crate::Result<()> {
        if self.densities.is_empty() || self.boxes.is_empty() || self.seeds == 0 {
            return Err(crate::Error::Parameter(
                "the truth benchmark needs at least one density, box side and seed".into(),
            ));
        }
        for &density in &self.densities {
            for &l in &self.boxes {
                RodParams::new(TRUTH_GAMMA, l as f64, density)?;
            }
        }
        Ok(())
    }
}

/// Figures of truth on one system.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthRow {
    pub gamma: f64,
    pub density: f64,
    pub box_len: usize,
    pub seed: u64,
    pub n_rods: usize,
    pub core_rods: usize,
    pub parts: usize,
    pub columns: usize,
    pub rows: usize,
    pub rank: Option<usize>,
    pub decided: bool,
    /// Rows times columns of the largest dense front of the elimination.
    pub largest_front: Option<(usize, usize)>,
    /// Wall time of `truth::of_system` on one thread.
    pub seconds: f64,
    /// CPU time of the thread that ran it, to 10 ms: unlike the wall time,
    /// not inflated when other processes share the cores.
    pub cpu_seconds: Option<f64>,
    /// Peak resident memory of the process while truth ran (the system and
    /// its contacts included), MiB.
    pub peak_mib: f64,
    /// What truth added to the resident memory: the peak above what was
    /// resident just before it, MiB.
    pub truth_mib: f64,
    /// Whether the peak was reset before truth ran. Where it was not, both
    /// figures are the process's high-water mark, which only ever rises.
    pub peak_reset: bool,
}

/// Truth on the system of `density`, box side `l` and `seed`, on a pool of
/// one thread, with its time and peak memory.
///
/// The memory figures are clean only in a fresh process: in one that ran
/// other systems before, pages the allocator kept from them are reused
/// without showing as growth. So `rgc bench --truth` runs each system in a
/// child process of its own.
pub fn measure_truth(density: f64, l: usize, seed: u64) -> crate::Result<TruthRow> {
    measure_truth_at(TRUTH_GAMMA, density, l, seed)
}

/// [`measure_truth`] at aspect ratio `gamma`.
pub fn measure_truth_at(gamma: f64, density: f64, l: usize, seed: u64) -> crate::Result<TruthRow> {
    let params = RodParams::new(gamma, l as f64, density)?;
    Ok(one_thread(|| {
        let system = RodSystem::generate(params, seed);
        let found = contacts::detect(&system);
        let graph = ContactGraph::from_contacts(system.len(), &found);
        let peak_reset = reset_peak_rss();
        let before = peak_rss_mib();
        let cpu_before = thread_cpu_seconds();
        let start = Instant::now();
        let t = truth::of_system(
            &system,
            &found,
            &graph,
            Criterion::Wrap,
            TruthOptions::seeded(seed),
        );
        let seconds = start.elapsed().as_secs_f64();
        let cpu_seconds = thread_cpu_seconds().zip(cpu_before).map(|(b, a)| b - a);
        let peak_mib = peak_rss_mib();
        TruthRow {
            gamma,
            density,
            box_len: l,
            seed,
            n_rods: t.n_rods,
            core_rods: t.core_rods,
            parts: t.parts,
            columns: t.columns,
            rows: t.rows,
            rank: t.rank,
            decided: t.decided(),
            largest_front: t.largest_front,
            seconds,
            cpu_seconds,
            peak_mib,
            truth_mib: (peak_mib - before).max(0.0),
            peak_reset,
        }
    }))
}

/// How a cost grows with the number of rods: `y = prefactor * x^exponent`,
/// fitted by least squares of `log y` against `log x`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Growth {
    pub exponent: f64,
    pub prefactor: f64,
    /// R² of the fit in logarithms.
    pub r2: f64,
    pub points: usize,
}

impl Growth {
    /// The fit through the points with both coordinates positive; `None`
    /// without two distinct `x` among them.
    pub fn fit(points: impl IntoIterator<Item = (f64, f64)>) -> Option<Growth> {
        let logs: Vec<(f64, f64)> = points
            .into_iter()
            .filter(|&(x, y)| x > 0.0 && y > 0.0)
            .map(|(x, y)| (x.ln(), y.ln()))
            .collect();
        let stats::Fit { beta, r2, .. } = stats::line(&logs)?;
        Some(Growth {
            exponent: beta[1],
            prefactor: beta[0].exp(),
            r2,
            points: logs.len(),
        })
    }

    pub fn at(&self, x: f64) -> f64 {
        self.prefactor * x.powf(self.exponent)
    }
}

/// The systems of the aspect-ratio benchmark of truth, `(gamma, density,
/// box side)`: each near its aspect ratio's true threshold (rho V_ex about
/// 2.7), where truth works hardest, in boxes of growing size.
pub const ASPECT_SYSTEMS: [(f64, f64, usize); 10] = [
    (23.0, 34.0, 8),
    (23.0, 34.0, 10),
    (23.0, 34.0, 12),
    (48.0, 78.0, 5),
    (48.0, 78.0, 6),
    (48.0, 78.0, 7),
    (98.0, 165.0, 4),
    (98.0, 165.0, 5),
    (98.0, 165.0, 6),
    (98.0, 165.0, 7),
];

/// The largest system, added on request: minutes and gigabytes.
pub const ASPECT_LARGE: (f64, f64, usize) = (98.0, 165.0, 10);

/// The pair whose cost per rod the benchmark compares: slender rods
/// against gamma 23 at about the same number of rods (56,595 and 58,752).
pub const ASPECT_PAIR: [(f64, usize); 2] = [(98.0, 7), (23.0, 12)];

/// How truth's CPU time and memory grow with the rods at one aspect ratio.
#[derive(Clone, Debug, Serialize)]
pub struct AspectScaling {
    pub gamma: f64,
    pub time: Option<Growth>,
    pub memory: Option<Growth>,
}

/// What the aspect-ratio benchmark of truth found.
#[derive(Clone, Debug, Serialize)]
pub struct AspectReport {
    pub rows: Vec<TruthRow>,
    pub scaling: Vec<AspectScaling>,
    /// CPU seconds per rod of the first system of [`ASPECT_PAIR`] over
    /// that of the second, measured in this run.
    pub per_rod_ratio: Option<f64>,
}

/// Truth on every system of [`ASPECT_SYSTEMS`] (and [`ASPECT_LARGE`] if
/// `large`), seed 1, each by `measure(gamma, density, box, seed)`, with the
/// growth per aspect ratio and the cost per rod of [`ASPECT_PAIR`].
pub fn run_truth_aspects(
    large: bool,
    mut measure: impl FnMut(f64, f64, usize, u64) -> crate::Result<TruthRow>,
    progress: &impl Progress,
) -> crate::Result<AspectReport> {
    let systems: Vec<_> = ASPECT_SYSTEMS
        .iter()
        .copied()
        .chain(large.then_some(ASPECT_LARGE))
        .collect();
    progress.start("truth systems", systems.len() as u64);
    let mut rows = Vec::new();
    for (gamma, density, l) in systems {
        rows.push(measure(gamma, density, l, 1)?);
        progress.advance(1);
    }
    progress.finish();
    let cpu = |r: &TruthRow| r.cpu_seconds.unwrap_or(r.seconds);
    let mut gammas: Vec<f64> = rows.iter().map(|r| r.gamma).collect();
    gammas.dedup();
    let scaling = gammas
        .into_iter()
        .map(|gamma| {
            let at = || rows.iter().filter(move |r| r.gamma == gamma);
            AspectScaling {
                gamma,
                time: Growth::fit(at().map(|r| (r.n_rods as f64, cpu(r)))),
                memory: Growth::fit(at().map(|r| (r.n_rods as f64, r.truth_mib))),
            }
        })
        .collect();
    let per_rod = |(gamma, l): (f64, usize)| {
        rows.iter()
            .find(|r| r.gamma == gamma && r.box_len == l)
            .map(|r| cpu(r) / r.n_rods as f64)
    };
    let per_rod_ratio = per_rod(ASPECT_PAIR[0])
        .zip(per_rod(ASPECT_PAIR[1]))
        .map(|(a, b)| a / b);
    Ok(AspectReport {
        rows,
        scaling,
        per_rod_ratio,
    })
}

/// Box sides of the tail fit: the largest ones of a plan.
pub const TAIL_BOXES: usize = 3;

/// How time and truth's memory grow with the number of rods at one density.
#[derive(Clone, Debug, Serialize)]
pub struct Scaling {
    pub density: f64,
    pub time: Option<Growth>,
    /// The time law of the [`TAIL_BOXES`] largest box sides alone. On small
    /// boxes fixed costs hide the growth of the dense fronts, so the law of
    /// all sizes is too flat to extrapolate; predictions use this one.
    pub time_tail: Option<Growth>,
    /// Fitted to `truth_mib`, the part that grows with truth's fronts.
    pub memory: Option<Growth>,
}

/// The largest box side whose system at `density` the time law puts within
/// `max_seconds` (up to [`PREDICT_MAX_BOX`]); `None` if not even the
/// smallest valid box.
pub fn predict_largest_box(time: &Growth, density: f64, max_seconds: f64) -> Option<usize> {
    (1..=PREDICT_MAX_BOX)
        .filter_map(|l| RodParams::new(TRUTH_GAMMA, l as f64, density).ok())
        .take_while(|p| time.at(p.n_rods() as f64) <= max_seconds)
        .last()
        .map(|p| p.box_len as usize)
}

/// The measured reach: one system (seed 1) per box side 3, 4, ... at
/// [`REACH_DENSITY`] until one takes longer than `max_seconds` or the cap.
#[derive(Clone, Debug, Serialize)]
pub struct Reach {
    pub max_seconds: f64,
    pub max_box: usize,
    /// The largest box side that finished within `max_seconds`.
    pub largest_box: Option<usize>,
    /// Whether a system took too long (else the cap stopped the search, and
    /// the true reach may be larger).
    pub stopped_by_time: bool,
    pub rows: Vec<TruthRow>,
}

/// Everything the truth benchmark found.
#[derive(Clone, Debug, Serialize)]
pub struct TruthReport {
    pub rows: Vec<TruthRow>,
    pub scaling: Vec<Scaling>,
    pub max_seconds: f64,
    /// The largest box side within `max_seconds` at [`REACH_DENSITY`] by the
    /// tail time law: a prediction, not a measurement.
    pub predicted_largest_box: Option<usize>,
    pub reach: Option<Reach>,
}

/// Runs `plan`, smallest boxes first, each system through `measure` (such
/// as [`measure_truth`]), fits the growth with the number of rods per
/// density and predicts the reach within `max_seconds` from the tail; with
/// `reach_max_box`, also measures the reach up to that box side (the last
/// system alone can take longer than `max_seconds`).
pub fn run_truth(
    plan: &TruthPlan,
    max_seconds: f64,
    reach_max_box: Option<usize>,
    mut measure: impl FnMut(f64, usize, u64) -> crate::Result<TruthRow>,
    progress: &impl Progress,
) -> crate::Result<TruthReport> {
    plan.check()?;
    if !(max_seconds.is_finite() && max_seconds > 0.0) {
        return Err(crate::Error::Parameter(format!(
            "the time limit must be a positive number of seconds, got {max_seconds}"
        )));
    }
    let mut boxes = plan.boxes.clone();
    boxes.sort_unstable();
    boxes.dedup();
    let mut rows = Vec::new();
    progress.start(
        "truth systems",
        (boxes.len() * plan.densities.len()) as u64 * plan.seeds,
    );
    for &l in &boxes {
        for &density in &plan.densities {
            for seed in 1..=plan.seeds {
                rows.push(measure(density, l, seed)?);
                progress.advance(1);
            }
        }
    }
    progress.finish();
    let tail = boxes[boxes.len().saturating_sub(TAIL_BOXES)];
    let scaling: Vec<Scaling> = plan
        .densities
        .iter()
        .map(|&density| {
            let at = || rows.iter().filter(move |r| r.density == density);
            let time = |r: &TruthRow| (r.n_rods as f64, r.seconds);
            Scaling {
                density,
                time: Growth::fit(at().map(time)),
                time_tail: Growth::fit(at().filter(|r| r.box_len >= tail).map(time)),
                memory: Growth::fit(at().map(|r| (r.n_rods as f64, r.truth_mib))),
            }
        })
        .collect();
    let predicted_largest_box = scaling
        .iter()
        .find(|s| s.density == REACH_DENSITY)
        .and_then(|s| s.time_tail)
        .and_then(|law| predict_largest_box(&law, REACH_DENSITY, max_seconds));
    let reach = reach_max_box
        .map(|max_box| measure_reach(max_seconds, max_box, &mut measure, progress))
        .transpose()?;
    Ok(TruthReport {
        rows,
        scaling,
        max_seconds,
        predicted_largest_box,
        reach,
    })
}

fn measure_reach(
    max_seconds: f64,
    max_box: usize,
    measure: &mut impl FnMut(f64, usize, u64) -> crate::Result<TruthRow>,
    progress: &impl Progress,
) -> crate::Result<Reach> {
    let mut reach = Reach {
        max_seconds,
        max_box,
        largest_box: None,
        stopped_by_time: false,
        rows: Vec::new(),
    };
    for l in 3..=max_box {
        progress.note(&format!("reach: box {l} at density {REACH_DENSITY}"));
        let row = measure(REACH_DENSITY, l, 1)?;
        let within = row.seconds <= max_seconds;
        reach.rows.push(row);
        if !within {
            reach.stopped_by_time = true;
            break;
        }
        reach.largest_box = Some(l);
    }
    Ok(reach)
}
