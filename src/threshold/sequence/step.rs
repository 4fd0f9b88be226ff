//! One compression (or truth evaluation) of a prefix, as a record keeps it.

use serde::{Deserialize, Serialize};

/// One compression of a prefix: whether it spans, and how many runs found
/// a spanning body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Step {
    /// Rods in the system.
    pub n: usize,
    pub spans: bool,
    /// Runs (of `Setup::runs`) with a spanning body.
    pub runs_spanning: usize,
    /// Truth (or certification) had no verdict here: a probe above the
    /// critical number that landed where the model has no realization, so
    /// the search looks below it (it does not span, by this step).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub undecided: bool,
    /// Truth kind: rods in the largest true rigid cluster, for the order of
    /// the transition (how much the cluster jumps at the critical number).
    /// `None` for compressions, and in records older than the field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub largest: Option<usize>,
}

impl Step {
    pub fn new(n: usize, spans: bool, runs_spanning: usize) -> Self {
        Step {
            n,
            spans,
            runs_spanning,
            undecided: false,
            largest: None,
        }
    }

    /// A probe without a verdict.
    pub(super) fn undecided(n: usize) -> Self {
        Step {
            undecided: true,
            ..Step::new(n, false, 0)
        }
    }
}
