//! The search in one system: the clusters truth holds that the engine's
//! quotient splits, seed pairs in them, the balls grown around those and
//! the minimal sets the balls shrink to, within the caps of [`Search`].

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustc_hash::{FxHashMap, FxHashSet};
use serde::{Deserialize, Serialize};

use super::quotient::{Probe, Quotient, pattern_of};
use crate::engine::{Compression, run_seed};
use crate::pattern::Pattern;
use crate::rule_file;
use crate::truth::Offset;
use crate::truth::{Topology, Truth};
use crate::{Error, Result};

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
    ///
    /// [`MAX_PATTERN_NODES`]: crate::pattern::MAX_PATTERN_NODES
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
