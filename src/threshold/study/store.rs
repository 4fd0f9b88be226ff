//! A study directory's files: `study.json` claimed or read, `grid.json`,
//! and the record files of the shards, appended to, read back against the
//! study and merged.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Seek};
use std::path::{Path, PathBuf};

use super::spec::{STUDY_FORMAT, StudySpec};
use crate::output;
use crate::threshold::fss::Protocol;
use crate::threshold::sequence::Record;
use crate::{Error, Result};

/// One slice `i/n` of a study's sequences (`--shard`), counted from 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Parses `i/n` with `0 <= i < n`.
    pub fn parse(s: &str) -> Result<Shard> {
        let bad = || {
            Error::Parameter(format!(
                "shard {s:?}: expected i/n with 0 <= i < n, e.g. 0/4"
            ))
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether the `k`-th sequence of the study (boxes in order, then
    /// index) belongs to this shard: round robin, so shards get equal work.
    pub(super) fn owns(&self, k: usize) -> bool {
        k % self.count == self.index
    }

    /// The shard's record file: `records.jsonl` for a whole study.
    pub fn file_name(&self) -> String {
        if *self == Shard::WHOLE {
            "records.jsonl".into()
        } else {
            format!("records-{}-of-{}.jsonl", self.index, self.count)
        }
    }
}

/// The fixed protocol's numbers of rods per box, from a pilot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    pub boxes: Vec<GridBox>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridBox {
    #[serde(rename = "box")]
    pub box_len: f64,
    /// Pilot critical densities it was built from.
    pub pilot: Vec<f64>,
    pub rods: Vec<usize>,
}

fn study_error(path: &Path, reason: impl Into<String>) -> Error {
    Error::Study {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// Writes `study.json`, or checks that the one there is the same study;
/// with `extend`, the same study with fewer sequences is grown to `spec`'s.
pub(super) fn claim(dir: &Path, spec: &StudySpec, extend: bool) -> Result<()> {
    let path = dir.join("study.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => {
            let there: StudySpec = serde_json::from_str(&text)
                .map_err(|e| study_error(&path, format!("unreadable study file: {e}")))?;
            let grown = StudySpec {
                sequences: spec.sequences,
                ..there.clone()
            };
            if grown.same(spec) && there.sequences < spec.sequences {
                if !extend {
                    return Err(study_error(
                        &path,
                        format!(
                            "this directory holds the same study with {} sequences per box, not {}; add --extend to grow it (its records are kept)",
                            there.sequences, spec.sequences
                        ),
                    ));
                }
                let text = serde_json::to_string_pretty(&StudySpec {
                    motifs: there.motifs,
                    ..spec.clone()
                })
                .expect("specs serialize");
                return output::write_atomic(&path, text);
            }
            if !there.same(spec) {
                return Err(study_error(
                    &path,
                    format!(
                        "this directory holds another study ({}); use another directory (threshold --out, compare and tradeoff --studies), or the same command\n  there: {}\n  asked: {}",
                        difference(&there, spec),
                        serde_json::to_string(&there).unwrap_or_default(),
                        serde_json::to_string(spec).unwrap_or_default()
                    ),
                ));
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let text = serde_json::to_string_pretty(spec).expect("specs serialize");
            output::write_atomic(&path, text)
        }
        Err(e) => Err(Error::io(&path, e)),
    }
}

/// The first fields in which two specs differ, for error messages.
fn difference(a: &StudySpec, b: &StudySpec) -> String {
    let (a, b) = (
        serde_json::to_value(a).unwrap_or_default(),
        serde_json::to_value(b).unwrap_or_default(),
    );
    let (Some(a), Some(b)) = (a.as_object(), b.as_object()) else {
        return String::new();
    };
    a.iter()
        .filter(|(k, v)| k.as_str() != "motifs" && b.get(*k) != Some(*v))
        .map(|(k, v)| format!("{k} {v} vs {}", b.get(k).cloned().unwrap_or_default()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Opens a record file for appending, first cutting off a last line left
/// unfinished by a kill.
pub(super) fn open_for_append(path: &Path) -> Result<File> {
    let mut f = OpenOptions::new()
        .create(true)
        .read(true)
        .append(true)
        .open(path)
        .map_err(|e| Error::io(path, e))?;
    let text = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let keep = text.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
    if keep < text.len() {
        f.set_len(keep as u64).map_err(|e| Error::io(path, e))?;
        f.seek(std::io::SeekFrom::End(0))
            .map_err(|e| Error::io(path, e))?;
    }
    Ok(f)
}

/// Key of a record: its box (as bits) and index.
type Key = (u64, u64);

/// Reads every record file of `dir` (`records*.jsonl`), checking each record
/// against the study and against itself ([`Record::check`]); an unfinished
/// last line (a kill) is ignored. Identical duplicates (shards run twice)
/// are allowed, different ones are not. Errors name the file and line.
pub fn read_records(dir: &Path, spec: &StudySpec) -> Result<BTreeMap<Key, Record>> {
    Ok(read_sourced(dir, spec)?
        .into_iter()
        .map(|(k, (r, _))| (k, r))
        .collect())
}

/// Where a record was read: its file and line (from 1).
type Source = (PathBuf, usize);

/// [`read_records`], each record with its source.
fn read_sourced(dir: &Path, spec: &StudySpec) -> Result<BTreeMap<Key, (Record, Source)>> {
    let grid = match spec.method {
        Protocol::Fixed => read_grid(dir)?,
        Protocol::Nested => None,
    };
    let mut records: BTreeMap<Key, (Record, Source)> = BTreeMap::new();
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("records") && n.ends_with(".jsonl"))
        })
        .collect();
    files.sort();
    for path in files {
        let text = std::fs::read(&path).map_err(|e| Error::io(&path, e))?;
        let complete = text.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
        for (k, line) in BufReader::new(&text[..complete]).lines().enumerate() {
            let line = line.map_err(|e| Error::io(&path, e))?;
            if line.trim().is_empty() {
                continue;
            }
            let at = |reason: String| study_error(&path, format!("line {}: {reason}", k + 1));
            let r: Record =
                serde_json::from_str(&line).map_err(|e| at(format!("not a record: {e}")))?;
            if !spec.boxes.contains(&r.box_len) || r.index >= spec.sequences {
                return Err(at(format!(
                    "sequence {} of box {} is not part of this study",
                    r.index, r.box_len
                )));
            }
            if r.seed != spec.sequence_seed(r.box_len, r.index) {
                return Err(at(format!(
                    "sequence {} of box {} has seed {}, not this study's",
                    r.index, r.box_len, r.seed
                )));
            }
            let grid_rods = match &grid {
                Some(g) => Some(
                    g.boxes
                        .iter()
                        .find(|b| b.box_len == r.box_len)
                        .map(|b| &b.rods[..])
                        .ok_or_else(|| at(format!("grid.json has no box {}", r.box_len)))?,
                ),
                None => None,
            };
            r.check(spec.kind, spec.method, spec.runs, grid_rods)
                .map_err(|reason| {
                    at(format!(
                        "sequence {} of box {} contradicts itself: {reason}",
                        r.index, r.box_len
                    ))
                })?;
            let key = (r.box_len.to_bits(), r.index);
            let source = (path.clone(), k + 1);
            match records.get(&key) {
                Some((seen, first)) if !same_record(seen, &r) => {
                    return Err(at(format!(
                        "sequence {} of box {} differs from {}",
                        r.index,
                        r.box_len,
                        describe(first)
                    )));
                }
                Some(_) => {}
                None => {
                    records.insert(key, (r, source));
                }
            }
        }
    }
    Ok(records)
}

/// `line N of FILE`, for messages that name two places.
fn describe((path, line): &Source) -> String {
    format!("line {line} of {}", path.display())
}

/// A study directory's `grid.json`, if it has one.
pub(super) fn read_grid(dir: &Path) -> Result<Option<Grid>> {
    let path = dir.join("grid.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| study_error(&path, format!("unreadable grid: {e}"))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(&path, e)),
    }
}

/// Equal results (timing aside).
fn same_record(a: &Record, b: &Record) -> bool {
    let plain = |r: &Record| Record {
        seconds: 0.0,
        peak_rss_mib: 0.0,
        cpu_seconds: None,
        ..r.clone()
    };
    plain(a) == plain(b)
}

/// Combines the records of `dirs` (shards of one study) into `out`: the
/// studies must be the same, every sequence present, duplicates equal.
/// Writes `out/study.json` and `out/records.jsonl` in study order, and
/// returns the spec and the records.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<(StudySpec, Vec<Record>)> {
    let Some(first) = dirs.first() else {
        return Err(Error::Parameter(
            "merge needs at least one study directory".into(),
        ));
    };
    let spec = read_spec(first)?;
    let mut all: BTreeMap<Key, (Record, Source)> = BTreeMap::new();
    for dir in dirs {
        let there = read_spec(dir)?;
        if !there.same(&spec) {
            return Err(study_error(
                dir,
                format!(
                    "a different study from {} ({})",
                    first.display(),
                    difference(&spec, &there)
                ),
            ));
        }
        for (key, (r, source)) in read_sourced(dir, &spec)? {
            match all.get(&key) {
                Some((seen, first)) if !same_record(seen, &r) => {
                    return Err(study_error(
                        &source.0,
                        format!(
                            "line {}: sequence {} of box {} differs from {}",
                            source.1,
                            r.index,
                            r.box_len,
                            describe(first)
                        ),
                    ));
                }
                Some(_) => {}
                None => {
                    all.insert(key, (r, source));
                }
            }
        }
    }
    let missing: Vec<String> = spec
        .boxes
        .iter()
        .flat_map(|&l| (0..spec.sequences).map(move |i| (l, i)))
        .filter(|&(l, i)| !all.contains_key(&(l.to_bits(), i)))
        .map(|(l, i)| format!("box {l} #{i}"))
        .collect();
    if !missing.is_empty() {
        let shown: Vec<_> = missing.iter().take(5).cloned().collect();
        return Err(study_error(
            out,
            format!(
                "{} sequence(s) missing from the shards ({}{}); run the missing shards first",
                missing.len(),
                shown.join(", "),
                if missing.len() > 5 { ", ..." } else { "" }
            ),
        ));
    }
    let records = in_study_order(&spec, all.into_iter().map(|(k, (r, _))| (k, r)).collect());
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let same_dir = dirs.iter().any(|d| same_path(d, out));
    if !same_dir {
        claim(out, &spec, false)?;
        // The fixed protocol's grid travels with the records.
        let grid = first.join("grid.json");
        if grid.exists() {
            let text = std::fs::read(&grid).map_err(|e| Error::io(&grid, e))?;
            output::write_atomic(&out.join("grid.json"), text)?;
        }
    }
    let mut text = String::new();
    for r in &records {
        text += &serde_json::to_string(r).expect("records serialize");
        text.push('\n');
    }
    // A study merged before is left as it is: re-analysing it writes nothing
    // into its directory, which may be read-only.
    let path = out.join("records.jsonl");
    if std::fs::read(&path).ok().as_deref() != Some(text.as_bytes()) {
        output::write_atomic(&path, text)?;
    }
    Ok((spec, records))
}

fn same_path(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Reads a study directory's `study.json`.
pub fn read_spec(dir: &Path) -> Result<StudySpec> {
    let path = dir.join("study.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let spec: StudySpec = serde_json::from_str(&text)
        .map_err(|e| study_error(&path, format!("unreadable study file: {e}")))?;
    if spec.format != STUDY_FORMAT {
        return Err(study_error(
            &path,
            format!("format {:?}, this rgc reads {STUDY_FORMAT:?}", spec.format),
        ));
    }
    Ok(spec)
}

/// Records sorted as the study lists them: boxes in the given order, then index.
pub fn in_study_order(spec: &StudySpec, records: BTreeMap<Key, Record>) -> Vec<Record> {
    let mut records: Vec<Record> = records.into_values().collect();
    let pos = |l: f64| {
        spec.boxes
            .iter()
            .position(|&b| b == l)
            .unwrap_or(usize::MAX)
    };
    records.sort_by_key(|r| (pos(r.box_len), r.index));
    records
}
