//! `rgc compress`: the engine on a contact graph given as graph6 or an edge list.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use rgc::body::{Body, BodyClass};
use rgc::engine::{self, Compression, Engine, RuleSet};
use rgc::graph::ContactGraph;
use rgc::graph::io as graphio;
use rgc::{Result, output};

use crate::args::{EngineArgs, MemoryArgs};

#[derive(Args)]
#[group(id = "input", required = true, multiple = false)]
struct GraphInput {
    /// The contact graph as a graph6 string.
    #[arg(long, group = "input")]
    graph6: Option<String>,
    /// The contact graph as an edge list file (`u v` per line, `#` comments).
    #[arg(long, group = "input")]
    edges: Option<PathBuf>,
}

#[derive(Args)]
pub struct CompressArgs {
    #[command(flatten)]
    input: GraphInput,
    #[command(flatten)]
    engine: EngineArgs,
    #[command(flatten)]
    memory: MemoryArgs,
    /// Print one JSON object (the summary and every body's rods) instead of a summary.
    #[arg(long)]
    json: bool,
    /// Write the bodies of the reported run (rods, class) as JSON to this file.
    #[arg(long)]
    save_bodies: Option<PathBuf>,
}

/// The JSON printed by `rgc compress`.
#[derive(Serialize)]
struct CompressReport<'a> {
    nodes: usize,
    contacts: usize,
    rules: RuleSet,
    seed: u64,
    runs: u64,
    /// Nodes left in the reported run (the one with fewest).
    components: usize,
    /// Index of the reported run.
    reported_run: usize,
    /// Bodies in the reported run, and rods in its largest.
    n_bodies: usize,
    largest_body_rods: usize,
    bodies: &'a [Body],
    /// Nodes left in each run.
    components_per_run: Vec<usize>,
    motifs: engine::MotifCounts,
}

/// The file `--save-bodies` writes.
#[derive(Serialize)]
struct SavedBodies<'a> {
    run: usize,
    bodies: &'a [Body],
}

pub fn run(a: CompressArgs, out: &mut String) -> Result<()> {
    if let Some(path) = &a.save_bodies {
        output::check_file(path)?;
    }
    let e = &a.engine;
    let (runs, limit) = (e.runs as usize, a.memory.memory_limit);
    let graph: ContactGraph = match (&a.input.graph6, &a.input.edges) {
        (Some(s), _) => graphio::parse_graph6(s)?,
        (None, Some(path)) => graphio::read_edge_list_within(path, |n, m| {
            engine::check_runs_memory(n, m, runs, graphio::graph_bytes(n, m), limit)
        })?,
        (None, None) => unreachable!("clap requires one input"),
    };
    engine::check_runs_memory(graph.n_nodes(), graph.n_edges(), runs, 0, limit)?;
    let rules = super::load(&e.rules.rule_files)?;
    let runs = Engine::with_rules(e.rules.rules, &rules).runs(&graph, e.seed, e.runs as usize);
    let best = (0..runs.len())
        .min_by_key(|&k| runs[k].components)
        .expect("at least one run");
    let c: &Compression = &runs[best];
    let report = CompressReport {
        nodes: graph.n_nodes(),
        contacts: graph.n_edges(),
        rules: e.rules.rules,
        seed: e.seed,
        runs: e.runs,
        components: c.components,
        reported_run: best,
        n_bodies: c.bodies.len(),
        largest_body_rods: c.largest_rods(),
        bodies: &c.bodies,
        components_per_run: runs.iter().map(|r| r.components).collect(),
        motifs: c.motifs,
    };
    if let Some(path) = &a.save_bodies {
        let saved = SavedBodies {
            run: best,
            bodies: &c.bodies,
        };
        let text = serde_json::to_string_pretty(&saved).expect("bodies serialize");
        output::write_atomic(path, text + "\n")?;
    }
    if a.json {
        return super::print_json(&report, out);
    }
    // A summary only: the bodies of a large graph run to megabytes.
    let planar = c
        .bodies
        .iter()
        .filter(|b| b.class == BodyClass::Planar)
        .count();
    say!(
        out,
        "{} rods, {} contacts -> {} nodes (run {best} of {}, rules {})",
        report.nodes,
        report.contacts,
        report.components,
        report.runs,
        report.rules
    );
    say!(
        out,
        "{} bodies ({planar} planar, {} spatial); largest body {} rods",
        report.n_bodies,
        report.n_bodies - planar,
        report.largest_body_rods
    );
    Ok(())
}
