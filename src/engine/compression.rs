//! What a compression run returns: its bodies, the nodes left, and the
//! motifs it compressed.

use serde::{Deserialize, Serialize};

use super::motif::{Motif, MotifCounts};
use crate::body::Body;

/// The outcome of one compression run.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Compression {
    /// Bodies, largest first (ties by smallest rod), each with sorted rods.
    pub bodies: Vec<Body>,
    /// Nodes left: bodies plus rods in no body.
    pub components: usize,
    /// Motif instances compressed, by motif.
    pub motifs: MotifCounts,
    /// The motifs in the order they were applied: how this run compressed
    /// what it did (the audit writes it beside each false compression).
    pub sequence: Vec<Motif>,
    /// Certified rules: bodies truth refuted (split along the true clusters).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub refuted: usize,
    /// Certified rules: truth was undecided, so nothing could be certified
    /// (every body dropped).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub undecided: bool,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Compression {
    /// The largest body, if any.
    pub fn largest(&self) -> Option<&Body> {
        self.bodies.first()
    }

    /// Rods in the largest body (1 when no body formed but rods exist, 0 for no rods).
    pub fn largest_rods(&self) -> usize {
        self.largest().map_or(0, |b| b.rods.len())
    }
}
