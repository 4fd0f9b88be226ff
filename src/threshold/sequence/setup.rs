//! What every sequence of a study shares: which spanning cluster defines
//! the threshold, the engine and its runs.

use serde::{Deserialize, Serialize};

use crate::engine::Engine;
use crate::spanning::Criterion;

/// Which spanning cluster defines the threshold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// A connected cluster of touching rods spans.
    Contact,
    /// A rigid body found by the engine spans.
    #[default]
    Rigid,
    /// A rigid cluster of the exact truth (MODEL §10) spans: the reference
    /// every engine variant is measured against.
    Truth,
}

impl Kind {
    /// Whether the critical number is found by bisection over compressions
    /// (or truth evaluations) rather than by one contact sweep.
    pub fn bisects(self) -> bool {
        self != Kind::Contact
    }
}

/// What every sequence of a study shares.
#[derive(Clone, Copy, Debug)]
pub struct Setup<'r> {
    pub kind: Kind,
    pub gamma: f64,
    pub criterion: Criterion,
    pub engine: Engine<'r>,
    /// Independent compressions per system; it spans if any of them does.
    pub runs: usize,
    /// For the truth kind: refuse a system whose elimination is estimated
    /// over this many bytes.
    pub memory_limit: Option<u64>,
}
