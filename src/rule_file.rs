//! Motif rule files (MODEL §6): typed patterns with their provenance and
//! exact-rank verdict, as plain JSON. Every rule is re-verified by exact
//! rank when it is loaded, and a rule that is not rigid on every
//! realization component is refused: it would create false rigidity.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::pattern::{NodeKind, Pattern};
use crate::{Error, Result};

/// How a rule was found, for the people who will trust it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// `base` (a published motif), `audit` (missed by the engine), `mined`
    /// (missed in generated systems, `rgc mine`) or `user`.
    pub source: String,
    /// The enumeration that produced it, e.g. `rods n=6, min degree 2, Maxwell`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enumeration: Option<String>,
    /// The engine rule set it was audited against.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub audited_against: Option<String>,
    /// The command that wrote it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub command: Option<String>,
    /// The rgc version that wrote it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    /// How often a mined rule occurred, per density (`rgc mine`); absent
    /// elsewhere, so older rule files read and write unchanged.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frequency: Vec<Frequency>,
}

/// How often a mined pattern occurred at one density.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Frequency {
    pub density: f64,
    /// Distinct minimal sets with the pattern.
    pub occurrences: u64,
    /// Systems holding at least one, of `of_systems` mined.
    pub systems: u64,
    pub of_systems: u64,
}

/// The exact-rank verdict stored with a rule.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RuleVerdict {
    pub class: String,
    pub dof: usize,
    /// Seed of the exact realizations.
    pub seed: u64,
    pub components: Vec<crate::rigidity::ComponentReport>,
}

/// A motif rule: a typed pattern proven rigid on every realization component.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rule {
    pub id: String,
    pub pattern: Pattern,
    /// Canonical form of the pattern: equal for isomorphic patterns.
    pub canonical: String,
    pub verdict: RuleVerdict,
    pub provenance: Provenance,
}

/// A rule file: a list of rules.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RuleFile {
    /// Always [`RULE_FORMAT`].
    pub format: String,
    pub rules: Vec<Rule>,
}

pub const RULE_FORMAT: &str = "rgc-rules/1";

/// Largest rule file read (a hostile file fails before it is parsed).
pub const MAX_RULE_FILE_BYTES: u64 = 64 << 20;

/// Seed of the exact verdicts of rules written by rgc.
pub const RULE_SEED: u64 = 20_261_122;

impl Rule {
    /// A rule for `pattern`, verified now: fails unless rigid on every component.
    pub fn new(id: String, pattern: Pattern, provenance: Provenance) -> Result<Self> {
        let verdict = verify(&pattern, &id)?;
        Ok(Rule {
            id,
            canonical: canonical_form(&pattern),
            pattern,
            verdict,
            provenance,
        })
    }
}

/// The canonical form of a pattern as a string (kinds, then sorted contacts).
pub fn canonical_form(p: &Pattern) -> String {
    let c = crate::enumerate::canonical_pattern(p);
    let kinds: String = c
        .kinds
        .iter()
        .map(|k| match k {
            NodeKind::Rod => 'r',
            NodeKind::Planar => 'p',
            NodeKind::Spatial => 's',
        })
        .collect();
    let mut contacts: Vec<String> = c
        .contacts
        .iter()
        .map(|x| format!("{}.{}-{}.{}", x.nodes[0], x.rods[0], x.nodes[1], x.rods[1]))
        .collect();
    contacts.sort();
    format!("{kinds}:{}", contacts.join(","))
}

/// The exact verdict of a rule's pattern; an error unless rigid everywhere.
fn verify(pattern: &Pattern, id: &str) -> Result<RuleVerdict> {
    let v = crate::rigidity::check_exact(pattern, RULE_SEED)
        .map_err(|e| Error::Parameter(format!("rule {id}: {}", detail(&e))))?;
    if v.rigid != Some(true) {
        return Err(Error::Parameter(format!(
            "rule {id} is not rigid on every realization component (exact rank: {}, {} DOF): \
             loading it would create false rigidity",
            v.class,
            v.dof.map_or("?".into(), |d| d.to_string())
        )));
    }
    Ok(RuleVerdict {
        class: v.class,
        dof: 0,
        seed: RULE_SEED,
        components: v.components,
    })
}

/// Rules loaded from files, and what loading left out as loaded already.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadedRules {
    /// Each distinct rule once, in the order of the files and of each file.
    pub rules: Vec<Rule>,
    /// What was left out, in the order met: the caller says so (the CLI
    /// prints one warning line each).
    pub dropped: Vec<Dropped>,
}

/// What [`load`] left out because it had it already.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dropped {
    /// A file given again, itself or inside a directory given: read once.
    File { path: PathBuf, first: PathBuf },
    /// A rule whose pattern an earlier rule has (the same canonical form
    /// under another id).
    Rule {
        id: String,
        file: PathBuf,
        kept: String,
        kept_file: PathBuf,
    },
}

impl std::fmt::Display for Dropped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Dropped::File { path, first } if path.as_os_str() == first.as_os_str() => write!(
                f,
                "rule file {} is given twice: its rules are loaded once",
                path.display()
            ),
            Dropped::File { path, first } => write!(
                f,
                "rule file {} is {} given again: its rules are loaded once",
                path.display(),
                first.display()
            ),
            Dropped::Rule {
                id,
                file,
                kept,
                kept_file,
            } => write!(
                f,
                "rule {id} ({}) has the pattern of rule {kept} ({}): dropped",
                file.display(),
                kept_file.display()
            ),
        }
    }
}

/// Reads rule files (a file, or every `*.json` in a directory, in name
/// order), checking each rule: well formed, canonical form matching its
/// pattern, unique id, and rigid by exact rank. The rules are checked in
/// parallel (exact rank is almost all the time, and rules are independent);
/// the error returned is the one a check in file order meets first.
///
/// A rule set loaded twice, or a rule repeated, is dropped, not refused,
/// and returned in [`LoadedRules::dropped`]: sets from different sources
/// overlap by nature (the committed `base.json` holds three patterns under
/// two variant ids each, and the mined rule `mined-11` is base
/// `3D2A-2-11`), and a repeated pattern matches exactly where its first
/// copy does, so it adds nothing the engine can compress, only the cost of
/// matching it again. A file is the same file by its canonical path; a rule
/// the same rule by its canonical form. Two rules with one id are refused:
/// ids name rules in reports.
pub fn load(paths: &[PathBuf]) -> Result<LoadedRules> {
    let mut loaded = LoadedRules::default();
    let mut files: Vec<(PathBuf, PathBuf)> = Vec::new();
    for file in rule_file_paths(paths)? {
        let real = std::fs::canonicalize(&file).unwrap_or_else(|_| file.clone());
        match files.iter().find(|(_, r)| *r == real) {
            Some((first, _)) => loaded.dropped.push(Dropped::File {
                path: file,
                first: first.clone(),
            }),
            None => files.push((file, real)),
        }
    }
    // Read in order up to the first file that cannot be read: its error
    // comes after those of the rules read before it.
    let mut read: Vec<(&Path, Vec<Rule>)> = Vec::new();
    let mut unread = None;
    for (file, _) in &files {
        match read_rule_file(file) {
            Ok(rules) => read.push((file, rules)),
            Err(e) => {
                unread = Some(e);
                break;
            }
        }
    }
    let all: Vec<(&Path, &Rule)> = read
        .iter()
        .flat_map(|(file, rules)| rules.iter().map(move |r| (*file, r)))
        .collect();
    let checked: Vec<Result<()>> = all.par_iter().map(|&(f, r)| check_rule(f, r)).collect();
    let mut ids = std::collections::HashMap::new();
    let mut patterns = std::collections::HashMap::new();
    for ((file, rule), check) in all.into_iter().zip(checked) {
        if let Some(prev) = ids.insert(rule.id.as_str(), file) {
            return Err(Error::Parameter(format!(
                "rule file {}: duplicate rule id {:?} (also in {})",
                file.display(),
                rule.id,
                prev.display()
            )));
        }
        check?;
        match patterns.get(rule.canonical.as_str()) {
            Some(&(kept, kept_file)) => loaded.dropped.push(Dropped::Rule {
                id: rule.id.clone(),
                file: file.to_path_buf(),
                kept: String::from(kept),
                kept_file: Path::to_path_buf(kept_file),
            }),
            None => {
                patterns.insert(rule.canonical.as_str(), (rule.id.as_str(), file));
                loaded.rules.push(rule.clone());
            }
        }
    }
    match unread {
        Some(e) => Err(e),
        None => Ok(loaded),
    }
}

/// [`load`]'s rules alone, for callers that report nothing of what it
/// dropped (the dropped repeats add nothing the engine can compress).
pub fn load_rules(paths: &[PathBuf]) -> Result<Vec<Rule>> {
    Ok(load(paths)?.rules)
}

/// The files `paths` name: each file, and every `*.json` in each directory
/// in name order.
fn rule_file_paths(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            let mut inside: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| Error::io(path, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "json"))
                .collect();
            inside.sort();
            files.extend(inside);
        } else {
            files.push(path.clone());
        }
    }
    Ok(files)
}

/// The rules of one file, parsed, not yet checked.
fn read_rule_file(file: &Path) -> Result<Vec<Rule>> {
    let bad = |m: String| Error::Parameter(format!("rule file {}: {m}", file.display()));
    let size = std::fs::metadata(file)
        .map_err(|e| Error::io(file, e))?
        .len();
    if size > MAX_RULE_FILE_BYTES {
        return Err(bad(format!(
            "{size} bytes is larger than the {MAX_RULE_FILE_BYTES} a rule file may have"
        )));
    }
    let text = std::fs::read_to_string(file).map_err(|e| Error::io(file, e))?;
    let parsed: RuleFile = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    if parsed.format != RULE_FORMAT {
        return Err(bad(format!(
            "format {:?} is not {RULE_FORMAT:?}",
            parsed.format
        )));
    }
    Ok(parsed.rules)
}

/// Checks one rule of `file`: a valid pattern, its canonical form the one
/// stored, and rigid by exact rank.
fn check_rule(file: &Path, rule: &Rule) -> Result<()> {
    let bad = |m: String| Error::Parameter(format!("rule file {}: {m}", file.display()));
    rule.pattern
        .validate()
        .map_err(|e| bad(format!("rule {}: {}", rule.id, detail(&e))))?;
    let canonical = canonical_form(&rule.pattern);
    if canonical != rule.canonical {
        return Err(bad(format!(
            "rule {}: canonical form {:?} does not match its pattern ({canonical:?})",
            rule.id, rule.canonical
        )));
    }
    verify(&rule.pattern, &rule.id).map_err(|e| bad(detail(&e)))?;
    Ok(())
}

/// An error's message without the "invalid parameter" prefix, for nesting.
fn detail(e: &Error) -> String {
    match e {
        Error::Parameter(m) => m.clone(),
        other => other.to_string(),
    }
}

/// Writes rules as one rule file.
pub fn write_rules(path: &Path, rules: &[Rule]) -> Result<()> {
    let file = RuleFile {
        format: RULE_FORMAT.into(),
        rules: rules.to_vec(),
    };
    let text = serde_json::to_string_pretty(&file).expect("rules serialize");
    crate::output::write_atomic(path, text + "\n")
}
