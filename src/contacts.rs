//! Which rods touch: robust segment–segment distance, an O(N) cell list with
//! periodic images, the contact graph, and its statistics (DESIGN §1).

use nalgebra::Vector3;
use serde::Serialize;

use crate::rods::RodSystem;
use crate::{Error, Result};

/// One contact between two rods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The two rods, `rods[0] < rods[1]`.
    pub rods: [u32; 2],
    /// Axis parameter of the closest point on each rod, in `[-1/2, 1/2]`.
    pub params: [f64; 2],
    /// Contact point: midpoint of the two closest points, wrapped into the primary box.
    pub point: Vector3<f64>,
    /// Periodic image of `rods[1]` that touches `rods[0]`: its center is
    /// shifted by `shift * L`.
    pub shift: [i32; 3],
}

/// Closest points of two segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// Squared distance between the closest points.
    pub dist2: f64,
    /// Parameter on the first segment.
    pub s: f64,
    /// Parameter on the second segment.
    pub t: f64,
}

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
                return Err(Error::Parameter(format!("edge {k} is a self-loop on node {a}")));
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

    /// The edge joining `a` and `b`, if any.
    pub fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        let nb = self.neighbors(a);
        nb.binary_search_by_key(&b, |&(v, _)| v)
            .ok()
            .map(|k| nb[k].1)
    }
}

/// Contact statistics of a contact graph (DESIGN §1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactStats {
    /// Mean contact number over all rods, `2 * contacts / N`.
    pub c0: f64,
    /// Mean degree within the largest connected component.
    pub c1: f64,
    /// Mean degree within the largest connected component of the 2-core.
    pub c2: f64,
    /// Average local clustering coefficient over all rods (rods of degree < 2 count 0).
    pub clustering: f64,
}
