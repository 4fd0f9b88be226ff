//! Running a study: the fixed protocol's grid from a pilot, one sequence
//! into one record, and the loop over the sequences a shard still owes.

use rayon::prelude::*;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use super::spec::StudySpec;
use super::store::{Grid, GridBox, Shard, claim, open_for_append, read_grid, read_records};
use crate::engine::{CompiledRule, Engine};
use crate::output;
use crate::progress::Progress;
use crate::threshold::fss::Protocol;
use crate::threshold::sequence::{self, Record, Sequence, Setup};
use crate::usage;
use crate::{Error, Result};

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

/// The fixed protocol's grid at the given `densities` in every box (no
/// pilot): each density's nearest number of rods, at least one.
fn given_grid(spec: &StudySpec, densities: &[f64]) -> Grid {
    let boxes = spec
        .boxes
        .iter()
        .map(|&l| {
            let volume = l.powi(3);
            let mut rods: Vec<usize> = densities
                .iter()
                .map(|d| ((d * volume).round() as usize).max(1))
                .collect();
            rods.dedup();
            GridBox {
                box_len: l,
                pilot: Vec::new(),
                rods,
            }
        })
        .collect();
    Grid { boxes }
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
    let mut record = Record::empty(box_len, index, seed);
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

fn load_or_make_grid(dir: &Path, spec: &StudySpec, setup: &Setup) -> Result<Grid> {
    if let Some(grid) = read_grid(dir)? {
        return Ok(grid);
    }
    let grid = match &spec.grid_densities {
        Some(densities) => given_grid(spec, densities),
        None => pilot_grid(spec, setup)?,
    };
    let text = serde_json::to_string_pretty(&grid).expect("grids serialize");
    output::write_atomic(&dir.join("grid.json"), text)?;
    Ok(grid)
}

#[cfg(test)]
mod tests {
    use super::super::spec::{MotifSet, STUDY_FORMAT};
    use super::super::store::{merge, read_records};
    use super::*;
    use crate::engine::RuleSet;
    use crate::spanning::Criterion;
    use crate::threshold::sequence::Kind;

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
            grid_densities: None,
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
                grid_densities: None,
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
            let report = crate::threshold::report::write_study(&elsewhere, &spec, &records, 20);
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
