//! The audit's files: per part (`rods`, `mixed`) its table, the JSON
//! beside it saying what made it, the falsely compressed rods-only patterns
//! as graph6, and the irreducible missed motifs as rule files; and the
//! check, before an audit runs, that it replaces only an equal audit's.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use super::funnel::{Audit, AuditOptions, AuditRow, FalseRigidity};
use crate::engine::{Motif, RuleSet};
use crate::output;
use crate::pattern::Pattern;
use crate::{Error, Result};

impl AuditOptions {
    /// The parameters that made one part's table (`rods` or `mixed`).
    fn part(&self, kind: &str) -> PartParameters {
        let mixed = kind == "mixed";
        PartParameters {
            max_size: if mixed {
                self.max_components
            } else {
                self.max_rods
            },
            rules: self.rules,
            runs: self.runs,
            rod_sharing: mixed.then_some(self.rod_sharing),
        }
    }

    /// The sizes one part audits (none for a part that does not run).
    fn sizes(&self, kind: &str) -> std::ops::RangeInclusive<usize> {
        2..=self.part(kind).max_size
    }

    /// The sizes whose rule files one part may write: every size it audits,
    /// or, for the extended audit, those above the default audit's.
    pub fn rule_sizes(&self, kind: &str) -> std::ops::RangeInclusive<usize> {
        let sizes = self.sizes(kind);
        if !self.extended {
            return sizes;
        }
        let default = AuditOptions::default().part(kind).max_size;
        (*sizes.start()).max(default + 1)..=*sizes.end()
    }
}

/// What made one part's table, written beside it (`audit-rods.json`) so
/// that a later run with other parameters does not silently replace it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct PartParameters {
    /// Rods (rods-only part) or components (mixed part).
    max_size: usize,
    rules: RuleSet,
    runs: u64,
    /// Mixed part only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    rod_sharing: Option<bool>,
}

impl std::fmt::Display for PartParameters {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "sizes up to {}, rules {}, {} motif orders",
            self.max_size,
            format!("{:?}", self.rules).to_lowercase(),
            self.runs
        )?;
        match self.rod_sharing {
            Some(true) => write!(f, ", rod sharing"),
            _ => Ok(()),
        }
    }
}

/// The JSON beside a part's table, as read back: only what made it counts.
#[derive(Deserialize)]
struct PartRead {
    parameters: PartParameters,
}

/// The JSON beside a part's table: what made it, and the part's falsely
/// compressed patterns with how each compressed.
#[derive(Serialize)]
struct PartWritten<'a> {
    made_by: String,
    parameters: PartParameters,
    falsely_compressed: Vec<FalseWritten<'a>>,
}

#[derive(Serialize)]
struct FalseWritten<'a> {
    size: usize,
    /// Rods-only patterns.
    #[serde(skip_serializing_if = "Option::is_none")]
    graph6: Option<String>,
    /// Mixed patterns (graph6 cannot hold their bodies).
    #[serde(skip_serializing_if = "Option::is_none")]
    pattern: Option<&'a Pattern>,
    class: &'a str,
    run: u64,
    sequence: &'a [Motif],
}

/// The files [`write_outputs`] wrote.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AuditFiles {
    /// `audit-rods.csv`, `audit-mixed.csv`.
    pub tables: Vec<PathBuf>,
    /// Beside each table: `audit-rods.json` (what made it, its falsely
    /// compressed patterns) and `falsely-compressed-rods.g6`.
    pub beside: Vec<PathBuf>,
    /// `rods-n.json`, `mixed-k.json`.
    pub rule_files: Vec<PathBuf>,
}

const PARTS: [&str; 2] = ["rods", "mixed"];

/// Checks, before an audit runs, that it would replace only files that an
/// audit with the same parameters made: each part's table (by the JSON
/// beside it, or, for tables older than that, by the sizes it lists) and
/// each rule file it may write (by its provenance). An exploratory run
/// (`--max-rods 6 --rules paper`) would otherwise cut the committed tables
/// and rewrite the rule files `compare` reads. The CLI's `--force` skips it.
pub fn check_outputs(opts: &AuditOptions, results: &Path, motifs: &Path) -> Result<()> {
    let mut conflicts = Vec::new();
    for kind in PARTS {
        let sizes: Vec<usize> = opts.sizes(kind).collect();
        if sizes.is_empty() {
            continue;
        }
        let table = results.join(format!("audit-{kind}.csv"));
        let beside = results.join(format!("audit-{kind}.json"));
        match std::fs::read_to_string(&beside) {
            Ok(text) => match serde_json::from_str::<PartRead>(&text) {
                Ok(made) if made.parameters == opts.part(kind) => {}
                Ok(made) => conflicts.push(format!(
                    "{} was made with {}",
                    table.display(),
                    made.parameters
                )),
                Err(_) => conflicts.push(format!("{} is not an audit's", beside.display())),
            },
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                if table.exists() {
                    let there = table_sizes(&table)?;
                    if there != sizes {
                        conflicts.push(format!("{} holds sizes {there:?}", table.display()));
                    }
                }
            }
            Err(e) => return Err(Error::io(&beside, e)),
        }
        for n in opts.rule_sizes(kind) {
            let path = motifs.join(format!("{kind}-{n}.json"));
            match rule_file_commands(&path)? {
                Some(commands) if commands.iter().all(|c| *c == opts.command()) => {}
                Some(commands) => conflicts.push(format!(
                    "{} was made by `{}`",
                    path.display(),
                    commands.join("`, `")
                )),
                None => {}
            }
        }
    }
    if conflicts.is_empty() {
        return Ok(());
    }
    Err(Error::Parameter(format!(
        "`{}` would replace files made with other parameters: {}; write elsewhere with --results and --rules-dir, or --force to replace them",
        opts.command(),
        conflicts.join("; ")
    )))
}

/// The sizes an audit table lists.
fn table_sizes(path: &Path) -> Result<Vec<usize>> {
    let bad = |m: String| Error::Parameter(format!("{}: {m}", path.display()));
    let mut reader = csv::Reader::from_path(path).map_err(|e| bad(e.to_string()))?;
    let column = reader
        .headers()
        .map_err(|e| bad(e.to_string()))?
        .iter()
        .position(|h| h == "size")
        .ok_or_else(|| bad("no size column: not an audit table".into()))?;
    reader
        .records()
        .map(|r| {
            let r = r.map_err(|e| bad(e.to_string()))?;
            r.get(column)
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| bad("a size is not a number".into()))
        })
        .collect()
}

/// The distinct commands a rule file's provenance names (`None` when there
/// is no such file; a file that is not a rule file names none).
fn rule_file_commands(path: &Path) -> Result<Option<Vec<String>>> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(Error::io(path, e)),
    };
    let Ok(file) = serde_json::from_str::<crate::rule_file::RuleFile>(&text) else {
        return Ok(Some(vec!["(not a rule file)".into()]));
    };
    let mut commands: Vec<String> = file
        .rules
        .iter()
        .map(|r| r.provenance.command.clone().unwrap_or_default())
        .collect();
    commands.sort();
    commands.dedup();
    Ok(Some(commands))
}

/// Writes what an audit found: per part that ran, its table, the JSON
/// beside it and (rods only) `falsely-compressed-rods.g6`, one graph6 line
/// per falsely compressed pattern, into `results`; the irreducible missed
/// motifs as rule files `rods-n.json` and `mixed-k.json` into `motifs`
/// (the extended audit: only those of [`AuditOptions::rule_sizes`]). A part
/// that did not run keeps its previous files.
pub fn write_outputs(
    audit: &Audit,
    opts: &AuditOptions,
    results: &Path,
    motifs: &Path,
) -> Result<AuditFiles> {
    let mut files = AuditFiles::default();
    for (kind, rows) in PARTS.into_iter().zip([&audit.rods, &audit.mixed]) {
        if rows.is_empty() {
            continue;
        }
        let table = results.join(format!("audit-{kind}.csv"));
        write_csv(&table, rows)?;
        files.tables.push(table);
        let false_rigidity: Vec<&FalseRigidity> = audit
            .false_rigidity
            .iter()
            .filter(|f| f.kind == kind)
            .collect();
        let part = PartWritten {
            made_by: opts.command(),
            parameters: opts.part(kind),
            falsely_compressed: false_rigidity
                .iter()
                .map(|f| {
                    let graph6 = f.graph6();
                    FalseWritten {
                        size: f.size,
                        pattern: graph6.is_none().then_some(&f.pattern),
                        graph6,
                        class: &f.class,
                        run: f.run,
                        sequence: &f.sequence,
                    }
                })
                .collect(),
        };
        let beside = results.join(format!("audit-{kind}.json"));
        output::write_atomic(
            &beside,
            serde_json::to_string_pretty(&part).expect("audit parts serialize") + "\n",
        )?;
        files.beside.push(beside);
        if kind == "rods" {
            let g6: String = part
                .falsely_compressed
                .iter()
                .filter_map(|f| f.graph6.as_deref())
                .map(|g| format!("{g}\n"))
                .collect();
            let path = results.join("falsely-compressed-rods.g6");
            output::write_atomic(&path, g6)?;
            files.beside.push(path);
        }
    }
    for (kind, sets) in [("rods", &audit.rod_rules), ("mixed", &audit.mixed_rules)] {
        let written = opts.rule_sizes(kind);
        for (size, rules) in sets
            .iter()
            .filter(|(size, r)| !r.is_empty() && written.contains(size))
        {
            let path = motifs.join(format!("{kind}-{size}.json"));
            crate::rule_file::write_rules(&path, rules)?;
            files.rule_files.push(path);
        }
    }
    Ok(files)
}

/// Writes a table as CSV: the kind, then the columns the terminal shows.
pub fn write_csv(path: &std::path::Path, rows: &[AuditRow]) -> Result<()> {
    let header = std::iter::once("kind").chain(AuditRow::COLUMNS);
    let text = output::csv_headed(header, rows.iter().map(|r| (&r.kind, r.cells())));
    output::write_atomic(path, text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The extended audit writes only the rule files above the default
    /// audit's sizes; any other audit, every size it audits.
    #[test]
    fn the_extended_audit_writes_only_the_larger_rule_files() {
        let sizes = |o: &AuditOptions, kind| o.rule_sizes(kind).collect::<Vec<usize>>();
        let extended = AuditOptions::extended();
        assert_eq!(sizes(&extended, "rods"), [9, 10]);
        assert_eq!(sizes(&extended, "mixed"), [5]);
        assert_eq!(
            extended.command(),
            "rgc audit --max-rods 10 --max-components 5 --rules sound --extended"
        );
        let small = AuditOptions {
            max_rods: 8,
            max_components: 0,
            ..AuditOptions::extended()
        };
        assert!(sizes(&small, "rods").is_empty() && sizes(&small, "mixed").is_empty());
        let default = AuditOptions::default();
        assert_eq!(sizes(&default, "rods"), (2..=8).collect::<Vec<_>>());
        assert_eq!(sizes(&default, "mixed"), [2, 3, 4]);
    }

    /// The committed tables, read back into rows, are written byte for byte.
    #[test]
    fn committed_tables_are_written_unchanged() {
        for name in [
            "audit-rods.csv",
            "audit-mixed.csv",
            "audit-extended/audit-rods.csv",
            "audit-extended/audit-mixed.csv",
        ] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("results")
                .join(name);
            let text = std::fs::read_to_string(&path).unwrap();
            let rows: Vec<AuditRow> = text
                .lines()
                .skip(1)
                .map(|line| {
                    let cells: Vec<&str> = line.split(',').collect();
                    assert_eq!(cells.len(), 13, "{name}: {line}");
                    let n: Vec<u64> = cells[1..].iter().map(|c| c.parse().unwrap()).collect();
                    AuditRow {
                        kind: cells[0].into(),
                        size: n[0] as usize,
                        connected: n[1],
                        two_core: n[2],
                        maxwell: n[3],
                        rigid: n[4],
                        component_dependent: n[5],
                        flexible: n[6],
                        undecided: n[7],
                        compressed: n[8],
                        missed: n[9],
                        irreducible: n[10],
                        falsely_compressed: n[11],
                        seconds: 0.0,
                    }
                })
                .collect();
            let out = std::env::temp_dir().join(format!(
                "rgc-audit-{}-{}",
                std::process::id(),
                name.replace('/', "-")
            ));
            write_csv(&out, &rows).unwrap();
            assert_eq!(std::fs::read_to_string(&out).unwrap(), text, "{name}");
            std::fs::remove_file(out).unwrap();
        }
    }
}
