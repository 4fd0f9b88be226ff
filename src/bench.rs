//! The foundation benchmark: contact detection and one compression, single
//! threaded, on the reference systems of the paper's aspect ratios.

use serde::Serialize;
use std::time::Instant;

use crate::contacts;
use crate::engine::{self, RuleSet};
use crate::graph::ContactGraph;
use crate::math::stats::median;
use crate::rods::{RodParams, RodSystem};

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
    /// Detection plus one compression, per rod.
    pub ns_per_rod: f64,
    /// Peak resident memory of the process after this system, MiB.
    pub peak_rss_mib: f64,
    pub components: usize,
    pub largest_body_rods: usize,
}

/// Peak resident set size of this process (Linux `VmHWM`), MiB; 0 where unknown.
pub fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(0.0, |kib| kib / 1024.0)
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

/// Runs the systems up to `max_rods` rods in order of size, `repeat` times
/// each, on one thread.
pub fn run(repeat: usize, max_rods: usize) -> Vec<BenchRow> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    pool.install(|| {
        SYSTEMS
            .iter()
            .filter_map(|&(gamma, density, box_len)| {
                let params =
                    RodParams::new(gamma, box_len, density).expect("valid reference system");
                (params.n_rods() <= max_rods).then(|| measure(params, repeat))
            })
            .collect()
    })
}

fn measure(params: RodParams, repeat: usize) -> BenchRow {
    let (mut gen_t, mut det_t, mut comp_t) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = None;
    for k in 0..repeat.max(1) as u64 {
        let t = Instant::now();
        let system = RodSystem::generate(params, k);
        gen_t.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let found = contacts::detect(&system);
        let graph = ContactGraph::from_contacts(system.len(), &found);
        det_t.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let c = engine::compress(&graph, RuleSet::Sound, k);
        comp_t.push(t.elapsed().as_secs_f64());
        last = Some((system.len(), found.len(), c));
    }
    let (n_rods, n_contacts, c) = last.expect("at least one repetition");
    let (detect, compress) = (median(&mut det_t), median(&mut comp_t));
    BenchRow {
        gamma: params.gamma,
        density: params.density,
        box_len: params.box_len,
        n_rods,
        n_contacts,
        seconds_generate: median(&mut gen_t),
        seconds_detect: detect,
        seconds_compress: compress,
        ns_per_rod: (detect + compress) * 1e9 / n_rods.max(1) as f64,
        peak_rss_mib: peak_rss_mib(),
        components: c.components,
        largest_body_rods: c.largest_rods(),
    }
}
