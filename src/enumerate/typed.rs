//! Typed multigraph patterns for mixed motifs (MODEL §7): nodes that are
//! rods or bodies, bounded contact multiplicities, and optionally every way
//! of letting a body's contacts share its rods.
//!
//! Patterns are made in two stages. First the typed multigraphs, one per
//! isomorphism class: each connected simple graph on the nodes (the support)
//! gets node kinds and edge multiplicities, kept only when lexicographically
//! smallest under the support's automorphisms. Then rod labels: one rod per
//! contact end, or, with rod sharing, every valid set partition of each
//! body's contact ends, deduplicated by [`canonical_pattern`].
//!
//! A pattern's isomorphism class is that of a coloured simple graph with
//! vertices for nodes, shared rods and contacts (see `Workspace::canonical`);
//! the canonical labelling of that graph gives the canonical pattern.

use rustc_hash::FxHashSet;

use rayon::prelude::*;

use super::canon::{Canon, DenseRows, Rows64, canonical_order};
use super::connected::connected_small_graphs;
use super::small::GraphFilter;
use crate::pattern::{MAX_PATTERN_CONTACTS, NodeKind, Pattern, PatternContact};
use crate::{Error, Result};

/// Most nodes [`typed_patterns`] accepts: node permutations are listed
/// outright, and the number of patterns explodes long before this.
pub const MAX_TYPED_NODES: usize = 7;

/// Largest multiplicity bound [`typed_patterns`] accepts.
pub const MAX_MULTIPLICITY: usize = 8;

/// What [`typed_patterns`] enumerates.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TypedFilter {
    /// Exactly this many nodes.
    pub nodes: usize,
    /// Most contacts between a rod and a body (rod–rod is always at most 1).
    pub max_mult_rod_body: usize,
    /// Most contacts between two bodies.
    pub max_mult_body_body: usize,
    /// Kinds a node may have.
    pub kinds: Vec<NodeKind>,
    /// Fewest contacts at every node, counted with multiplicity.
    pub min_contacts_per_node: usize,
    /// Keep only patterns that pass Maxwell's count ([`Pattern::maxwell`]).
    pub maxwell: bool,
    /// Also let contact ends on a body share rods, in every valid way.
    pub rod_sharing: bool,
}

impl TypedFilter {
    /// The defaults: rod–body at most 2, body–body at most 3, every kind,
    /// at least 2 contacts per node, no Maxwell filter, no rod sharing.
    pub fn new(nodes: usize) -> Self {
        TypedFilter {
            nodes,
            max_mult_rod_body: 2,
            max_mult_body_body: 3,
            kinds: vec![NodeKind::Rod, NodeKind::Planar, NodeKind::Spatial],
            min_contacts_per_node: 2,
            maxwell: false,
            rod_sharing: false,
        }
    }

    fn max_mult(&self, a: NodeKind, b: NodeKind) -> usize {
        match (a.is_body(), b.is_body()) {
            (false, false) => 1,
            (true, true) => self.max_mult_body_body,
            _ => self.max_mult_rod_body,
        }
    }

    fn check(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Parameter(m));
        if self.nodes == 0 || self.nodes > MAX_TYPED_NODES {
            return bad(format!(
                "typed patterns have 1 to {MAX_TYPED_NODES} nodes, got {}",
                self.nodes
            ));
        }
        if self.max_mult_rod_body > MAX_MULTIPLICITY || self.max_mult_body_body > MAX_MULTIPLICITY {
            return bad(format!(
                "multiplicity bounds are at most {MAX_MULTIPLICITY}, got rod-body {} and body-body {}",
                self.max_mult_rod_body, self.max_mult_body_body
            ));
        }
        if self.kinds.is_empty() {
            return bad("no node kind allowed".into());
        }
        let most = self.nodes * (self.nodes - 1) / 2
            * self.max_mult_rod_body.max(self.max_mult_body_body).max(1);
        if most > MAX_PATTERN_CONTACTS {
            return bad(format!(
                "{} nodes with multiplicities up to {} could need {most} contacts, more than a pattern holds ({MAX_PATTERN_CONTACTS})",
                self.nodes,
                self.max_mult_rod_body.max(self.max_mult_body_body)
            ));
        }
        Ok(())
    }
}

/// Every connected typed pattern the filter allows, one per isomorphism
/// class, each in canonical form ([`canonical_pattern`]), ordered by
/// contact count, then kinds, then contacts. Rod labellings of different
/// typed multigraphs are worked on in parallel.
pub fn typed_patterns(filter: &TypedFilter) -> Result<Vec<Pattern>> {
    filter.check()?;
    let bases = multigraphs(filter)?;
    let per_base: Vec<Vec<Pattern>> = bases
        .par_iter()
        .map_init(Workspace::default, |ws, base| {
            if filter.rod_sharing {
                let mut found = FxHashSet::default();
                sharings(base, ws, &mut found);
                found.into_iter().collect()
            } else {
                vec![ws.canonical(base)]
            }
        })
        .collect();
    // Different typed multigraphs give non-isomorphic patterns: no
    // deduplication across them.
    let mut out: Vec<Pattern> = per_base.into_iter().flatten().collect();
    out.sort_by(|a, b| {
        (a.contacts.len(), &a.kinds, &a.contacts).cmp(&(b.contacts.len(), &b.kinds, &b.contacts))
    });
    Ok(out)
}

/// The typed multigraphs the filter allows, one per isomorphism class, as
/// patterns with one rod per contact end.
fn multigraphs(filter: &TypedFilter) -> Result<Vec<Pattern>> {
    let n = filter.nodes;
    let mut kinds: Vec<NodeKind> = filter.kinds.clone();
    kinds.sort_unstable();
    kinds.dedup();
    let mut bases = Vec::new();
    let supports = connected_small_graphs(n, &GraphFilter::all())?;
    let perms = permutations(n);
    for support in &supports {
        let edges: Vec<(usize, usize)> = support
            .edges()
            .iter()
            .map(|&[a, b]| (a as usize, b as usize))
            .collect();
        let automorphisms: Vec<&Vec<usize>> = perms
            .iter()
            .filter(|p| edges.iter().all(|&(a, b)| support.has_edge(p[a], p[b])))
            .collect();
        let mut assignment = vec![0usize; n];
        loop {
            // One kind assignment per orbit of the support's automorphisms.
            let smallest = automorphisms.iter().all(|p| {
                let image = (0..n).map(|i| assignment[p[i]]);
                assignment.iter().copied().le(image)
            });
            if smallest {
                let node_kinds: Vec<NodeKind> = assignment.iter().map(|&k| kinds[k]).collect();
                let stabilizer: Vec<Vec<usize>> = automorphisms
                    .iter()
                    .filter(|p| (0..n).all(|i| assignment[p[i]] == assignment[i]))
                    .map(|p| edge_permutation(&edges, p))
                    .collect();
                multiplicities(filter, &node_kinds, &edges, &stabilizer, &mut bases);
            }
            if !next_tuple(&mut assignment, kinds.len()) {
                break;
            }
        }
    }
    Ok(bases)
}

/// Every multiplicity vector on the support edges, one per orbit of
/// `stabilizer` (edge permutations preserving the kinds), that passes the
/// filter.
fn multiplicities(
    filter: &TypedFilter,
    kinds: &[NodeKind],
    edges: &[(usize, usize)],
    stabilizer: &[Vec<usize>],
    bases: &mut Vec<Pattern>,
) {
    let n = kinds.len();
    let bound: Vec<usize> = edges
        .iter()
        .map(|&(a, b)| filter.max_mult(kinds[a], kinds[b]))
        .collect();
    if bound.contains(&0) {
        return;
    }
    let mut mult = vec![1usize; edges.len()];
    let mut contacts_at = vec![0usize; n];
    loop {
        let smallest = stabilizer.iter().all(|p| {
            // The image's entry e is the multiplicity of the edge p maps to e.
            let image = (0..edges.len()).map(|e| mult[p[e]]);
            mult.iter().copied().le(image)
        });
        if smallest {
            contacts_at.iter_mut().for_each(|c| *c = 0);
            for (&(a, b), &m) in edges.iter().zip(&mult) {
                contacts_at[a] += m;
                contacts_at[b] += m;
            }
            if contacts_at
                .iter()
                .all(|&c| c >= filter.min_contacts_per_node)
            {
                let base = labelled(kinds, edges, &mult);
                if !filter.maxwell || base.maxwell() {
                    bases.push(base);
                }
            }
        }
        if !next_bounded(&mut mult, &bound) {
            break;
        }
    }
}

/// The pattern with the given multiplicities, one rod per contact end on a
/// body, labelled in contact order.
fn labelled(kinds: &[NodeKind], edges: &[(usize, usize)], mult: &[usize]) -> Pattern {
    let mut next = vec![0u8; kinds.len()];
    let mut label = |i: usize| {
        if kinds[i].is_body() {
            next[i] += 1;
            next[i] - 1
        } else {
            0
        }
    };
    let mut contacts = Vec::new();
    for (&(a, b), &m) in edges.iter().zip(mult) {
        for _ in 0..m {
            let rods = [label(a), label(b)];
            contacts.push(PatternContact {
                nodes: [a as u8, b as u8],
                rods,
            });
        }
    }
    Pattern {
        kinds: kinds.to_vec(),
        contacts,
    }
}

/// Every valid way of letting the contact ends on each body share rods.
fn sharings(base: &Pattern, ws: &mut Workspace, found: &mut FxHashSet<Pattern>) {
    // Contact ends on bodies, in contact order.
    let ends: Vec<(usize, usize)> = base
        .contacts
        .iter()
        .enumerate()
        .flat_map(|(k, _)| (0..2).map(move |s| (k, s)))
        .filter(|&(k, s)| base.kinds[base.contacts[k].nodes[s] as usize].is_body())
        .collect();
    let mut p = base.clone();
    let mut used = vec![0u8; base.kinds.len()];
    assign(&mut p, &ends, 0, &mut used, ws, found);
}

/// Labels `ends[i..]` as restricted growth strings per body.
///
/// Parallel contacts (same two nodes, consecutive in the list) must come
/// out with strictly increasing label pairs. Strict because two rods touch
/// at most once, and increasing loses no class: the lexicographically
/// smallest labelling of a class, over relabellings and permutations of
/// parallel contacts, has that form, since swapping two adjacent parallel
/// contacts out of order would make it smaller (the smaller pair's labels
/// already occur before them). Only contacts between the same two nodes
/// can repeat a pair of rods, so this is also the whole validity check.
fn assign(
    p: &mut Pattern,
    ends: &[(usize, usize)],
    i: usize,
    used: &mut [u8],
    ws: &mut Workspace,
    found: &mut FxHashSet<Pattern>,
) {
    let Some(&(k, s)) = ends.get(i) else {
        found.insert(ws.canonical(p));
        return;
    };
    let node = p.contacts[k].nodes[s] as usize;
    let complete = match ends.get(i + 1) {
        Some(&(k2, _)) => k2 != k || s == 1,
        None => true,
    };
    for label in 0..=used[node] {
        p.contacts[k].rods[s] = label;
        if complete
            && k > 0
            && p.contacts[k - 1].nodes == p.contacts[k].nodes
            && p.contacts[k - 1].rods >= p.contacts[k].rods
        {
            continue;
        }
        let fresh = label == used[node];
        if fresh {
            used[node] += 1;
        }
        assign(p, ends, i + 1, used, ws, found);
        if fresh {
            used[node] -= 1;
        }
    }
}

/// The canonical form of a pattern: nodes renumbered and rod labels of each
/// node renumbered from 0, so that isomorphic patterns (a node bijection
/// keeping kinds and a rod bijection per node, carrying contacts to
/// contacts) give equal results. Contacts come out with `nodes[0] <
/// nodes[1]`, sorted. A pattern that fails [`Pattern::validate`] has no
/// canonical form and comes back unchanged.
pub fn canonical_pattern(p: &Pattern) -> Pattern {
    if p.validate().is_err() {
        return p.clone();
    }
    // The engine asks for canonical forms of small patterns in its inner
    // loop: a thread's buffers are reused rather than allocated per call.
    thread_local! {
        static WORKSPACE: std::cell::RefCell<Workspace> = std::cell::RefCell::new(Workspace::default());
    }
    WORKSPACE.with(|ws| ws.borrow_mut().canonical(p))
}

/// Buffers for canonical forms, reused across the patterns of a thread.
#[derive(Default)]
struct Workspace {
    canon: Canon,
    /// Contact ends per (node, label), and which of those are shared rods.
    ends: Vec<(u8, u8)>,
    shared: Vec<(u8, u8)>,
    /// Contacts as pairs of attachment vertices, with multiplicities.
    groups: Vec<(usize, usize, u32)>,
    rows: Vec<u64>,
    colour: Vec<u32>,
}

impl Workspace {
    /// The canonical form of a valid pattern.
    ///
    /// The coloured graph labelled here has a vertex per node (coloured by
    /// kind), a vertex per body rod carrying two or more contacts (joined
    /// to its body), and a vertex per class of parallel contacts (coloured
    /// by how many) joined to where the contact attaches at each end: the
    /// shared rod, or else the node itself (a rod node's one rod, or a
    /// body rod of its own). Parallel contacts would be interchangeable
    /// twins; merging them keeps the automorphism groups small.
    fn canonical(&mut self, p: &Pattern) -> Pattern {
        let n = p.n_nodes();
        self.ends.clear();
        self.ends.extend(
            p.contacts
                .iter()
                .flat_map(|c| [(c.nodes[0], c.rods[0]), (c.nodes[1], c.rods[1])]),
        );
        self.ends.sort_unstable();
        self.shared.clear();
        for w in self.ends.windows(2) {
            if w[0] == w[1]
                && p.kinds[w[0].0 as usize].is_body()
                && self.shared.last() != Some(&w[0])
            {
                self.shared.push(w[0]);
            }
        }
        let shared = &self.shared;
        let attach = |node: u8, label: u8| match shared.binary_search(&(node, label)) {
            Ok(r) => n + r,
            Err(_) => node as usize,
        };
        self.groups.clear();
        self.groups.extend(p.contacts.iter().map(|c| {
            let (a, b) = (attach(c.nodes[0], c.rods[0]), attach(c.nodes[1], c.rods[1]));
            (a.min(b), a.max(b), 1)
        }));
        self.groups.sort_unstable();
        self.groups.dedup_by(|later, kept| {
            let same = (later.0, later.1) == (kept.0, kept.1);
            if same {
                kept.2 += 1;
            }
            same
        });
        let first_group = n + shared.len();
        let total = first_group + self.groups.len();
        self.colour.clear();
        self.colour.extend(p.kinds.iter().map(|k| match k {
            NodeKind::Rod => 0,
            NodeKind::Planar => 1,
            NodeKind::Spatial => 2,
        }));
        self.colour.extend(shared.iter().map(|_| 3));
        self.colour.extend(self.groups.iter().map(|g| 3 + g.2));
        let edges = shared
            .iter()
            .enumerate()
            .map(|(r, &(node, _))| (node as usize, n + r))
            .chain(
                self.groups
                    .iter()
                    .enumerate()
                    .flat_map(|(k, g)| [(g.0, first_group + k), (g.1, first_group + k)]),
            );
        let lab = if total <= 64 {
            self.rows.clear();
            self.rows.resize(total, 0);
            for (a, b) in edges {
                self.rows[a] |= 1 << b;
                self.rows[b] |= 1 << a;
            }
            canonical_order(&mut self.canon, &Rows64 { rows: &self.rows }, &self.colour)
        } else {
            let dense = DenseRows::new(total, edges);
            canonical_order(&mut self.canon, &dense, &self.colour)
        };
        // Vertices come by colour: nodes, shared rods, contact classes; each
        // kind of vertex in canonical order.
        let mut new_node = vec![0u8; n];
        let mut kinds = Vec::with_capacity(n);
        for (i, &v) in lab[..n].iter().enumerate() {
            new_node[v as usize] = i as u8;
            kinds.push(p.kinds[v as usize]);
        }
        let mut next = vec![0u8; n];
        let mut rod_label = vec![0u8; shared.len()];
        for &v in &lab[n..first_group] {
            let r = v as usize - n;
            let node = new_node[shared[r].0 as usize] as usize;
            rod_label[r] = next[node];
            next[node] += 1;
        }
        let mut contacts = Vec::with_capacity(p.contacts.len());
        for &v in &lab[first_group..] {
            let (a, b, m) = self.groups[v as usize - first_group];
            for _ in 0..m {
                let mut end = |x: usize| {
                    if x >= n {
                        let node = new_node[shared[x - n].0 as usize];
                        (node, rod_label[x - n])
                    } else {
                        let node = new_node[x];
                        if kinds[node as usize].is_body() {
                            next[node as usize] += 1;
                            (node, next[node as usize] - 1)
                        } else {
                            (node, 0)
                        }
                    }
                };
                let (ea, eb) = (end(a), end(b));
                let (ea, eb) = if ea <= eb { (ea, eb) } else { (eb, ea) };
                contacts.push(PatternContact {
                    nodes: [ea.0, eb.0],
                    rods: [ea.1, eb.1],
                });
            }
        }
        contacts.sort_unstable();
        Pattern { kinds, contacts }
    }
}

/// All permutations of `0..n`, as image lists.
fn permutations(n: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut p: Vec<usize> = (0..n).collect();
    permute(&mut p, 0, &mut out);
    out
}

fn permute(p: &mut Vec<usize>, k: usize, out: &mut Vec<Vec<usize>>) {
    if k == p.len() {
        out.push(p.clone());
        return;
    }
    for i in k..p.len() {
        p.swap(k, i);
        permute(p, k + 1, out);
        p.swap(k, i);
    }
}

/// The permutation a node automorphism induces on the edge list:
/// `result[e]` is the index of the edge mapped onto edge `e`.
fn edge_permutation(edges: &[(usize, usize)], p: &[usize]) -> Vec<usize> {
    let index = |a: usize, b: usize| {
        edges
            .iter()
            .position(|&(x, y)| (x, y) == (a, b) || (x, y) == (b, a))
            .unwrap_or(0)
    };
    let mut result = vec![0; edges.len()];
    for (e, &(a, b)) in edges.iter().enumerate() {
        result[index(p[a], p[b])] = e;
    }
    result
}

/// Advances a tuple over `0..base` in lexicographic order; false at the end.
fn next_tuple(t: &mut [usize], base: usize) -> bool {
    for x in t.iter_mut().rev() {
        *x += 1;
        if *x < base {
            return true;
        }
        *x = 0;
    }
    false
}

/// Advances a tuple with entries in `1..=bound[i]`; false at the end.
fn next_bounded(t: &mut [usize], bound: &[usize]) -> bool {
    for (x, &b) in t.iter_mut().zip(bound).rev() {
        *x += 1;
        if *x <= b {
            return true;
        }
        *x = 1;
    }
    false
}
