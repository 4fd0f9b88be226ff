//! A threshold study on disk (MODEL §9): what was asked (`study.json`), the
//! fixed protocol's density grid (`grid.json`), and one JSON line per
//! finished sequence (`records*.jsonl`). A study killed at any moment
//! resumes from its records, and a finished one grows by more sequences per
//! box (`--extend`) without rerunning any; shards (`--shard i/n`) write
//! their own record files, in one directory or several, and [`merge`]
//! combines them exactly.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use super::fss::Protocol;
use super::sequence::{self, Kind, Record, Sequence, Setup};
use crate::engine::{CompiledRule, Engine, RuleSet, run_seed};
use crate::output;
use crate::progress::Progress;
use crate::rods::{RodParams, excluded_volume};
use crate::rule_file::Rule;
use crate::spanning::Criterion;
use crate::usage;
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
        Ok(())
    }

    /// [`StudySpec::validate`], and that the scaling analysis can use the
    /// study at all ([`super::fss::check_design`]): what a command that will
    /// analyse a study checks before any sequence runs. A study itself
    /// (records, shards, merges) needs no more than `validate`.
    pub fn validate_for_analysis(&self) -> Result<()> {
        self.validate()?;
        super::fss::check_design(self.boxes.len(), self.sequences, self.method)
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
    fn first_rods(&self, box_len: f64) -> usize {
        let c0 = match self.kind {
            Kind::Contact => 2.0,
            Kind::Rigid | Kind::Truth => 5.0,
        };
        (c0 / excluded_volume(self.gamma) * box_len.powi(3)).ceil() as usize
    }
}

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
    fn owns(&self, k: usize) -> bool {
        k % self.count == self.index
    }

    fn file_name(&self) -> String {
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

/// Pilot sequences per box for the fixed grid.
pub const PILOT: u64 = 16;

/// Builds the fixed protocol's grid: the nested protocol on [`PILOT`]
/// sequences of their own seeds, then `grid_points` numbers of rods
/// evenly over the pilot's mean plus or minus 2.5 standard deviations
/// (where a logistic spanning curve runs from 1% to 99%), widened to the
/// pilot's extremes.
fn pilot_grid(spec: &StudySpec, setup: &Setup) -> Result<Grid> {
    let pilot_spec = StudySpec {
        seed: spec.seed ^ 0x9170_7000_0000_0001,
        ..spec.clone()
    };
    let boxes = spec
        .boxes
        .iter()
        .map(|&l| {
            let volume = l.powi(3);
            let pilot: Vec<f64> = (0..PILOT)
                .into_par_iter()
                .map(|i| {
                    let r = run_sequence(&pilot_spec, setup, l, i, Protocol::Nested, None)?;
                    let n = r
                        .critical(spec.kind)
                        .expect("nested records a critical number");
                    Ok(n as f64 / volume)
                })
                .collect::<Result<_>>()?;
            let (mean, sd) = crate::math::stats::mean_sd(&pilot);
            let spread = 2.5 * sd.max(mean * 1e-3);
            let lo = (mean - spread).min(pilot.iter().copied().fold(f64::INFINITY, f64::min));
            let hi = (mean + spread).max(pilot.iter().copied().fold(0.0, f64::max));
            let m = spec.grid_points;
            let mut rods: Vec<usize> = (0..m)
                .map(|j| {
                    ((lo + (hi - lo) * j as f64 / (m - 1) as f64).max(0.0) * volume).round()
                        as usize
                })
                .map(|n| n.max(1))
                .collect();
            rods.dedup();
            Ok(GridBox {
                box_len: l,
                pilot,
                rods,
            })
        })
        .collect::<Result<_>>()?;
    Ok(Grid { boxes })
}

/// Runs one sequence.
fn run_sequence(
    spec: &StudySpec,
    setup: &Setup,
    box_len: f64,
    index: u64,
    method: Protocol,
    grid: Option<&GridBox>,
) -> Result<Record> {
    let seed = spec.sequence_seed(box_len, index);
    // The clock includes generating the rods and detecting their contacts.
    let t = Instant::now();
    let mut seq = Sequence::new(spec.gamma, box_len, spec.first_rods(box_len), seed)?;
    let mut record = Record {
        box_len,
        index,
        seed,
        contact_critical: 0,
        rigid_critical: None,
        steps: Vec::new(),
        fresh: None,
        fixed: Vec::new(),
        contacts: Vec::new(),
        undecided: None,
        seconds: 0.0,
        peak_rss_mib: 0.0,
        cpu_seconds: None,
    };
    match method {
        Protocol::Nested => sequence::nested(setup, &mut seq, &mut record)?,
        Protocol::Fixed => {
            let grid = grid.expect("the fixed protocol has a grid");
            sequence::fixed(setup, &mut seq, &grid.rods, &mut record)?
        }
    }
    record.seconds = t.elapsed().as_secs_f64();
    record.peak_rss_mib = crate::usage::peak_rss_mib();
    Ok(record)
}

/// How to run a study besides what determines its records.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub out: PathBuf,
    pub shard: Shard,
    /// Grow a study found in `out` with fewer sequences to the spec's
    /// count (`--extend`). Its records stay valid: a sequence's seed depends
    /// only on its box and index. Never implicit, so that a run with other
    /// parameters cannot silently rewrite a committed study.
    pub extend: bool,
    /// Truth refuses a system whose elimination would need more bytes
    /// (the study then stops with the estimate, its records kept).
    pub memory_limit: Option<u64>,
}

/// What [`run`] did.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Sequences of this shard found done on disk before starting.
    pub resumed: usize,
    /// Sequences run now.
    pub ran: usize,
    /// Whether every sequence of the study (all shards) is on disk in `out`.
    pub complete: bool,
    pub seconds: f64,
}

/// Runs the sequences of `shard` not yet recorded in `opts.out`, appending
/// each record as it finishes (rayon over sequences, largest boxes first).
/// Progress is one stage counted in box volume (L³ per sequence), which
/// the work follows, so it runs evenly although the largest boxes come first.
pub fn run(
    spec: &StudySpec,
    rules: &[CompiledRule],
    opts: &RunOptions,
    progress: &dyn Progress,
) -> Result<RunReport> {
    let started = Instant::now();
    spec.validate()?;
    let dir = &opts.out;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    claim(dir, spec, opts.extend)?;
    let setup = Setup {
        kind: spec.kind,
        gamma: spec.gamma,
        criterion: spec.criterion,
        engine: Engine::with_rules(spec.rules, rules),
        runs: spec.runs,
        memory_limit: opts.memory_limit,
    };
    let grid = match spec.method {
        Protocol::Nested => None,
        Protocol::Fixed => Some(load_or_make_grid(dir, spec, &setup)?),
    };
    let done = read_records(dir, spec)?;
    let mut todo: Vec<(f64, u64)> = Vec::new();
    let mut resumed = 0;
    let mut k = 0;
    for &l in &spec.boxes {
        for i in 0..spec.sequences {
            if opts.shard.owns(k) {
                if done.contains_key(&(l.to_bits(), i)) {
                    resumed += 1;
                } else {
                    todo.push((l, i));
                }
            }
            k += 1;
        }
    }
    // Largest boxes first, so the last sequences to finish are short.
    todo.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let weight = |l: f64| (l.powi(3)).ceil() as u64;
    progress.start(
        &format!(
            "{} sequences, {} done before (counted by box volume)",
            todo.len(),
            resumed
        ),
        todo.iter().map(|t| weight(t.0)).sum(),
    );
    let path = dir.join(opts.shard.file_name());
    // A finished shard is not opened, so a read-only study can be re-analysed.
    let writer = Mutex::new(if todo.is_empty() {
        None
    } else {
        Some(open_for_append(&path)?)
    });
    // The process's CPU time when it last wrote a record: each record
    // carries what the process spent since.
    let cpu_before = Mutex::new(usage::process_cpu_seconds());
    todo.par_iter()
        .map(|&(l, i)| {
            let grid_box = grid
                .as_ref()
                .and_then(|g| g.boxes.iter().find(|b| b.box_len == l));
            let mut record = run_sequence(spec, &setup, l, i, spec.method, grid_box)?;
            let mut w = writer.lock().expect("no writer panicked");
            let mut before = cpu_before.lock().expect("no writer panicked");
            let now = usage::process_cpu_seconds();
            record.cpu_seconds = now
                .zip(*before)
                .map(|(now, before)| (now - before).max(0.0));
            *before = now;
            let mut line = serde_json::to_string(&record).expect("records serialize");
            line.push('\n');
            let w = w.as_mut().expect("opened when there is work");
            w.write_all(line.as_bytes())
                .and_then(|_| w.flush())
                .map_err(|e| Error::io(&path, e))?;
            progress.advance(weight(l));
            Ok(())
        })
        .collect::<Result<()>>()?;
    progress.finish();
    let total = spec.boxes.len() * spec.sequences as usize;
    let complete = read_records(dir, spec)?.len() == total;
    Ok(RunReport {
        resumed,
        ran: todo.len(),
        complete,
        seconds: started.elapsed().as_secs_f64(),
    })
}

fn study_error(path: &Path, reason: impl Into<String>) -> Error {
    Error::Study {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// Writes `study.json`, or checks that the one there is the same study;
/// with `extend`, the same study with fewer sequences is grown to `spec`'s.
fn claim(dir: &Path, spec: &StudySpec, extend: bool) -> Result<()> {
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

fn load_or_make_grid(dir: &Path, spec: &StudySpec, setup: &Setup) -> Result<Grid> {
    if let Some(grid) = read_grid(dir)? {
        return Ok(grid);
    }
    let grid = pilot_grid(spec, setup)?;
    let text = serde_json::to_string_pretty(&grid).expect("grids serialize");
    output::write_atomic(&dir.join("grid.json"), text)?;
    Ok(grid)
}

/// Opens a record file for appending, first cutting off a last line left
/// unfinished by a kill.
fn open_for_append(path: &Path) -> Result<File> {
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
fn read_grid(dir: &Path) -> Result<Option<Grid>> {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(kind: Kind, method: Protocol) -> StudySpec {
        StudySpec {
            format: STUDY_FORMAT.into(),
            kind,
            gamma: 10.0,
            boxes: vec![3.0, 3.5, 4.0],
            sequences: 3,
            rules: RuleSet::Sound,
            motifs: MotifSet::default(),
            runs: 2,
            criterion: Criterion::Wrap,
            method,
            grid_points: 4,
            seed: 5,
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rgc-study-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    fn run_in(spec: &StudySpec, dir: &Path, shard: Shard) -> RunReport {
        let opts = RunOptions {
            out: dir.to_path_buf(),
            shard,
            extend: false,
            memory_limit: None,
        };
        run(spec, &[], &opts, &crate::progress::Silent).unwrap()
    }

    /// Rewrites line `k` (from 0) of a record file through `edit`.
    fn edit_line(path: &Path, k: usize, edit: impl Fn(&mut serde_json::Value)) {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let mut v: serde_json::Value = serde_json::from_str(&lines[k]).unwrap();
        edit(&mut v);
        lines[k] = v.to_string();
        std::fs::write(path, lines.join("\n") + "\n").unwrap();
    }

    fn refusal(dir: &Path, spec: &StudySpec) -> String {
        read_records(dir, spec).unwrap_err().to_string()
    }

    #[test]
    fn records_that_contradict_themselves_are_refused_with_file_and_line() {
        let spec = spec(Kind::Rigid, Protocol::Nested);
        let dir = scratch("contradict");
        run_in(&spec, &dir, Shard::WHOLE);
        let path = dir.join("records.jsonl");
        let clean = std::fs::read_to_string(&path).unwrap();
        let first: Record = serde_json::from_str(clean.lines().next().unwrap()).unwrap();
        let n_r = first.rigid_critical.unwrap();
        let line1 = format!("study {}: line 1: ", path.display());
        for (edit, expected) in [
            (
                Box::new(move |v: &mut serde_json::Value| v["rigid_critical"] = (n_r + 1).into())
                    as Box<dyn Fn(&mut serde_json::Value)>,
                format!("rigid_critical is {}, but its steps find {n_r}", n_r + 1),
            ),
            (
                Box::new(move |v: &mut serde_json::Value| v["contact_critical"] = (n_r + 1).into()),
                format!("rigid_critical {n_r} is below contact_critical {}", n_r + 1),
            ),
            (
                Box::new(|v: &mut serde_json::Value| v["steps"][0]["runs_spanning"] = 3.into()),
                "of 2 runs spanning".into(),
            ),
            (
                Box::new(|v: &mut serde_json::Value| {
                    v["steps"].as_array_mut().unwrap().pop();
                }),
                "the steps end where the bisection compresses".into(),
            ),
            (
                Box::new(|v: &mut serde_json::Value| v["fresh"] = serde_json::Value::Null),
                "no fresh compression".into(),
            ),
            (
                Box::new(|v: &mut serde_json::Value| v["contacts"][0]["density"] = 1.0.into()),
                "contact numbers measured at".into(),
            ),
        ] {
            edit_line(&path, 0, edit);
            let err = refusal(&dir, &spec);
            assert!(
                err.starts_with(&line1)
                    && err.contains("contradicts itself")
                    && err.contains(&expected),
                "{err}"
            );
            // Neither merge nor a resumed run accepts it.
            assert!(merge(std::slice::from_ref(&dir), &scratch("contradict-merged")).is_err());
            let opts = RunOptions {
                out: dir.clone(),
                shard: Shard::WHOLE,
                extend: false,
                memory_limit: None,
            };
            assert!(run(&spec, &[], &opts, &crate::progress::Silent).is_err());
            std::fs::write(&path, &clean).unwrap();
        }
        assert_eq!(read_records(&dir, &spec).unwrap().len(), 9);
        let _ = std::fs::remove_dir_all(scratch("contradict-merged"));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn fixed_records_follow_the_grid_and_contact_spanning() {
        let spec = spec(Kind::Contact, Protocol::Fixed);
        let dir = scratch("fixed-grid");
        run_in(&spec, &dir, Shard::WHOLE);
        let path = dir.join("records.jsonl");
        let clean = std::fs::read_to_string(&path).unwrap();
        edit_line(&path, 1, |v| {
            let n = v["fixed"][0]["n"].as_u64().unwrap();
            v["fixed"][0]["n"] = (n + 1).into();
        });
        let err = refusal(&dir, &spec);
        assert!(
            err.contains("line 2: ") && err.contains("the grid"),
            "{err}"
        );
        std::fs::write(&path, &clean).unwrap();
        edit_line(&path, 1, |v| {
            let spans = v["fixed"][0]["spans"].as_bool().unwrap();
            v["fixed"][0]["spans"] = (!spans).into();
            v["fixed"][0]["runs_spanning"] = usize::from(!spans).into();
        });
        let err = refusal(&dir, &spec);
        assert!(
            err.contains("line 2: ") && err.contains("but contact_critical is"),
            "{err}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Names, lengths and modification times of a directory's files.
    fn snapshot(dir: &Path) -> Vec<(String, u64, std::time::SystemTime)> {
        let mut v: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                let m = e.metadata().unwrap();
                let name = e.file_name().to_string_lossy().into_owned();
                (name, m.len(), m.modified().unwrap())
            })
            .collect();
        v.sort();
        v
    }

    fn set_read_only(dir: &Path, read_only: bool) {
        for path in std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .chain([dir.to_path_buf()])
        {
            let mut p = std::fs::metadata(&path).unwrap().permissions();
            p.set_readonly(read_only);
            std::fs::set_permissions(&path, p).unwrap();
        }
    }

    /// Re-analysing a finished study writes nothing into its directory (made
    /// read-only here, which binds unless the tests run as root).
    #[test]
    fn a_finished_study_is_re_analysed_without_writing_to_it() {
        for method in [Protocol::Nested, Protocol::Fixed] {
            // Large enough for the scaling analysis to fit.
            let spec = StudySpec {
                sequences: 12,
                grid_points: 6,
                seed: 7,
                ..spec(Kind::Rigid, method)
            };
            let dir = scratch("read-only");
            let elsewhere = scratch("read-only-report");
            run_in(&spec, &dir, Shard::WHOLE);
            // Merged in place once, as `rgc merge` does by default.
            merge(std::slice::from_ref(&dir), &dir).unwrap();
            let before = snapshot(&dir);
            set_read_only(&dir, true);
            let again = run_in(&spec, &dir, Shard::WHOLE);
            assert_eq!((again.ran, again.resumed, again.complete), (0, 36, true));
            let (_, in_place) = merge(std::slice::from_ref(&dir), &dir).unwrap();
            let (_, records) = merge(std::slice::from_ref(&dir), &elsewhere).unwrap();
            assert_eq!(in_place, records);
            let report = super::super::report::write_study(&elsewhere, &spec, &records, 20);
            set_read_only(&dir, false);
            report.unwrap();
            assert_eq!(snapshot(&dir), before, "{method:?}");
            assert_eq!(read_records(&elsewhere, &spec).unwrap().len(), 36);
            for d in [dir, elsewhere] {
                std::fs::remove_dir_all(d).unwrap();
            }
        }
    }

    #[test]
    fn merge_names_both_records_that_disagree() {
        let spec = spec(Kind::Contact, Protocol::Nested);
        let (a, b) = (scratch("disagree-a"), scratch("disagree-b"));
        run_in(&spec, &a, Shard { index: 0, count: 2 });
        run_in(&spec, &b, Shard::WHOLE);
        // Sequence 2 of box 3 is the study's third, so in shard 0 of 2 (the
        // even-numbered ones), on a line that depends on thread timing.
        let shard = a.join("records-0-of-2.jsonl");
        let line = |path: &Path| {
            std::fs::read_to_string(path)
                .unwrap()
                .lines()
                .position(|l| l.contains("\"box\":3.0,\"index\":2,"))
                .unwrap()
        };
        let (k, j) = (line(&b.join("records.jsonl")), line(&shard));
        edit_line(&b.join("records.jsonl"), k, |v| {
            let n = v["contact_critical"].as_u64().unwrap() + 1;
            v["contact_critical"] = n.into();
            let volume = 27.0;
            v["contacts"][0]["density"] = (n as f64 / volume).into();
        });
        let err = merge(&[a.clone(), b.clone()], &scratch("disagree-out"))
            .unwrap_err()
            .to_string();
        let named = format!(
            "study {}: line {}: sequence 2 of box 3 differs from line {} of {}",
            b.join("records.jsonl").display(),
            k + 1,
            j + 1,
            shard.display()
        );
        assert_eq!(err, named);
        // Two files of one directory are named the same way.
        std::fs::copy(b.join("records.jsonl"), a.join("records.jsonl")).unwrap();
        let err = refusal(&a, &spec);
        assert!(
            err.contains(&format!("line {} of {}", j + 1, shard.display()))
                && err.contains(&format!("line {}: sequence 2 of box 3 differs", k + 1)),
            "{err}"
        );
        for d in [a, b, scratch("disagree-out")] {
            let _ = std::fs::remove_dir_all(d);
        }
    }

    #[test]
    fn an_impossible_study_claims_nothing() {
        let mut spec = spec(Kind::Rigid, Protocol::Nested);
        spec.gamma = 23.0;
        spec.boxes = vec![4.0, 5.0, 100.0];
        let dir = scratch("impossible");
        let opts = RunOptions {
            out: dir.clone(),
            shard: Shard::WHOLE,
            extend: false,
            memory_limit: None,
        };
        let err = run(&spec, &[], &opts, &crate::progress::Silent)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("box of side 100 means") && err.contains("more than the 50000000"),
            "{err}"
        );
        assert!(!dir.exists());
    }
}
