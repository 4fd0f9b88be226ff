//! The truth benchmark: how the cost of exact whole-system rigidity grows
//! with the system, and so how large a box truth can decide; each system
//! measured in a process of its own.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::growth::Growth;
use super::measure::{one_thread, run_child};
use crate::network::Network;
use crate::progress::Progress;
use crate::rods::{RodParams, RodSystem};
use crate::sample::Rods;
use crate::spanning::Criterion;
use crate::truth::{self, TruthOptions};
use crate::usage::{peak_rss_mib, reset_peak_rss, thread_cpu_seconds};
use crate::{Error, Result};

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
    /// What the strain rank costs: CPU seconds of truth again without the
    /// strain columns, then with them, after the run above in the same
    /// process (both warm, so neither pays the first run's page faults).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strain_cost: Option<StrainCost>,
}

/// CPU seconds of truth on one system without and with the strain columns.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct StrainCost {
    pub without: f64,
    pub with: f64,
}

impl StrainCost {
    /// With over without.
    pub fn ratio(&self) -> f64 {
        self.with / self.without
    }
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
        let network = Network::detect(RodSystem::generate(params, seed));
        let peak_reset = reset_peak_rss();
        let before = peak_rss_mib();
        let cpu_before = thread_cpu_seconds();
        let start = Instant::now();
        let t = truth::of_system(network.view(), Criterion::Wrap, TruthOptions::seeded(seed));
        let seconds = start.elapsed().as_secs_f64();
        let cpu_seconds = thread_cpu_seconds().zip(cpu_before).map(|(b, a)| b - a);
        let peak_mib = peak_rss_mib();
        let cpu = |strain: bool| {
            let before = thread_cpu_seconds();
            let opts = TruthOptions {
                strain,
                ..TruthOptions::seeded(seed)
            };
            truth::of_system(network.view(), Criterion::Wrap, opts);
            thread_cpu_seconds().zip(before).map(|(b, a)| b - a)
        };
        let strain_cost = cpu(false)
            .zip(cpu(true))
            .map(|(without, with)| StrainCost { without, with });
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
            rank: t.outcome.rank(),
            decided: t.decided(),
            largest_front: t.largest_front,
            seconds,
            cpu_seconds,
            peak_mib,
            truth_mib: (peak_mib - before).max(0.0),
            peak_reset,
            strain_cost,
        }
    }))
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

/// One system of the truth benchmark, `gamma,density,box,seed` on the
/// command line: what a child process measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthSystem {
    pub gamma: f64,
    pub density: f64,
    pub box_len: usize,
    pub seed: u64,
}

impl std::fmt::Display for TruthSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{},{},{},{}",
            self.gamma, self.density, self.box_len, self.seed
        )
    }
}

impl std::str::FromStr for TruthSystem {
    type Err = Error;

    fn from_str(spec: &str) -> Result<Self> {
        let bad = || {
            Error::Parameter(format!(
                "--truth-system wants gamma,density,box,seed, got {spec:?}"
            ))
        };
        let [gamma, density, l, seed] = spec.split(',').collect::<Vec<_>>()[..] else {
            return Err(bad());
        };
        Ok(TruthSystem {
            gamma: gamma.trim().parse().map_err(|_| bad())?,
            density: density.trim().parse().map_err(|_| bad())?,
            box_len: l.trim().parse().map_err(|_| bad())?,
            seed: seed.trim().parse().map_err(|_| bad())?,
        })
    }
}

impl TruthSystem {
    /// [`measure_truth_at`] on this system, in this process.
    pub fn measure(&self) -> Result<TruthRow> {
        measure_truth_at(self.gamma, self.density, self.box_len, self.seed)
    }

    /// Truth on this system in a child process of its own, `rgc bench
    /// --truth-system` of the executable `rgc`, so that its peak memory is
    /// its own: in one long process, pages the allocator kept from earlier
    /// systems would hide what later ones need. (The standard library
    /// cannot read a child's peak memory, so the child reports it.)
    pub fn measure_in_child(&self, rgc: &Path) -> Result<TruthRow> {
        let spec = self.to_string();
        let child = Command::new(rgc)
            .args(["bench", "--truth-system", &spec])
            .output()
            .map_err(|e| Error::io(rgc, e))?;
        let failed = |why: String| Error::io(rgc, std::io::Error::other(why));
        if !child.status.success() {
            return Err(failed(format!(
                "truth on system {spec} failed: {}",
                String::from_utf8_lossy(&child.stderr).trim()
            )));
        }
        serde_json::from_slice(&child.stdout)
            .map_err(|e| failed(format!("truth on system {spec}: unreadable row: {e}")))
    }
}

/// One system run under a memory limit in a process of its own: the
/// process's peak against the limit, and whether it was refused.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LimitRow {
    pub gamma: f64,
    pub density: f64,
    pub box_len: usize,
    pub seed: u64,
    pub limit_mib: f64,
    /// Peak resident memory of the whole process (`VmHWM`), MiB.
    pub peak_mib: f64,
    /// The refusal's message where the limit stopped it; `None`: truth
    /// finished.
    pub refused: Option<String>,
    pub seconds: f64,
    /// Whether the peak kept to [`within_limit`].
    pub within: bool,
}

/// The rule a memory limit keeps: the process's peak passes it by at most
/// 5% or 20 MB, the larger (what the guard's estimates between two
/// readings of the process's size, and allocations too small to guard, may
/// add).
pub fn within_limit(peak_bytes: u64, limit: u64) -> bool {
    peak_bytes as f64 <= (limit as f64 * 1.05).max(limit as f64 + 20e6)
}

const MIB: f64 = (1u64 << 20) as f64;

impl TruthSystem {
    /// What `rgc truth --memory-limit` does on this system, on one thread
    /// in this process: the rods checked up front, then truth under the
    /// limit; with the process's peak.
    pub fn under_limit(&self, limit: u64) -> Result<LimitRow> {
        let params = RodParams::new(self.gamma, self.box_len as f64, self.density)?;
        let start = Instant::now();
        let refused = one_thread(|| {
            if let Err(e) = Rods::from(params).check_memory(Some(limit)) {
                return Some(match e {
                    Error::Memory(why) => why,
                    other => other.to_string(),
                });
            }
            let network = Network::detect(RodSystem::generate(params, self.seed));
            let opts = TruthOptions {
                memory_limit: Some(limit),
                ..TruthOptions::seeded(self.seed)
            };
            let t = truth::of_system(network.view(), Criterion::Wrap, opts);
            t.outcome
                .refused()
                .map(|_| t.outcome.reason().unwrap_or_default().to_string())
        });
        let peak_mib = peak_rss_mib();
        Ok(LimitRow {
            gamma: self.gamma,
            density: self.density,
            box_len: self.box_len,
            seed: self.seed,
            limit_mib: limit as f64 / MIB,
            peak_mib,
            refused,
            seconds: start.elapsed().as_secs_f64(),
            within: within_limit((peak_mib * MIB) as u64, limit),
        })
    }

    /// [`TruthSystem::under_limit`] in a child process of its own, `rgc
    /// bench --truth-system ... --memory-limit`: the peak is the child's.
    pub fn under_limit_in_child(&self, rgc: &Path, limit: u64) -> Result<LimitRow> {
        let spec = self.to_string();
        let child = run_child(
            Command::new(rgc).args([
                "bench",
                "--truth-system",
                &spec,
                "--memory-limit",
                &limit.to_string(),
            ]),
            rgc,
            &format!("truth on system {spec} under {limit} bytes"),
        )?;
        serde_json::from_slice(&child.stdout).map_err(|e| {
            Error::io(
                rgc,
                std::io::Error::other(format!("truth on system {spec}: unreadable row: {e}")),
            )
        })
    }
}

/// [`TruthSystem::measure_in_child`] on the system these numbers name: what
/// `rgc bench` gives [`run_truth`] and [`run_truth_aspects`] to measure.
///
/// [`run_truth_aspects`]: super::aspects::run_truth_aspects
pub fn truth_in_child(
    rgc: &Path,
    gamma: f64,
    density: f64,
    box_len: usize,
    seed: u64,
) -> Result<TruthRow> {
    TruthSystem {
        gamma,
        density,
        box_len,
        seed,
    }
    .measure_in_child(rgc)
}
