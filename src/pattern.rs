//! Motifs as typed patterns: nodes that are rods or bodies (planar or
//! spatial), and contacts that say which rod of each node they sit on
//! (MODEL §6). The enumerator produces them, the rank decides them, rule
//! files store them and the engine matches them.

use serde::{Deserialize, Serialize};

use crate::body::{Body, BodyClass};
use crate::graph::ContactGraph;
use crate::{Error, Result};

/// What a pattern node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NodeKind {
    /// A single rod: 5 degrees of freedom, all its contacts on one line.
    Rod,
    /// A rigid body whose rods lie in one plane.
    Planar,
    /// A rigid body in general position.
    Spatial,
}

impl NodeKind {
    pub fn is_body(self) -> bool {
        self != NodeKind::Rod
    }

    /// The body class of a body kind.
    pub fn class(self) -> Option<BodyClass> {
        match self {
            NodeKind::Rod => None,
            NodeKind::Planar => Some(BodyClass::Planar),
            NodeKind::Spatial => Some(BodyClass::Spatial),
        }
    }

    /// Degrees of freedom of a free node: 5 for a rod, 6 for a body.
    pub fn dof(self) -> usize {
        if self.is_body() { 6 } else { 5 }
    }
}

/// A contact between two pattern nodes, with the rod it sits on in each
/// (rod labels are local to a node; a rod node has only rod 0). Two contacts
/// of a body with the same label share that rod: they are collinear.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PatternContact {
    pub nodes: [u8; 2],
    pub rods: [u8; 2],
}

/// A typed contact pattern.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Pattern {
    pub kinds: Vec<NodeKind>,
    pub contacts: Vec<PatternContact>,
}

/// Largest pattern the toolkit handles (nodes, and contacts).
pub const MAX_PATTERN_NODES: usize = 24;
pub const MAX_PATTERN_CONTACTS: usize = 96;

impl Pattern {
    /// A rods-only pattern from a simple graph.
    pub fn from_graph(g: &ContactGraph) -> Result<Self> {
        if g.n_nodes() > MAX_PATTERN_NODES || g.n_edges() > MAX_PATTERN_CONTACTS {
            return Err(Error::Parameter(format!(
                "a pattern has at most {MAX_PATTERN_NODES} nodes and {MAX_PATTERN_CONTACTS} contacts, got {} and {}",
                g.n_nodes(),
                g.n_edges()
            )));
        }
        Ok(Pattern {
            kinds: vec![NodeKind::Rod; g.n_nodes()],
            contacts: g
                .edges()
                .iter()
                .map(|&[a, b]| PatternContact {
                    nodes: [a as u8, b as u8],
                    rods: [0, 0],
                })
                .collect(),
        })
    }

    /// Checks the pattern is well formed: sizes, node indices, no self-contact,
    /// rods carry only rod label 0, two rods touch at most once and a body's
    /// rod touches another rod at most once.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Parameter(m));
        if self.kinds.is_empty() || self.kinds.len() > MAX_PATTERN_NODES {
            return bad(format!(
                "a pattern has 1 to {MAX_PATTERN_NODES} nodes, got {}",
                self.kinds.len()
            ));
        }
        if self.contacts.len() > MAX_PATTERN_CONTACTS {
            return bad(format!(
                "a pattern has at most {MAX_PATTERN_CONTACTS} contacts, got {}",
                self.contacts.len()
            ));
        }
        // The first contact repeating an earlier one's pair of rods, found
        // by sorting the pairs (a hash set per pattern costs more than the
        // rest of a small pattern's checks).
        let key = |c: &PatternContact| {
            let (x, y) = ((c.nodes[0], c.rods[0]), (c.nodes[1], c.rods[1]));
            (x.min(y), x.max(y))
        };
        let mut keys: Vec<_> = self
            .contacts
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let (x, y) = key(c);
                (x, y, k)
            })
            .collect();
        keys.sort_unstable();
        let first_repeat = keys
            .windows(2)
            .filter(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
            .map(|w| w[1].2)
            .min();
        for (k, c) in self.contacts.iter().enumerate() {
            let [a, b] = c.nodes;
            if a as usize >= self.kinds.len() || b as usize >= self.kinds.len() {
                return bad(format!(
                    "contact {k} names a node outside 0..{}",
                    self.kinds.len()
                ));
            }
            if a == b {
                return bad(format!("contact {k} joins node {a} to itself"));
            }
            for side in 0..2 {
                if self.kinds[c.nodes[side] as usize] == NodeKind::Rod && c.rods[side] != 0 {
                    return bad(format!(
                        "contact {k}: node {} is a rod and has only rod 0",
                        c.nodes[side]
                    ));
                }
            }
            if first_repeat == Some(k) {
                return bad(format!(
                    "contact {k} repeats rod {} of node {a} touching rod {} of node {b}: two rods touch at most once",
                    c.rods[0], c.rods[1]
                ));
            }
        }
        Ok(())
    }

    pub fn n_nodes(&self) -> usize {
        self.kinds.len()
    }

    pub fn n_rods(&self) -> usize {
        self.kinds.iter().filter(|k| !k.is_body()).count()
    }

    pub fn n_bodies(&self) -> usize {
        self.kinds.len() - self.n_rods()
    }

    /// Maxwell's necessary count for rigidity: `3 contacts >= 5 rods + 6 bodies - 6`.
    pub fn maxwell(&self) -> bool {
        3 * self.contacts.len() + 6 >= 5 * self.n_rods() + 6 * self.n_bodies()
    }

    /// Number of contacts between nodes `a` and `b`.
    pub fn multiplicity(&self, a: u8, b: u8) -> usize {
        self.contacts
            .iter()
            .filter(|c| c.nodes == [a, b] || c.nodes == [b, a])
            .count()
    }

    /// The rods of node `i`: the distinct labels its contacts use (at least one).
    pub fn rods_of(&self, i: u8) -> Vec<u8> {
        let mut rods: Vec<u8> = self
            .contacts
            .iter()
            .flat_map(|c| {
                (0..2)
                    .filter(move |&s| c.nodes[s] == i)
                    .map(move |s| c.rods[s])
            })
            .collect();
        rods.push(0);
        rods.sort_unstable();
        rods.dedup();
        if self.kinds[i as usize] == NodeKind::Rod {
            rods.truncate(1);
        }
        rods
    }

    /// The pattern as a rods-level host: one rod per (node, rod label), the
    /// pattern's bodies declared rigid. Returns the graph, the declared bodies
    /// and, for each pattern node, its rods in the host. A body with a single
    /// rod label gets a second, contact-free rod so that it is a body.
    pub fn to_host(&self) -> Result<(ContactGraph, Vec<Body>, Vec<Vec<u32>>)> {
        self.validate()?;
        let mut rod_of = std::collections::HashMap::new();
        let mut members: Vec<Vec<u32>> = Vec::with_capacity(self.kinds.len());
        let mut next = 0u32;
        for (i, kind) in self.kinds.iter().enumerate() {
            let mut rods = Vec::new();
            for label in self.rods_of(i as u8) {
                rod_of.insert((i as u8, label), next);
                rods.push(next);
                next += 1;
            }
            if kind.is_body() && rods.len() < 2 {
                rods.push(next);
                next += 1;
            }
            members.push(rods);
        }
        let edges = self
            .contacts
            .iter()
            .map(|c| {
                [
                    rod_of[&(c.nodes[0], c.rods[0])],
                    rod_of[&(c.nodes[1], c.rods[1])],
                ]
            })
            .collect();
        let graph = ContactGraph::new(next as usize, edges)?;
        let bodies = self
            .kinds
            .iter()
            .zip(&members)
            .filter_map(|(k, rods)| k.class().map(|class| Body::new(rods.clone(), class)))
            .collect();
        Ok((graph, bodies, members))
    }

    /// The pattern of a rods-level host: each declared body becomes a body
    /// node whose rods are its member rods that have contacts, every other rod
    /// a rod node. Contacts inside one body are dropped (the body is rigid).
    pub fn from_host(graph: &ContactGraph, bodies: &[Body]) -> Result<Self> {
        let mut node_of = vec![None; graph.n_nodes()];
        let mut kinds = Vec::new();
        let mut label_of = vec![0u8; graph.n_nodes()];
        for body in bodies {
            let node = kinds.len() as u8;
            kinds.push(match body.class {
                BodyClass::Planar => NodeKind::Planar,
                BodyClass::Spatial => NodeKind::Spatial,
            });
            for (label, &r) in body.rods.iter().enumerate() {
                let slot = node_of.get_mut(r as usize).ok_or_else(|| {
                    Error::Parameter(format!("body rod {r} is outside 0..{}", graph.n_nodes()))
                })?;
                *slot = Some(node);
                label_of[r as usize] = u8::try_from(label).map_err(|_| {
                    Error::Parameter(format!(
                        "a body has more than 255 rods ({})",
                        body.rods.len()
                    ))
                })?;
            }
        }
        for slot in node_of.iter_mut().filter(|s| s.is_none()) {
            *slot = Some(kinds.len() as u8);
            kinds.push(NodeKind::Rod);
        }
        if kinds.len() > MAX_PATTERN_NODES {
            return Err(Error::Parameter(format!(
                "a pattern has at most {MAX_PATTERN_NODES} nodes, this host makes {}",
                kinds.len()
            )));
        }
        let contacts = graph
            .edges()
            .iter()
            .filter_map(|&[a, b]| {
                let (na, nb) = (node_of[a as usize]?, node_of[b as usize]?);
                (na != nb).then(|| PatternContact {
                    nodes: [na, nb],
                    rods: [label_of[a as usize], label_of[b as usize]],
                })
            })
            .collect();
        let mut p = Pattern { kinds, contacts };
        p.compact_labels();
        p.validate()?;
        Ok(p)
    }

    /// Renumbers each body's rod labels `0..` in order of first use, so that
    /// labels of rods without contacts leave no gaps.
    fn compact_labels(&mut self) {
        for node in 0..self.kinds.len() as u8 {
            let mut map: Vec<u8> = Vec::new();
            for c in &mut self.contacts {
                for side in 0..2 {
                    if c.nodes[side] == node {
                        let old = c.rods[side];
                        let new = match map.iter().position(|&x| x == old) {
                            Some(k) => k,
                            None => {
                                map.push(old);
                                map.len() - 1
                            }
                        };
                        c.rods[side] = new as u8;
                    }
                }
            }
        }
    }
}
