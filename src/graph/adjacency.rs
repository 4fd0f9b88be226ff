//! The contact graph's storage: nodes and edges in compressed adjacency
//! form, built once from a list of pairs and read by every algorithm.

use crate::contacts::Contact;
use crate::{Error, Result};

/// An undirected simple graph in compressed adjacency form: node `i`'s
/// neighbours are `adjacency[offsets[i]..offsets[i+1]]`, each with the index
/// of the edge that joins them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ContactGraph {
    n: usize,
    edges: Vec<[u32; 2]>,
    offsets: Vec<u32>,
    adjacency: Vec<(u32, u32)>,
}

impl ContactGraph {
    /// Builds the graph; rejects self-loops, repeated pairs and out-of-range ends.
    pub fn new(n: usize, edges: Vec<[u32; 2]>) -> Result<Self> {
        if n > u32::MAX as usize / 2 {
            return Err(Error::Parameter(format!("{n} nodes are too many")));
        }
        let mut degree = vec![0u32; n + 1];
        for (k, &[a, b]) in edges.iter().enumerate() {
            if a as usize >= n || b as usize >= n {
                return Err(Error::Parameter(format!(
                    "edge {k} ({a}, {b}) names a node outside 0..{n}"
                )));
            }
            if a == b {
                return Err(Error::Parameter(format!(
                    "edge {k} is a self-loop on node {a}"
                )));
            }
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
        let mut offsets = Vec::with_capacity(n + 1);
        let mut acc = 0u32;
        for d in &degree[..n] {
            offsets.push(acc);
            acc += d;
        }
        offsets.push(acc);
        let mut fill = offsets.clone();
        let mut adjacency = vec![(0u32, 0u32); acc as usize];
        for (k, &[a, b]) in edges.iter().enumerate() {
            adjacency[fill[a as usize] as usize] = (b, k as u32);
            fill[a as usize] += 1;
            adjacency[fill[b as usize] as usize] = (a, k as u32);
            fill[b as usize] += 1;
        }
        for i in 0..n {
            let nb = &mut adjacency[offsets[i] as usize..offsets[i + 1] as usize];
            nb.sort_unstable();
            if let Some(w) = nb.windows(2).find(|w| w[0].0 == w[1].0) {
                return Err(Error::Parameter(format!(
                    "nodes {i} and {} are joined twice: a pair of rods touches at most once",
                    w[0].0
                )));
            }
        }
        Ok(ContactGraph {
            n,
            edges,
            offsets,
            adjacency,
        })
    }

    /// The graph of a list of detected contacts.
    pub fn from_contacts(n: usize, contacts: &[Contact]) -> Self {
        Self::new(n, contacts.iter().map(|c| c.rods).collect())
            .expect("detected contacts form a simple graph")
    }

    pub fn n_nodes(&self) -> usize {
        self.n
    }

    pub fn n_edges(&self) -> usize {
        self.edges.len()
    }

    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Neighbours of `i` with the joining edge, sorted by neighbour.
    pub fn neighbors(&self, i: u32) -> &[(u32, u32)] {
        let i = i as usize;
        &self.adjacency[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    pub fn degree(&self, i: u32) -> usize {
        self.neighbors(i).len()
    }

    /// The 2-core: nodes with fewer than two neighbours left are peeled
    /// until none is (petgraph 0.8 has no k-core algorithm). Returns each
    /// node's membership, and the peeled nodes in order with their degree
    /// when peeled (0 or 1).
    pub fn two_core(&self) -> (Vec<bool>, Vec<(u32, u8)>) {
        let n = self.n;
        let mut degree: Vec<usize> = (0..n as u32).map(|i| self.degree(i)).collect();
        let mut alive = vec![true; n];
        let mut stack: Vec<u32> = (0..n as u32).filter(|&i| degree[i as usize] < 2).collect();
        let mut peeled = Vec::new();
        while let Some(i) = stack.pop() {
            if !alive[i as usize] {
                continue;
            }
            alive[i as usize] = false;
            peeled.push((i, degree[i as usize] as u8));
            for &(j, _) in self.neighbors(i) {
                let j = j as usize;
                if alive[j] {
                    degree[j] -= 1;
                    if degree[j] == 1 {
                        stack.push(j as u32);
                    }
                }
            }
        }
        (alive, peeled)
    }

    /// The edge joining `a` and `b`, if any.
    pub fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        let nb = self.neighbors(a);
        nb.binary_search_by_key(&b, |&(v, _)| v)
            .ok()
            .map(|k| nb[k].1)
    }
}
