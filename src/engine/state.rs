//! The compression state: a multigraph of rods and bodies whose edges are the
//! original rod–rod contacts, each still knowing its two rods (MODEL §5).
//!
//! Nodes are identified by a representative rod (union–find over rods). Rods
//! keep no adjacency of their own: their contacts are read from the static
//! contact graph and resolved to current nodes on the fly. Bodies keep a map
//! from each neighbouring node to the contacts they share, seen from the body
//! (own rod, other rod). Merging moves the smaller maps into the largest, so
//! the total work of all merges is O(E log E) and only the neighbours of the
//! absorbed parts see their relation change.

use rustc_hash::FxHashMap;

use crate::body::BodyClass;
use crate::graph::ContactGraph;

/// One original contact seen from a node: its rod on this side and on the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Link {
    pub own: u32,
    pub other: u32,
}

#[derive(Default)]
pub(super) struct Node {
    /// Member rods of a body (empty for a rod).
    pub members: Vec<u32>,
    /// Contacts of a body with each neighbouring node (empty for a rod).
    pub adj: FxHashMap<u32, Vec<Link>>,
}

pub(super) struct State<'g> {
    pub g: &'g ContactGraph,
    /// Union-find over rods, by hand: the root must be the part that keeps
    /// the merged node's data ([`State::merge`] picks it), which petgraph's
    /// rank-based `UnionFind` cannot be told.
    parent: Vec<u32>,
    /// Class of each node (`None` for a rod), apart from the bulky node data
    /// so that the hot membership tests stay in cache.
    class: Vec<Option<BodyClass>>,
    /// The plane each rod lies in, if it was ever part of a planar body: a
    /// planar body keeps its plane when it becomes part of a spatial one.
    plane: Vec<u32>,
    planes: u32,
    pub nodes: Vec<Node>,
}

/// No plane: the rod was never part of a planar body.
pub(super) const NO_PLANE: u32 = u32::MAX;

impl<'g> State<'g> {
    pub fn new(g: &'g ContactGraph) -> Self {
        let n = g.n_nodes();
        State {
            g,
            parent: (0..n as u32).collect(),
            class: vec![None; n],
            plane: vec![NO_PLANE; n],
            planes: 0,
            nodes: (0..n).map(|_| Node::default()).collect(),
        }
    }

    /// The node that rod `x` currently belongs to.
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let p = self.parent[x as usize];
            let gp = self.parent[p as usize];
            self.parent[x as usize] = gp;
            x = gp;
        }
        x
    }

    /// Whether `x` is a node that is a single rod.
    pub fn is_free_rod(&self, x: u32) -> bool {
        self.parent[x as usize] == x && self.class[x as usize].is_none()
    }

    /// Class of node `x` (`None` for a rod).
    pub fn class(&self, x: u32) -> Option<BodyClass> {
        self.class[x as usize]
    }

    /// The nodes body `b` touches.
    pub fn neighbours(&self, b: u32) -> impl Iterator<Item = u32> + '_ {
        self.nodes[b as usize].adj.keys().copied()
    }

    /// The plane rod `r` lies in ([`NO_PLANE`] if none).
    pub fn plane(&self, r: u32) -> u32 {
        self.plane[r as usize]
    }

    /// Number of contacts between nodes `x` and `y` (at least one is a body,
    /// or both rods).
    pub fn multiplicity(&self, x: u32, y: u32) -> usize {
        if self.class(x).is_some() {
            self.body_links(x, y).len()
        } else if self.class(y).is_some() {
            self.body_links(y, x).len()
        } else {
            usize::from(self.g.edge_between(x, y).is_some())
        }
    }

    /// Contacts of body `b` with node `y`.
    pub fn body_links(&self, b: u32, y: u32) -> &[Link] {
        self.nodes[b as usize]
            .adj
            .get(&y)
            .map_or(&[][..], |v| v.as_slice())
    }

    /// Contacts between nodes `x` and `y`, seen from `x`.
    pub fn links_between(&self, x: u32, y: u32) -> Vec<Link> {
        let mut links = Vec::new();
        self.links_into(x, y, &mut links);
        links
    }

    /// Appends the contacts between nodes `x` and `y`, seen from `x`, to `out`.
    pub fn links_into(&self, x: u32, y: u32, out: &mut Vec<Link>) {
        if self.class(x).is_some() {
            out.extend_from_slice(self.body_links(x, y));
        } else if self.class(y).is_some() {
            out.extend(self.body_links(y, x).iter().map(|l| Link {
                own: l.other,
                other: l.own,
            }));
        } else if self.g.edge_between(x, y).is_some() {
            out.push(Link { own: x, other: y });
        }
    }

    /// Number of contacts or neighbouring nodes of node `x`: the cost of
    /// listing its neighbours, and the size that decides which part of a
    /// merge survives.
    pub fn degree(&self, x: u32) -> usize {
        if self.class(x).is_some() {
            self.nodes[x as usize].adj.len()
        } else {
            self.g.degree(x)
        }
    }

    /// Rods of node `x` that rod `r` touches (the other ends of `r`'s
    /// contacts with `x`), sorted.
    pub fn rod_contacts_with(&mut self, r: u32, x: u32, out: &mut Vec<u32>) {
        out.clear();
        if self.class(x).is_some() && self.is_free_rod(r) {
            // A body keeps its contacts with each neighbour: one look-up
            // instead of resolving every contact of `r`.
            out.extend(self.body_links(x, r).iter().map(|l| l.own));
            out.sort_unstable();
            return;
        }
        let g = self.g;
        for &(nb, _) in g.neighbors(r) {
            if self.find(nb) == x {
                out.push(nb);
            }
        }
    }

    /// Every contact of node `x`, grouped by the neighbouring node it reaches.
    fn take_links(&mut self, x: u32) -> Vec<(u32, Vec<Link>)> {
        if self.class[x as usize].is_some() {
            return std::mem::take(&mut self.nodes[x as usize].adj)
                .into_iter()
                .collect();
        }
        let g = self.g;
        let mut out: Vec<(u32, Vec<Link>)> = Vec::with_capacity(g.degree(x));
        for &(nb, _) in g.neighbors(x) {
            let y = self.find(nb);
            let link = Link { own: x, other: nb };
            match out.iter_mut().find(|(n, _)| *n == y) {
                Some((_, v)) => v.push(link),
                None => out.push((y, vec![link])),
            }
        }
        out
    }

    /// Merges the nodes `parts` into one body of class `class`. Returns the new
    /// node and the neighbours whose relation to it changed (all of them when
    /// the surviving part changed kind or class).
    pub fn merge(&mut self, parts: &[u32], class: BodyClass) -> (u32, Vec<u32>) {
        debug_assert!(parts.len() >= 2);
        if class == BodyClass::Planar {
            self.assign_plane(parts);
        }
        let keep = *parts
            .iter()
            .max_by_key(|&&x| (self.degree(x), std::cmp::Reverse(x)))
            .expect("a merge has parts");
        let all_changed = self.class[keep as usize] != Some(class);
        if self.class[keep as usize].is_none() {
            let links = self.take_links(keep);
            let node = &mut self.nodes[keep as usize];
            node.adj = links.into_iter().collect();
            node.members.push(keep);
        }
        let mut changed = Vec::new();
        for &part in parts.iter().filter(|&&p| p != keep) {
            let links = self.take_links(part);
            for (y, ls) in links {
                if parts.contains(&y) {
                    continue;
                }
                changed.push(y);
                if self.class[y as usize].is_some() {
                    let mut moved = self.nodes[y as usize]
                        .adj
                        .remove(&part)
                        .expect("adjacency is symmetric between bodies");
                    self.nodes[y as usize]
                        .adj
                        .entry(keep)
                        .or_default()
                        .append(&mut moved);
                }
                self.nodes[keep as usize]
                    .adj
                    .entry(y)
                    .or_default()
                    .extend(ls);
            }
            let members = std::mem::take(&mut self.nodes[part as usize].members);
            self.class[part as usize] = None;
            let keep_node = &mut self.nodes[keep as usize];
            if members.is_empty() {
                keep_node.members.push(part);
            } else {
                keep_node.members.extend(members);
            }
            self.parent[part as usize] = keep;
        }
        let keep_node = &mut self.nodes[keep as usize];
        for p in parts {
            keep_node.adj.remove(p);
        }
        self.class[keep as usize] = Some(class);
        if all_changed {
            changed = keep_node.adj.keys().copied().collect();
        }
        changed.sort_unstable();
        changed.dedup();
        (keep, changed)
    }

    /// Puts the rods of a new planar body in its plane: the plane of the
    /// planar body among `parts` (a rod joining it by 3D2B), else a new one.
    fn assign_plane(&mut self, parts: &[u32]) {
        let existing = parts
            .iter()
            .find(|&&x| self.class[x as usize] == Some(BodyClass::Planar))
            .map(|&x| self.plane[self.nodes[x as usize].members[0] as usize]);
        let id = existing.unwrap_or_else(|| {
            self.planes += 1;
            self.planes - 1
        });
        for &x in parts {
            if self.class[x as usize].is_none() {
                self.plane[x as usize] = id;
            } else {
                for &r in &self.nodes[x as usize].members {
                    self.plane[r as usize] = id;
                }
            }
        }
    }

    /// Puts `rods` in one new plane (a planar part declared in a spatial body).
    pub fn put_in_plane(&mut self, rods: &[u32]) {
        for &r in rods {
            self.plane[r as usize] = self.planes;
        }
        self.planes += 1;
    }

    /// The bodies left: rods, class and, for spatial bodies, the rods of each
    /// planar part (sorted, largest first).
    pub fn bodies(&self) -> impl Iterator<Item = (&[u32], BodyClass, Vec<Vec<u32>>)> {
        self.nodes.iter().enumerate().filter_map(|(i, n)| {
            let class = self.class[i]?;
            (self.parent[i] == i as u32).then(|| {
                let mut planes: Vec<Vec<u32>> = Vec::new();
                if class == BodyClass::Spatial {
                    let mut by_plane: Vec<(u32, u32)> = n
                        .members
                        .iter()
                        .map(|&r| (self.plane[r as usize], r))
                        .filter(|&(p, _)| p != NO_PLANE)
                        .collect();
                    by_plane.sort_unstable();
                    planes = by_plane
                        .chunk_by(|a, b| a.0 == b.0)
                        .map(|c| c.iter().map(|&(_, r)| r).collect())
                        .collect();
                    planes.sort_by(|a: &Vec<u32>, b| b.len().cmp(&a.len()).then(a.cmp(b)));
                }
                (n.members.as_slice(), class, planes)
            })
        })
    }

    /// Number of nodes left (bodies and free rods).
    pub fn n_nodes(&self) -> usize {
        self.parent
            .iter()
            .enumerate()
            .filter(|&(i, &p)| p == i as u32)
            .count()
    }
}
