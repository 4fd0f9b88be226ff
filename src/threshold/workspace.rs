//! A study run from a row or signac workspace (MODEL §9): each directory's
//! value (`value.json`, or a signac statepoint) names one slice of one
//! study, and the directory holds that slice's study files. Workflow tools
//! count a directory done when its product files exist, so a slice's
//! product, `slice.json`, appears only once all its records are on disk;
//! merging writes `merged.json` into every directory of the study once the
//! merged study, named by its spec, is complete.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::output;
use crate::spanning::Criterion;
use crate::threshold::sequence::Record;
use crate::threshold::study::{self, Shard, StudySpec};
use crate::threshold::variants;
use crate::{Error, Result};

/// The value file row reads by default (`workspace.value_file`).
pub const VALUE_FILE: &str = "value.json";
/// A finished slice's product.
pub const SLICE_FILE: &str = "slice.json";
/// A merged directory's product.
pub const MERGED_FILE: &str = "merged.json";

/// The parameters a value gives, by their `rgc threshold` flag names
/// (underscores for dashes); the first three are required, the others
/// default as the flags do.
pub const PARAMETERS: [&str; 12] = [
    "gamma",
    "boxes",
    "sequences",
    "kind",
    "rules",
    "rule_files",
    "runs",
    "protocol",
    "grid_points",
    "criterion",
    "seed",
    "shard",
];

/// A key of a value that rgc does not read but allows: a label that groups
/// a study's directories (row's `group.sort_by`).
pub const LABEL: &str = "study";

/// Where in a value each parameter is: `/NAME` unless given otherwise.
#[derive(Clone, Debug, Default)]
pub struct Pointers(BTreeMap<String, String>);

impl Pointers {
    /// Parses `NAME=/json/pointer` items (`gamma=/sp/aspect_ratio`).
    pub fn parse(items: &[String]) -> Result<Pointers> {
        let mut map = BTreeMap::new();
        for item in items {
            let bad = |why: &str| Error::Parameter(format!("--pointer {item:?}: {why}"));
            let (name, pointer) = item
                .split_once('=')
                .ok_or_else(|| bad("expected NAME=/json/pointer, e.g. gamma=/sp/gamma"))?;
            if !PARAMETERS.contains(&name) {
                return Err(bad(&format!(
                    "no parameter {name:?} (one of {})",
                    PARAMETERS.join(", ")
                )));
            }
            if !pointer.starts_with('/') {
                return Err(bad("a JSON pointer starts with '/'"));
            }
            if map.insert(name.to_string(), pointer.to_string()).is_some() {
                return Err(bad(&format!("{name} is given twice")));
            }
        }
        Ok(Pointers(map))
    }

    fn of(&self, name: &str) -> String {
        self.0
            .get(name)
            .cloned()
            .unwrap_or_else(|| format!("/{name}"))
    }
}

/// One directory's slice: its study (motifs still unloaded), the rule
/// files to load, which shard, and the parameters as the value gave them.
#[derive(Clone, Debug)]
pub struct Slice {
    pub spec: StudySpec,
    pub rule_files: Vec<PathBuf>,
    pub shard: Shard,
    /// The parameters found, by name: what `slice.json` keeps to recognise
    /// the value it was made from.
    pub parameters: BTreeMap<String, Value>,
}

/// Reads `dir/value_file` into a slice, checked as `rgc threshold` checks
/// its flags (and for the analysis the merge will do). Every key of the
/// value must be read by a pointer or be the [`LABEL`], so that a
/// misspelt parameter is refused rather than left at its default.
pub fn read_slice(dir: &Path, value_file: &str, pointers: &Pointers) -> Result<Slice> {
    let path = dir.join(value_file);
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let at = |what: String| Error::Parameter(format!("{}: {what}", path.display()));
    let value: Value = serde_json::from_str(&text).map_err(|e| at(format!("not JSON: {e}")))?;
    let Some(object) = value.as_object() else {
        return Err(at("expected a JSON object of the study's parameters".into()));
    };
    let mut parameters = BTreeMap::new();
    for name in PARAMETERS {
        if let Some(v) = value.pointer(&pointers.of(name)) {
            parameters.insert(name.to_string(), v.clone());
        }
    }
    let read: Vec<String> = PARAMETERS.iter().map(|n| pointers.of(n)).collect();
    if let Some(key) = object.keys().find(|k| {
        k.as_str() != LABEL && !read.iter().any(|p| p.split('/').nth(1) == Some(k.as_str()))
    }) {
        return Err(at(format!(
            "unknown key {key:?} (rgc reads {}, and `{LABEL}` as a label; --pointer NAME=/KEY maps others)",
            PARAMETERS.join(", ")
        )));
    }
    let param = |name: &'static str| Param {
        found: &parameters,
        name,
        pointers,
        path: &path,
    };
    let mut spec = StudySpec::new(
        param("gamma").required()?,
        param("boxes").required()?,
        param("sequences").required()?,
        Criterion::Wrap,
        1,
    );
    spec.kind = param("kind").get()?.unwrap_or(spec.kind);
    spec.rules = param("rules").get()?.unwrap_or(spec.rules);
    spec.runs = param("runs").get()?.unwrap_or(spec.runs);
    spec.method = param("protocol").get()?.unwrap_or(spec.method);
    spec.grid_points = param("grid_points").get()?.unwrap_or(spec.grid_points);
    spec.criterion = param("criterion").get()?.unwrap_or(spec.criterion);
    spec.seed = param("seed").get()?.unwrap_or(spec.seed);
    let rule_files: Vec<PathBuf> = param("rule_files").get()?.unwrap_or_default();
    let shard = match param("shard").get::<String>()? {
        Some(s) => {
            Shard::parse(&s).map_err(|e| at(format!("{}: {}", pointers.of("shard"), reason(e))))?
        }
        None => Shard::WHOLE,
    };
    if spec.runs > 1000 {
        return Err(at(format!("runs {} is over 1000", spec.runs)));
    }
    spec.validate_for_analysis().map_err(|e| at(reason(e)))?;
    Ok(Slice {
        spec,
        rule_files,
        shard,
        parameters,
    })
}

/// One parameter of a value, read by its pointer.
struct Param<'a> {
    found: &'a BTreeMap<String, Value>,
    name: &'static str,
    pointers: &'a Pointers,
    path: &'a Path,
}

impl Param<'_> {
    /// The parameter as a `T` (serde's message where it is not one), if
    /// the value gives it.
    fn get<T: DeserializeOwned>(&self) -> Result<Option<T>> {
        self.found
            .get(self.name)
            .map(|v| {
                serde_json::from_value(v.clone()).map_err(|e| {
                    Error::Parameter(format!(
                        "{}: {} ({}): {e}",
                        self.path.display(),
                        self.pointers.of(self.name),
                        self.name
                    ))
                })
            })
            .transpose()
    }

    /// The parameter as a `T`, which the value must give.
    fn required<T: DeserializeOwned>(&self) -> Result<T> {
        self.get()?.ok_or_else(|| {
            Error::Parameter(format!(
                "{}: no {} (at {})",
                self.path.display(),
                self.name,
                self.pointers.of(self.name)
            ))
        })
    }
}

/// A parameter error's message without its kind, to follow the value's path.
fn reason(e: Error) -> String {
    match e {
        Error::Parameter(m) => m,
        e => e.to_string(),
    }
}

/// What `slice.json` says: the slice, its record file, and the parameters
/// of the value it was made from.
#[derive(Debug, Serialize, Deserialize)]
struct SliceDone {
    shard: String,
    records: String,
    sequences: usize,
    parameters: BTreeMap<String, Value>,
}

fn shard_text(s: Shard) -> String {
    format!("{}/{}", s.index, s.count)
}

/// Whether `dir` holds this slice finished (`slice.json`); one finished
/// from another value is refused, since a directory's value never changes.
pub fn is_done(dir: &Path, slice: &Slice) -> Result<bool> {
    let path = dir.join(SLICE_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(Error::io(&path, e)),
    };
    let bad = |reason: String| Error::Study {
        path: path.clone(),
        reason,
    };
    let done: SliceDone =
        serde_json::from_str(&text).map_err(|e| bad(format!("unreadable: {e}")))?;
    if done.parameters != slice.parameters || done.shard != shard_text(slice.shard) {
        return Err(bad(format!(
            "made from another value ({}); a workspace directory's value never changes: make a new directory",
            serde_json::to_string(&done.parameters).unwrap_or_default()
        )));
    }
    Ok(true)
}

/// Writes `slice.json` (atomically): every sequence of the slice is in its
/// record file.
pub fn mark_done(dir: &Path, slice: &Slice, sequences: usize) -> Result<()> {
    let done = SliceDone {
        shard: shard_text(slice.shard),
        records: slice.shard.file_name(),
        sequences,
        parameters: slice.parameters.clone(),
    };
    let text = serde_json::to_string_pretty(&done).expect("markers serialize");
    output::write_atomic(&dir.join(SLICE_FILE), text + "\n")
}

/// Merges the slices in `dirs` (one study) into the directory under
/// `studies` that [`variants::study_name`] names; returns it with the
/// spec and the records in study order.
pub fn merge(dirs: &[PathBuf], studies: &Path) -> Result<(PathBuf, StudySpec, Vec<Record>)> {
    let Some(first) = dirs.first() else {
        return Err(Error::Parameter(
            "merge needs at least one workspace directory".into(),
        ));
    };
    let spec = study::read_spec(first)?;
    let out = studies.join(variants::study_name(&spec));
    let (spec, records) = study::merge(dirs, &out)?;
    Ok((out, spec, records))
}

/// What `merged.json` says: where the study went and how many sequences it has.
#[derive(Serialize)]
struct Merged<'a> {
    study: &'a Path,
    sequences: usize,
}

/// Writes `merged.json` into each of `dirs` (atomically), once the study in
/// `out` is merged and analysed.
pub fn mark_merged(dirs: &[PathBuf], out: &Path, sequences: usize) -> Result<()> {
    let text = serde_json::to_string_pretty(&Merged {
        study: out,
        sequences,
    })
    .expect("markers serialize");
    for dir in dirs {
        output::write_atomic(&dir.join(MERGED_FILE), format!("{text}\n"))?;
    }
    Ok(())
}
