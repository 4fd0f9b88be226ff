//! Small graphs as bitmask rows, the filters that generation applies, and
//! canonical forms.

use crate::graph::{ContactGraph, io};
use crate::{Error, Result};

use super::canon::{Canon, DenseRows, Rows16, Rows64, canonical_order};

/// Largest order the generator handles (adjacency rows are 16-bit masks).
/// The counts decide what is practical: 1.0e9 connected graphs on 11
/// vertices take minutes, 1.6e11 on 12 about a day, larger orders longer.
pub const MAX_ORDER: usize = 16;

/// Filters applied inside generation; a graph is produced iff it passes all.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GraphFilter {
    /// Every vertex has at least this degree.
    pub min_degree: usize,
    /// At least this many edges.
    pub min_edges: usize,
    /// At most this many edges.
    pub max_edges: usize,
}

impl Default for GraphFilter {
    fn default() -> Self {
        Self::all()
    }
}

impl GraphFilter {
    /// No restriction: every connected graph.
    pub fn all() -> Self {
        GraphFilter {
            min_degree: 0,
            min_edges: 0,
            max_edges: usize::MAX,
        }
    }

    /// Maxwell's count for rods only: `3 e >= 5 n - 6`.
    pub fn maxwell_rods(n: usize) -> Self {
        GraphFilter {
            min_edges: maxwell_rod_edges(n),
            ..Self::all()
        }
    }

    /// The same filter with a minimum degree.
    pub fn with_min_degree(self, min_degree: usize) -> Self {
        GraphFilter { min_degree, ..self }
    }

    /// Whether a graph passes (connectivity is not checked here).
    pub fn accepts(&self, g: &SmallGraph) -> bool {
        let e = g.n_edges();
        e >= self.min_edges
            && e <= self.max_edges
            && (0..g.order()).all(|v| g.degree(v) >= self.min_degree)
    }
}

/// The fewest contacts Maxwell's count allows `n` rods: `ceil((5n - 6) / 3)`
/// for `n >= 2`, zero for a single rod.
pub fn maxwell_rod_edges(n: usize) -> usize {
    if n < 2 { 0 } else { (5 * n - 6).div_ceil(3) }
}

/// A graph of at most [`MAX_ORDER`] vertices with bitmask adjacency rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SmallGraph {
    pub(super) n: u8,
    pub(super) rows: [u16; MAX_ORDER],
}

impl SmallGraph {
    /// The graph on `n` vertices without edges.
    pub fn empty(n: usize) -> Result<Self> {
        if n > MAX_ORDER {
            return Err(Error::Parameter(format!(
                "a small graph has at most {MAX_ORDER} vertices, got {n}"
            )));
        }
        Ok(SmallGraph {
            n: n as u8,
            rows: [0; MAX_ORDER],
        })
    }

    /// The same graph as a [`SmallGraph`].
    pub fn from_contact_graph(g: &ContactGraph) -> Result<Self> {
        let mut s = Self::empty(g.n_nodes())?;
        for &[a, b] in g.edges() {
            s.rows[a as usize] |= 1 << b;
            s.rows[b as usize] |= 1 << a;
        }
        Ok(s)
    }

    pub fn order(&self) -> usize {
        self.n as usize
    }

    /// The neighbours of `v` as a bitmask.
    pub fn row(&self, v: usize) -> u16 {
        self.rows[v]
    }

    pub fn has_edge(&self, a: usize, b: usize) -> bool {
        self.rows[a] >> b & 1 == 1
    }

    pub fn degree(&self, v: usize) -> usize {
        self.rows[v].count_ones() as usize
    }

    pub fn n_edges(&self) -> usize {
        self.rows[..self.order()]
            .iter()
            .map(|r| r.count_ones() as usize)
            .sum::<usize>()
            / 2
    }

    /// Edges `[i, j]`, `i < j`, in graph6 bit order (by `j`, then `i`), as
    /// [`crate::graph::io::parse_graph6`] would give them.
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut edges = Vec::with_capacity(self.n_edges());
        for j in 1..self.order() {
            let mut lower = self.rows[j] & ((1u16 << j) - 1);
            while lower != 0 {
                edges.push([lower.trailing_zeros(), j as u32]);
                lower &= lower - 1;
            }
        }
        edges
    }

    pub fn to_contact_graph(&self) -> ContactGraph {
        let mut g = ContactGraph::default();
        // A simple graph from valid rows always builds; the fallback only
        // keeps this total.
        if let Ok(built) = ContactGraph::new(self.order(), self.edges()) {
            g = built;
        }
        g
    }

    /// Appends the graph6 string and nothing else.
    pub fn write_graph6(&self, out: &mut Vec<u8>) {
        let n = self.order();
        out.push(63 + n as u8);
        let mut acc = 0u128;
        for j in 1..n {
            // Row j's lower bits, vertex 0 first: graph6's column order.
            let lower = self.rows[j] & ((1u16 << j) - 1);
            acc = acc << j | u128::from(lower.reverse_bits() >> (16 - j));
        }
        let bits = n * n.saturating_sub(1) / 2;
        let bytes = bits.div_ceil(6);
        acc <<= bytes * 6 - bits;
        for b in (0..bytes).rev() {
            out.push(63 + (acc >> (6 * b) & 63) as u8);
        }
    }

    pub fn graph6(&self) -> String {
        let mut out = Vec::with_capacity(24);
        self.write_graph6(&mut out);
        // Every byte is in '?'..='~'.
        out.into_iter().map(char::from).collect()
    }

    /// The graph with vertex `lab[i]` renamed `i`.
    fn relabelled(&self, lab: &[u32]) -> SmallGraph {
        let mut inv = [0u8; MAX_ORDER];
        for (i, &v) in lab.iter().enumerate() {
            inv[v as usize] = i as u8;
        }
        let mut out = SmallGraph {
            n: self.n,
            rows: [0; MAX_ORDER],
        };
        for (i, &v) in lab.iter().enumerate() {
            let mut row = self.rows[v as usize];
            while row != 0 {
                out.rows[i] |= 1 << inv[row.trailing_zeros() as usize];
                row &= row - 1;
            }
        }
        out
    }

    /// The canonical form: isomorphic graphs give equal results.
    pub fn canonical(&self) -> SmallGraph {
        let n = self.order();
        if n == 0 {
            return *self;
        }
        let g = Rows16 {
            rows: &self.rows[..n],
        };
        let mut canon = Canon::new();
        canonical_order(&mut canon, &g, &[0; MAX_ORDER][..n]);
        self.relabelled(canon.canonical_lab())
    }
}

/// The graph6 string of the canonical form of `g`: two graphs get the same
/// string iff they are isomorphic. Meant for motifs; time and memory grow
/// at least as `n²` (the string itself has `n² / 12` bytes).
pub fn canonical_graph6(g: &ContactGraph) -> String {
    if let Ok(small) = SmallGraph::from_contact_graph(g) {
        return small.canonical().graph6();
    }
    let n = g.n_nodes();
    let pairs = || g.edges().iter().map(|&[a, b]| (a as usize, b as usize));
    let colour = vec![0; n];
    let mut canon = Canon::new();
    let lab = if n <= 64 {
        let mut rows = vec![0u64; n];
        for (a, b) in pairs() {
            rows[a] |= 1 << b;
            rows[b] |= 1 << a;
        }
        canonical_order(&mut canon, &Rows64 { rows: &rows }, &colour)
    } else {
        canonical_order(&mut canon, &DenseRows::new(n, pairs()), &colour)
    };
    let mut inv = vec![0u32; n];
    for (i, &v) in lab.iter().enumerate() {
        inv[v as usize] = i as u32;
    }
    let edges = g
        .edges()
        .iter()
        .map(|&[a, b]| [inv[a as usize], inv[b as usize]])
        .collect();
    let relabelled = ContactGraph::new(n, edges).expect("a relabelling of a simple graph");
    io::to_graph6(&relabelled)
}
