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
    /// Truth kind: how many strains of the box the first `n` rods resist
    /// (MODEL §10, the strain rank; 6 is a solid). `None` for compressions,
    /// where truth does not know it, and in records older than the field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strain_rank: Option<u8>,
}

impl Step {
    pub fn new(n: usize, spans: bool, runs_spanning: usize) -> Self {
        Step {
            n,
            spans,
            runs_spanning,
            undecided: false,
            largest: None,
            strain_rank: None,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_keeps_its_strain_rank_and_reads_records_without_it() {
        let old = r#"{"n":120,"spans":true,"runs_spanning":1,"largest":80}"#;
        let step: Step = serde_json::from_str(old).unwrap();
        assert_eq!((step.largest, step.strain_rank), (Some(80), None));
        assert_eq!(serde_json::to_string(&step).unwrap(), old);
        let solid = Step {
            strain_rank: Some(6),
            ..step
        };
        let text = serde_json::to_string(&solid).unwrap();
        assert_eq!(
            text,
            r#"{"n":120,"spans":true,"runs_spanning":1,"largest":80,"strain_rank":6}"#
        );
        assert_eq!(serde_json::from_str::<Step>(&text).unwrap(), solid);
    }
}
