//! Motifs mined from real systems: where truth (MODEL §10) finds rigidity
//! that 3D-RGC misses, the smallest sets of the engine's nodes that carry
//! it, as typed patterns (MODEL §6), counted over many generated systems
//! and written as a rule file.
//!
//! Per system:
//! * one `sound` compression, run 0 of the system's seed (the order `rgc
//!   sample --seed S --runs 1` uses); its bodies and free rods are the
//!   nodes of the *quotient*;
//! * truth of the whole system; a rigid cluster holding two or more whole
//!   quotient nodes is rigidity the engine missed;
//! * per such cluster, up to [`Search::pairs`] seed pairs `(x, y)` of
//!   adjacent whole nodes per started ten whole nodes of it (so that the
//!   spanning cluster is sampled in proportion), drawn by a shuffle seeded
//!   by the system seed and the cluster's index;
//! * for each pair, the quotient ball around `{x, y}`, over the nodes in or
//!   touching the cluster (a lock can stay outside it), grows one layer at
//!   a time from radius 0, at most [`Search::max_radius`] layers and
//!   [`Search::max_ball_rods`] rods (beyond, or when those nodes run out,
//!   the pair is *not local*). At each radius where truth puts `x` and `y`
//!   in one cluster, the nodes that cluster holds whole are restricted to
//!   themselves until truth holds all of them in one cluster; if the pair
//!   survives, they shrink to a *whole* minimal set. If no radius gives one,
//!   the first ball that held the pair shrinks to a minimal set that only
//!   keeps the pair together (*not whole*, see below);
//! * shrinking drops the nodes other than the pair, farthest from it first:
//!   halves, quarters ... while the set keeps what it must, then single
//!   nodes, pass after pass until no node can go (rigidity is not monotone
//!   under forced planes, so one pass is not enough). No node of the result
//!   can be removed: it is a *minimal missed rigid set*.
//!
//! Truth on a set is that of the rods of its nodes with every contact among
//! them, in the system's own periodic box (a finite framework for a graph
//! given without one: the two agree on a set that does not wrap the box).
//! Each call ranks one realization: a rigid answer is proved by it, a
//! flexible one is wrong with probability about `1/p`, which could only keep
//! a node that might go.
//!
//! A set becomes a pattern ([`Pattern::from_host`]): a body a planar or
//! spatial node labelled by its rods that touch the rest of the set, a free
//! rod a rod node. The planes kept inside a spatial body cannot be
//! expressed, so such a pattern is more generic than its host. Equal
//! patterns (canonical form) are counted together; each distinct one gets
//! its exact verdict on every realization component and whether the
//! `sound` engine compresses it to one node in [`Parameters::runs`] orders.
//! The ones rigid on every component and missed become rules.
//!
//! A minimal set need not be one rigid cluster: a body touching the rest at
//! two points (a locking bar) holds `x` and `y` together while itself
//! turning about the line through its two contacts; two touching rods held
//! at one further point each by one body are a rigid pair that turns about
//! the line through those points. Such a set is recorded (not *whole*);
//! its pattern is flexible, and no rule can merge it, since a rule merges
//! all of its nodes.
//!
//! A pattern also forgets the contacts inside a body, and a planar body's
//! inner contacts can force another rod into its plane (a rod touching two
//! rods of a plane lies in it): a whole set can then be rigid under truth
//! while its pattern is only component-dependent, and is no rule either.

use std::path::Path;
use std::time::Instant;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};
use serde::{Deserialize, Serialize};

use crate::body::{Body, BodyClass};
use crate::contacts;
use crate::engine::{CompiledRule, Compression, Engine, RuleSet, run_seed};
use crate::graph::ContactGraph;
use crate::output::{self, cell};
use crate::pattern::{MAX_PATTERN_NODES, NodeKind, Pattern};
use crate::progress::Progress;
use crate::rods::{RodParams, RodSystem};
use crate::rule_file::{self, Frequency, Provenance, Rule};
use crate::spanning::{Criterion, SpanChecker};
use crate::truth::Offset;
use crate::truth::{self, Topology, Truth, TruthOptions};
use crate::{Error, Result};

/// The format tag of `mined-motifs.json`.
pub const FORMAT: &str = "rgc-mined-motifs/1";

/// The caps on the search in one system, so that a run takes a predictable time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Search {
    /// Seed pairs tried per missed cluster, per started ten whole nodes of it.
    pub pairs: usize,
    /// Quotient layers grown around a seed pair.
    pub max_radius: usize,
    /// Rods in a ball truth is asked about.
    pub max_ball_rods: usize,
}

impl Default for Search {
    fn default() -> Self {
        Search {
            pairs: 3,
            max_radius: 3,
            max_ball_rods: 800,
        }
    }
}

impl Search {
    /// Seed pairs drawn in a missed cluster of `whole` whole nodes:
    /// [`Search::pairs`] per started ten, so that the spanning cluster,
    /// where the engine's failure to span lies, is sampled in proportion.
    pub fn per_cluster(&self, whole: usize) -> usize {
        self.pairs * whole.div_ceil(10).max(1)
    }

    pub fn validate(&self) -> Result<()> {
        if self.pairs == 0 || self.max_radius == 0 || self.max_ball_rods < 2 {
            return Err(Error::Parameter(format!(
                "the search needs at least one seed pair, one layer and two rods per ball, got {} pairs, radius {}, {} rods",
                self.pairs, self.max_radius, self.max_ball_rods
            )));
        }
        Ok(())
    }
}

/// What a mining run is made of: what the refusal to replace its results compares.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameters {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    /// Rods per unit volume, in the order given.
    pub densities: Vec<f64>,
    /// Systems per density; system `i` has seed `seed + i` at every density
    /// (so one seed's systems are nested, and `rgc sample`/`rgc truth` with
    /// that seed make the same rods).
    pub systems: u64,
    pub seed: u64,
    #[serde(flatten)]
    pub search: Search,
    /// Motif orders in which the engine may compress a pattern.
    pub runs: u64,
    /// Rules written at most (the most frequent first).
    pub top: usize,
    /// Extended rule files also tried on every pattern (informative only).
    #[serde(default)]
    pub extended: Vec<String>,
}

impl Parameters {
    /// Checks everything before any work: every system valid, densities
    /// distinct, at least one system, a search and an engine check that do something.
    pub fn validate(&self) -> Result<()> {
        if self.densities.is_empty() {
            return Err(Error::Parameter("no density to mine".into()));
        }
        for (i, &rho) in self.densities.iter().enumerate() {
            RodParams::new(self.gamma, self.box_len, rho)?;
            if self.densities[..i].contains(&rho) {
                return Err(Error::Parameter(format!("density {rho} is given twice")));
            }
        }
        if self.systems == 0 {
            return Err(Error::Parameter(
                "at least one system per density is needed".into(),
            ));
        }
        if self.runs == 0 {
            return Err(Error::Parameter(
                "at least one motif order is needed to tell whether the engine compresses a pattern"
                    .into(),
            ));
        }
        self.search.validate()
    }

    /// The seeds of the systems of each density.
    pub fn seeds(&self) -> impl Iterator<Item = u64> + '_ {
        (0..self.systems).map(|i| self.seed.wrapping_add(i))
    }

    /// What the rules' provenance says was mined.
    pub fn enumeration(&self) -> String {
        let densities: Vec<String> = self.densities.iter().map(f64::to_string).collect();
        format!(
            "minimal missed rigid sets in generated systems: gamma {}, box {}, densities {}, \
             {} systems each (seeds {} to {}), sound run 0 as the quotient, truth in the box; \
             {} seed pairs per missed cluster, radius <= {}, <= {} rods per ball",
            self.gamma,
            self.box_len,
            densities.join(","),
            self.systems,
            self.seed,
            self.seed.wrapping_add(self.systems - 1),
            self.search.pairs,
            self.search.max_radius,
            self.search.max_ball_rods
        )
    }

    /// What the rules were checked against.
    pub fn audited_against(&self) -> String {
        format!(
            "sound base motifs, {} motif orders (compressed to one node in none)",
            self.runs
        )
    }
}

/// The engine's nodes: bodies (in the compression's order) then free rods.
struct Quotient {
    node_of: Vec<u32>,
    members: Vec<Vec<u32>>,
    class: Vec<Option<BodyClass>>,
    adj: Vec<Vec<u32>>,
}

impl Quotient {
    fn new(graph: &ContactGraph, bodies: &[Body]) -> Self {
        let n = graph.n_nodes();
        let mut node_of = vec![u32::MAX; n];
        let mut members: Vec<Vec<u32>> = Vec::new();
        let mut class = Vec::new();
        for b in bodies {
            for &r in &b.rods {
                node_of[r as usize] = members.len() as u32;
            }
            members.push(b.rods.clone());
            class.push(Some(b.class));
        }
        for (r, node) in node_of.iter_mut().enumerate() {
            if *node == u32::MAX {
                *node = members.len() as u32;
                members.push(vec![r as u32]);
                class.push(None);
            }
        }
        let mut adj = vec![Vec::new(); members.len()];
        for &[a, b] in graph.edges() {
            let (x, y) = (node_of[a as usize], node_of[b as usize]);
            if x != y {
                adj[x as usize].push(y);
                adj[y as usize].push(x);
            }
        }
        for a in &mut adj {
            a.sort_unstable();
            a.dedup();
        }
        Quotient {
            node_of,
            members,
            class,
            adj,
        }
    }

    fn rods(&self, nodes: &[u32]) -> Vec<u32> {
        let mut rods: Vec<u32> = nodes
            .iter()
            .flat_map(|&x| self.members[x as usize].iter().copied())
            .collect();
        rods.sort_unstable();
        rods
    }

    /// Whether the sorted cluster holds every rod of the nodes `held`.
    fn holds(&self, cluster: &[u32], held: &[u32]) -> bool {
        held.iter().all(|&x| {
            self.members[x as usize]
                .iter()
                .all(|r| cluster.binary_search(r).is_ok())
        })
    }
}

/// Truth on sets of quotient nodes, counting its calls.
struct Probe<'a> {
    topo: &'a Topology<'a>,
    q: &'a Quotient,
    opts: TruthOptions,
    /// Each rod's index in the set being built, `u32::MAX` outside it.
    local: Vec<u32>,
    calls: usize,
    undecided: usize,
}

impl<'a> Probe<'a> {
    fn new(topo: &'a Topology<'a>, q: &'a Quotient, seed: u64) -> Self {
        Probe {
            topo,
            q,
            opts: TruthOptions {
                twins: false,
                ..TruthOptions::seeded(seed)
            },
            local: vec![u32::MAX; topo.graph.n_nodes()],
            calls: 0,
            undecided: 0,
        }
    }

    /// The rigid clusters (global rods, sorted) of the rods of `nodes` with
    /// every contact among them, in the system's own box; `None` when truth
    /// is undecided.
    fn clusters(&mut self, nodes: &[u32]) -> Option<Vec<Vec<u32>>> {
        let rods = self.q.rods(nodes);
        for (k, &r) in rods.iter().enumerate() {
            self.local[r as usize] = k as u32;
        }
        let graph = self.topo.graph;
        let mut edges = Vec::new();
        let mut shifts: Vec<Offset> = Vec::new();
        for &r in &rods {
            for &(s, e) in graph.neighbors(r) {
                if s > r && self.local[s as usize] != u32::MAX {
                    let [a, b] = graph.edges()[e as usize];
                    edges.push([self.local[a as usize], self.local[b as usize]]);
                    if let Some(all) = self.topo.shifts {
                        shifts.push(all[e as usize]);
                    }
                }
            }
        }
        for &r in &rods {
            self.local[r as usize] = u32::MAX;
        }
        let sub = ContactGraph::new(rods.len(), edges).expect("an induced subgraph is simple");
        let topo = Topology {
            graph: &sub,
            shifts: self.topo.shifts.map(|_| &shifts[..]),
        };
        let t = truth::truth(&topo, self.opts);
        self.calls += 1;
        if !t.decided() {
            self.undecided += 1;
            return None;
        }
        // Local indices follow the sorted global rods, so clusters stay sorted.
        Some(
            t.clusters
                .into_iter()
                .map(|c| c.rods.iter().map(|&k| rods[k as usize]).collect())
                .collect(),
        )
    }

    /// The nodes of `nodes` that truth on them puts, whole, in one cluster
    /// with the `pair` (the cluster holding most of them), sorted; `None`
    /// when no cluster holds the pair.
    fn held(&mut self, nodes: &[u32], pair: [u32; 2]) -> Option<Vec<u32>> {
        let q = self.q;
        self.clusters(nodes)?
            .iter()
            .filter(|c| q.holds(c, &pair))
            .map(|c| {
                let mut held: Vec<u32> = nodes
                    .iter()
                    .copied()
                    .filter(|&x| q.holds(c, &[x]))
                    .collect();
                held.sort_unstable();
                held
            })
            .max_by_key(|h| h.len())
    }
}

/// Whether the rods, with the contacts among them, reach some rod at two
/// different images of the box (always false for a finite framework).
fn wraps(topo: &Topology, rods: &[u32]) -> bool {
    if topo.shifts.is_none() {
        return false;
    }
    let mut offset: FxHashMap<u32, Offset> = FxHashMap::default();
    for &start in rods {
        if offset.contains_key(&start) {
            continue;
        }
        offset.insert(start, [0; 3]);
        let mut stack = vec![start];
        while let Some(r) = stack.pop() {
            let o = offset[&r];
            for &(s, e) in topo.graph.neighbors(r) {
                if rods.binary_search(&s).is_err() {
                    continue;
                }
                let d = topo.seen(e, r);
                let want = [o[0] + d[0], o[1] + d[1], o[2] + d[2]];
                match offset.get(&s) {
                    Some(&there) if there != want => return true,
                    Some(_) => {}
                    None => {
                        offset.insert(s, want);
                        stack.push(s);
                    }
                }
            }
        }
    }
    false
}

/// A minimal missed rigid set found in one system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MinimalSet {
    /// The seed pair: two quotient nodes (bodies first, then free rods).
    pub pair: [u32; 2],
    /// Its quotient nodes, sorted.
    pub nodes: Vec<u32>,
    /// Every rod of those nodes, sorted.
    pub rods: Vec<u32>,
    /// Ball radius at which the pair was first rigid together.
    pub radius: usize,
    /// The nodes that truth on the set puts, whole, in one cluster with the
    /// pair, sorted, and their rods.
    pub held: Vec<u32>,
    pub held_rods: Vec<u32>,
    /// Whether that is every node (otherwise the others only hold it
    /// together, turning themselves, and the pattern cannot be rigid).
    pub whole: bool,
    /// Whether its rods close a loop through the periodic box.
    pub wraps: bool,
    /// The canonical pattern and its form; `None` beyond the pattern sizes.
    pub pattern: Option<Pattern>,
    pub canonical: Option<String>,
}

/// What mining one system counted.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Counts {
    pub rods: usize,
    pub contacts: usize,
    /// Bodies of the `sound` run, and its quotient nodes (bodies and free rods).
    pub bodies: usize,
    pub nodes: usize,
    /// Bodies inside no true cluster (rigidity the engine made up).
    pub refuted_bodies: usize,
    /// Whether truth of the whole system was decided (nothing is mined otherwise).
    pub decided: bool,
    pub true_clusters: usize,
    /// True clusters holding two or more whole quotient nodes, and their rods.
    pub missed_clusters: usize,
    pub missed_rods: usize,
    /// Missed clusters with no two adjacent whole nodes (no seed pair).
    pub unseeded_clusters: usize,
    /// Seed pairs tried, and those that gave a minimal set.
    pub pairs: usize,
    pub found: usize,
    /// Pairs not rigid together within the radius cap, within the rods cap,
    /// or before the nodes in or touching their cluster ran out: not local.
    pub beyond_radius: usize,
    pub beyond_rods: usize,
    pub exhausted: usize,
    /// Distinct minimal sets; of them, those too large for a pattern
    /// ([`MAX_PATTERN_NODES`] nodes, 96 contacts), not whole, and wrapping the box.
    pub sets: usize,
    pub too_large: usize,
    pub not_whole: usize,
    pub wrapping: usize,
    /// Truth evaluations of sets, and the undecided ones.
    pub truth_calls: usize,
    pub undecided_calls: usize,
}

/// One system mined.
#[derive(Clone, Debug, PartialEq)]
pub struct Mined {
    pub counts: Counts,
    pub sets: Vec<MinimalSet>,
}

/// Mines one system: `run` is a `sound` compression of `topo`'s graph and
/// `truth` its truth; `seed` draws the seed pairs and seeds truth on the sets.
pub fn mine(
    topo: &Topology,
    run: &Compression,
    truth: &Truth,
    seed: u64,
    search: &Search,
) -> Mined {
    let graph = topo.graph;
    let q = Quotient::new(graph, &run.bodies);
    let mut counts = Counts {
        rods: graph.n_nodes(),
        contacts: graph.n_edges(),
        bodies: run.bodies.len(),
        nodes: q.members.len(),
        decided: truth.decided(),
        true_clusters: truth.clusters.len(),
        ..Counts::default()
    };
    counts.refuted_bodies = (0..run.bodies.len() as u32)
        .filter(|&b| !truth.clusters.iter().any(|c| q.holds(&c.rods, &[b])))
        .count();
    let mut probe = Probe::new(topo, &q, seed);
    let mut found: FxHashMap<Vec<u32>, ([u32; 2], usize)> = FxHashMap::default();
    let mut order: Vec<Vec<u32>> = Vec::new();
    for (k, cluster) in truth.clusters.iter().enumerate() {
        let mut held: FxHashMap<u32, usize> = FxHashMap::default();
        for &r in &cluster.rods {
            *held.entry(q.node_of[r as usize]).or_default() += 1;
        }
        let mut whole: Vec<u32> = held
            .iter()
            .filter(|&(&x, &n)| q.members[x as usize].len() == n)
            .map(|(&x, _)| x)
            .collect();
        if whole.len() < 2 {
            continue;
        }
        whole.sort_unstable();
        counts.missed_clusters += 1;
        counts.missed_rods += cluster.rods.len();
        let mut pairs: Vec<[u32; 2]> = whole
            .iter()
            .flat_map(|&a| {
                q.adj[a as usize]
                    .iter()
                    .filter(move |&&b| b > a)
                    .filter(|b| whole.binary_search(b).is_ok())
                    .map(move |&b| [a, b])
            })
            .collect();
        if pairs.is_empty() {
            counts.unseeded_clusters += 1;
            continue;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(run_seed(seed, k as u64));
        let take = search.per_cluster(whole.len()).min(pairs.len());
        for i in 0..take {
            let j = rng.random_range(i..pairs.len());
            pairs.swap(i, j);
        }
        let mut allowed: FxHashSet<u32> = held.keys().copied().collect();
        for &r in &cluster.rods {
            allowed.extend(
                graph
                    .neighbors(r)
                    .iter()
                    .map(|&(s, _)| q.node_of[s as usize]),
            );
        }
        for &pair in &pairs[..take] {
            counts.pairs += 1;
            match minimal_set(&mut probe, &allowed, pair, search) {
                Outcome::Found(nodes, radius) => {
                    counts.found += 1;
                    if let std::collections::hash_map::Entry::Vacant(e) = found.entry(nodes) {
                        order.push(e.key().clone());
                        e.insert((pair, radius));
                    }
                }
                Outcome::Radius => counts.beyond_radius += 1,
                Outcome::Rods => counts.beyond_rods += 1,
                Outcome::Exhausted => counts.exhausted += 1,
            }
        }
    }
    let sets: Vec<MinimalSet> = order
        .into_iter()
        .map(|nodes| {
            let (pair, radius) = found[&nodes];
            let held = probe.held(&nodes, pair).unwrap_or_default();
            let rods = q.rods(&nodes);
            let pattern = pattern_of(graph, &q, &nodes).ok();
            MinimalSet {
                pair,
                wraps: wraps(topo, &rods),
                canonical: pattern.as_ref().map(rule_file::canonical_form),
                pattern: pattern.map(|p| crate::enumerate::canonical_pattern(&p)),
                whole: held.len() == nodes.len(),
                held_rods: q.rods(&held),
                held,
                nodes,
                rods,
                radius,
            }
        })
        .collect();
    counts.sets = sets.len();
    counts.too_large = sets.iter().filter(|s| s.pattern.is_none()).count();
    counts.not_whole = sets.iter().filter(|s| !s.whole).count();
    counts.wrapping = sets.iter().filter(|s| s.wraps).count();
    counts.truth_calls = probe.calls;
    counts.undecided_calls = probe.undecided;
    Mined { counts, sets }
}

/// How the search around one seed pair ended.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Outcome {
    /// A minimal set (nodes sorted) and the ball radius it came from.
    Found(Vec<u32>, usize),
    /// The pair was never rigid together within [`Search::max_radius`].
    Radius,
    /// The ball would have had more than [`Search::max_ball_rods`] rods.
    Rods,
    /// The nodes in or touching the cluster ran out first.
    Exhausted,
}

/// Grows the ball around `pair` over `allowed`, one layer at a time, and
/// cuts it down to a minimal set.
///
/// A whole set is preferred: at each radius where the pair is rigid
/// together, the nodes its cluster holds, restricted to themselves until
/// they are one cluster, shrink to a minimal set that is one cluster. When
/// that loses the pair at every radius up to the caps (its rigidity needs a
/// node that is not rigid with it), the first ball that held the pair
/// shrinks to a minimal set that only keeps the pair together.
fn minimal_set(
    probe: &mut Probe,
    allowed: &FxHashSet<u32>,
    pair: [u32; 2],
    search: &Search,
) -> Outcome {
    let q = probe.q;
    let size = |x: u32| q.members[x as usize].len();
    let mut dist: FxHashMap<u32, usize> = pair.iter().map(|&x| (x, 0)).collect();
    let mut ball = pair.to_vec();
    let mut frontier = pair.to_vec();
    let mut rods = size(pair[0]) + size(pair[1]);
    let mut first: Option<(Vec<u32>, usize)> = None;
    let mut end = Outcome::Radius;
    for radius in 0..=search.max_radius {
        if radius > 0 {
            let mut next: Vec<u32> = Vec::new();
            for &a in &frontier {
                for &b in &q.adj[a as usize] {
                    if allowed.contains(&b) && !dist.contains_key(&b) {
                        dist.insert(b, radius);
                        next.push(b);
                    }
                }
            }
            if next.is_empty() {
                end = Outcome::Exhausted;
                break;
            }
            next.sort_unstable();
            rods += next.iter().map(|&x| size(x)).sum::<usize>();
            if rods > search.max_ball_rods {
                end = Outcome::Rods;
                break;
            }
            ball.extend(&next);
            frontier = next;
        }
        let Some(mut held) = probe.held(&ball, pair) else {
            continue;
        };
        if first.is_none() {
            first = Some((ball.clone(), radius));
        }
        let whole = loop {
            match probe.held(&held, pair) {
                Some(h) if h.len() == held.len() => break true,
                Some(h) => held = h,
                None => break false,
            }
        };
        if whole {
            let rest = farthest_first(held, pair, &dist);
            let nodes = shrink(pair, rest, |nodes| {
                probe
                    .held(nodes, pair)
                    .is_some_and(|h| h.len() == nodes.len())
            });
            return Outcome::Found(nodes, radius);
        }
    }
    match first {
        Some((ball, radius)) => {
            let rest = farthest_first(ball, pair, &dist);
            Outcome::Found(
                shrink(pair, rest, |nodes| probe.held(nodes, pair).is_some()),
                radius,
            )
        }
        None => end,
    }
}

/// The nodes other than the pair, farthest from it first (then by
/// decreasing index): what is dropped first is what the pair needs least.
fn farthest_first(mut nodes: Vec<u32>, pair: [u32; 2], dist: &FxHashMap<u32, usize>) -> Vec<u32> {
    nodes.retain(|x| !pair.contains(x));
    nodes.sort_by_key(|&x| (std::cmp::Reverse(dist[&x]), std::cmp::Reverse(x)));
    nodes
}

/// Drops nodes of `rest` (in its order) while `keeps` holds for the pair
/// and what is left: chunks of halving size, then single nodes until none
/// can go. Returns the pair and what is left, sorted.
fn shrink(pair: [u32; 2], mut rest: Vec<u32>, mut keeps: impl FnMut(&[u32]) -> bool) -> Vec<u32> {
    let mut holds = |rest: &[u32]| {
        let mut nodes = pair.to_vec();
        nodes.extend_from_slice(rest);
        keeps(&nodes)
    };
    let mut chunk = rest.len() / 2;
    while chunk > 1 {
        let mut i = 0;
        while i < rest.len() {
            let end = (i + chunk).min(rest.len());
            let trial = [&rest[..i], &rest[end..]].concat();
            if holds(&trial) {
                rest = trial;
            } else {
                i = end;
            }
        }
        chunk /= 2;
    }
    loop {
        let before = rest.len();
        let mut i = 0;
        while i < rest.len() {
            let trial = [&rest[..i], &rest[i + 1..]].concat();
            if holds(&trial) {
                rest = trial;
            } else {
                i += 1;
            }
        }
        if rest.len() == before {
            rest.extend(pair);
            rest.sort_unstable();
            return rest;
        }
    }
}

/// The typed pattern of a set of quotient nodes: each body with the rods
/// that touch another node of the set, each free rod, and the contacts
/// between different nodes. An error when it is too large for a pattern.
fn pattern_of(graph: &ContactGraph, q: &Quotient, nodes: &[u32]) -> Result<Pattern> {
    if nodes.len() > MAX_PATTERN_NODES {
        return Err(Error::Parameter(format!(
            "{} nodes, more than a pattern's {MAX_PATTERN_NODES}",
            nodes.len()
        )));
    }
    let in_set = |r: u32| nodes.binary_search(&q.node_of[r as usize]).is_ok();
    let across = |r: u32| {
        graph
            .neighbors(r)
            .iter()
            .any(|&(s, _)| in_set(s) && q.node_of[s as usize] != q.node_of[r as usize])
    };
    let carry: Vec<u32> = q.rods(nodes).into_iter().filter(|&r| across(r)).collect();
    let local = |r: u32| carry.binary_search(&r).ok().map(|k| k as u32);
    let mut edges = Vec::new();
    for &r in &carry {
        for &(s, _) in graph.neighbors(r) {
            if s > r
                && q.node_of[s as usize] != q.node_of[r as usize]
                && let (Some(a), Some(b)) = (local(r), local(s))
            {
                edges.push([a, b]);
            }
        }
    }
    let host = ContactGraph::new(carry.len(), edges)?;
    let bodies: Vec<Body> = nodes
        .iter()
        .filter_map(|&x| {
            let class = q.class[x as usize]?;
            let rods = q.members[x as usize]
                .iter()
                .filter_map(|&r| local(r))
                .collect();
            Some(Body::new(rods, class))
        })
        .collect();
    Pattern::from_host(&host, &bodies)
}

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
    let system = RodSystem::generate(RodParams::new(gamma, box_len, density)?, seed);
    let found = contacts::detect(&system);
    let graph = ContactGraph::from_contacts(system.len(), &found);
    let run = Engine::base(RuleSet::Sound).runs(&graph, seed, 1).remove(0);
    let t = truth::of_system(
        &system,
        &found,
        &graph,
        Criterion::Wrap,
        TruthOptions::seeded(seed),
    );
    let shifts: Vec<Offset> = found.iter().map(|c| c.shift).collect();
    let topo = Topology::periodic(&graph, &shifts)?;
    let mined = mine(&topo, &run, &t, seed, search);
    let mut checker = SpanChecker::new();
    let sound_spans = run
        .bodies
        .iter()
        .any(|b| checker.spans(&system, &found, &graph, &b.rods, Criterion::Wrap));
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

/// One distinct pattern, over every system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MinedMotif {
    /// 1 for the most frequent.
    pub rank: usize,
    pub canonical: String,
    /// The canonical pattern (not in the JSON: [`MinedMotif::canonical`]
    /// spells it, kinds then contacts `a.i-b.j`, and the rule file holds the rules').
    #[serde(skip, default = "no_pattern")]
    pub pattern: Pattern,
    pub nodes: usize,
    pub rod_nodes: usize,
    pub planar: usize,
    pub spatial: usize,
    pub contacts: usize,
    /// The exact verdict on every realization component, and its largest DOF.
    pub class: String,
    pub dof: Option<usize>,
    /// Whether the `sound` engine compresses it to one node in some of the orders tried.
    pub sound_compresses: bool,
    /// The same with the extended rule files (when any were given).
    pub extended_compresses: Option<bool>,
    /// Rigid on every component and missed by `sound`: a rule candidate.
    pub candidate: bool,
    /// Its id in the rule file written, if it is one of the top candidates.
    pub rule: Option<String>,
    /// Distinct minimal sets with this pattern, and the systems holding one.
    pub occurrences: u64,
    pub systems: u64,
    /// Of the occurrences, those that were one rigid cluster, and those wrapping the box.
    pub whole: u64,
    pub wrapping: u64,
    pub per_density: Vec<Frequency>,
    /// The first occurrence: its system and rods.
    pub example: Example,
}

fn no_pattern() -> Pattern {
    Pattern {
        kinds: Vec::new(),
        contacts: Vec::new(),
    }
}

/// Where a pattern was first found: the system, the rods of the set, and,
/// when the set is not whole, those the pair's cluster holds. Rods are
/// written as one space-separated string, which keeps the JSON short.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Example {
    pub density: f64,
    pub seed: u64,
    #[serde(with = "spaced")]
    pub rods: Vec<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none", with = "spaced_opt")]
    pub held_rods: Option<Vec<u32>>,
}

/// Rod lists as one space-separated string.
mod spaced {
    use serde::{Deserialize, Deserializer, Serializer, de::Error};

    pub fn serialize<S: Serializer>(rods: &[u32], s: S) -> Result<S::Ok, S::Error> {
        let words: Vec<String> = rods.iter().map(u32::to_string).collect();
        s.serialize_str(&words.join(" "))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u32>, D::Error> {
        String::deserialize(d)?
            .split_whitespace()
            .map(|w| w.parse().map_err(D::Error::custom))
            .collect()
    }
}

/// [`spaced`] for an optional list.
mod spaced_opt {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(rods: &Option<Vec<u32>>, s: S) -> Result<S::Ok, S::Error> {
        match rods {
            Some(r) => super::spaced::serialize(r, s),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<u32>>, D::Error> {
        #[derive(Deserialize)]
        struct Wrap(#[serde(with = "super::spaced")] Vec<u32>);
        Ok(Option::<Wrap>::deserialize(d)?.map(|Wrap(r)| r))
    }
}

/// One density summarized.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DensitySummary {
    pub density: f64,
    pub systems: usize,
    pub truth_spans: usize,
    pub sound_spans: usize,
    pub mean_nodes: f64,
    pub missed_clusters: usize,
    pub mean_missed_rods: f64,
    pub pairs: usize,
    pub found: usize,
    /// Pairs not rigid together within the caps (every reason).
    pub not_local: usize,
    pub sets: usize,
    pub too_large: usize,
    pub not_whole: usize,
    /// Quotient nodes per distinct minimal set: mean and largest.
    pub mean_set_nodes: f64,
    pub max_set_nodes: usize,
    /// Distinct patterns at this density, and the rule candidates among them.
    pub patterns: usize,
    pub candidates: usize,
}

/// What `mined-motifs.json` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    pub format: String,
    pub command: String,
    pub parameters: Parameters,
    pub densities: Vec<DensitySummary>,
    pub systems: Vec<SystemReport>,
    /// Every distinct pattern, most frequent first.
    pub motifs: Vec<MinedMotif>,
    pub seconds: f64,
}

/// Mines every system of `params` (in parallel; the result does not depend
/// on the thread count), then checks every distinct pattern exactly and
/// against the engine. `extended` are the rules of `params.extended`.
pub fn run(
    params: &Parameters,
    extended: &[CompiledRule],
    command: &str,
    progress: &dyn Progress,
) -> Result<Report> {
    params.validate()?;
    let start = Instant::now();
    let jobs: Vec<(f64, u64)> = params
        .densities
        .iter()
        .flat_map(|&rho| params.seeds().map(move |s| (rho, s)))
        .collect();
    progress.start("systems mined", jobs.len() as u64);
    let mined = jobs
        .par_iter()
        .map(|&(rho, seed)| {
            let m = mine_system(params.gamma, params.box_len, rho, seed, &params.search);
            progress.advance(1);
            m
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    let mut motifs = tally(params, &mined);
    progress.start("patterns checked", motifs.len() as u64);
    let sound = Engine::base(RuleSet::Sound);
    let with = Engine::with_rules(RuleSet::Sound, extended);
    let checks = motifs
        .par_iter()
        .map(|m| {
            let v = crate::rigidity::check_exact(&m.pattern, rule_file::RULE_SEED)?;
            let compresses = crate::audit::compresses(&sound, &m.pattern, params.runs)?;
            let extended = (!params.extended.is_empty())
                .then(|| crate::audit::compresses(&with, &m.pattern, params.runs))
                .transpose()?;
            progress.advance(1);
            Ok((v.class, v.dof, compresses, extended))
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    let mut k = 0;
    for (m, (class, dof, compresses, extended)) in motifs.iter_mut().zip(checks) {
        m.candidate = class == "rigid" && !compresses;
        m.class = class;
        m.dof = dof;
        m.sound_compresses = compresses;
        m.extended_compresses = extended;
        if m.candidate && k < params.top {
            m.rule = Some(format!("mined-{k}"));
            k += 1;
        }
    }
    let densities = summaries(params, &mined, &motifs);
    Ok(Report {
        format: FORMAT.into(),
        command: command.into(),
        parameters: params.clone(),
        densities,
        systems: mined.into_iter().map(|(s, _)| s).collect(),
        motifs,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Counts the patterns of every system (in job order), most frequent first;
/// the verdicts are filled in later.
fn tally(params: &Parameters, mined: &[(SystemReport, Vec<MinimalSet>)]) -> Vec<MinedMotif> {
    let mut index: FxHashMap<String, usize> = FxHashMap::default();
    let mut motifs: Vec<MinedMotif> = Vec::new();
    for (system, sets) in mined {
        let d = params
            .densities
            .iter()
            .position(|&rho| rho == system.density)
            .expect("a system of a mined density");
        let mut seen_here: FxHashSet<usize> = FxHashSet::default();
        for set in sets {
            let (Some(pattern), Some(canonical)) = (&set.pattern, &set.canonical) else {
                continue;
            };
            let k = *index.entry(canonical.clone()).or_insert_with(|| {
                motifs.push(new_motif(params, system, set, pattern, canonical));
                motifs.len() - 1
            });
            let m = &mut motifs[k];
            m.occurrences += 1;
            m.whole += u64::from(set.whole);
            m.wrapping += u64::from(set.wraps);
            m.per_density[d].occurrences += 1;
            if seen_here.insert(k) {
                m.systems += 1;
                m.per_density[d].systems += 1;
            }
        }
    }
    motifs.sort_by(|a, b| {
        b.occurrences
            .cmp(&a.occurrences)
            .then(b.systems.cmp(&a.systems))
            .then(a.canonical.cmp(&b.canonical))
    });
    for (k, m) in motifs.iter_mut().enumerate() {
        m.rank = k + 1;
    }
    motifs
}

fn new_motif(
    params: &Parameters,
    system: &SystemReport,
    set: &MinimalSet,
    pattern: &Pattern,
    canonical: &str,
) -> MinedMotif {
    let count = |k: NodeKind| pattern.kinds.iter().filter(|&&x| x == k).count();
    MinedMotif {
        rank: 0,
        canonical: canonical.to_string(),
        pattern: pattern.clone(),
        nodes: pattern.n_nodes(),
        rod_nodes: count(NodeKind::Rod),
        planar: count(NodeKind::Planar),
        spatial: count(NodeKind::Spatial),
        contacts: pattern.contacts.len(),
        class: String::new(),
        dof: None,
        sound_compresses: false,
        extended_compresses: None,
        candidate: false,
        rule: None,
        occurrences: 0,
        systems: 0,
        whole: 0,
        wrapping: 0,
        per_density: params
            .densities
            .iter()
            .map(|&density| Frequency {
                density,
                occurrences: 0,
                systems: 0,
                of_systems: params.systems,
            })
            .collect(),
        example: Example {
            density: system.density,
            seed: system.seed,
            rods: set.rods.clone(),
            held_rods: (!set.whole).then(|| set.held_rods.clone()),
        },
    }
}

fn summaries(
    params: &Parameters,
    mined: &[(SystemReport, Vec<MinimalSet>)],
    motifs: &[MinedMotif],
) -> Vec<DensitySummary> {
    params
        .densities
        .iter()
        .enumerate()
        .map(|(d, &density)| {
            let here: Vec<&SystemReport> = mined
                .iter()
                .map(|(s, _)| s)
                .filter(|s| s.density == density)
                .collect();
            let set_nodes: Vec<usize> = mined
                .iter()
                .filter(|(s, _)| s.density == density)
                .flat_map(|(_, sets)| sets.iter().map(|m| m.nodes.len()))
                .collect();
            let n = here.len().max(1) as f64;
            let sum =
                |f: &dyn Fn(&Counts) -> usize| here.iter().map(|s| f(&s.counts)).sum::<usize>();
            let present = || motifs.iter().filter(|m| m.per_density[d].occurrences > 0);
            DensitySummary {
                density,
                systems: here.len(),
                truth_spans: here.iter().filter(|s| s.truth_spans == Some(true)).count(),
                sound_spans: here.iter().filter(|s| s.sound_spans).count(),
                mean_nodes: sum(&|c| c.nodes) as f64 / n,
                missed_clusters: sum(&|c| c.missed_clusters),
                mean_missed_rods: sum(&|c| c.missed_rods) as f64 / n,
                pairs: sum(&|c| c.pairs),
                found: sum(&|c| c.found),
                not_local: sum(&|c| c.beyond_radius + c.beyond_rods + c.exhausted),
                sets: sum(&|c| c.sets),
                too_large: sum(&|c| c.too_large),
                not_whole: sum(&|c| c.not_whole),
                mean_set_nodes: set_nodes.iter().sum::<usize>() as f64
                    / set_nodes.len().max(1) as f64,
                max_set_nodes: set_nodes.iter().copied().max().unwrap_or(0),
                patterns: present().count(),
                candidates: present().filter(|m| m.candidate).count(),
            }
        })
        .collect()
}

/// The rules of the report: its top candidates, most frequent first, each
/// verified now, with the frequency per density in its provenance.
pub fn rules(report: &Report) -> Result<Vec<Rule>> {
    let p = &report.parameters;
    report
        .motifs
        .iter()
        .filter_map(|m| m.rule.as_ref().map(|id| (id, m)))
        .map(|(id, m)| {
            let provenance = Provenance {
                source: "mined".into(),
                enumeration: Some(p.enumeration()),
                audited_against: Some(p.audited_against()),
                command: Some(report.command.clone()),
                version: Some(env!("CARGO_PKG_VERSION").into()),
                frequency: m.per_density.clone(),
            };
            Rule::new(id.clone(), m.pattern.clone(), provenance)
        })
        .collect()
}

/// Refuses to replace results or a rule file that another mining run made:
/// `results` (`mined-motifs.json`) made with other parameters, or a rule
/// file whose rules were not mined with the same enumeration (a rule file
/// without rules holds nothing to lose). A missing file is fine.
pub fn check_replace(results: &Path, rule_file_path: &Path, params: &Parameters) -> Result<()> {
    let read = |path: &Path| match std::fs::read_to_string(path) {
        Ok(text) => Ok(Some(text)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(path, e)),
    };
    let mut conflicts = Vec::new();
    if let Some(text) = read(results)? {
        let there: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
        match serde_json::from_value::<Parameters>(there["parameters"].clone()) {
            Ok(made) if made == *params => {}
            Ok(_) => conflicts.push(format!(
                "{} holds a mining run with other parameters",
                results.display()
            )),
            Err(_) => conflicts.push(format!("{} is not a mining run's", results.display())),
        }
    }
    if let Some(text) = read(rule_file_path)? {
        let same = serde_json::from_str::<rule_file::RuleFile>(&text).is_ok_and(|f| {
            f.rules.iter().all(|r| {
                r.provenance.source == "mined"
                    && r.provenance.enumeration.as_deref() == Some(&params.enumeration())
                    && r.provenance.audited_against.as_deref() == Some(&params.audited_against())
            })
        });
        if !same {
            conflicts.push(format!(
                "{} holds rules not mined with these parameters",
                rule_file_path.display()
            ));
        }
    }
    if conflicts.is_empty() {
        return Ok(());
    }
    Err(Error::Parameter(format!(
        "{}; choose another --out or --results, or --force to replace them",
        conflicts.join("; ")
    )))
}

/// One row of `mined-motifs.csv`, before the per-density cells.
#[derive(Serialize)]
struct Row<'a> {
    rank: usize,
    canonical: &'a str,
    nodes: usize,
    rod_nodes: usize,
    planar: usize,
    spatial: usize,
    contacts: usize,
    class: &'a str,
    #[serde(serialize_with = "cell::display_opt")]
    dof: Option<usize>,
    sound_compresses: bool,
    #[serde(serialize_with = "cell::display_opt")]
    extended_compresses: Option<bool>,
    candidate: bool,
    rule: &'a str,
    occurrences: u64,
    systems: u64,
    whole: u64,
    wrapping: u64,
    example_density: f64,
    example_seed: u64,
}

/// Every pattern, with its occurrences and systems per density.
pub fn csv(report: &Report) -> Vec<u8> {
    let more: Vec<String> = report
        .parameters
        .densities
        .iter()
        .flat_map(|rho| [format!("occurrences_{rho}"), format!("systems_{rho}")])
        .collect();
    output::csv_with_more(
        &more,
        report.motifs.iter().map(|m| {
            let cells: Vec<u64> = m
                .per_density
                .iter()
                .flat_map(|f| [f.occurrences, f.systems])
                .collect();
            (
                Row {
                    rank: m.rank,
                    canonical: &m.canonical,
                    nodes: m.nodes,
                    rod_nodes: m.rod_nodes,
                    planar: m.planar,
                    spatial: m.spatial,
                    contacts: m.contacts,
                    class: &m.class,
                    dof: m.dof,
                    sound_compresses: m.sound_compresses,
                    extended_compresses: m.extended_compresses,
                    candidate: m.candidate,
                    rule: m.rule.as_deref().unwrap_or(""),
                    occurrences: m.occurrences,
                    systems: m.systems,
                    whole: m.whole,
                    wrapping: m.wrapping,
                    example_density: m.example.density,
                    example_seed: m.example.seed,
                },
                cells,
            )
        }),
    )
}

/// Patterns listed in each Markdown table.
const MARKDOWN_MOTIFS: usize = 30;

/// The per-density summary, the most frequent patterns and the most
/// frequent rule candidates as Markdown.
pub fn markdown(report: &Report) -> String {
    let p = &report.parameters;
    let mut md = format!(
        "# Motifs 3D-RGC misses, mined from generated systems\n\n\
         Command: `{}`\n\n{}.\n\n",
        report.command,
        p.enumeration()
    );
    md += "| density | systems | truth spans | sound spans | quotient nodes | missed clusters | rods in them | seed pairs | minimal sets (found) | not local | too large | not whole | nodes per set (mean, max) | patterns | rule candidates |\n";
    md += "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for d in &report.densities {
        md += &format!(
            "| {} | {} | {} | {} | {:.1} | {} | {:.1} | {} | {} ({}) | {} | {} | {} | {:.1}, {} | {} | {} |\n",
            d.density,
            d.systems,
            d.truth_spans,
            d.sound_spans,
            d.mean_nodes,
            d.missed_clusters,
            d.mean_missed_rods,
            d.pairs,
            d.sets,
            d.found,
            d.not_local,
            d.too_large,
            d.not_whole,
            d.mean_set_nodes,
            d.max_set_nodes,
            d.patterns,
            d.candidates
        );
    }
    md += &format!(
        "\nQuotient nodes (the `sound` run's bodies and free rods) and rods in missed clusters \
         (true clusters holding two or more whole nodes) are means per system; the other counts \
         are sums over the systems of a density. *Minimal sets*: distinct sets the seed pairs \
         gave (*found*: pairs that gave one). *Not local*: pairs not rigid together within \
         radius {} and {} rods of the quotient ball, or before the nodes in or touching their \
         cluster ran out. *Too large*: sets beyond a pattern's {MAX_PATTERN_NODES} nodes or 96 \
         contacts. *Not whole*: sets in which some node only holds the others together while \
         turning itself (a lock); their patterns cannot be rigid, and no rule can express them.\n\n",
        p.search.max_radius, p.search.max_ball_rods
    );
    md += &format!(
        "## The {} most frequent of {} patterns\n\n",
        MARKDOWN_MOTIFS.min(report.motifs.len()),
        report.motifs.len()
    );
    md += &motif_table(p, report.motifs.iter().take(MARKDOWN_MOTIFS));
    let candidates: Vec<&MinedMotif> = report.motifs.iter().filter(|m| m.candidate).collect();
    md += &format!(
        "\n## The {} most frequent of {} rule candidates (rigid on every component, missed by sound)\n\n",
        MARKDOWN_MOTIFS.min(candidates.len()),
        candidates.len()
    );
    md += &motif_table(p, candidates.into_iter().take(MARKDOWN_MOTIFS));
    md += "\nPer density: occurrences (distinct minimal sets) and, in parentheses, the systems \
           holding one. *Whole*: occurrences that truth holds in one cluster, of all. \
           *Extended*: whether sound with the extended rule files compresses it.\n";
    md
}

/// A Markdown table of patterns.
fn motif_table<'a>(p: &Parameters, motifs: impl Iterator<Item = &'a MinedMotif>) -> String {
    let heads: Vec<String> = p.densities.iter().map(|rho| format!("rho {rho}")).collect();
    let mut md = format!(
        "| rank | rule | nodes (rod/planar/spatial) | contacts | exact verdict | sound compresses | extended | whole | {} | example (density, seed) | canonical form |\n",
        heads.join(" | ")
    );
    md += &format!(
        "|---:|---|---|---:|---|---|---|---:|{}---|---|\n",
        "---:|".repeat(heads.len())
    );
    let yes = |b: bool| if b { "yes" } else { "no" };
    for m in motifs {
        let cells: Vec<String> = m
            .per_density
            .iter()
            .map(|f| format!("{} ({})", f.occurrences, f.systems))
            .collect();
        md += &format!(
            "| {} | {} | {} ({}/{}/{}) | {} | {}{} | {} | {} | {}/{} | {} | {}, {} | `{}` |\n",
            m.rank,
            m.rule.as_deref().unwrap_or(""),
            m.nodes,
            m.rod_nodes,
            m.planar,
            m.spatial,
            m.contacts,
            m.class,
            m.dof.map_or(String::new(), |d| format!(", {d} DOF")),
            yes(m.sound_compresses),
            m.extended_compresses.map_or("", yes),
            m.whole,
            m.occurrences,
            cells.join(" | "),
            m.example.density,
            m.example.seed,
            m.canonical
        );
    }
    md
}

/// Writes `mined-motifs.{json,csv,md}` into `dir`, atomically.
pub fn write(report: &Report, dir: &Path) -> Result<()> {
    output::write_atomic(
        &dir.join("mined-motifs.json"),
        serde_json::to_string_pretty(report).expect("reports serialize") + "\n",
    )?;
    output::write_atomic(&dir.join("mined-motifs.csv"), csv(report))?;
    output::write_atomic(&dir.join("mined-motifs.md"), markdown(report))
}
