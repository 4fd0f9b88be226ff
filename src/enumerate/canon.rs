//! Canonical labelling by partition refinement and individualization, in
//! the manner of McKay's nauty: equitable refinement, a search tree whose
//! leaves are discrete partitions, node invariants (refinement traces) to
//! prune subtrees that cannot hold the canonical leaf, and automorphisms found
//! on the way to prune subtrees equivalent to explored ones. The automorphisms
//! found generate the whole group, so the orbits it reports are exact.
//!
//! The graph is reached only through [`Adjacency`], so one search serves the
//! generator's 16-bit rows and arbitrary [`crate::graph::ContactGraph`]s.

use std::cmp::Ordering;

/// What the search needs from a graph: neighbour counts into a vertex set and
/// the relabelled adjacency as a certificate.
pub(crate) trait Adjacency {
    /// A set of vertices.
    type Set;
    fn order(&self) -> usize;
    fn empty_set(&self) -> Self::Set;
    fn clear(&self, s: &mut Self::Set);
    fn insert(&self, s: &mut Self::Set, v: usize);
    /// Number of neighbours of `u` in `s`.
    fn count_in(&self, u: usize, s: &Self::Set) -> u32;
    /// Words per certificate row.
    fn row_words(&self) -> usize;
    /// Writes the adjacency of the graph relabelled by `inv` (old vertex ->
    /// new index): row `i` (of `row_words` words) is the neighbourhood of the
    /// vertex `lab[i]`, as a bitset over new indices.
    fn certificate(&self, lab: &[u32], inv: &[u32], out: &mut [u64]);
}

/// Adjacency rows as single-word masks, for graphs that fit a word.
macro_rules! word_rows {
    ($name:ident, $word:ty, $what:literal) => {
        #[doc = $what]
        #[derive(Clone, Copy)]
        pub(crate) struct $name<'a> {
            pub rows: &'a [$word],
        }

        impl Adjacency for $name<'_> {
            type Set = $word;

            #[inline]
            fn order(&self) -> usize {
                self.rows.len()
            }
            #[inline]
            fn empty_set(&self) -> $word {
                0
            }
            #[inline]
            fn clear(&self, s: &mut $word) {
                *s = 0;
            }
            #[inline]
            fn insert(&self, s: &mut $word, v: usize) {
                *s |= 1 << v;
            }
            #[inline]
            fn count_in(&self, u: usize, s: &$word) -> u32 {
                (self.rows[u] & *s).count_ones()
            }
            #[inline]
            fn row_words(&self) -> usize {
                1
            }
            #[inline]
            fn certificate(&self, lab: &[u32], inv: &[u32], out: &mut [u64]) {
                for (o, &u) in out.iter_mut().zip(lab) {
                    let mut row = self.rows[u as usize];
                    let mut r = 0u64;
                    while row != 0 {
                        r |= 1 << inv[row.trailing_zeros() as usize];
                        row &= row - 1;
                    }
                    *o = r;
                }
            }
        }
    };
}

word_rows!(
    Rows16,
    u16,
    "Rows of at most 16 vertices: the generator's graphs."
);
word_rows!(
    Rows64,
    u64,
    "Rows of at most 64 vertices: motifs and patterns."
);

/// Adjacency rows as multi-word bitsets: any order.
pub(crate) struct DenseRows {
    n: usize,
    words: usize,
    bits: Vec<u64>,
}

impl DenseRows {
    pub fn new(n: usize, edges: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let words = n.div_ceil(64).max(1);
        let mut bits = vec![0u64; n * words];
        for (a, b) in edges {
            bits[a * words + b / 64] |= 1 << (b % 64);
            bits[b * words + a / 64] |= 1 << (a % 64);
        }
        DenseRows { n, words, bits }
    }

    fn row(&self, u: usize) -> &[u64] {
        &self.bits[u * self.words..(u + 1) * self.words]
    }
}

impl Adjacency for DenseRows {
    type Set = Vec<u64>;

    fn order(&self) -> usize {
        self.n
    }
    fn empty_set(&self) -> Vec<u64> {
        vec![0; self.words]
    }
    fn clear(&self, s: &mut Vec<u64>) {
        s.iter_mut().for_each(|w| *w = 0);
    }
    fn insert(&self, s: &mut Vec<u64>, v: usize) {
        s[v / 64] |= 1 << (v % 64);
    }
    fn count_in(&self, u: usize, s: &Vec<u64>) -> u32 {
        self.row(u)
            .iter()
            .zip(s)
            .map(|(a, b)| (a & b).count_ones())
            .sum()
    }
    fn row_words(&self) -> usize {
        self.words
    }
    fn certificate(&self, lab: &[u32], inv: &[u32], out: &mut [u64]) {
        let w = self.words;
        out.iter_mut().for_each(|x| *x = 0);
        for (i, &u) in lab.iter().enumerate() {
            let out_row = &mut out[i * w..(i + 1) * w];
            for (k, &word) in self.row(u as usize).iter().enumerate() {
                let mut word = word;
                while word != 0 {
                    let j = inv[k * 64 + word.trailing_zeros() as usize] as usize;
                    out_row[j / 64] |= 1 << (j % 64);
                    word &= word - 1;
                }
            }
        }
    }
}

/// The canonical order of a coloured graph (colours ascending, compared as
/// given): position `i` of the canonical graph is vertex `result[i]`.
pub(crate) fn canonical_order<'c, G: Adjacency>(
    canon: &'c mut Canon,
    g: &G,
    colour: &[u32],
) -> &'c [u32] {
    canon.set_colours(g, colour);
    let mut set = g.empty_set();
    let mut trace = 0;
    canon.refine(g, &mut set, &mut trace, None);
    canon.search(g, &mut set, trace, false);
    canon.canonical_lab()
}

/// Outcome of a search below one node: finished, or abandon every subtree
/// up to the node at the given level (an automorphism showed the current
/// subtree to be the image of an explored one).
enum Step {
    Done,
    Abort(usize),
}

/// Reusable workspace of the search; allocation-free once sized.
#[derive(Default)]
pub(crate) struct Canon {
    n: usize,
    words: usize,
    /// The current ordered partition: `lab[p]` is the vertex at position `p`,
    /// `pos` its inverse, and `end[p]` one past the last position of the cell
    /// starting at `p` (meaningful at cell starts only).
    lab: Vec<u32>,
    pos: Vec<u32>,
    end: Vec<u32>,
    cells: usize,
    /// Start of the last cell.
    last_start: usize,
    /// Refinement queue of cell starts (FIFO) and its membership flags.
    queue: Vec<u32>,
    queued: Vec<bool>,
    count: Vec<u32>,
    scratch: Vec<u32>,
    tmp_lab: Vec<u32>,
    tmp_count: Vec<u32>,
    /// Partitions saved per search level (`lab`, `pos`, `end`, cells, last start).
    saved: Vec<u32>,
    saved_meta: Vec<(usize, usize)>,
    /// Search state per level.
    path: Vec<u32>,
    traces: Vec<u64>,
    eq_first: Vec<bool>,
    cmp_best: Vec<Ordering>,
    /// First and best leaves.
    first_lab: Vec<u32>,
    first_path: Vec<u32>,
    first_traces: Vec<u64>,
    first_cert: Vec<u64>,
    first_len: usize,
    have_first: bool,
    best_lab: Vec<u32>,
    best_path: Vec<u32>,
    best_traces: Vec<u64>,
    best_cert: Vec<u64>,
    best_len: usize,
    cert: Vec<u64>,
    inv: Vec<u32>,
    /// Orbits (union-find) of the stabilizer of the first path's first `j`
    /// vertices, for each level `j` of the first path: `orb[j * n + v]`. By
    /// hand, in one buffer reset in place: petgraph's `UnionFind` has no
    /// reset and would allocate per level in each of millions of searches.
    orb: Vec<u32>,
    /// Generators found, `n` entries each, when requested.
    gens: Vec<u32>,
    keep_gens: bool,
    explored: Vec<u32>,
}

impl Canon {
    pub fn new() -> Self {
        Self::default()
    }

    fn size_for(&mut self, n: usize, words: usize) {
        self.n = n;
        self.words = words;
        if self.lab.len() < n {
            self.lab.resize(n, 0);
            self.pos.resize(n, 0);
            self.end.resize(n + 1, 0);
            self.queued.resize(n + 1, false);
            self.count.resize(n, 0);
            self.scratch.resize(n + 1, 0);
            self.tmp_lab.resize(n, 0);
            self.tmp_count.resize(n, 0);
            self.inv.resize(n, 0);
            self.first_lab.resize(n, 0);
            self.best_lab.resize(n, 0);
        }
        let levels = n + 1;
        if self.saved_meta.len() < levels {
            self.saved_meta.resize(levels, (0, 0));
            self.path.resize(levels, 0);
            self.traces.resize(levels, 0);
            self.eq_first.resize(levels, false);
            self.cmp_best.resize(levels, Ordering::Equal);
            self.first_path.resize(levels, 0);
            self.first_traces.resize(levels, 0);
            self.best_path.resize(levels, 0);
            self.best_traces.resize(levels, 0);
        }
        if self.orb.len() < n {
            self.orb.resize(n, 0);
        }
        let cert_len = n * words;
        if self.cert.len() < cert_len {
            self.cert.resize(cert_len, 0);
            self.first_cert.resize(cert_len, 0);
            self.best_cert.resize(cert_len, 0);
        }
    }

    /// Sets the initial partition: cells in the order given by `colour`
    /// (ascending), vertices of a cell in index order.
    pub fn set_colours<G: Adjacency>(&mut self, g: &G, colour: &[u32]) {
        let n = g.order();
        self.size_for(n, g.row_words());
        for (p, l) in self.lab[..n].iter_mut().enumerate() {
            *l = p as u32;
        }
        self.lab[..n].sort_by_key(|&v| (colour[v as usize], v));
        self.cells = 0;
        let mut start = 0;
        while start < n {
            let c = colour[self.lab[start] as usize];
            let mut stop = start + 1;
            while stop < n && colour[self.lab[stop] as usize] == c {
                stop += 1;
            }
            self.end[start] = stop as u32;
            self.last_start = start;
            self.cells += 1;
            start = stop;
        }
        for p in 0..n {
            self.pos[self.lab[p] as usize] = p as u32;
        }
        self.queue.clear();
        self.queued[..=n].iter_mut().for_each(|q| *q = false);
        let mut start = 0;
        while start < n {
            self.queue.push(start as u32);
            self.queued[start] = true;
            start = self.end[start] as usize;
        }
    }

    /// Sets the partition `[rest | last]` with `last` (a 16-bit vertex mask,
    /// non-empty) as the final cell: the generator's candidate cell.
    pub fn set_last_cell(&mut self, n: usize, last: u16) {
        self.size_for(n, 1);
        let mut a = 0;
        let mut b = n - last.count_ones() as usize;
        let split = b;
        for v in 0..n {
            if last >> v & 1 == 1 {
                self.lab[b] = v as u32;
                self.pos[v] = b as u32;
                b += 1;
            } else {
                self.lab[a] = v as u32;
                self.pos[v] = a as u32;
                a += 1;
            }
        }
        self.queue.clear();
        self.queued[..=n].iter_mut().for_each(|q| *q = false);
        if split > 0 {
            self.end[0] = split as u32;
            self.cells = 2;
            self.queue.push(0);
            self.queued[0] = true;
        } else {
            self.cells = 1;
        }
        self.end[split] = n as u32;
        self.last_start = split;
        self.queue.push(split as u32);
        self.queued[split] = true;
    }

    pub fn is_discrete(&self) -> bool {
        self.cells == self.n
    }

    /// Position of the start of the last cell of the current partition.
    pub fn last_cell(&self) -> (usize, usize) {
        (self.last_start, self.n)
    }

    /// Refines the current partition to the coarsest equitable one below it,
    /// folding what happens into `trace` (an isomorphism invariant). With
    /// `watch`, stops early and returns false as soon as that vertex leaves
    /// the last cell.
    pub fn refine<G: Adjacency>(
        &mut self,
        g: &G,
        set: &mut G::Set,
        trace: &mut u64,
        watch: Option<usize>,
    ) -> bool {
        let n = self.n;
        let mut head = 0;
        while head < self.queue.len() && self.cells < n {
            let ws = self.queue[head] as usize;
            head += 1;
            self.queued[ws] = false;
            let we = self.end[ws] as usize;
            g.clear(set);
            for p in ws..we {
                g.insert(set, self.lab[p] as usize);
            }
            *trace = mix(*trace, (ws as u64) << 32 | we as u64);
            let mut cs = 0;
            while cs < n {
                let ce = self.end[cs] as usize;
                if ce - cs > 1 {
                    self.split(g, set, cs, ce, trace);
                    if let Some(w) = watch
                        && (self.pos[w] as usize) < self.last_start
                    {
                        self.clear_queue(head);
                        return false;
                    }
                }
                cs = ce;
            }
        }
        self.clear_queue(head);
        *trace = mix(*trace, self.cells as u64);
        true
    }

    fn clear_queue(&mut self, head: usize) {
        for &s in &self.queue[head..] {
            self.queued[s as usize] = false;
        }
        self.queue.clear();
    }

    /// Splits the cell `[cs, ce)` by neighbour counts into `set`, pieces in
    /// ascending count order (ties keep their relative order).
    #[inline]
    fn split<G: Adjacency>(&mut self, g: &G, set: &G::Set, cs: usize, ce: usize, trace: &mut u64) {
        let mut lo = u32::MAX;
        let mut hi = 0;
        for p in cs..ce {
            let c = g.count_in(self.lab[p] as usize, set);
            self.count[p] = c;
            lo = lo.min(c);
            hi = hi.max(c);
        }
        if lo == hi {
            return;
        }
        let len = ce - cs;
        // Counting sort by count, stable in position; counts are at most n.
        let range = (hi - lo + 1) as usize;
        let bucket = &mut self.scratch[..range];
        bucket.iter_mut().for_each(|b| *b = 0);
        for p in cs..ce {
            bucket[(self.count[p] - lo) as usize] += 1;
        }
        let mut acc = 0;
        for b in bucket.iter_mut() {
            let c = *b;
            *b = acc;
            acc += c;
        }
        for p in cs..ce {
            let c = self.count[p];
            let b = &mut bucket[(c - lo) as usize];
            self.tmp_lab[*b as usize] = self.lab[p];
            self.tmp_count[*b as usize] = c;
            *b += 1;
        }
        for k in 0..len {
            let v = self.tmp_lab[k];
            self.lab[cs + k] = v;
            self.pos[v as usize] = (cs + k) as u32;
        }
        let was_queued = self.queued[cs];
        let mut largest = (0, cs);
        let mut start = cs;
        let mut pieces = 0;
        for k in 1..=len {
            if k == len || self.tmp_count[k] != self.tmp_count[k - 1] {
                let stop = cs + k;
                self.end[start] = stop as u32;
                let c = u64::from(self.tmp_count[k - 1]);
                *trace = mix(*trace, c << 40 | (start as u64) << 20 | stop as u64);
                if stop - start > largest.0 {
                    largest = (stop - start, start);
                }
                pieces += 1;
                if ce == self.n {
                    self.last_start = start;
                }
                start = stop;
            }
        }
        self.cells += pieces - 1;
        // Queue the pieces: all of them if the cell was queued (its start
        // stays queued), else all but the largest (Hopcroft's trick).
        let mut p = cs;
        while p < ce {
            if !self.queued[p] && (was_queued || p != largest.1) {
                self.queued[p] = true;
                self.queue.push(p as u32);
            }
            p = self.end[p] as usize;
        }
    }

    /// Individualizes the vertex at position `p` of the cell starting at `cs`.
    fn individualize(&mut self, cs: usize, p: usize) {
        let ce = self.end[cs] as usize;
        let (a, b) = (self.lab[cs], self.lab[p]);
        self.lab[cs] = b;
        self.lab[p] = a;
        self.pos[b as usize] = cs as u32;
        self.pos[a as usize] = p as u32;
        self.end[cs] = cs as u32 + 1;
        self.end[cs + 1] = ce as u32;
        self.cells += 1;
        if ce == self.n {
            self.last_start = cs + 1;
        }
        self.queue.clear();
        self.queue.push(cs as u32);
        self.queued[cs] = true;
    }

    fn save(&mut self, level: usize) {
        let n = self.n;
        let base = 3 * n * level;
        // Levels are allocated as the search reaches them: deep searches are
        // rare, and a level costs 3n words.
        if self.saved.len() < base + 3 * n {
            self.saved.resize(base + 3 * n, 0);
        }
        self.saved[base..base + n].copy_from_slice(&self.lab[..n]);
        self.saved[base + n..base + 2 * n].copy_from_slice(&self.pos[..n]);
        self.saved[base + 2 * n..base + 3 * n].copy_from_slice(&self.end[..n]);
        self.saved_meta[level] = (self.cells, self.last_start);
    }

    fn restore(&mut self, level: usize) {
        let n = self.n;
        let base = 3 * n * level;
        self.lab[..n].copy_from_slice(&self.saved[base..base + n]);
        self.pos[..n].copy_from_slice(&self.saved[base + n..base + 2 * n]);
        self.end[..n].copy_from_slice(&self.saved[base + 2 * n..base + 3 * n]);
        (self.cells, self.last_start) = self.saved_meta[level];
    }

    /// Runs the search from the current (refined) partition, whose trace is
    /// `trace`. Afterwards [`Canon::canonical_lab`] is the canonical order,
    /// [`Canon::same_orbit`] answers orbit questions and, with `keep_gens`,
    /// [`Canon::generators`] lists generators of the automorphism group of
    /// the coloured graph.
    pub fn search<G: Adjacency>(&mut self, g: &G, set: &mut G::Set, trace: u64, keep_gens: bool) {
        let n = self.n;
        self.keep_gens = keep_gens;
        self.gens.clear();
        self.have_first = false;
        self.traces[0] = trace;
        self.eq_first[0] = true;
        self.cmp_best[0] = Ordering::Equal;
        for v in 0..n {
            self.orb[v] = v as u32;
        }
        self.node(g, set, 0, true);
    }

    /// The canonical order: position `i` of the canonical graph is vertex
    /// `canonical_lab()[i]`.
    pub fn canonical_lab(&self) -> &[u32] {
        &self.best_lab[..self.n]
    }

    /// Whether `a` and `b` lie in one orbit of the automorphism group.
    pub fn same_orbit(&self, a: usize, b: usize) -> bool {
        find(&self.orb[..self.n], a) == find(&self.orb[..self.n], b)
    }

    /// Generators found by the last search (`keep_gens`), `n` images each.
    pub fn generators(&self) -> impl Iterator<Item = &[u32]> {
        self.gens.chunks_exact(self.n.max(1))
    }

    fn node<G: Adjacency>(
        &mut self,
        g: &G,
        set: &mut G::Set,
        level: usize,
        on_first: bool,
    ) -> Step {
        if self.cells == self.n {
            return self.leaf(g, level);
        }
        // Target: the first non-singleton cell.
        let mut cs = 0;
        while self.end[cs] as usize - cs == 1 {
            cs = self.end[cs] as usize;
        }
        let ce = self.end[cs] as usize;
        self.save(level);
        let base = 3 * self.n * level;
        let explored_mark = self.explored.len();
        for idx in cs..ce {
            let w = self.saved[base + idx];
            // The first child is never skipped; by the time another child of a
            // first-path node comes up, the first leaf exists.
            if on_first && idx != cs {
                let orb = &self.orb[level * self.n..(level + 1) * self.n];
                let rw = find(orb, w as usize);
                if self.explored[explored_mark..]
                    .iter()
                    .any(|&u| find(orb, u as usize) == rw)
                {
                    continue;
                }
            }
            self.explored.push(w);
            if idx != cs {
                self.restore(level);
            }
            let p = self.pos[w as usize] as usize;
            self.individualize(cs, p);
            let mut t = self.traces[level];
            self.refine(g, set, &mut t, None);
            let child = level + 1;
            self.path[child] = w;
            self.traces[child] = t;
            let first_child = on_first && idx == cs;
            if self.have_first {
                self.eq_first[child] = self.eq_first[level]
                    && child <= self.first_len
                    && t == self.first_traces[child];
                self.cmp_best[child] = match self.cmp_best[level] {
                    Ordering::Equal if child <= self.best_len => t.cmp(&self.best_traces[child]),
                    Ordering::Equal => Ordering::Less,
                    other => other,
                };
                if !self.eq_first[child] && self.cmp_best[child] == Ordering::Less {
                    continue;
                }
            } else {
                self.eq_first[child] = true;
                self.cmp_best[child] = Ordering::Equal;
            }
            if let Step::Abort(d) = self.node(g, set, child, first_child)
                && d < level
            {
                self.explored.truncate(explored_mark);
                return Step::Abort(d);
            }
        }
        self.explored.truncate(explored_mark);
        Step::Done
    }

    fn leaf<G: Adjacency>(&mut self, g: &G, level: usize) -> Step {
        let n = self.n;
        let len = n * self.words;
        for p in 0..n {
            self.inv[self.lab[p] as usize] = p as u32;
        }
        g.certificate(&self.lab[..n], &self.inv[..n], &mut self.cert[..len]);
        if !self.have_first {
            self.have_first = true;
            self.first_len = level;
            self.best_len = level;
            self.first_lab[..n].copy_from_slice(&self.lab[..n]);
            self.best_lab[..n].copy_from_slice(&self.lab[..n]);
            self.first_cert[..len].copy_from_slice(&self.cert[..len]);
            self.best_cert[..len].copy_from_slice(&self.cert[..len]);
            self.first_traces[..=level].copy_from_slice(&self.traces[..=level]);
            self.best_traces[..=level].copy_from_slice(&self.traces[..=level]);
            self.first_path[..=level].copy_from_slice(&self.path[..=level]);
            self.best_path[..=level].copy_from_slice(&self.path[..=level]);
            // Orbits of every first-path level start trivial.
            if self.orb.len() < n * level.max(1) {
                self.orb.resize(n * level.max(1), 0);
            }
            for j in 1..level {
                for v in 0..n {
                    self.orb[j * n + v] = v as u32;
                }
            }
            return Step::Done;
        }
        if self.eq_first[level]
            && level == self.first_len
            && self.cert[..len] == self.first_cert[..len]
        {
            self.automorphism(true);
            return Step::Abort(common_prefix(
                &self.path[1..=level],
                &self.first_path[1..=level],
            ));
        }
        let better = match self.cmp_best[level] {
            Ordering::Greater => Ordering::Greater,
            Ordering::Less => Ordering::Less,
            Ordering::Equal if level == self.best_len => {
                self.cert[..len].cmp(&self.best_cert[..len])
            }
            Ordering::Equal => Ordering::Less,
        };
        match better {
            Ordering::Greater => {
                self.best_len = level;
                self.best_lab[..n].copy_from_slice(&self.lab[..n]);
                self.best_cert[..len].copy_from_slice(&self.cert[..len]);
                self.best_traces[..=level].copy_from_slice(&self.traces[..=level]);
                self.best_path[..=level].copy_from_slice(&self.path[..=level]);
                // The current path is now the best one: its other subtrees
                // compare against it from here on.
                self.cmp_best[..=level]
                    .iter_mut()
                    .for_each(|c| *c = Ordering::Equal);
                Step::Done
            }
            Ordering::Equal => {
                self.automorphism(false);
                Step::Abort(common_prefix(
                    &self.path[1..=level],
                    &self.best_path[1..=level],
                ))
            }
            Ordering::Less => Step::Done,
        }
    }

    /// Records the automorphism mapping the first (or best) leaf to the
    /// current one, merging orbits at every first-path level it stabilizes.
    fn automorphism(&mut self, from_first: bool) {
        let n = self.n;
        let from = if from_first {
            &self.first_lab
        } else {
            &self.best_lab
        };
        // gamma(from[i]) = lab[i]; keep it in `inv` (no longer needed).
        for (&f, &l) in from[..n].iter().zip(&self.lab[..n]) {
            self.inv[f as usize] = l;
        }
        if self.keep_gens {
            self.gens.extend_from_slice(&self.inv[..n]);
        }
        for j in 0..self.first_len {
            if j > 0 {
                let f = self.first_path[j] as usize;
                if self.inv[f] as usize != f {
                    break;
                }
            }
            let orb = &mut self.orb[j * n..(j + 1) * n];
            for v in 0..n {
                union(orb, v, self.inv[v] as usize);
            }
        }
    }
}

/// Length of the common prefix of two paths.
fn common_prefix(a: &[u32], b: &[u32]) -> usize {
    a.iter().zip(b).take_while(|(x, y)| x == y).count()
}

#[inline]
fn mix(h: u64, x: u64) -> u64 {
    (h ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29) ^ (h >> 7)
}

fn find(uf: &[u32], mut v: usize) -> usize {
    while uf[v] as usize != v {
        v = uf[v] as usize;
    }
    v
}

fn union(uf: &mut [u32], a: usize, b: usize) {
    let ra = find(uf, a);
    let rb = find(uf, b);
    if ra < rb {
        uf[rb] = ra as u32;
    } else if rb < ra {
        uf[ra] = rb as u32;
    }
}
