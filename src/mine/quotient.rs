//! The engine's nodes as a graph of their own (the *quotient*), truth on
//! sets of them, and the typed pattern of such a set: what the search asks
//! of every set it tries.

use crate::body::{Body, BodyClass};
use crate::graph::ContactGraph;
use crate::pattern::{MAX_PATTERN_NODES, Pattern};
use crate::truth::Offset;
use crate::truth::{self, Topology, TruthOptions};
use crate::{Error, Result};

/// The engine's nodes: bodies (in the compression's order) then free rods.
pub(super) struct Quotient {
    pub(super) node_of: Vec<u32>,
    pub(super) members: Vec<Vec<u32>>,
    pub(super) class: Vec<Option<BodyClass>>,
    pub(super) adj: Vec<Vec<u32>>,
}

impl Quotient {
    pub(super) fn new(graph: &ContactGraph, bodies: &[Body]) -> Self {
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

    pub(super) fn rods(&self, nodes: &[u32]) -> Vec<u32> {
        let mut rods: Vec<u32> = nodes
            .iter()
            .flat_map(|&x| self.members[x as usize].iter().copied())
            .collect();
        rods.sort_unstable();
        rods
    }

    /// Whether the sorted cluster holds every rod of the nodes `held`.
    pub(super) fn holds(&self, cluster: &[u32], held: &[u32]) -> bool {
        held.iter().all(|&x| {
            self.members[x as usize]
                .iter()
                .all(|r| cluster.binary_search(r).is_ok())
        })
    }
}

/// Truth on sets of quotient nodes, counting its calls.
pub(super) struct Probe<'a> {
    topo: &'a Topology<'a>,
    pub(super) q: &'a Quotient,
    opts: TruthOptions,
    /// Each rod's index in the set being built, `u32::MAX` outside it.
    local: Vec<u32>,
    pub(super) calls: usize,
    pub(super) undecided: usize,
}

impl<'a> Probe<'a> {
    pub(super) fn new(topo: &'a Topology<'a>, q: &'a Quotient, seed: u64) -> Self {
        Probe {
            topo,
            q,
            opts: TruthOptions {
                realizations: 1,
                strain: false,
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
        let topo = match self.topo.shifts {
            Some(_) => Topology::periodic(&sub, &shifts).expect("one shift per induced contact"),
            None => Topology::finite(&sub),
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
    pub(super) fn held(&mut self, nodes: &[u32], pair: [u32; 2]) -> Option<Vec<u32>> {
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

/// The typed pattern of a set of quotient nodes: each body with the rods
/// that touch another node of the set, each free rod, and the contacts
/// between different nodes. An error when it is too large for a pattern.
pub(super) fn pattern_of(graph: &ContactGraph, q: &Quotient, nodes: &[u32]) -> Result<Pattern> {
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
