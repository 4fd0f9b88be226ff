//! The audit's funnel (MODEL §7): every connected pattern of a size,
//! filtered to the 2-core and Maxwell's count, classified by exact rank and
//! put to the engine; the rigid ones it misses, reduced to those still
//! missed with the smaller ones added as rules, and the ones it compresses
//! although they are not rigid.

use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;

use crate::body::Body;
use crate::engine::{CompiledRule, Compression, Engine, Motif, RuleSet};
use crate::enumerate::{
    GraphFilter, SmallGraph, TypedFilter, count_connected, par_fold_connected, typed_patterns,
};
use crate::graph::ContactGraph;
use crate::graph::io::to_graph6;
use crate::pattern::Pattern;
use crate::progress::Progress;
use crate::rigidity::exact_class;
use crate::rule_file::{Provenance, Rule};
use crate::{Error, Result};

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
    /// Write rule files only for the sizes above the default audit's (rods
    /// beyond 8, components beyond 4): the extended audit adds `rods-9.json`,
    /// `rods-10.json` and `mixed-5.json` and leaves the default audit's rule
    /// files as they are (their provenance names the default command).
    pub extended: bool,
}

impl AuditOptions {
    /// The command these options stand for, as the rule files' provenance
    /// records it: the options that change what the audit finds, with runs
    /// and rod sharing only when they differ from the defaults.
    pub fn command(&self) -> String {
        let mut command = format!(
            "rgc audit --max-rods {} --max-components {} --rules {:?}",
            self.max_rods, self.max_components, self.rules
        );
        if self.runs != AuditOptions::default().runs {
            command += &format!(" --runs {}", self.runs);
        }
        if self.rod_sharing {
            command += " --rod-sharing";
        }
        if self.extended {
            command += " --extended";
        }
        command.to_lowercase()
    }

    /// The extended audit (`rgc audit --extended`): rods-only motifs up to
    /// 10 rods and mixed motifs up to 5 components, writing the rule files
    /// of the sizes above the defaults only.
    pub fn extended() -> Self {
        AuditOptions {
            max_rods: 10,
            max_components: 5,
            extended: true,
            ..AuditOptions::default()
        }
    }
}

impl Default for AuditOptions {
    fn default() -> Self {
        AuditOptions {
            max_rods: 8,
            max_components: 4,
            rules: RuleSet::Sound,
            runs: 8,
            rod_sharing: false,
            extended: false,
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
    /// Wall time of this size (in the JSON, not the tables).
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
    /// Falsely compressed patterns (compressed, not rigid on every component).
    pub false_rigidity: Vec<FalseRigidity>,
}

/// A pattern the engine compressed to one node although exact rank finds
/// it not rigid on every realization component, and how it compressed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FalseRigidity {
    /// `rods` or `mixed`.
    pub kind: String,
    /// Rods, or components.
    pub size: usize,
    pub pattern: Pattern,
    /// The exact verdict's class (`component-dependent`, `flexible` ...).
    pub class: String,
    /// The motif order (seed) of the first run that compressed it.
    pub run: u64,
    /// The motifs that run applied, in order.
    pub sequence: Vec<Motif>,
}

impl FalseRigidity {
    /// The pattern as graph6, for a rods-only pattern.
    pub fn graph6(&self) -> Option<String> {
        let (graph, bodies, _) = self.pattern.to_host().ok()?;
        bodies.is_empty().then(|| to_graph6(&graph))
    }
}

/// The counts of one table row and what its candidates found, over
/// consecutive candidates in enumeration order: tallies of consecutive
/// stretches add up ([`Tally::append`]) to that of the whole size.
#[derive(Default)]
struct Tally {
    connected: u64,
    two_core: u64,
    maxwell: u64,
    rigid: u64,
    component_dependent: u64,
    flexible: u64,
    undecided: u64,
    compressed: u64,
    falsely_compressed: u64,
    /// Rigid and not compressed, in order.
    missed: Vec<Pattern>,
    /// Compressed and not rigid: the pattern, its class, the run and its motifs.
    false_rigidity: Vec<(Pattern, String, u64, Vec<Motif>)>,
    /// The first error, which stops the audit.
    error: Option<Error>,
    /// Candidates checked and not yet reported to the progress.
    unreported: u64,
}

/// Candidates a tally checks between two progress reports: a report takes
/// a lock, and there are millions of candidates.
const REPORT_EVERY: u64 = 1 << 10;

impl Tally {
    /// Classifies a candidate exactly, runs the engine on its host (the
    /// pattern's rods and declared bodies) and counts both.
    fn check(
        &mut self,
        p: &Pattern,
        host: &(ContactGraph, Vec<Body>),
        engine: &Engine,
        runs: u64,
        progress: &dyn Progress,
    ) {
        if self.error.is_some() {
            return;
        }
        let outcome = exact_class(p, crate::rule_file::RULE_SEED).and_then(|class| {
            let run = engine.compressing_run_from(&host.0, &host.1, runs)?;
            Ok((class, run))
        });
        let (class, run) = match outcome {
            Ok(found) => found,
            Err(e) => {
                self.error = Some(e);
                return;
            }
        };
        match class.as_str() {
            "rigid" => self.rigid += 1,
            "component-dependent" => self.component_dependent += 1,
            "flexible" => self.flexible += 1,
            _ => self.undecided += 1,
        }
        match run {
            None if class == "rigid" => self.missed.push(p.clone()),
            None => {}
            Some((seed, c)) => {
                self.compressed += 1;
                if class != "rigid" {
                    self.falsely_compressed += 1;
                    self.false_rigidity
                        .push((p.clone(), class, seed, c.sequence));
                }
            }
        }
        self.unreported += 1;
        if self.unreported == REPORT_EVERY {
            progress.advance(self.unreported);
            self.unreported = 0;
        }
    }

    /// Adds the tally of the candidates that come next.
    fn append(&mut self, mut next: Tally) {
        self.connected += next.connected;
        self.two_core += next.two_core;
        self.maxwell += next.maxwell;
        self.rigid += next.rigid;
        self.component_dependent += next.component_dependent;
        self.flexible += next.flexible;
        self.undecided += next.undecided;
        self.compressed += next.compressed;
        self.falsely_compressed += next.falsely_compressed;
        self.missed.append(&mut next.missed);
        self.false_rigidity.append(&mut next.false_rigidity);
        if self.error.is_none() {
            self.error = next.error;
        }
        self.unreported += next.unreported;
    }

    /// Fills `row` and `false_rigidity`; returns the missed patterns.
    fn finish(
        self,
        row: &mut AuditRow,
        false_rigidity: &mut Vec<FalseRigidity>,
    ) -> Result<Vec<Pattern>> {
        if let Some(e) = self.error {
            return Err(e);
        }
        row.connected = self.connected;
        row.two_core = self.two_core;
        row.maxwell = self.maxwell;
        row.rigid = self.rigid;
        row.component_dependent = self.component_dependent;
        row.flexible = self.flexible;
        row.undecided = self.undecided;
        row.compressed = self.compressed;
        row.missed = self.missed.len() as u64;
        row.falsely_compressed = self.falsely_compressed;
        false_rigidity.extend(self.false_rigidity.into_iter().map(
            |(pattern, class, run, sequence)| FalseRigidity {
                kind: row.kind.clone(),
                size: row.size,
                pattern,
                class,
                run,
                sequence,
            },
        ));
        Ok(self.missed)
    }
}

/// The rods-only candidate of a graph and its host (the graph itself, with
/// the contacts in the same order, as [`Pattern::to_host`] would build it).
fn rods_candidate(g: &SmallGraph) -> Result<(Pattern, (ContactGraph, Vec<Body>))> {
    let graph = ContactGraph::new(g.order(), g.edges())?;
    let pattern = Pattern::from_graph(&graph)?;
    Ok((pattern, (graph, Vec::new())))
}

/// Tallies the rods-only patterns on `n` rods: every connected graph is
/// counted, those of the 2-core, and the candidates (2-core and Maxwell's
/// count) are checked as they are generated. Candidates come in the order of
/// their own enumeration: the filters only prune the generation tree, which
/// is otherwise the same.
fn tally_rods(n: usize, engine: &Engine, runs: u64, progress: &dyn Progress) -> Result<Tally> {
    let candidates = GraphFilter::maxwell_rods(n).with_min_degree(2);
    let mut total = Tally::default();
    par_fold_connected(
        n,
        &GraphFilter::all(),
        Tally::default,
        |t, g| {
            t.connected += 1;
            if (0..n).any(|v| g.degree(v) < 2) {
                return;
            }
            t.two_core += 1;
            if !candidates.accepts(g) {
                return;
            }
            t.maxwell += 1;
            match rods_candidate(g) {
                Ok((p, host)) => t.check(&p, &host, engine, runs, progress),
                Err(e) => t.error = t.error.take().or(Some(e)),
            }
        },
        |t| total.append(t),
    )?;
    progress.advance(std::mem::take(&mut total.unreported));
    Ok(total)
}

/// Mixed candidates checked per task: enough to amortize a task, few enough
/// to balance the slow ones.
const MIXED_TASK: usize = 64;

/// Tallies the mixed patterns with `k` components: all connected ones are
/// enumerated once, and the 2-core and Maxwell's count filter that list
/// (the enumeration applies the same tests to the same canonical patterns,
/// in the same sorted order).
fn tally_mixed(
    opts: &AuditOptions,
    k: usize,
    engine: &Engine,
    progress: &dyn Progress,
) -> Result<Tally> {
    let all = typed_patterns(&TypedFilter {
        min_contacts_per_node: 0,
        maxwell: false,
        rod_sharing: opts.rod_sharing,
        ..TypedFilter::new(k)
    })?;
    let two_core: Vec<&Pattern> = all.iter().filter(|p| min_contacts(p) >= 2).collect();
    let candidates: Vec<&Pattern> = two_core.iter().copied().filter(|p| p.maxwell()).collect();
    progress.start(&format!("mixed k={k}"), candidates.len() as u64);
    let parts: Vec<Tally> = candidates
        .par_chunks(MIXED_TASK)
        .map(|chunk| {
            let mut t = Tally::default();
            for &p in chunk {
                match p.to_host() {
                    Ok((graph, bodies, _)) => {
                        t.check(p, &(graph, bodies), engine, opts.runs, progress)
                    }
                    Err(e) => t.error = t.error.take().or(Some(e)),
                }
            }
            t
        })
        .collect();
    let mut total = Tally {
        connected: all.len() as u64,
        two_core: two_core.len() as u64,
        maxwell: candidates.len() as u64,
        ..Tally::default()
    };
    for t in parts {
        total.append(t);
    }
    progress.advance(std::mem::take(&mut total.unreported));
    progress.finish();
    Ok(total)
}

/// The fewest contacts at a node of `p`, counted with multiplicity.
fn min_contacts(p: &Pattern) -> usize {
    let mut at = vec![0usize; p.n_nodes()];
    for c in &p.contacts {
        at[c.nodes[0] as usize] += 1;
        at[c.nodes[1] as usize] += 1;
    }
    at.into_iter().min().unwrap_or(0)
}

/// Whether the engine (`rules` with `known` added) compresses each pattern
/// to one node, and how: the first of `runs` motif orders that does, with
/// its compression, or `None` when it is still missed. This is what makes a
/// missed motif reducible, in the audit and in [`super::redundant`].
pub(super) fn reduced_by(
    patterns: &[&Pattern],
    rules: RuleSet,
    known: &[CompiledRule],
    runs: u64,
) -> Result<Vec<Option<(u64, Compression)>>> {
    let engine = Engine::with_rules(rules, known);
    patterns
        .par_iter()
        .map(|p| engine.compressing_run(p, runs))
        .collect()
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
    let all: Vec<&Pattern> = missed.iter().collect();
    let reduced = reduced_by(&all, opts.rules, known, opts.runs)?;
    let kept: Vec<&Pattern> = all
        .into_iter()
        .zip(reduced)
        .filter_map(|(p, r)| r.is_none().then_some(p))
        .collect();
    kept.par_iter()
        .enumerate()
        .map(|(k, p)| {
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
                command: Some(opts.command()),
                version: Some(env!("CARGO_PKG_VERSION").into()),
                frequency: Vec::new(),
            };
            Rule::new(format!("{id}-{k}"), (*p).clone(), provenance)
        })
        .collect()
}

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
            ..AuditRow::default()
        };
        // The stage's total first: a count of the candidates alone prunes
        // most of the tree and takes seconds at n = 10.
        let candidates = count_connected(n, &GraphFilter::maxwell_rods(n).with_min_degree(2))?;
        progress.start(&format!("rods n={n}"), candidates);
        let missed = tally_rods(n, &base, opts.runs, progress)?
            .finish(&mut row, &mut audit.false_rigidity)?;
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
        let mut row = AuditRow {
            kind: "mixed".into(),
            size: k,
            ..AuditRow::default()
        };
        let missed =
            tally_mixed(opts, k, &base, progress)?.finish(&mut row, &mut audit.false_rigidity)?;
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
    /// Column names, as in the CSV header: the counts only, so that a rerun
    /// rewrites the committed tables byte for byte (the time each size took
    /// is in `seconds`, which the CLI prints on stderr).
    pub const COLUMNS: [&'static str; 12] = [
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
    ];

    /// The row's values in [`AuditRow::COLUMNS`] order.
    pub fn cells(&self) -> [String; 12] {
        [
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
        ]
        .map(|n| n.to_string())
    }
}
