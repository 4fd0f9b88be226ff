//! The stiffness across the critical rod (MODEL §10, elastic moduli): on
//! the sequences of finished truth studies, the elastic moduli of the first
//! `n_c - 1` and `n_c` rods, `n_c` the study's critical number (where a true
//! cluster first wraps the box, or where the rods first resist every strain
//! for a study of the solid criterion). The largest cluster jumps at that
//! rod ([`super::transition`]); whether the shear modulus jumps with it is
//! what tells a rigidity transition that stiffens at once from one whose
//! moduli rise continuously, as Chubynsky and Thorpe found for central
//! forces. Each sequence is one line of `stiffening.jsonl` (a
//! [`journal`]), so a killed run resumes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::journal;
use super::sequence::{Record, Sequence};
use crate::engine::run_seed;
use crate::math::stats;
use crate::moduli::{self, ModuliOptions};
use crate::progress::Progress;
use crate::truth::TruthOptions;
use crate::{Error, Result, output};

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
}

/// The moduli of one prefix of a sequence, or why there are none.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Side {
    /// Rods in the prefix.
    pub rods: usize,
    /// The exact strain rank, and the moduli in `k / L_rod` (none where
    /// they could not be computed: `failed` says why).
    pub strain_rank: Option<u8>,
    pub shear: Option<f64>,
    pub bulk: Option<f64>,
    pub born_shear: Option<f64>,
    /// Which realization the floats used, and how far it moved the
    /// contact points (root mean square, rod lengths).
    pub realization: Option<String>,
    pub moved: Option<f64>,
    pub failed: Option<String>,
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
    pub seconds: f64,
}

impl journal::Line for SequenceStiffening {
    fn key(&self) -> (f64, f64, u64) {
        (self.gamma, self.box_len, self.index)
    }
}

/// The moduli of the first `n` rods of `r`'s sequence, truth's
/// realizations seeded as the study's step at `n`.
fn side(gamma: f64, r: &Record, n: usize, stiffness: f64) -> Result<Side> {
    let seq = Sequence::new(gamma, r.box_len, n, r.seed)?;
    let graph = seq.graph(n);
    let opts = ModuliOptions {
        stiffness,
        truth: TruthOptions::seeded(run_seed(r.seed, n as u64)),
    };
    Ok(match moduli::of_system(seq.view(n, &graph), opts) {
        Ok(e) => Side {
            rods: n,
            strain_rank: Some(e.strain_rank),
            shear: Some(e.shear),
            bulk: Some(e.bulk),
            born_shear: Some(e.born_shear),
            realization: Some(e.realization),
            moved: e.moved.map(|m| m.contacts),
            failed: None,
        },
        // Over the memory limit is no answer about the sequence: stop.
        Err(e @ Error::Memory(_)) => return Err(e),
        Err(e) => Side {
            rods: n,
            strain_rank: None,
            shear: None,
            bulk: None,
            born_shear: None,
            realization: None,
            moved: None,
            failed: Some(e.to_string()),
        },
    })
}

/// One sequence: its moduli one rod below and at the critical number.
fn probe(gamma: f64, r: &Record, stiffness: f64) -> Result<SequenceStiffening> {
    let start = Instant::now();
    let n = r.rigid_critical.expect("chosen records are decided");
    Ok(SequenceStiffening {
        gamma,
        box_len: r.box_len,
        index: r.index,
        before: side(gamma, r, n - 1, stiffness)?,
        at: side(gamma, r, n, stiffness)?,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The directory's spec file and lines.
fn files(out: &Path) -> (PathBuf, PathBuf) {
    (out.join("stiffening.json"), out.join("stiffening.jsonl"))
}

/// Measures the chosen sequences of the truth studies `dirs` into `out`
/// (resuming what is there) and summarizes per aspect ratio and box.
pub fn run(
    dirs: &[PathBuf],
    spec: &StiffeningSpec,
    out: &Path,
    progress: &dyn Progress,
) -> Result<Vec<StiffeningSummary>> {
    if !(spec.stiffness.is_finite() && spec.stiffness > 0.0) {
        return Err(Error::Parameter(format!(
            "the spring stiffness k must be positive and finite, not {}",
            spec.stiffness
        )));
    }
    let decided = journal::decided_truth_records(
        dirs,
        &spec.boxes,
        spec.sequences,
        "the stiffness across the critical rod",
    )?;
    output::check_dir(out)?;
    let (spec_file, lines) = files(out);
    let all = journal::measure(
        (&spec_file, spec, "stiffening spec"),
        &lines,
        &decided,
        progress,
        |gamma, r| probe(gamma, r, spec.stiffness),
    )?;
    Ok(summarize(&all))
}

/// The sequences measured so far.
pub fn read(lines: &Path) -> Result<Vec<SequenceStiffening>> {
    journal::read(lines, "stiffening")
}

/// A mean with its 95% normal interval (`1.96 sd / sqrt n`), over the
/// sequences where both sides have moduli.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Mean {
    pub mean: f64,
    pub half_width: f64,
}

impl Mean {
    fn of(x: &[f64]) -> Option<Mean> {
        (!x.is_empty()).then(|| {
            let (mean, sd) = stats::mean_sd(x);
            Mean {
                mean,
                half_width: 1.96 * sd / (x.len() as f64).sqrt(),
            }
        })
    }
}

/// One box of one aspect ratio, over the sequences with moduli on both
/// sides of the critical rod.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StiffeningSummary {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub sequences: usize,
    /// Sequences with moduli on both sides, and those where a side failed.
    pub measured: usize,
    pub failed: usize,
    /// Of the measured: the strain rank below and at the critical rod.
    pub strain_rank_before: Option<Mean>,
    pub strain_rank_at: Option<Mean>,
    /// How many resist no strain below it and some at it, and how many
    /// resist every strain at it.
    pub rank_rises_from_zero: usize,
    pub solid_at: usize,
    /// The shear modulus below and at the rod (`k / L_rod`), and their
    /// difference per sequence.
    pub shear_before: Option<Mean>,
    pub shear_at: Option<Mean>,
    pub shear_jump: Option<Mean>,
    /// Where both realizations were the one nearest the rods.
    pub both_nearest: usize,
}

/// Per aspect ratio and box, in that order.
pub fn summarize(all: &[SequenceStiffening]) -> Vec<StiffeningSummary> {
    let mut keys: Vec<(f64, f64)> = all.iter().map(|s| (s.gamma, s.box_len)).collect();
    keys.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
    keys.dedup();
    keys.into_iter()
        .map(|(gamma, box_len)| {
            let of: Vec<&SequenceStiffening> = all
                .iter()
                .filter(|s| (s.gamma, s.box_len) == (gamma, box_len))
                .collect();
            let measured: Vec<(&Side, &Side)> = of
                .iter()
                .filter(|s| s.before.failed.is_none() && s.at.failed.is_none())
                .map(|s| (&s.before, &s.at))
                .collect();
            let values = |f: &dyn Fn(&Side, &Side) -> Option<f64>| -> Vec<f64> {
                measured.iter().filter_map(|(b, a)| f(b, a)).collect()
            };
            let rank = |s: &Side| s.strain_rank.map(f64::from);
            StiffeningSummary {
                gamma,
                box_len,
                sequences: of.len(),
                measured: measured.len(),
                failed: of.len() - measured.len(),
                strain_rank_before: Mean::of(&values(&|b, _| rank(b))),
                strain_rank_at: Mean::of(&values(&|_, a| rank(a))),
                rank_rises_from_zero: measured
                    .iter()
                    .filter(|(b, a)| b.strain_rank == Some(0) && a.strain_rank > Some(0))
                    .count(),
                solid_at: measured
                    .iter()
                    .filter(|(_, a)| a.strain_rank == Some(6))
                    .count(),
                shear_before: Mean::of(&values(&|b, _| b.shear)),
                shear_at: Mean::of(&values(&|_, a| a.shear)),
                shear_jump: Mean::of(&values(&|b, a| Some(a.shear? - b.shear?))),
                both_nearest: measured
                    .iter()
                    .filter(|(b, a)| {
                        [b, a]
                            .iter()
                            .all(|s| s.realization.as_deref() == Some("nearest"))
                    })
                    .count(),
            }
        })
        .collect()
}

/// Writes `PREFIX.json` (with the command that made it), one entry per
/// aspect ratio and box.
pub fn write(prefix: &Path, summaries: &[StiffeningSummary], command: &str) -> Result<PathBuf> {
    let json = output::with_extension(prefix, "json");
    let doc = serde_json::json!({ "command": command, "boxes": summaries });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("summaries serialize"),
    )?;
    Ok(json)
}
