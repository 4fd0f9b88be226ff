//! Generation of connected graphs (MODEL §7).
//!
//! Graphs are made by McKay's canonical augmentation, vertex by vertex. A
//! connected graph always has a vertex whose removal leaves it connected (a
//! non-cut vertex), so every intermediate graph is connected: a graph `H` is
//! accepted from its parent `G = H - v` only when the new vertex `v` lies in
//! the orbit of `H`'s canonical deletion vertex: a non-cut vertex of
//! maximum degree, among those one with the largest sum of neighbour
//! degrees, among those the last one in the canonical labelling (the
//! `canon` submodule). Parents extend by one neighbourhood per orbit of
//! their automorphism group, so each isomorphism class comes out exactly
//! once. Most candidates are settled by these invariants alone; refinement
//! runs only on ties, and the full search only when refinement leaves one.
//!
//! Filters prune whole subtrees and never change the set: with `rem`
//! vertices still to come, a vertex of degree `d` ends with at most
//! `d + rem`, the edge count only grows (by at least one per vertex, the
//! graphs being connected) and grows by at most `k` when a `k`-th vertex is
//! added. Work is spread over rayon's threads by subtrees below a fixed
//! level, and their outputs are concatenated in order, so the order of the
//! graphs does not depend on the thread count.

use std::io::{self, Write};
use std::sync::OnceLock;

use rayon::prelude::*;

use super::canon::{Canon, Rows16};
use super::small::{GraphFilter, MAX_ORDER, SmallGraph};
use crate::graph::ContactGraph;
use crate::{Error, Result};

/// All connected graphs on `n` vertices passing `filter`, one per
/// isomorphism class, in generation order.
pub fn connected_graphs(n: usize, filter: &GraphFilter) -> Result<Vec<ContactGraph>> {
    Ok(connected_small_graphs(n, filter)?
        .iter()
        .map(SmallGraph::to_contact_graph)
        .collect())
}

/// [`connected_graphs`] as [`SmallGraph`]s (34 bytes each).
pub fn connected_small_graphs(n: usize, filter: &GraphFilter) -> Result<Vec<SmallGraph>> {
    let mut out = Vec::new();
    run(n, filter, Vec::new, |chunk: Vec<SmallGraph>| {
        out.extend(chunk);
        Ok::<(), Error>(())
    })?;
    Ok(out)
}

/// The number of connected graphs on `n` vertices passing `filter`, without
/// keeping them.
pub fn count_connected(n: usize, filter: &GraphFilter) -> Result<u64> {
    let mut total = 0;
    run(
        n,
        filter,
        || 0u64,
        |c| {
            total += c;
            Ok::<(), Error>(())
        },
    )?;
    Ok(total)
}

/// Calls `f` on every graph of [`connected_graphs`], in the same order, on
/// the calling thread (generation runs on rayon's threads, a batch of
/// subtrees at a time, holding at most about 64 MB of graphs). Returns the
/// number of graphs.
pub fn for_each_connected(
    n: usize,
    filter: &GraphFilter,
    mut f: impl FnMut(&SmallGraph),
) -> Result<u64> {
    let mut total = 0;
    run(n, filter, Vec::new, |chunk: Vec<SmallGraph>| {
        total += chunk.len() as u64;
        chunk.iter().for_each(&mut f);
        Ok::<(), Error>(())
    })?;
    Ok(total)
}

/// Calls `f` on every graph of [`connected_graphs`] from rayon's threads,
/// in no particular order, keeping nothing. Returns the number of graphs.
pub fn par_for_each_connected(
    n: usize,
    filter: &GraphFilter,
    f: impl Fn(&SmallGraph) + Sync,
) -> Result<u64> {
    let f = &f;
    let mut total = 0;
    run(
        n,
        filter,
        || Calls { f, count: 0 },
        |c| {
            total += c.count;
            Ok::<(), Error>(())
        },
    )?;
    Ok(total)
}

/// Folds every graph of [`connected_graphs`] into accumulators on rayon's
/// threads, one accumulator per subtree of the generation tree (made by
/// `init`), and hands them to `consume` in generation order: the graphs of
/// the first accumulator come first, each accumulator saw its graphs in
/// generation order. Nothing is kept but the accumulators, so work on each
/// graph (the audit's verdicts) runs as it is generated, with no list of
/// all graphs and no barrier between chunks of them. Returns the number of
/// graphs.
pub fn par_fold_connected<T: Send>(
    n: usize,
    filter: &GraphFilter,
    init: impl Fn() -> T + Sync + Send,
    fold: impl Fn(&mut T, &SmallGraph) + Sync,
    mut consume: impl FnMut(T),
) -> Result<u64> {
    let fold = &fold;
    let mut total = 0;
    run(
        n,
        filter,
        || Fold {
            acc: init(),
            fold,
            count: 0,
        },
        |f| {
            total += f.count;
            consume(f.acc);
            Ok::<(), Error>(())
        },
    )?;
    Ok(total)
}

/// Writes the graphs of [`connected_graphs`] as graph6 lines, in the same
/// order, and returns how many. An order outside `1..=MAX_ORDER` is an
/// `InvalidInput` error.
pub fn write_connected_graph6(
    n: usize,
    filter: &GraphFilter,
    w: &mut impl Write,
) -> io::Result<u64> {
    let mut total = 0;
    let result = run(n, filter, Graph6Lines::default, |lines| {
        total += lines.count;
        w.write_all(&lines.bytes)
    });
    match result {
        Ok(()) => Ok(total),
        Err(RunError::Order(e)) => Err(io::Error::new(io::ErrorKind::InvalidInput, e.to_string())),
        Err(RunError::Consumer(e)) => Err(e),
    }
}

/// Where a generator puts the graphs it accepts.
trait Sink: Send {
    fn emit(&mut self, g: &SmallGraph);
    /// Memory the sink holds, which sizes the batches.
    fn bytes(&self) -> usize {
        0
    }
}

impl Sink for u64 {
    #[inline]
    fn emit(&mut self, _: &SmallGraph) {
        *self += 1;
    }
}

impl Sink for Vec<SmallGraph> {
    #[inline]
    fn emit(&mut self, g: &SmallGraph) {
        self.push(*g);
    }
    fn bytes(&self) -> usize {
        self.len() * std::mem::size_of::<SmallGraph>()
    }
}

#[derive(Default)]
struct Graph6Lines {
    bytes: Vec<u8>,
    count: u64,
}

impl Sink for Graph6Lines {
    #[inline]
    fn emit(&mut self, g: &SmallGraph) {
        g.write_graph6(&mut self.bytes);
        self.bytes.push(b'\n');
        self.count += 1;
    }
    fn bytes(&self) -> usize {
        self.bytes.len()
    }
}

struct Calls<'f, F> {
    f: &'f F,
    count: u64,
}

impl<F: Fn(&SmallGraph) + Sync> Sink for Calls<'_, F> {
    #[inline]
    fn emit(&mut self, g: &SmallGraph) {
        (self.f)(g);
        self.count += 1;
    }
}

struct Fold<'f, T, F> {
    acc: T,
    fold: &'f F,
    count: u64,
}

impl<T: Send, F: Fn(&mut T, &SmallGraph) + Sync> Sink for Fold<'_, T, F> {
    #[inline]
    fn emit(&mut self, g: &SmallGraph) {
        (self.fold)(&mut self.acc, g);
        self.count += 1;
    }
}

enum RunError<E> {
    Order(Error),
    Consumer(E),
}

impl From<RunError<Error>> for Error {
    fn from(e: RunError<Error>) -> Self {
        match e {
            RunError::Order(e) | RunError::Consumer(e) => e,
        }
    }
}

/// Output a batch of subtrees may hold before it is handed on, in bytes.
const BATCH_BYTES: usize = 64 << 20;

/// Generates everything, one sink per subtree, and hands the sinks to
/// `consume` in generation order.
///
/// Subtrees go to rayon in batches. A batch's size follows the output its
/// predecessor produced per subtree, so that a batch holds about
/// [`BATCH_BYTES`]; sinks that hold nothing (counters) get one batch.
fn run<S: Sink, E>(
    n: usize,
    filter: &GraphFilter,
    make: impl Fn() -> S + Sync + Send,
    mut consume: impl FnMut(S) -> std::result::Result<(), E>,
) -> std::result::Result<(), RunError<E>> {
    if n == 0 || n > MAX_ORDER {
        return Err(RunError::Order(Error::Parameter(format!(
            "graphs are enumerated on 1 to {MAX_ORDER} vertices, got {n}"
        ))));
    }
    // Subtrees rooted at this order are the tasks: thousands of small ones
    // for the orders that take long (11117 for n = 10), at most 261080.
    let split = if n <= 6 { n } else { (n - 2).min(9) };
    let mut head = Worker::new(n, *filter, make(), Some(split));
    head.start();
    consume(head.sink).map_err(RunError::Consumer)?;
    let tasks = head.tasks;
    let threads = rayon::current_num_threads().max(1);
    let mut batch = 4 * threads;
    let mut next = 0;
    while next < tasks.len() {
        let end = tasks.len().min(next.saturating_add(batch));
        let sinks: Vec<S> = tasks[next..end]
            .par_iter()
            .map_init(
                || Worker::new(n, *filter, make(), None),
                |w, task| {
                    w.sink = make();
                    w.gens.clear();
                    w.gens.extend_from_slice(&task.gens);
                    let node = task.node;
                    w.extend(&node, 0..task.gens.len());
                    std::mem::replace(&mut w.sink, make())
                },
            )
            .collect();
        let per_task = sinks.iter().map(Sink::bytes).sum::<usize>() / (end - next);
        batch = match per_task {
            0 => usize::MAX,
            b => (BATCH_BYTES / b).max(4 * threads),
        };
        next = end;
        for s in sinks {
            consume(s).map_err(RunError::Consumer)?;
        }
    }
    Ok(())
}

/// A graph in the generation tree with what its extension needs.
#[derive(Clone, Copy)]
struct Node {
    g: SmallGraph,
    deg: [u8; MAX_ORDER],
    edges: usize,
    rigid: bool,
}

impl Node {
    fn order(&self) -> usize {
        self.g.order()
    }
}

/// A subtree for a worker thread: its root and the root's automorphism
/// group generators.
struct Task {
    node: Node,
    gens: Vec<[u8; MAX_ORDER]>,
}

/// Subsets of `0..k` for each `k`, sorted by size, with where each size starts.
struct Subsets {
    sets: Vec<Vec<u16>>,
    starts: Vec<Vec<usize>>,
}

fn subsets() -> &'static Subsets {
    static TABLE: OnceLock<Subsets> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut sets = Vec::new();
        let mut starts = Vec::new();
        for k in 0..MAX_ORDER {
            let mut s: Vec<u16> = (0..1u32 << k).map(|x| x as u16).collect();
            s.sort_by_key(|&x| (x.count_ones(), x));
            let st: Vec<usize> = (0..=k + 1)
                .map(|size| s.partition_point(|&x| (x.count_ones() as usize) < size))
                .collect();
            sets.push(s);
            starts.push(st);
        }
        Subsets { sets, starts }
    })
}

/// Connectivity facts about a parent: its non-cut vertices and, for each
/// cut vertex, the components left by removing it.
struct CutInfo {
    non_cut: u16,
    cut: u16,
    comps: [[u16; MAX_ORDER]; MAX_ORDER],
    n_comps: [u8; MAX_ORDER],
}

impl CutInfo {
    fn of(g: &SmallGraph) -> Self {
        let k = g.order();
        let all = ((1u32 << k) - 1) as u16;
        let mut info = CutInfo {
            non_cut: 0,
            cut: 0,
            comps: [[0; MAX_ORDER]; MAX_ORDER],
            n_comps: [0; MAX_ORDER],
        };
        for u in 0..k {
            let mut left = all & !(1 << u);
            let mut c = 0;
            while left != 0 {
                let comp = component(g, left & left.wrapping_neg(), left);
                info.comps[u][c] = comp;
                c += 1;
                left &= !comp;
            }
            info.n_comps[u] = c as u8;
            if c <= 1 {
                info.non_cut |= 1 << u;
            } else {
                info.cut |= 1 << u;
            }
        }
        info
    }

    /// Whether adding a vertex joined to `x` makes cut vertex `u` a non-cut one.
    #[inline]
    fn joined(&self, u: usize, x: u16) -> bool {
        self.comps[u][..self.n_comps[u] as usize]
            .iter()
            .all(|&c| c & x != 0)
    }
}

/// The component of `start` within the vertex set `within`.
#[inline]
fn component(g: &SmallGraph, start: u16, within: u16) -> u16 {
    let mut seen = start;
    let mut frontier = start;
    while frontier != 0 {
        let mut next = 0;
        while frontier != 0 {
            next |= g.rows[frontier.trailing_zeros() as usize];
            frontier &= frontier - 1;
        }
        frontier = next & within & !seen;
        seen |= frontier;
    }
    seen
}

/// One thread's generator: workspace, generator stack and sink.
struct Worker<S> {
    n: usize,
    filter: GraphFilter,
    canon: Canon,
    /// Union-find over neighbourhood masks, for orbits of the parent's group.
    /// By hand: only the masks a node tries are reset, where petgraph's
    /// `UnionFind` would rebuild all 2^15 entries at every node of the search.
    uf: Vec<u16>,
    /// Neighbourhoods still to try, for every node on the current path.
    reps: Vec<u16>,
    /// Automorphism group generators of the nodes on the current path.
    gens: Vec<[u8; MAX_ORDER]>,
    sink: S,
    /// With `Some(k)`, nodes of order `k` are collected as tasks instead of
    /// being extended.
    split: Option<usize>,
    tasks: Vec<Task>,
}

impl<S: Sink> Worker<S> {
    fn new(n: usize, filter: GraphFilter, sink: S, split: Option<usize>) -> Self {
        Worker {
            n,
            filter,
            canon: Canon::new(),
            uf: vec![0; 1 << (MAX_ORDER - 1)],
            reps: Vec::new(),
            gens: Vec::new(),
            sink,
            split,
            tasks: Vec::new(),
        }
    }

    /// Generates from the one-vertex graph.
    fn start(&mut self) {
        let root = Node {
            g: SmallGraph {
                n: 1,
                rows: [0; MAX_ORDER],
            },
            deg: [0; MAX_ORDER],
            edges: 0,
            rigid: true,
        };
        // Extensions check the filter on the way; the root alone has none.
        if self.n > 1 || self.filter.accepts(&root.g) {
            self.accept(root, 0);
        }
    }

    /// A node has been accepted with `ngens` generators on top of the stack:
    /// output it, queue it as a task, or extend it.
    fn accept(&mut self, node: Node, ngens: usize) {
        let k = node.order();
        let top = self.gens.len();
        if k == self.n {
            debug_assert!(self.filter.accepts(&node.g));
            self.sink.emit(&node.g);
        } else if self.split == Some(k) {
            self.tasks.push(Task {
                node,
                gens: self.gens[top - ngens..].to_vec(),
            });
        } else {
            self.extend(&node, top - ngens..top);
        }
        self.gens.truncate(top - ngens);
    }

    /// Every accepted child of `node` (whose generators are `gens`).
    fn extend(&mut self, node: &Node, gens: std::ops::Range<usize>) {
        let n = self.n;
        let k = node.order();
        let rem = n - k - 1;
        let f = self.filter;
        // Degree bounds: a vertex of degree `d` can still gain `rem + 1`.
        let mut must = 0u16;
        for u in 0..k {
            let d = node.deg[u] as usize;
            if d + rem + 1 < f.min_degree {
                return;
            }
            if d + rem < f.min_degree {
                must |= 1 << u;
            }
        }
        let mut xlb = 1
            .max(f.min_degree.saturating_sub(rem))
            .max(must.count_ones() as usize);
        let mut xub = k;
        // Edge bounds: later vertices add at least 1 and at most their order.
        let future_max: usize = (k + 1..n).sum();
        xlb = xlb.max(f.min_edges.saturating_sub(node.edges + future_max));
        match f.max_edges.checked_sub(node.edges + rem) {
            Some(room) => xub = xub.min(room),
            None => return,
        }
        if xlb > xub {
            return;
        }
        let info = CutInfo::of(&node.g);
        let mut deg_mask = [0u16; MAX_ORDER + 1];
        for u in 0..k {
            deg_mask[node.deg[u] as usize] |= 1 << u;
        }
        let nc = info.non_cut;
        let dm = (0..k)
            .filter(|&u| nc >> u & 1 == 1)
            .map(|u| node.deg[u] as usize)
            .max()
            .unwrap_or(0);
        let top = nc & deg_mask[dm];
        // Non-cut vertices of degree >= 2: a leaf may only hang on them.
        let heavy_nc = nc & !deg_mask[0] & !deg_mask[1];
        let allowed = |x: u16, s: usize| -> bool {
            if x & must != must {
                return false;
            }
            if s == 1 {
                // The new leaf must out-degree every other non-cut vertex;
                // its neighbour turns into a cut vertex (unless k == 1).
                heavy_nc & !x == 0
            } else {
                s > dm || (s == dm && x & top == 0)
            }
        };
        let table = subsets();
        let sets = &table.sets[k];
        let starts = &table.starts[k];
        let rigid = node.rigid || gens.is_empty();
        if !rigid {
            for s in xlb..=xub {
                for &x in &sets[starts[s]..starts[s + 1]] {
                    if allowed(x, s) {
                        self.uf[x as usize] = x;
                    }
                }
            }
            for gi in gens.clone() {
                let perm = self.gens[gi];
                for s in xlb..=xub {
                    for &x in &sets[starts[s]..starts[s + 1]] {
                        if !allowed(x, s) {
                            continue;
                        }
                        let mut y = 0u16;
                        let mut b = x;
                        while b != 0 {
                            y |= 1 << perm[b.trailing_zeros() as usize];
                            b &= b - 1;
                        }
                        union_masks(&mut self.uf, x, y);
                    }
                }
            }
        }
        // The representatives go on a stack first: the children's own
        // extensions reuse the union-find.
        let base = self.reps.len();
        for s in xlb..=xub {
            for &x in &sets[starts[s]..starts[s + 1]] {
                if allowed(x, s) && (rigid || find_mask(&mut self.uf, x) == x) {
                    self.reps.push(x);
                }
            }
        }
        for i in base..self.reps.len() {
            let x = self.reps[i];
            self.try_child(node, &info, &deg_mask, x, x.count_ones() as usize);
        }
        self.reps.truncate(base);
    }

    /// Builds the child of `node` with the new vertex joined to `x` and
    /// accepts it if the new vertex is its canonical deletion vertex.
    fn try_child(
        &mut self,
        node: &Node,
        info: &CutInfo,
        deg_mask: &[u16; MAX_ORDER + 1],
        x: u16,
        s: usize,
    ) {
        let k = node.order();
        let v = k;
        let vbit = 1u16 << v;
        // Competitors: non-cut vertices of the child with degree s.
        let mut ties = if s == 1 && k > 1 {
            info.non_cut & !x & deg_mask[1]
        } else {
            info.non_cut & ((deg_mask[s] & !x) | (deg_mask[s - 1] & x))
        };
        if s >= 2 {
            let mut cut = info.cut;
            while cut != 0 {
                let u = cut.trailing_zeros() as usize;
                cut &= cut - 1;
                let du = node.deg[u] as usize + (x >> u & 1) as usize;
                if du >= s && info.joined(u, x) {
                    if du > s {
                        return;
                    }
                    ties |= 1 << u;
                }
            }
        }
        let mut child = *node;
        child.g.n += 1;
        child.g.rows[v] = x;
        let mut b = x;
        while b != 0 {
            let u = b.trailing_zeros() as usize;
            b &= b - 1;
            child.g.rows[u] |= vbit;
            child.deg[u] += 1;
        }
        child.deg[v] = s as u8;
        child.edges += s;
        // Among the tied vertices only those with the largest sum of
        // neighbour degrees stay candidates: a cheap invariant that settles
        // most ties before any refinement.
        if ties != 0 {
            let score = |u: usize| -> u32 {
                let mut r = child.g.rows[u];
                let mut t = 0;
                while r != 0 {
                    t += u32::from(child.deg[r.trailing_zeros() as usize]);
                    r &= r - 1;
                }
                t
            };
            let fv = score(v);
            let mut kept = 0;
            let mut b = ties;
            while b != 0 {
                let u = b.trailing_zeros() as usize;
                b &= b - 1;
                let fu = score(u);
                if fu > fv {
                    return;
                }
                if fu == fv {
                    kept |= 1 << u;
                }
            }
            ties = kept;
        }
        let last = k + 1 == self.n;
        let n1 = k + 1;
        let rows = Rows16 {
            rows: &child.g.rows[..n1],
        };
        if last && ties == 0 {
            child.rigid = true;
            self.accept(child, 0);
            return;
        }
        // Refine the partition [rest | candidates]; the deletion vertex is
        // taken from the last cell.
        self.canon.set_last_cell(n1, ties | vbit);
        let mut set = 0u16;
        let mut trace = 0u64;
        if !self.canon.refine(&rows, &mut set, &mut trace, Some(v)) {
            return;
        }
        if self.canon.is_discrete() {
            child.rigid = true;
            self.accept(child, 0);
            return;
        }
        let (ls, le) = self.canon.last_cell();
        if last && le - ls == 1 {
            self.accept(child, 0);
            return;
        }
        self.canon.search(&rows, &mut set, trace, !last);
        let c = self.canon.canonical_lab()[n1 - 1] as usize;
        if !self.canon.same_orbit(c, v) {
            return;
        }
        let before = self.gens.len();
        if !last {
            for g in self.canon.generators() {
                let mut p = [0u8; MAX_ORDER];
                for (i, &img) in g.iter().enumerate() {
                    p[i] = img as u8;
                }
                self.gens.push(p);
            }
        }
        let ngens = self.gens.len() - before;
        child.rigid = ngens == 0;
        self.accept(child, ngens);
    }
}

#[inline]
fn find_mask(uf: &mut [u16], mut x: u16) -> u16 {
    while uf[x as usize] != x {
        let p = uf[x as usize];
        uf[x as usize] = uf[p as usize];
        x = p;
    }
    x
}

#[inline]
fn union_masks(uf: &mut [u16], a: u16, b: u16) {
    let ra = find_mask(uf, a);
    let rb = find_mask(uf, b);
    if ra < rb {
        uf[rb as usize] = ra;
    } else if rb < ra {
        uf[ra as usize] = rb;
    }
}
