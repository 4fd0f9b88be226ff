//! `rgc truth`: the exact rigidity of a whole contact graph or rod system.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use crate::args::{MemoryArgs, RodsArgs};

use rgc::graph::ContactGraph;
use rgc::graph::io as graphio;
use rgc::network::Network;
use rgc::sample::Rods;
use rgc::spanning::Criterion;
use rgc::truth::{self, Decision, Outcome, Strain, Strains, Topology, Truth, TruthOptions};
use rgc::{Error, Result, output};

#[derive(Args)]
pub struct TruthArgs {
    /// A rods-only contact graph as graph6 (a finite framework).
    #[arg(long, conflicts_with = "edges")]
    graph6: Option<String>,
    /// A contact graph as an edge list file (`u v` per line, `#` comments).
    #[arg(long)]
    edges: Option<PathBuf>,
    /// Or a rod system: read with --rods, or generated.
    #[command(flatten)]
    rods: RodsArgs,
    #[command(flatten)]
    memory: MemoryArgs,
    /// Seed of the generated rods (and of the realizations).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Spanning criterion for a generated system.
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    criterion: Criterion,
    /// Exact realizations ranked, each in a prime drawn at random below 2^24: 1 (no check of a flexibility), 2 (twins) or 3 (a third checks the twins, at the cost of one more contracted rank).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u64).range(1..=3))]
    realizations: u64,
    /// Print JSON (every cluster's rods) instead of a summary.
    #[arg(long)]
    json: bool,
    /// Write the rods as VTK PolyData (.vtp: line cells with their radius and the box outline; per rod its degree, its true rigid cluster, -1 if none, and whether that cluster spans) to this file (rod systems only).
    #[arg(long)]
    save_vtk: Option<PathBuf>,
    /// Write the true rigid clusters (rods, whether each spans, the ids of rods read with ids) as JSON to this file.
    #[arg(long)]
    save_clusters: Option<PathBuf>,
}

/// The file `--save-clusters` writes: largest cluster first, as in truth's
/// answer; a rod where clusters meet is in each.
#[derive(Serialize)]
struct SavedClusters {
    method: Decision,
    /// The spanning criterion, for a rod system.
    #[serde(skip_serializing_if = "Option::is_none")]
    criterion: Option<Criterion>,
    #[serde(skip_serializing_if = "Option::is_none")]
    spanning: Option<bool>,
    clusters: Vec<SavedCluster>,
}

#[derive(Serialize)]
struct SavedCluster {
    rods: Vec<u32>,
    /// Whether it spans under the criterion (rod systems only).
    #[serde(skip_serializing_if = "Option::is_none")]
    spans: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    ids: Option<Vec<u64>>,
}

/// The outputs given, checked before the work: writable, no two the same
/// file, and a VTK file only for rods.
fn check_outputs(a: &TruthArgs) -> Result<()> {
    if let Some(path) = &a.save_vtk {
        if !a.rods.given() {
            return Err(Error::Parameter(
                "--save-vtk draws rods: it needs a rod system (--rods FILE or generated rods), not a graph"
                    .into(),
            ));
        }
        rgc::vtk::check_extension(path)?;
    }
    super::check_outputs(&[
        ("--save-vtk", &a.save_vtk),
        ("--save-clusters", &a.save_clusters),
    ])
}

pub fn run(a: TruthArgs, out: &mut String) -> Result<()> {
    let opts = TruthOptions {
        memory_limit: a.memory.memory_limit,
        realizations: a.realizations as usize,
        ..TruthOptions::seeded(a.seed)
    };
    let inputs = [a.graph6.is_some(), a.edges.is_some(), a.rods.given()];
    if inputs.iter().filter(|&&on| on).count() != 1 {
        return Err(Error::Parameter(
            "give one system: --graph6, --edges, --rods FILE, or generated rods (--gamma, --box, --density)"
                .into(),
        ));
    }
    check_outputs(&a)?;
    // Rods read from a file: their ids, if it numbers them, and what reading did.
    let mut ids = None;
    let mut read = String::new();
    // A rod system with its contacts, for --save-vtk.
    let mut drawn = None;
    let t = match (&a.graph6, &a.edges) {
        (Some(s), _) => {
            let graph = graphio::parse_graph6(s)?;
            opts.check_memory(graph.n_nodes(), graph.n_edges(), 0)?;
            finite(&graph, opts)
        }
        (_, Some(path)) => {
            let graph = graphio::read_edge_list_within(path, |n, m| {
                opts.check_memory(n, m, graphio::graph_bytes(n, m))
            })?;
            finite(&graph, opts)
        }
        (None, None) => {
            let rods = a.rods.rods()?;
            rods.check_memory(a.memory.memory_limit)?;
            let system = match rods {
                Rods::Generated(e) => e.generate(a.seed)?,
                Rods::Read { loaded, .. } => {
                    for line in rgc::rods::file::placement(loaded.cut, loaded.wrapped) {
                        say!(read, "{line}");
                    }
                    ids = loaded.ids;
                    loaded.system
                }
            };
            let network = Network::detect(system);
            let t = truth::of_system(network.view(), a.criterion, opts);
            drawn = Some(network);
            t
        }
    };
    if t.outcome.refused().is_some() {
        return Err(Error::Memory(format!(
            "truth refused this system: {}",
            t.outcome.reason().unwrap_or_default()
        )));
    }
    if let (Some(path), Some(Network { system, graph, .. })) = (&a.save_vtk, &drawn) {
        let mut fields = vec![rgc::vtk::degree_field(graph)];
        fields.extend(rgc::vtk::truth_fields(&t, system.len(), a.criterion));
        fields.extend(ids.as_deref().map(rgc::vtk::id_field));
        rgc::vtk::save(system, &fields, path)?;
    }
    if let Some(path) = &a.save_clusters {
        let criterion = t.criterion;
        let saved = SavedClusters {
            method: t.outcome.decision(),
            criterion,
            spanning: t.spanning,
            clusters: t
                .clusters
                .iter()
                .map(|c| SavedCluster {
                    rods: c.rods.clone(),
                    spans: criterion.map(|k| c.spans.is_some_and(|s| s.under(k))),
                    ids: ids
                        .as_ref()
                        .map(|ids| c.rods.iter().map(|&r| ids[r as usize]).collect()),
                })
                .collect(),
        };
        let text = serde_json::to_string_pretty(&saved).expect("clusters serialize");
        output::write_atomic(path, text + "\n")?;
    }
    if a.json {
        let Some(ids) = ids else {
            return super::print_json(&t, out);
        };
        // Each cluster's rods also by the ids the file gave them.
        let mut v = serde_json::to_value(&t).expect("truth serializes");
        for c in v["clusters"].as_array_mut().into_iter().flatten() {
            let named: Vec<u64> = c["rods"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|r| Some(ids[r.as_u64()? as usize]))
                .collect();
            c["ids"] = named.into();
        }
        return super::print_json(&v, out);
    }
    out.push_str(&read);
    summary(&t, out);
    Ok(())
}

/// The strain rank: how many of the box's strains it resists, over which
/// strains, and which it resists alone; or why it is unknown.
fn strains(s: &Strains, out: &mut String) {
    let names = |v: &[Strain]| {
        v.iter()
            .map(Strain::to_string)
            .collect::<Vec<_>>()
            .join(" ")
    };
    let over = if s.considered.len() == 6 {
        "of the 6 strains of the periodic box".to_string()
    } else {
        format!(
            "of the {} strains of the periodic axes ({})",
            s.considered.len(),
            names(&s.considered)
        )
    };
    match s.rank {
        Some(r) => say!(
            out,
            "strain rank {r} {over}; resisted alone: {}",
            if s.resisted.is_empty() {
                "none".to_string()
            } else {
                names(&s.resisted)
            }
        ),
        None => say!(
            out,
            "strain rank unknown: {}",
            s.reason.as_deref().unwrap_or_default()
        ),
    }
}

fn finite(graph: &ContactGraph, opts: TruthOptions) -> Truth {
    truth::truth(&Topology::finite(graph), opts)
}

fn summary(t: &Truth, out: &mut String) {
    let opt = |v: Option<usize>| v.map_or("?".to_string(), |v| v.to_string());
    say!(
        out,
        "{} rods, {} contacts; 2-core {} rods, {} contacts",
        t.n_rods,
        t.n_contacts,
        t.core_rods,
        t.core_contacts
    );
    say!(
        out,
        "forced planes: {} classes, largest {} rods",
        t.plane_classes,
        t.largest_plane_class
    );
    say!(
        out,
        "matrix: {} parts, {} columns, {} rows, rank {}{}",
        t.parts,
        t.columns,
        t.rows,
        opt(t.outcome.rank()),
        t.largest_front
            .map_or(String::new(), |(r, c)| format!(", largest front {r} x {c}"))
    );
    say!(
        out,
        "dof {} (trivial motions not counted: {}{})",
        opt(t.outcome.dof()),
        t.trivial_motions,
        if t.trivial_motions == 3 {
            ", translations of the fixed periodic box"
        } else {
            ", rigid motions of a finite framework"
        }
    );
    if let Some(s) = &t.strains {
        strains(s, out);
    }
    let sizes: Vec<String> = t
        .clusters
        .iter()
        .take(8)
        .map(|c| c.rods.len().to_string())
        .collect();
    if t.clusters.is_empty() {
        say!(out, "clusters: none of two or more rods");
    } else {
        say!(
            out,
            "clusters: {} of two or more rods; largest {}{}",
            t.clusters.len(),
            sizes.join(", "),
            if t.clusters.len() > 8 { ", ..." } else { "" }
        );
    }
    if let (Some(c), Some(s)) = (t.criterion, t.spanning) {
        say!(out, "spanning ({c}): {s}");
    }
    match &t.outcome {
        Outcome::Undecided { reason, .. } => say!(out, "method: undecided: {reason}"),
        Outcome::Float { gap, reason, .. } => say!(
            out,
            "method: float, twins agree: true, singular-value gap {gap:.1e} ({reason})"
        ),
        Outcome::Exact { twins_agree, .. } => say!(
            out,
            "method: exact in F_q for q = {}, realizations agree: {}",
            t.primes
                .iter()
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", "),
            match twins_agree {
                Some(agree) => agree.to_string(),
                None => "not checked (one realization)".to_string(),
            }
        ),
    }
    say!(out, "seconds: {:.3}", t.seconds);
}
