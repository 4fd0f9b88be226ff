//! The stiffness across the critical rod (MODEL §10, elastic moduli): on
//! the sequences of finished truth studies, the elastic moduli of the first
//! `n_c - 1` and `n_c` rods, `n_c` the study's critical number (where a true
//! cluster first wraps the box, or where the rods first resist every strain
//! for a study of the solid criterion). The largest cluster jumps at that
//! rod ([`super::transition`]); whether the shear modulus jumps with it is
//! what tells a rigidity transition that stiffens at once from one whose
//! moduli rise continuously, as Chubynsky and Thorpe found for central
//! forces. At given densities too, the moduli against the density (the
//! stiffening curve `G(rho)`, `K(rho)`) beside the largest true cluster's
//! share of the rods. Each sequence is one line of `stiffening.jsonl` (a
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
    /// Densities (rods per unit volume) at which each sequence is measured
    /// too.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub densities: Vec<f64>,
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
    /// Rods in truth's largest rigid cluster.
    #[serde(default)]
    pub largest: Option<usize>,
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
    /// At each of the spec's densities, in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grid: Vec<Side>,
    pub seconds: f64,
}

impl journal::Line for SequenceStiffening {
    fn key(&self) -> (f64, f64, u64) {
        (self.gamma, self.box_len, self.index)
    }
}

/// The moduli of the first `n` rods of `r`'s sequence `seq`, truth's
/// realizations seeded as the study's step at `n`.
fn side(seq: &Sequence, r: &Record, n: usize, stiffness: f64) -> Result<Side> {
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
            largest: e.largest_cluster,
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
            largest: None,
            failed: Some(e.to_string()),
        },
    })
}

/// Rods at `density` in a cubic box of side `box_len`.
fn rods_at(density: f64, box_len: f64) -> usize {
    (density * box_len.powi(3)).round() as usize
}

/// One sequence: its moduli one rod below and at the critical number, and
/// at each density of `spec`.
fn probe(gamma: f64, r: &Record, spec: &StiffeningSpec) -> Result<SequenceStiffening> {
    let start = Instant::now();
    let n = r.rigid_critical.expect("chosen records are decided");
    let k = spec.stiffness;
    let grid: Vec<usize> = spec
        .densities
        .iter()
        .map(|&d| rods_at(d, r.box_len))
        .collect();
    // One sequence to the most rods any side needs; each side a prefix.
    let most = grid.iter().copied().fold(n, usize::max);
    let seq = Sequence::new(gamma, r.box_len, most, r.seed)?;
    Ok(SequenceStiffening {
        gamma,
        box_len: r.box_len,
        index: r.index,
        before: side(&seq, r, n - 1, k)?,
        at: side(&seq, r, n, k)?,
        grid: grid
            .into_iter()
            .map(|m| side(&seq, r, m, k))
            .collect::<Result<_>>()?,
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
    if spec.densities.iter().any(|d| !(d.is_finite() && *d > 0.0))
        || spec.densities.windows(2).any(|w| w[0] >= w[1])
    {
        return Err(Error::Parameter(format!(
            "--densities must increase and be positive, not {:?}",
            spec.densities
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
        |gamma, r| probe(gamma, r, spec),
    )?;
    Ok(summarize(&all, spec))
}

/// The sequences measured so far.
pub fn read(lines: &Path) -> Result<Vec<SequenceStiffening>> {
    journal::read(lines, "stiffening")
}

/// A mean with the half-width of its 95% normal interval (`1.96 sd /
/// sqrt n`; none from a single value).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Mean {
    pub mean: f64,
    pub half_width: Option<f64>,
}

impl Mean {
    fn of(x: &[f64]) -> Option<Mean> {
        (!x.is_empty()).then(|| {
            let (mean, sd) = stats::mean_sd(x);
            Mean {
                mean,
                half_width: (x.len() > 1).then(|| 1.96 * sd / (x.len() as f64).sqrt()),
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
    /// At each density of the spec.
    pub grid: Vec<GridPoint>,
}

/// One density of one box: the moduli over the sequences measured there.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GridPoint {
    pub density: f64,
    pub rods: usize,
    pub measured: usize,
    pub failed: usize,
    /// How many resist every strain; the mean strain rank.
    pub solid: usize,
    pub strain_rank: Option<Mean>,
    /// `k / L_rod`.
    pub shear: Option<Mean>,
    pub bulk: Option<Mean>,
    /// The largest true cluster's share of the rods.
    pub largest_share: Option<Mean>,
    /// Realizations nearest the rods (the rest projected from a random
    /// start: not comparable).
    pub nearest: usize,
}

impl GridPoint {
    fn of(density: f64, sides: &[&Side]) -> GridPoint {
        let ok: Vec<&&Side> = sides.iter().filter(|s| s.failed.is_none()).collect();
        let mean = |f: &dyn Fn(&Side) -> Option<f64>| {
            Mean::of(&ok.iter().filter_map(|s| f(s)).collect::<Vec<_>>())
        };
        GridPoint {
            density,
            rods: sides.first().map_or(0, |s| s.rods),
            measured: ok.len(),
            failed: sides.len() - ok.len(),
            solid: ok.iter().filter(|s| s.strain_rank == Some(6)).count(),
            strain_rank: mean(&|s| s.strain_rank.map(f64::from)),
            shear: mean(&|s| s.shear),
            bulk: mean(&|s| s.bulk),
            largest_share: mean(&|s| s.largest.map(|l| l as f64 / s.rods as f64)),
            nearest: ok
                .iter()
                .filter(|s| s.realization.as_deref() == Some("nearest"))
                .count(),
        }
    }
}

/// Per aspect ratio and box, in that order, at the densities of `spec`.
pub fn summarize(all: &[SequenceStiffening], spec: &StiffeningSpec) -> Vec<StiffeningSummary> {
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
                grid: spec
                    .densities
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| {
                        let sides: Vec<&Side> = of.iter().filter_map(|s| s.grid.get(i)).collect();
                        GridPoint::of(d, &sides)
                    })
                    .collect(),
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
