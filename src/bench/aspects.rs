//! Truth across aspect ratios: systems near each aspect ratio's true
//! threshold in boxes of growing size, the growth per aspect ratio and the
//! cost per rod of slender rods against gamma 23.

use serde::Serialize;

use super::growth::Growth;
use super::truth::{LimitRow, TruthRow, TruthSystem};
use crate::progress::Progress;

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
    /// Every system again under memory limits ([`run_memory_limits`]), when asked.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub limits: Vec<LimitRow>,
}

/// A small fixed memory limit every system is also run under, bytes.
pub const SMALL_LIMIT: u64 = 64 << 20;

/// The limits each system of `rows` runs under: [`SMALL_LIMIT`], half its
/// measured peak (refused midway) and one and a half times it (room to
/// finish), bytes.
pub fn limits_of(row: &TruthRow) -> [u64; 3] {
    let peak = row.peak_mib * (1u64 << 20) as f64;
    [SMALL_LIMIT, (peak * 0.5) as u64, (peak * 1.5) as u64]
}

/// Every system of `rows` under each of its [`limits_of`], by
/// `measure(system, limit)` (a child process of its own each).
pub fn run_memory_limits(
    rows: &[TruthRow],
    mut measure: impl FnMut(&TruthSystem, u64) -> crate::Result<LimitRow>,
    progress: &impl Progress,
) -> crate::Result<Vec<LimitRow>> {
    progress.start("memory limits", 3 * rows.len() as u64);
    let mut out = Vec::new();
    for row in rows {
        let system = TruthSystem {
            gamma: row.gamma,
            density: row.density,
            box_len: row.box_len,
            seed: row.seed,
        };
        for limit in limits_of(row) {
            out.push(measure(&system, limit)?);
            progress.advance(1);
        }
    }
    progress.finish();
    Ok(out)
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
        limits: Vec::new(),
    })
}
