//! The elastic moduli against truth on the same gamma 23 systems near and
//! above truth's threshold: both timed in one run (the moduli include the
//! truth they take the strain rank from, so the ratio is at least 1), by
//! the QR, and the relaxation alone by LSMR on the same realization.

use std::time::Instant;

use serde::Serialize;

use super::truth::TRUTH_GAMMA;
use crate::moduli::{self, ModuliOptions, Solver};
use crate::network::Network;
use crate::rods::{RodParams, RodSystem};
use crate::truth::TruthOptions;

/// The systems: density near (34) and above (38, 45) the threshold, box 3, seeds 1 and 2.
pub const SYSTEMS: [(f64, usize, u64); 6] = [
    (34.0, 3, 1),
    (34.0, 3, 2),
    (38.0, 3, 1),
    (38.0, 3, 2),
    (45.0, 3, 1),
    (45.0, 3, 2),
];

/// One system's moduli and their cost against truth's.
#[derive(Clone, Debug, Serialize)]
pub struct ModuliRow {
    pub density: f64,
    pub box_len: usize,
    pub seed: u64,
    pub strain_rank: u8,
    pub shear: f64,
    pub realization: String,
    pub truth_seconds: f64,
    pub seconds: f64,
    /// `seconds / truth_seconds`.
    pub ratio: f64,
    /// The relaxation alone on the realization, over truth's seconds: what
    /// the moduli would cost against truth with a realization for free.
    pub relaxation_ratio: f64,
    /// The same relaxation by LSMR instead of the QR, on the same
    /// realization, over truth's seconds, and the G it gives (none where
    /// the strain rank is 0: no relaxation).
    #[serde(default)]
    pub lsmr_relaxation_ratio: Option<f64>,
    #[serde(default)]
    pub lsmr_shear: Option<f64>,
}

/// The moduli of one system at gamma 23, timed with the truth inside them.
pub fn measure(density: f64, box_len: usize, seed: u64) -> crate::Result<ModuliRow> {
    let params = RodParams::new(TRUTH_GAMMA, box_len as f64, density)?;
    let network = Network::detect(RodSystem::generate(params, seed));
    let opts = ModuliOptions {
        stiffness: 1.0,
        truth: TruthOptions::seeded(seed),
        solver: Solver::Qr,
        lsmr_iterations: moduli::LSMR_ITERATIONS,
    };
    // `of_system`'s steps, timed as it times them, with the realization
    // kept for LSMR's relaxation on it.
    let view = network.view();
    let start = Instant::now();
    let exact = moduli::exact(view, opts)?;
    let floats = moduli::floats(view, opts.truth.seed, true, None)?;
    let mut e = moduli::of_floats(view, exact, &floats, opts)?;
    e.seconds = start.elapsed().as_secs_f64();
    let lsmr = (e.strain_rank > 0)
        .then(|| {
            let opts = ModuliOptions {
                solver: Solver::Lsmr,
                ..opts
            };
            moduli::of_floats(view, exact, &floats, opts)
        })
        .transpose()?;
    let over_truth = |s: f64| s / e.truth_seconds.max(f64::MIN_POSITIVE);
    Ok(ModuliRow {
        density,
        box_len,
        seed,
        strain_rank: e.strain_rank,
        shear: e.shear,
        realization: e.realization,
        truth_seconds: e.truth_seconds,
        seconds: e.seconds,
        ratio: over_truth(e.seconds),
        relaxation_ratio: over_truth(e.relaxation_seconds),
        lsmr_relaxation_ratio: lsmr.as_ref().map(|l| over_truth(l.relaxation_seconds)),
        lsmr_shear: lsmr.map(|l| l.shear),
    })
}
