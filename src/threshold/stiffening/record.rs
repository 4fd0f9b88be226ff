//! What one line of a stiffening measurement stores: the spec it was
//! measured under, and one sequence's sides (its moduli at a number of
//! rods, or why there are none); and what a sequence in progress has
//! measured so far.

use serde::{Deserialize, Serialize};

use crate::moduli::{FIRST_LSMR_ITERATIONS, Solver};
use crate::threshold::journal;

/// What a measurement takes: which studies, boxes and sequences, and the
/// springs' stiffness.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StiffeningSpec {
    /// Truth study directories, as given.
    pub studies: Vec<String>,
    /// Boxes of each study (all when empty).
    pub boxes: Vec<f64>,
    /// The first this many sequences of each box.
    pub sequences: u64,
    /// The spring stiffness `k` of a contact.
    pub stiffness: f64,
    /// Densities (rods per unit volume) at which each sequence is measured
    /// too.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub densities: Vec<f64>,
    /// How the springs' least squares is solved: the QR or LSMR, never
    /// chosen by the memory free at the time (absent: the QR). Sides
    /// added by `--extend` take the extending run's; each side records
    /// its own.
    #[serde(default = "Solver::qr", skip_serializing_if = "Solver::is_qr")]
    pub solver: Solver,
    /// LSMR's iterations per strain at most (absent: 1,000, the cap before
    /// it was a choice). `--extend` with a larger one measures again the
    /// sides that did not settle under theirs.
    #[serde(default = "first_cap")]
    pub lsmr_iterations: usize,
}

fn first_cap() -> usize {
    FIRST_LSMR_ITERATIONS
}

/// The moduli of one prefix of a sequence, or why there are none.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Side {
    /// Rods in the prefix.
    pub rods: usize,
    /// The exact strain rank, and the moduli in `k / L_rod` (none where
    /// they could not be computed: `failed` says why). Where the strain
    /// rank is 0 the moduli are zero without floats: no realization and no
    /// Born modulus.
    pub strain_rank: Option<u8>,
    pub shear: Option<f64>,
    pub bulk: Option<f64>,
    pub born_shear: Option<f64>,
    /// Which realization the floats used, and how far it moved the
    /// contact points (root mean square, rod lengths).
    pub realization: Option<String>,
    pub moved: Option<f64>,
    /// Rods in truth's largest rigid cluster.
    #[serde(default)]
    pub largest: Option<usize>,
    pub failed: Option<String>,
    /// Whether the relaxation's energies settled (none without floats,
    /// and in records older than the field); if not, the moduli are upper
    /// bounds the refinement had not reached.
    #[serde(default)]
    pub settled: Option<bool>,
    /// The solver that relaxed it (none without floats, and absent in
    /// sides older than LSMR, which the QR relaxed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<Solver>,
    /// LSMR's cap on iterations per strain when it relaxed this side
    /// (absent in sides relaxed under the first cap, 1,000, or by the QR).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lsmr_iterations: Option<usize>,
}

impl Side {
    /// Its relaxation ran out of refinement steps.
    pub fn unsettled(&self) -> bool {
        self.settled == Some(false)
    }

    /// Whether LSMR with `cap` iterations per strain could settle it where
    /// its own relaxation did not: LSMR's, under a smaller cap.
    pub fn settles_under(&self, cap: usize) -> bool {
        self.unsettled()
            && self.solver == Some(Solver::Lsmr)
            && self.lsmr_iterations.unwrap_or(FIRST_LSMR_ITERATIONS) < cap
    }

    /// Whether its moduli compare with other sequences': exact where the
    /// rods resist no strain, else from the realization nearest the rods,
    /// its own or the next side's (one from a random start is another
    /// member of the family, with another `G`).
    pub fn comparable(&self) -> bool {
        self.strain_rank == Some(0)
            || matches!(
                self.realization.as_deref(),
                Some("nearest" | "nearest-next")
            )
    }

    /// Whether `self`, the side below the critical rod, and `at` are one
    /// geometry: exact zeros below it, or the critical side's realization.
    pub(super) fn one_geometry_with(&self, at: &Side) -> bool {
        at.comparable()
            && (self.strain_rank == Some(0)
                || (self.realization.as_deref() == Some("nearest-next")
                    && at.realization.as_deref() == Some("nearest")))
    }
}

/// One sequence one rod below and at its critical number.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SequenceStiffening {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub index: u64,
    pub before: Side,
    pub at: Side,
    /// At each of the spec's densities, in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grid: Vec<Side>,
    pub seconds: f64,
}

/// The sides a sequence in progress has measured, saved after each one:
/// a sequence of a large box takes hours, and a killed run loses only the
/// side it was on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Partial {
    /// One rod below and at the critical number, measured together (one
    /// geometry).
    pub pair: Option<(Side, Side)>,
    /// The first sides of the density grid, in order.
    pub grid: Vec<Side>,
    /// Seconds spent on them, over every run.
    pub seconds: f64,
}

impl journal::Line for SequenceStiffening {
    fn key(&self) -> (f64, f64, u64) {
        (self.gamma, self.box_len, self.index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measurements_made_before_the_cap_was_a_choice_read_as_1000() {
        let spec: StiffeningSpec = serde_json::from_str(
            r#"{"studies": ["s"], "boxes": [5.0], "sequences": 40, "stiffness": 1.0, "solver": "lsmr"}"#,
        )
        .unwrap();
        assert_eq!(spec.lsmr_iterations, 1000);
        // An unsettled LSMR side of then settles only under a larger cap;
        // a settled one, and one the QR relaxed, never.
        let side: Side = serde_json::from_str(
            r#"{"rods": 4295, "strain_rank": 6, "shear": 1e-9, "bulk": 1e-9, "born_shear": 1.4,
                "realization": "nearest", "moved": 0.2, "largest": 900, "failed": null,
                "settled": false, "solver": "lsmr"}"#,
        )
        .unwrap();
        assert!(side.settles_under(1001) && !side.settles_under(1000));
        let settled = Side {
            settled: Some(true),
            ..side.clone()
        };
        let qr = Side {
            solver: Some(Solver::Qr),
            ..side.clone()
        };
        assert!(!settled.settles_under(10_000) && !qr.settles_under(10_000));
        let later = Side {
            lsmr_iterations: Some(10_000),
            ..side
        };
        assert!(!later.settles_under(10_000) && later.settles_under(20_000));
    }
}
