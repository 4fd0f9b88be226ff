//! Measurements that revisit the sequences of finished truth studies, one
//! line per sequence: a spec file that claims the directory, and a journal
//! of lines appended as each sequence finishes, so that a killed run
//! resumes where it stopped and the tally reads the lines in study order
//! whatever the thread count (`twins`, `locality`).

use std::collections::BTreeSet;
use std::fmt::Debug;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::sequence::{Kind, Record};
use super::study;
use crate::progress::Progress;
use crate::{Error, Result, output};

/// The decided and undecided records of the first `sequences` sequences of
/// `boxes` (every box when empty) of the truth studies `dirs`, each with
/// its study's aspect ratio; `what` names the measurement in the refusal
/// of a study of another kind.
pub fn truth_records(
    dirs: &[PathBuf],
    boxes: &[f64],
    sequences: u64,
    what: &str,
) -> Result<Vec<(f64, Record)>> {
    let mut chosen = Vec::new();
    for dir in dirs {
        let s = study::read_spec(dir)?;
        if s.kind != Kind::Truth {
            return Err(Error::Parameter(format!(
                "{} is a {:?} study: {what} needs a truth study (--kind truth)",
                dir.display(),
                s.kind
            )));
        }
        if let Some(l) = boxes.iter().find(|l| !s.boxes.contains(l)) {
            return Err(Error::Parameter(format!(
                "box {l} is not one of {}'s boxes {:?}",
                dir.display(),
                s.boxes
            )));
        }
        let records = study::read_records(dir, &s)?;
        chosen.extend(
            records
                .into_values()
                .filter(|r| boxes.is_empty() || boxes.contains(&r.box_len))
                .filter(|r| r.index < sequences)
                .map(|r| (s.gamma, r)),
        );
    }
    Ok(chosen)
}

/// [`truth_records`] with a critical number (truth decided there).
pub fn decided_truth_records(
    dirs: &[PathBuf],
    boxes: &[f64],
    sequences: u64,
    what: &str,
) -> Result<Vec<(f64, Record)>> {
    let mut chosen = truth_records(dirs, boxes, sequences, what)?;
    chosen.retain(|(_, r)| r.rigid_critical.is_some());
    Ok(chosen)
}

/// The spec a measurement's `path` holds.
pub fn read_spec<S: DeserializeOwned>(path: &Path, format: &'static str) -> Result<S> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::Malformed {
        format,
        path: path.to_path_buf(),
        line: e.line(),
        reason: e.to_string(),
    })
}

/// Writes `spec` into a new directory's `path`, or checks that the one
/// there is the same: another measurement never appends to this one's lines.
pub fn claim<S>(path: &Path, spec: &S, format: &'static str) -> Result<()>
where
    S: Serialize + DeserializeOwned + PartialEq + Debug,
{
    if path.exists() {
        let there: S = read_spec(path, format)?;
        if &there != spec {
            return Err(Error::Parameter(format!(
                "{} holds another measurement ({there:?}): write elsewhere",
                path.display()
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
pub fn drop_cut_line(lines: &Path) -> Result<()> {
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

/// The lines written so far; a last line cut short by a kill is left out
/// (its sequence is measured again).
pub fn read<T: DeserializeOwned>(lines: &Path, format: &'static str) -> Result<Vec<T>> {
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
                format,
                path: lines.to_path_buf(),
                line: i + 1,
                reason: e.to_string(),
            })
        })
        .collect()
}

/// Appends one line per finished sequence, from any thread.
pub struct Journal {
    path: PathBuf,
    file: Mutex<std::fs::File>,
}

impl Journal {
    /// Opens `lines` for appending, after cutting a line a kill left.
    pub fn open(lines: &Path) -> Result<Journal> {
        drop_cut_line(lines)?;
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(lines)
            .map_err(|e| Error::io(lines, e))?;
        Ok(Journal {
            path: lines.to_path_buf(),
            file: Mutex::new(file),
        })
    }

    /// Writes `item` as one line and flushes it.
    pub fn append<T: Serialize>(&self, item: &T) -> Result<()> {
        let mut line = serde_json::to_string(item).expect("lines serialize");
        line.push('\n');
        let mut file = self.file.lock().expect("no writer panicked");
        file.write_all(line.as_bytes())
            .and_then(|_| file.flush())
            .map_err(|e| Error::io(&self.path, e))
    }
}

/// A journal's line: one sequence of one aspect ratio.
pub trait Line: Serialize + DeserializeOwned {
    /// Its aspect ratio, box and index.
    fn key(&self) -> (f64, f64, u64);
}

/// Measures every chosen record not yet in the journal `lines` (in
/// parallel, each line appended as its sequence finishes) after claiming
/// `spec_file` for `spec`; returns every line, old and new.
pub fn measure<S, T>(
    (spec_file, spec, format): (&Path, &S, &'static str),
    lines: &Path,
    chosen: &[(f64, Record)],
    progress: &dyn Progress,
    one: impl Fn(f64, &Record) -> Result<T> + Sync,
) -> Result<Vec<T>>
where
    S: Serialize + DeserializeOwned + PartialEq + Debug,
    T: Line,
{
    use rayon::prelude::*;
    claim(spec_file, spec, format)?;
    let journal = Journal::open(lines)?;
    let bits = |(g, l, i): (f64, f64, u64)| (g.to_bits(), l.to_bits(), i);
    let done: BTreeSet<(u64, u64, u64)> = read::<T>(lines, format)?
        .iter()
        .map(|t| bits(t.key()))
        .collect();
    let todo: Vec<&(f64, Record)> = chosen
        .iter()
        .filter(|(g, r)| !done.contains(&bits((*g, r.box_len, r.index))))
        .collect();
    progress.start("sequences measured", todo.len() as u64);
    todo.par_iter()
        .map(|(gamma, r)| {
            journal.append(&one(*gamma, r)?)?;
            progress.advance(1);
            Ok(())
        })
        .collect::<Result<()>>()?;
    progress.finish();
    read(lines, format)
}
