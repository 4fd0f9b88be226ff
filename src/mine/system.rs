//! One system mined whole: a generated one in its periodic box, or a
//! contact graph as a finite framework, each with its `sound` run 0 and its
//! truth made here before the search.

use serde::{Deserialize, Serialize};
use std::time::Instant;

use super::search::{Counts, Mined, MinimalSet, Search, mine};
use crate::Result;
use crate::engine::{Engine, RuleSet};
use crate::graph::{ContactGraph, Topology};
use crate::network::Network;
use crate::rods::{RodParams, RodSystem};
use crate::spanning::{Criterion, SpanChecker};
use crate::truth::{self, TruthOptions};

/// Mines a rods-only contact graph as a finite framework: the `sound`
/// compression of run 0 of `seed`, and truth without a box.
pub fn mine_graph(graph: &ContactGraph, seed: u64, search: &Search) -> Mined {
    let topo = Topology::finite(graph);
    let run = Engine::base(RuleSet::Sound).runs(graph, seed, 1).remove(0);
    let t = truth::truth(&topo, TruthOptions::seeded(seed));
    mine(&topo, &run, &t, seed, search)
}

/// One generated system mined.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SystemReport {
    pub density: f64,
    pub seed: u64,
    #[serde(flatten)]
    pub counts: Counts,
    /// Whether a true cluster spans (wrap), and whether a body of the `sound` run does.
    pub truth_spans: Option<bool>,
    pub sound_spans: bool,
    pub seconds: f64,
}

/// Mines the generated system of `seed` at `density` in its periodic box.
pub fn mine_system(
    gamma: f64,
    box_len: f64,
    density: f64,
    seed: u64,
    search: &Search,
) -> Result<(SystemReport, Vec<MinimalSet>)> {
    let start = Instant::now();
    let network = Network::detect(RodSystem::generate(
        RodParams::new(gamma, box_len, density)?,
        seed,
    ));
    let Network {
        system,
        contacts: found,
        graph,
        ..
    } = &network;
    let run = Engine::base(RuleSet::Sound).runs(graph, seed, 1).remove(0);
    let t = truth::of_system(network.view(), Criterion::Wrap, TruthOptions::seeded(seed));
    let topo = network.topology();
    let mined = mine(&topo, &run, &t, seed, search);
    let mut checker = SpanChecker::new();
    let sound_spans = run
        .bodies
        .iter()
        .any(|b| checker.spans(system, found, graph, &b.rods, Criterion::Wrap));
    Ok((
        SystemReport {
            density,
            seed,
            counts: mined.counts,
            truth_spans: t.spanning,
            sound_spans,
            seconds: start.elapsed().as_secs_f64(),
        },
        mined.sets,
    ))
}
