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
//! all are ranked, so a killed run resumes where it stopped, and the tally
//! reads the lines in study order whatever the thread count.

use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use super::sequence::{Kind, Record, Sequence};
use super::study;
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
    use rayon::prelude::*;
    if !(2..=MAX_REALIZATIONS).contains(&spec.realizations) {
        return Err(Error::Parameter(format!(
            "--realizations {}: a disagreement needs 2 to {MAX_REALIZATIONS} realizations",
            spec.realizations
        )));
    }
    let mut chosen: Vec<(f64, Record)> = Vec::new();
    for dir in dirs {
        let s = study::read_spec(dir)?;
        if s.kind != Kind::Truth {
            return Err(Error::Parameter(format!(
                "{} is a {:?} study: the realizations' ranks need a truth study (--kind truth)",
                dir.display(),
                s.kind
            )));
        }
        for l in &spec.boxes {
            if !s.boxes.contains(l) {
                return Err(Error::Parameter(format!(
                    "box {l} is not one of {}'s boxes {:?}",
                    dir.display(),
                    s.boxes
                )));
            }
        }
        let records = study::read_records(dir, &s)?;
        chosen.extend(
            records
                .into_values()
                .filter(|r| spec.boxes.is_empty() || spec.boxes.contains(&r.box_len))
                .filter(|r| r.index < spec.sequences)
                .map(|r| (s.gamma, r)),
        );
    }
    output::check_dir(out)?;
    if let Some(prefix) = tally_prefix {
        output::check_file(prefix)?;
    }
    let (spec_file, lines) = files(out);
    claim(&spec_file, spec)?;
    drop_cut_line(&lines)?;
    let done: BTreeSet<(u64, u64, u64)> = read(&lines)?
        .iter()
        .map(|s| (s.gamma.to_bits(), s.box_len.to_bits(), s.index))
        .collect();
    let todo: Vec<&(f64, Record)> = chosen
        .iter()
        .filter(|(g, r)| !done.contains(&(g.to_bits(), r.box_len.to_bits(), r.index)))
        .collect();
    progress.start("sequences ranked again", todo.len() as u64);
    let file = Mutex::new(
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&lines)
            .map_err(|e| Error::io(&lines, e))?,
    );
    todo.par_iter()
        .map(|(gamma, r)| {
            let ranked = rank_sequence(*gamma, r, spec.realizations)?;
            let mut line = serde_json::to_string(&ranked).expect("ranks serialize");
            line.push('\n');
            file.lock()
                .expect("no writer panicked")
                .write_all(line.as_bytes())
                .map_err(|e| Error::io(&lines, e))?;
            progress.advance(1);
            Ok(())
        })
        .collect::<Result<()>>()?;
    progress.finish();
    Ok(tally(&read(&lines)?))
}

/// Writes the spec into a new directory, or checks that the one there is
/// the same: another measurement never appends to this one's lines.
fn claim(path: &Path, spec: &TwinsSpec) -> Result<()> {
    if path.exists() {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let there: TwinsSpec = serde_json::from_str(&text).map_err(|e| Error::Malformed {
            format: "twins spec",
            path: path.to_path_buf(),
            line: e.line(),
            reason: e.to_string(),
        })?;
        if &there != spec {
            return Err(Error::Parameter(format!(
                "{} holds another measurement ({:?}): write elsewhere",
                path.display(),
                there
            )));
        }
        return Ok(());
    }
    output::write_atomic(
        path,
        serde_json::to_string_pretty(spec).expect("spec serializes"),
    )
}

/// Cuts a last line that a kill left without its newline, so that what
/// is appended next starts a line of its own.
fn drop_cut_line(lines: &Path) -> Result<()> {
    let Ok(text) = std::fs::read(lines) else {
        return Ok(());
    };
    if text.last().is_some_and(|&b| b != b'\n') {
        let keep = text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(lines)
            .map_err(|e| Error::io(lines, e))?;
        file.set_len(keep as u64).map_err(|e| Error::io(lines, e))?;
    }
    Ok(())
}

/// The sequences already ranked; a last line cut short by a kill is left
/// out (it is ranked again).
pub fn read(lines: &Path) -> Result<Vec<SequenceRanks>> {
    let text = match std::fs::read_to_string(lines) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(Error::io(lines, e)),
    };
    let complete = text.rfind('\n').map_or("", |end| &text[..end]);
    complete
        .lines()
        .enumerate()
        .map(|(i, l)| {
            serde_json::from_str(l).map_err(|e| Error::Malformed {
                format: "ranks",
                path: lines.to_path_buf(),
                line: i + 1,
                reason: e.to_string(),
            })
        })
        .collect()
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
