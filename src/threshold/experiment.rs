//! The files of the experiments that measure variants on shared sequences,
//! each under its [`Stamp`]: `results/NAME.json` of `rgc compare` and
//! `rgc tradeoff` ([`Experiment`]), `truth-vs-rgc.json` and
//! `truth-monotone.json` of `rgc bias` ([`BiasReport`], [`MonotoneReport`]).
//!
//! What made an experiment is its template and its variants; a run builds
//! the stamp it would write and [`Stamp::check_replace`] compares it with
//! the file's. These files were first written through `serde_json::Value`,
//! so they are written with sorted keys ([`crate::stamp::json_sorted`]).

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use super::bias::{Scan, VariantBias};
use super::fss::Protocol;
use super::sequence::Kind;
use super::study::StudySpec;
use super::variants::{Design, VariantOutcome};
use crate::engine::RuleSet;
use crate::stamp::{Nothing, Stamp};

/// The `made` of a `compare` or `tradeoff` file, and with its outcomes
/// (`V = VariantOutcome`) the whole file: the template every variant's
/// study starts from, and the variants. Each outcome carries the
/// [`VariantKey`] it was made with, so the file read with `V = VariantKey`
/// is what made it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Experiment<V = VariantOutcome> {
    pub template: StudySpec,
    pub variants: Vec<V>,
}

/// What determines a variant's outcome, under the keys its outcome has.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantKey {
    pub label: String,
    pub rules: RuleSet,
    pub runs: usize,
    pub method: Protocol,
    // The stored key of `VariantOutcome::sequences`.
    #[serde(rename = "realizations")]
    pub sequences: u64,
}

impl Experiment<VariantKey> {
    /// What the variants of `design` on `template` are made of.
    pub fn of(template: &StudySpec, design: &Design) -> Self {
        Experiment {
            template: template.clone(),
            variants: design
                .variants
                .iter()
                .map(|v| VariantKey {
                    label: v.label.clone(),
                    rules: v.rules,
                    runs: v.runs,
                    method: v.method,
                    sequences: v.sequences,
                })
                .collect(),
        }
    }
}

/// What made a `bias` file: the template and the design, variant by variant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    pub template: StudySpec,
    pub design: Vec<PlannedVariant>,
}

/// One variant of a [`Plan`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedVariant {
    pub label: String,
    pub kind: Kind,
    pub rules: RuleSet,
    pub runs: usize,
    pub motifs: Vec<PathBuf>,
    pub sequences: u64,
}

/// The `made` of `truth-vs-rgc.json`: its plan, under `made_by`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MadeBy {
    pub made_by: Plan,
}

impl MadeBy {
    /// What the variants of `design` on `template` are made of.
    pub fn of(template: &StudySpec, design: &Design) -> Self {
        let design = design
            .variants
            .iter()
            .map(|v| PlannedVariant {
                label: v.label.clone(),
                kind: v.kind,
                rules: v.rules,
                runs: v.runs,
                motifs: v.motifs.clone(),
                sequences: v.sequences,
            })
            .collect();
        MadeBy {
            made_by: Plan {
                template: template.clone(),
                design,
            },
        }
    }
}

/// What `truth-vs-rgc.json` holds: every variant against truth and, where
/// truth's monotonicity was scanned, the scan's summary in words.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BiasReport {
    #[serde(flatten)]
    pub stamp: Stamp<MadeBy>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monotonicity: Option<String>,
    pub variants: Vec<VariantBias>,
}

/// What `truth-monotone.json` holds: truth's monotonicity scans.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MonotoneReport {
    #[serde(flatten)]
    pub stamp: Stamp<Nothing>,
    pub scans: Vec<Scan>,
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::threshold::variants::{csv, markdown};

    /// The committed comparisons (`variants`' tables of an experiment), written again from their JSON, are the
    /// committed Markdown and CSV byte for byte.
    #[test]
    fn committed_tables_are_written_unchanged() {
        for name in ["compare-base-extended", "speed-accuracy"] {
            let path = |ext: &str| {
                Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("results/{name}.{ext}"))
            };
            let read = |ext: &str| std::fs::read_to_string(path(ext)).unwrap();
            let file: Stamp<Experiment> = serde_json::from_str(&read("json")).unwrap();
            let outcomes = &file.made.variants;
            let md = read("md");
            let title = md.lines().next().unwrap().strip_prefix("# ").unwrap();
            assert_eq!(markdown(title, &file.command, outcomes), md, "{name}.md");
            assert_eq!(csv(outcomes), read("csv"), "{name}.csv");
        }
    }

    #[test]
    fn labels_with_commas_are_quoted() {
        let json = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("results/compare-base-extended.json"),
        )
        .unwrap();
        let file: Stamp<Experiment> = serde_json::from_str(&json).unwrap();
        let mut outcomes = file.made.variants;
        outcomes[0].label = "K=1, \"base\"".into();
        let text = csv(&outcomes);
        let row = text.lines().nth(1).unwrap();
        assert!(
            row.starts_with("\"k=1, \"\"base\"\"\",rules,paper,"),
            "{row}"
        );
        assert_eq!(row.matches(',').count(), 25, "{row}");
    }
}
