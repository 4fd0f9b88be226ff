//! How often truth's realizations disagree (MODEL §10): the evaluations of
//! finished truth studies ranked again, every realization whole, each in a
//! prime of its own.
//!
//! A realization can only lose rank, so a disagreement is an unlucky draw
//! of the one with the smaller rank. The Schwartz–Zippel bound says nothing
//! useful for whole systems (the degree of their minors far exceeds the
//! prime), so the rate is measured instead: the first realization against
//! the second (the twins, before the second's contracted check), and a
//! third, lone one against the larger of the two.
//!
//! Each sequence's evaluations go to `evaluations.jsonl` as one line once
//! all are ranked (a [`journal`]).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::journal;
use super::sequence::{Record, Sequence};
use crate::engine::run_seed;
use crate::progress::Progress;
use crate::truth::{MAX_REALIZATIONS, TruthOptions, realization_ranks};
use crate::{Error, Result, output};

/// What a measurement ranks: which studies, boxes and sequences.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwinsSpec {
    /// Truth study directories, as given.
    pub studies: Vec<String>,
    /// Boxes of each study to rank (all when empty).
    pub boxes: Vec<f64>,
    /// The first this many sequences of each box.
    pub sequences: u64,
    /// Realizations ranked per evaluation.
    pub realizations: usize,
}

/// One evaluation: the first `n` rods of a sequence, every realization's
/// prime and whole rank (empty where truth would not rank it exactly).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    pub n: usize,
    pub primes: Vec<u32>,
    pub ranks: Vec<usize>,
}

/// One sequence's evaluations: one line of `evaluations.jsonl`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SequenceRanks {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub index: u64,
    pub evaluations: Vec<Evaluation>,
}

/// The disagreements of one box of one aspect ratio.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tally {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub sequences: usize,
    /// Evaluations ranked exactly by every realization.
    pub evaluations: usize,
    /// Evaluations where the first realization's rank differs from the
    /// second's (the twins before the contracted check).
    pub twins_differ: usize,
    /// Evaluations where the third realization's rank differs from the
    /// larger of the first two.
    pub lone_differs: usize,
    /// Evaluations where some realization's rank is below the largest.
    pub any_below: usize,
}

/// The directory's spec file and evaluations file.
fn files(out: &Path) -> (PathBuf, PathBuf) {
    (out.join("twins.json"), out.join("evaluations.jsonl"))
}

/// Ranks every evaluation of the chosen sequences of the truth studies
/// `dirs` again, `spec.realizations` times each, into `out` (resuming what
/// is there), and tallies the disagreements per aspect ratio and box. A
/// `tally_prefix` the tally will be written to is checked before the work.
pub fn run(
    dirs: &[PathBuf],
    spec: &TwinsSpec,
    out: &Path,
    tally_prefix: Option<&Path>,
    progress: &dyn Progress,
) -> Result<Vec<Tally>> {
    if !(2..=MAX_REALIZATIONS).contains(&spec.realizations) {
        return Err(Error::Parameter(format!(
            "--realizations {}: a disagreement needs 2 to {MAX_REALIZATIONS} realizations",
            spec.realizations
        )));
    }
    let chosen = journal::truth_records(
        dirs,
        &spec.boxes,
        spec.sequences,
        "ranking realizations again",
    )?;
    output::check_dir(out)?;
    if let Some(prefix) = tally_prefix {
        output::check_file(prefix)?;
    }
    let (spec_file, lines) = files(out);
    let all = journal::measure(
        (&spec_file, spec, "twins spec"),
        &lines,
        &chosen,
        progress,
        |gamma, r| rank_sequence(gamma, r, spec.realizations),
    )?;
    Ok(tally(&all))
}

/// The sequences already ranked; a last line cut short by a kill is left
/// out (it is ranked again).
pub fn read(lines: &Path) -> Result<Vec<SequenceRanks>> {
    journal::read(lines, "ranks")
}

/// Every step of one record, each evaluation once, ranked as truth's
/// evaluation of that step draws its realizations.
fn rank_sequence(gamma: f64, r: &Record, realizations: usize) -> Result<SequenceRanks> {
    let ns: BTreeSet<usize> = r.steps.iter().map(|s| s.n).collect();
    let largest = ns.last().copied().unwrap_or(0);
    let seq = Sequence::new(gamma, r.box_len, largest, r.seed)?;
    let evaluations = ns
        .into_iter()
        .map(|n| {
            let graph = seq.graph(n);
            let view = seq.view(n, &graph);
            let opts = TruthOptions {
                realizations,
                ..TruthOptions::seeded(run_seed(r.seed, n as u64))
            };
            let ranked = realization_ranks(&view.topology(), opts).unwrap_or_default();
            let (primes, ranks) = ranked.into_iter().unzip();
            Evaluation { n, primes, ranks }
        })
        .collect();
    Ok(SequenceRanks {
        gamma,
        box_len: r.box_len,
        index: r.index,
        evaluations,
    })
}

impl journal::Line for SequenceRanks {
    fn key(&self) -> (f64, f64, u64) {
        (self.gamma, self.box_len, self.index)
    }
}

/// The disagreements per aspect ratio and box, in that order.
pub fn tally(all: &[SequenceRanks]) -> Vec<Tally> {
    let mut out: Vec<Tally> = Vec::new();
    let mut sorted: Vec<&SequenceRanks> = all.iter().collect();
    sorted.sort_by(|a, b| {
        (a.gamma, a.box_len, a.index)
            .partial_cmp(&(b.gamma, b.box_len, b.index))
            .expect("finite")
    });
    for s in sorted {
        if out
            .last()
            .is_none_or(|t| (t.gamma, t.box_len) != (s.gamma, s.box_len))
        {
            out.push(Tally {
                gamma: s.gamma,
                box_len: s.box_len,
                sequences: 0,
                evaluations: 0,
                twins_differ: 0,
                lone_differs: 0,
                any_below: 0,
            });
        }
        let t = out.last_mut().expect("pushed above");
        t.sequences += 1;
        for e in s.evaluations.iter().filter(|e| e.ranks.len() >= 2) {
            let r = &e.ranks;
            let max = *r.iter().max().expect("two or more");
            t.evaluations += 1;
            t.twins_differ += usize::from(r[0] != r[1]);
            t.lone_differs += usize::from(r.get(2).is_some_and(|&x| x != r[0].max(r[1])));
            t.any_below += usize::from(r.iter().any(|&x| x < max));
        }
    }
    out
}

/// Writes `PREFIX.json` (with the command that made it) and `PREFIX.csv`,
/// one row per aspect ratio and box.
pub fn write(prefix: &Path, tallies: &[Tally], command: &str) -> Result<Vec<PathBuf>> {
    let with = |ext: &str| output::with_extension(prefix, ext);
    let (json, csv) = (with("json"), with("csv"));
    let doc = serde_json::json!({ "command": command, "tallies": tallies });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("tallies serialize"),
    )?;
    output::write_csv(&csv, tallies)?;
    Ok(vec![json, csv])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seq(gamma: f64, index: u64, ranks: &[&[usize]]) -> SequenceRanks {
        SequenceRanks {
            gamma,
            box_len: 3.0,
            index,
            evaluations: ranks
                .iter()
                .enumerate()
                .map(|(n, r)| Evaluation {
                    n,
                    primes: vec![8_388_617; r.len()],
                    ranks: r.to_vec(),
                })
                .collect(),
        }
    }

    #[test]
    fn the_tally_counts_each_kind_of_disagreement() {
        let all = [
            seq(23.0, 1, &[&[5, 5, 5], &[5, 4, 5], &[4, 5, 5], &[]]),
            seq(23.0, 0, &[&[7, 7, 6]]),
            seq(48.0, 0, &[&[3, 3]]),
        ];
        let t = tally(&all);
        assert_eq!(t.len(), 2);
        let g23 = &t[0];
        assert_eq!((g23.gamma, g23.sequences, g23.evaluations), (23.0, 2, 4));
        assert_eq!(
            (g23.twins_differ, g23.lone_differs, g23.any_below),
            (2, 1, 3)
        );
        assert_eq!((t[1].evaluations, t[1].any_below), (1, 0));
    }

    #[test]
    fn a_line_cut_by_a_kill_is_left_out() {
        let dir = std::env::temp_dir().join(format!("rgc-twins-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("evaluations.jsonl");
        let line = serde_json::to_string(&seq(23.0, 0, &[&[1, 1]])).unwrap();
        std::fs::write(&path, format!("{line}\n{}", &line[..20])).unwrap();
        assert_eq!(read(&path).unwrap().len(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
