//! What a variant measured against truth: its paired bias per box and over
//! all boxes, below both the measurement that fills it and the tables that
//! print it.

use serde::{Deserialize, Serialize};

use crate::engine::RuleSet;
use crate::threshold::fss::Estimate;
use crate::threshold::sequence::Kind;

/// The paired bias of one variant in one box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxBias {
    #[serde(rename = "box")]
    pub box_len: f64,
    /// Sequences both the variant and truth have.
    pub sequences: usize,
    /// Mean over sequences of (variant's critical density - truth's), with
    /// a 95% normal interval.
    pub bias: Estimate,
    /// Sequences where the variant first spans below truth (false rigid
    /// spans), and above it (rigidity it misses at truth's critical density).
    pub below: usize,
    pub above: usize,
}

/// What one variant measured against truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantBias {
    pub label: String,
    pub family: String,
    pub kind: Kind,
    pub rules: RuleSet,
    pub motif_rules: usize,
    pub runs: usize,
    pub sequences: u64,
    /// The paired bias per box (empty for truth itself).
    pub boxes: Vec<BoxBias>,
    /// The paired bias over all boxes' sequences.
    pub bias: Option<Estimate>,
    /// Share of sequences where it spans below truth.
    pub false_span_share: Option<f64>,
    /// The finite-size-scaling threshold, where the fit succeeds.
    pub threshold: Option<Estimate>,
    /// CPU seconds of its sequences (all boxes).
    pub cpu_seconds: f64,
    /// Sequences where truth (or certification) was undecided, left out.
    pub undecided: usize,
    pub study: String,
}
