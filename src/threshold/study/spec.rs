//! What determines a study's records (`study.json`): the spec, the identity
//! of its rule set, what a person can get wrong in it, and the seed of each
//! sequence.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use crate::engine::{RuleSet, run_seed};
use crate::rods::{RodParams, excluded_volume};
use crate::rule_file::Rule;
use crate::spanning::Criterion;
use crate::threshold::fss::{self, Protocol};
use crate::threshold::sequence::Kind;
use crate::{Error, Result};

/// Version of the study files; a change that alters records bumps it.
pub const STUDY_FORMAT: &str = "rgc-threshold/1";

/// Everything that determines a study's records: two runs with equal specs
/// produce equal records, whatever the thread count or interruptions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudySpec {
    pub format: String,
    pub kind: Kind,
    pub gamma: f64,
    pub boxes: Vec<f64>,
    // Keeps its stored key, so existing studies (`study.json`) read back.
    #[serde(rename = "realizations")]
    pub sequences: u64,
    pub rules: RuleSet,
    /// Loaded rule set: how many rules and a digest of their canonical forms.
    pub motifs: MotifSet,
    pub runs: usize,
    pub criterion: Criterion,
    pub method: Protocol,
    /// Densities of the fixed protocol's grid per box (ignored by `nested`).
    pub grid_points: usize,
    /// The fixed protocol's densities, the same in every box, instead of a
    /// grid of `grid_points` found by a pilot run: what a quantity compared
    /// across boxes at one density needs (the Binder cumulant).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid_densities: Option<Vec<f64>>,
    pub seed: u64,
}

impl StudySpec {
    /// A study in the current format of the rigidity threshold under the
    /// sound base motifs, one run per system, by the nested protocol (with
    /// 12 grid points should it be switched to fixed): what `rgc threshold`
    /// does by default, and what the variants of `compare` and `tradeoff`
    /// start from. Change the fields that differ.
    pub fn new(
        gamma: f64,
        boxes: Vec<f64>,
        sequences: u64,
        criterion: Criterion,
        seed: u64,
    ) -> StudySpec {
        StudySpec {
            format: STUDY_FORMAT.into(),
            kind: Kind::Rigid,
            gamma,
            boxes,
            sequences,
            rules: RuleSet::Sound,
            motifs: MotifSet::default(),
            runs: 1,
            criterion,
            method: Protocol::Nested,
            grid_points: 12,
            grid_densities: None,
            seed,
        }
    }
}

/// The identity of a loaded rule set, independent of file names and order.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MotifSet {
    pub rules: usize,
    /// FNV-1a of the sorted canonical forms, hex; empty without rules.
    pub digest: String,
    /// The files they came from (for people; not compared).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
}

impl MotifSet {
    pub fn of(rules: &[Rule], files: &[PathBuf]) -> Self {
        if rules.is_empty() {
            return MotifSet::default();
        }
        let mut forms: Vec<&str> = rules.iter().map(|r| r.canonical.as_str()).collect();
        forms.sort_unstable();
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for f in forms {
            for b in f.bytes().chain([b'\n']) {
                h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        MotifSet {
            rules: rules.len(),
            digest: format!("{h:016x}"),
            files: files.iter().map(|p| p.display().to_string()).collect(),
        }
    }

    /// Same rules (file names aside).
    fn same(&self, other: &MotifSet) -> bool {
        self.rules == other.rules && self.digest == other.digest
    }
}

impl StudySpec {
    /// Checks what a person can get wrong on the command line.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Parameter(m));
        if self.boxes.is_empty() {
            return bad("no box sizes given".into());
        }
        let mut sorted = self.boxes.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        if sorted.len() != self.boxes.len() {
            return bad(format!("box sizes repeat: {:?}", self.boxes));
        }
        // Each box as the first sequence fills it, so that a study too large
        // for memory is refused before it claims a directory.
        for &l in &self.boxes {
            RodParams::new(self.gamma, l, self.first_rods(l).max(1) as f64 / l.powi(3))?;
        }
        if self.sequences == 0 {
            return bad("--sequences must be at least 1".into());
        }
        if self.runs == 0 {
            return bad("--runs must be at least 1".into());
        }
        if self.method == Protocol::Fixed && self.grid_points < 2 {
            return bad("--grid-points must be at least 2".into());
        }
        if let Some(d) = &self.grid_densities {
            if self.method != Protocol::Fixed {
                return bad("--grid-densities needs --protocol fixed".into());
            }
            if d.len() < 2
                || d.iter().any(|x| !x.is_finite() || *x <= 0.0)
                || d.windows(2).any(|w| w[0] >= w[1])
            {
                return bad(format!(
                    "--grid-densities must be two or more increasing positive densities, got {d:?}"
                ));
            }
        }
        if self.kind != Kind::Truth {
            let kind = format!("{:?}", self.kind).to_lowercase();
            self.criterion
                .check_clusters(&format!("a {kind} study (use --kind truth)"))?;
        }
        Ok(())
    }

    /// [`StudySpec::validate`], and that the scaling analysis can use the
    /// study at all ([`fss::check_design`]): what a command that will
    /// analyse a study checks before any sequence runs. A study itself
    /// (records, shards, merges) needs no more than `validate`.
    pub fn validate_for_analysis(&self) -> Result<()> {
        self.validate()?;
        fss::check_design(self.boxes.len(), self.sequences, self.method)
    }

    /// Whether `other` is the same study (file names of the rules aside).
    pub fn same(&self, other: &StudySpec) -> bool {
        let strip = |s: &StudySpec| StudySpec {
            motifs: MotifSet::default(),
            ..s.clone()
        };
        strip(self) == strip(other) && self.motifs.same(&other.motifs)
    }

    /// The seed of sequence `index` in box `box_len`: the same for every
    /// kind, rule set and method, so they are compared on the same rods.
    pub fn sequence_seed(&self, box_len: f64, index: u64) -> u64 {
        run_seed(run_seed(self.seed, box_len.to_bits()), index)
    }

    /// Rods to generate first for a box: past the typical threshold, so a
    /// sequence rarely needs to grow (mean contact number 2 for contact
    /// percolation, 5 for rigidity).
    pub fn first_rods(&self, box_len: f64) -> usize {
        let c0 = match self.kind {
            Kind::Contact => 2.0,
            Kind::Rigid | Kind::Truth => 5.0,
        };
        (c0 / excluded_volume(self.gamma) * box_len.powi(3)).ceil() as usize
    }
}
