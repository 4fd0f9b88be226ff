//! Which rigid motifs the engine misses (MODEL §7), and the rule files that
//! carry motifs to the engine: the base motifs written as rules, and the
//! missed motifs the audit finds.

use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;

use crate::engine::{CompiledRule, Engine, RuleSet};
use crate::enumerate::{
    GraphFilter, TypedFilter, connected_small_graphs, count_connected, typed_patterns,
};
use crate::output;
use crate::pattern::Pattern;
use crate::progress::Progress;
use crate::rigidity::check_exact;
use crate::rule_file::{Provenance, Rule};
use crate::{Error, Result};

/// Whether the engine compresses `pattern` to one node in any of `runs` orders.
pub fn compresses(engine: &Engine, pattern: &Pattern, runs: u64) -> Result<bool> {
    let (graph, bodies, _) = pattern.to_host()?;
    for seed in 0..runs {
        if engine.compress(&graph, &bodies, seed)?.components == 1 {
            return Ok(true);
        }
    }
    Ok(false)
}

/// Checks, before an audit relies on the engine, that it compresses the base
/// motifs' own examples as expected under both rule sets; returns how many
/// examples there are, or an error naming the first that failed.
pub fn self_check() -> Result<usize> {
    let examples = crate::engine::examples::check_all(16);
    match examples.iter().find(|r| !r.pass) {
        Some(bad) => Err(Error::Parameter(format!(
            "base motif example {:?} did not compress as expected",
            bad.name
        ))),
        None => Ok(examples.len()),
    }
}

/// The rows as a text table: a header of [`AuditRow::COLUMNS`] and one line
/// per row, each column right-aligned to its name (at least 7 wide).
pub fn table(rows: &[AuditRow]) -> String {
    let width = |k: usize| AuditRow::COLUMNS[k].len().max(7);
    let line = |cells: &[String]| -> String {
        let mut text = cells
            .iter()
            .enumerate()
            .map(|(k, c)| format!("{c:>w$}", w = width(k)))
            .collect::<Vec<_>>()
            .join(" ");
        text.push('\n');
        text
    };
    let mut text = line(&AuditRow::COLUMNS.map(String::from));
    for r in rows {
        text += &line(&r.cells());
    }
    text
}

/// What to audit.
#[derive(Clone, Debug)]
pub struct AuditOptions {
    /// Rods-only motifs with 2 to this many rods.
    pub max_rods: usize,
    /// Mixed motifs (rods, planar and spatial bodies) with 2 to this many components.
    pub max_components: usize,
    /// The engine's rule set.
    pub rules: RuleSet,
    /// Motif orders tried per pattern (compressed if any of them compresses it).
    pub runs: u64,
    /// Also audit every way a body's contacts can share its rods (mixed only).
    pub rod_sharing: bool,
}

impl Default for AuditOptions {
    fn default() -> Self {
        AuditOptions {
            max_rods: 8,
            max_components: 4,
            rules: RuleSet::Sound,
            runs: 8,
            rod_sharing: false,
        }
    }
}

/// One row of the audit table: the funnel from all patterns of a size to
/// the irreducible missed motifs.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AuditRow {
    /// `rods` or `mixed`.
    pub kind: String,
    /// Rods, or components.
    pub size: usize,
    /// Connected patterns.
    pub connected: u64,
    /// Of those, every node with two or more contacts (the 2-core is everything).
    pub two_core: u64,
    /// Of those, passing Maxwell's count.
    pub maxwell: u64,
    /// Rigid on every realization component (exact rank).
    pub rigid: u64,
    /// Rigid on some components only.
    pub component_dependent: u64,
    /// Flexible on every component.
    pub flexible: u64,
    /// No exact verdict (a realization family could not be built).
    pub undecided: u64,
    /// Compressed to one node by the engine in some motif order.
    pub compressed: u64,
    /// Rigid but not compressed.
    pub missed: u64,
    /// Missed, and still missed with the smaller missed motifs added as rules.
    pub irreducible: u64,
    /// Compressed but not rigid on every component: false rigidity.
    pub falsely_compressed: u64,
    pub seconds: f64,
}

/// The audit's tables and the rules it found.
#[derive(Clone, Debug, Default)]
pub struct Audit {
    pub rods: Vec<AuditRow>,
    pub mixed: Vec<AuditRow>,
    /// Irreducible missed rods-only motifs, as verified rules, by size.
    pub rod_rules: Vec<(usize, Vec<Rule>)>,
    /// Irreducible missed mixed motifs, as verified rules, by size.
    pub mixed_rules: Vec<(usize, Vec<Rule>)>,
    /// Falsely compressed patterns (compressed, not rigid), with their verdict class.
    pub false_rigidity: Vec<(Pattern, String)>,
}

/// The verdict and the engine's outcome for one candidate.
struct Outcome {
    class: String,
    compressed: bool,
}

/// Checks candidates in parallel: exact verdict and whether the engine compresses each.
fn outcomes(
    candidates: &[Pattern],
    engine: &Engine,
    runs: u64,
    progress: &dyn Progress,
) -> Result<Vec<Outcome>> {
    candidates
        .par_iter()
        .map(|p| {
            let v = check_exact(p, crate::rule_file::RULE_SEED)?;
            let compressed = compresses(engine, p, runs)?;
            progress.advance(1);
            Ok(Outcome {
                class: v.class,
                compressed,
            })
        })
        .collect()
}

/// Fills a row from the outcomes and returns the missed rigid patterns.
fn tally(
    row: &mut AuditRow,
    candidates: &[Pattern],
    out: &[Outcome],
    false_rigidity: &mut Vec<(Pattern, String)>,
) -> Vec<Pattern> {
    let mut missed = Vec::new();
    for (p, o) in candidates.iter().zip(out) {
        match o.class.as_str() {
            "rigid" => row.rigid += 1,
            "component-dependent" => row.component_dependent += 1,
            "flexible" => row.flexible += 1,
            _ => row.undecided += 1,
        }
        if o.compressed {
            row.compressed += 1;
        }
        if o.class == "rigid" && !o.compressed {
            missed.push(p.clone());
        }
        if o.compressed && o.class != "rigid" {
            row.falsely_compressed += 1;
            false_rigidity.push((p.clone(), o.class.clone()));
        }
    }
    missed
}

/// Of the missed patterns, those the engine still misses with `known` rules
/// added; returned as verified rules.
fn irreducible(
    missed: &[Pattern],
    opts: &AuditOptions,
    known: &[CompiledRule],
    id: &str,
    enumeration: &str,
) -> Result<Vec<Rule>> {
    let engine = Engine::with_rules(opts.rules, known);
    let still: Vec<bool> = missed
        .par_iter()
        .map(|p| compresses(&engine, p, opts.runs).map(|c| !c))
        .collect::<Result<_>>()?;
    missed
        .iter()
        .zip(still)
        .filter(|(_, s)| *s)
        .enumerate()
        .map(|(k, (p, _))| {
            let provenance = Provenance {
                source: "audit".into(),
                enumeration: Some(enumeration.to_string()),
                audited_against: Some(
                    format!(
                        "{:?} base motifs and the smaller irreducible motifs",
                        opts.rules
                    )
                    .to_lowercase(),
                ),
                command: Some(
                    format!(
                        "rgc audit --max-rods {} --max-components {} --rules {:?}",
                        opts.max_rods, opts.max_components, opts.rules
                    )
                    .to_lowercase(),
                ),
                version: Some(env!("CARGO_PKG_VERSION").into()),
            };
            Rule::new(format!("{id}-{k}"), p.clone(), provenance)
        })
        .collect()
}

/// Candidates checked at a time.
const CHUNK: usize = 1 << 16;

/// Audits rods-only motifs of 2 to `max_rods` rods and mixed motifs of 2 to
/// `max_components` components against the engine, one progress stage per size.
pub fn run(opts: &AuditOptions, progress: &dyn Progress) -> Result<Audit> {
    let mut audit = Audit::default();
    let base = Engine::base(opts.rules);
    let mut known: Vec<CompiledRule> = Vec::new();
    for n in 2..=opts.max_rods {
        let t = Instant::now();
        let mut row = AuditRow {
            kind: "rods".into(),
            size: n,
            connected: count_connected(n, &GraphFilter::all())?,
            two_core: count_connected(n, &GraphFilter::all().with_min_degree(2))?,
            ..AuditRow::default()
        };
        // Candidates as 34-byte graphs, checked a chunk at a time: at n = 10
        // there are 9 million, too many to hold as patterns.
        let graphs = connected_small_graphs(n, &GraphFilter::maxwell_rods(n).with_min_degree(2))?;
        row.maxwell = graphs.len() as u64;
        progress.start(&format!("rods n={n}"), row.maxwell);
        let mut missed = Vec::new();
        for chunk in graphs.chunks(CHUNK) {
            let candidates: Vec<Pattern> = chunk
                .iter()
                .map(|g| Pattern::from_graph(&g.to_contact_graph()))
                .collect::<Result<_>>()?;
            let out = outcomes(&candidates, &base, opts.runs, progress)?;
            missed.extend(tally(
                &mut row,
                &candidates,
                &out,
                &mut audit.false_rigidity,
            ));
        }
        row.missed = missed.len() as u64;
        progress.finish();
        let enumeration = format!("connected rods-only graphs, n={n}, min degree 2, Maxwell");
        let rules = irreducible(&missed, opts, &known, &format!("rods-{n}"), &enumeration)?;
        row.irreducible = rules.len() as u64;
        known.extend(rules.iter().map(CompiledRule::new));
        audit.rod_rules.push((n, rules));
        row.seconds = t.elapsed().as_secs_f64();
        audit.rods.push(row);
    }
    let mut known_mixed: Vec<CompiledRule> = Vec::new();
    for k in 2..=opts.max_components {
        let t = Instant::now();
        let filter = |min_contacts: usize, maxwell: bool| TypedFilter {
            min_contacts_per_node: min_contacts,
            maxwell,
            rod_sharing: opts.rod_sharing,
            ..TypedFilter::new(k)
        };
        let mut row = AuditRow {
            kind: "mixed".into(),
            size: k,
            connected: typed_patterns(&filter(0, false))?.len() as u64,
            two_core: typed_patterns(&filter(2, false))?.len() as u64,
            ..AuditRow::default()
        };
        let candidates = typed_patterns(&filter(2, true))?;
        row.maxwell = candidates.len() as u64;
        progress.start(&format!("mixed k={k}"), candidates.len() as u64);
        let out = outcomes(&candidates, &base, opts.runs, progress)?;
        progress.finish();
        let missed = tally(&mut row, &candidates, &out, &mut audit.false_rigidity);
        row.missed = missed.len() as u64;
        let enumeration = format!(
            "connected typed patterns, {k} components, rod-body <= 2 and body-body <= 3 contacts, \
             >= 2 contacts per node, Maxwell{}",
            if opts.rod_sharing {
                ", every rod sharing"
            } else {
                ", contacts on distinct rods"
            }
        );
        let rules = irreducible(
            &missed,
            opts,
            &known_mixed,
            &format!("mixed-{k}"),
            &enumeration,
        )?;
        row.irreducible = rules.len() as u64;
        known_mixed.extend(rules.iter().map(CompiledRule::new));
        audit.mixed_rules.push((k, rules));
        row.seconds = t.elapsed().as_secs_f64();
        audit.mixed.push(row);
    }
    Ok(audit)
}

impl AuditRow {
    /// Column names, as in the CSV header.
    pub const COLUMNS: [&'static str; 13] = [
        "size",
        "connected",
        "two_core",
        "maxwell",
        "rigid",
        "component_dependent",
        "flexible",
        "undecided",
        "compressed",
        "missed",
        "irreducible",
        "falsely_compressed",
        "seconds",
    ];

    /// The row's values in [`AuditRow::COLUMNS`] order.
    pub fn cells(&self) -> [String; 13] {
        let counts = [
            self.size as u64,
            self.connected,
            self.two_core,
            self.maxwell,
            self.rigid,
            self.component_dependent,
            self.flexible,
            self.undecided,
            self.compressed,
            self.missed,
            self.irreducible,
            self.falsely_compressed,
        ];
        std::array::from_fn(|k| {
            counts
                .get(k)
                .map_or_else(|| format!("{:.3}", self.seconds), u64::to_string)
        })
    }
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

    /// The committed tables, read back into rows, are written byte for byte.
    #[test]
    fn committed_tables_are_written_unchanged() {
        for name in ["audit-rods.csv", "audit-mixed.csv", "audit-rods-10.csv"] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("results")
                .join(name);
            let text = std::fs::read_to_string(&path).unwrap();
            let rows: Vec<AuditRow> = text
                .lines()
                .skip(1)
                .map(|line| {
                    let cells: Vec<&str> = line.split(',').collect();
                    let n: Vec<u64> = cells[1..13].iter().map(|c| c.parse().unwrap()).collect();
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
                        seconds: cells[13].parse().unwrap(),
                    }
                })
                .collect();
            let out = std::env::temp_dir().join(format!("rgc-audit-{}-{name}", std::process::id()));
            write_csv(&out, &rows).unwrap();
            assert_eq!(std::fs::read_to_string(&out).unwrap(), text, "{name}");
            std::fs::remove_file(out).unwrap();
        }
    }
}
