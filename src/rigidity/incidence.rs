//! The incidence model of a pattern (MODEL §3): one line per rod, one
//! point per contact on both its lines, and plane groupings, the families of
//! realizations in which chosen lines share a plane.

use std::collections::{BTreeSet, HashMap};

use crate::pattern::{NodeKind, Pattern};

/// The lines, contacts and planes of a pattern.
#[derive(Clone, Debug)]
pub struct Incidence {
    /// For each line (one per rod: a rod node, or a rod label of a body), its node.
    pub line_node: Vec<u8>,
    /// The two lines of each contact.
    pub contact_lines: Vec<[usize; 2]>,
    /// The contacts on each line.
    pub line_contacts: Vec<Vec<usize>>,
    /// The lines of each node.
    pub node_lines: Vec<Vec<usize>>,
    pub kinds: Vec<NodeKind>,
}

impl Incidence {
    pub fn new(p: &Pattern) -> Self {
        let mut line_of: HashMap<(u8, u8), usize> = HashMap::new();
        let mut line_node = Vec::new();
        let mut node_lines = vec![Vec::new(); p.kinds.len()];
        for i in 0..p.kinds.len() as u8 {
            for label in p.rods_of(i) {
                line_of.insert((i, label), line_node.len());
                node_lines[i as usize].push(line_node.len());
                line_node.push(i);
            }
        }
        let contact_lines: Vec<[usize; 2]> = p
            .contacts
            .iter()
            .map(|c| {
                [
                    line_of[&(c.nodes[0], c.rods[0])],
                    line_of[&(c.nodes[1], c.rods[1])],
                ]
            })
            .collect();
        let mut line_contacts = vec![Vec::new(); line_node.len()];
        for (k, &[a, b]) in contact_lines.iter().enumerate() {
            line_contacts[a].push(k);
            line_contacts[b].push(k);
        }
        Incidence {
            line_node,
            contact_lines,
            line_contacts,
            node_lines,
            kinds: p.kinds.clone(),
        }
    }

    pub fn n_lines(&self) -> usize {
        self.line_node.len()
    }

    pub fn n_contacts(&self) -> usize {
        self.contact_lines.len()
    }

    /// The line across contact `c` from line `l`.
    fn other(&self, c: usize, l: usize) -> usize {
        let [a, b] = self.contact_lines[c];
        if a == l { b } else { a }
    }

    /// Lines touching line `l`.
    pub(super) fn touching(&self, l: usize) -> impl Iterator<Item = usize> + '_ {
        self.line_contacts[l].iter().map(move |&c| self.other(c, l))
    }

    fn touch(&self, a: usize, b: usize) -> bool {
        self.touching(a).any(|x| x == b)
    }

    /// Contacts whose points must lie in the plane of a group of lines.
    pub(super) fn group_contacts(&self, group: &BTreeSet<usize>) -> Vec<usize> {
        let mut cs: Vec<usize> = group
            .iter()
            .flat_map(|&l| self.line_contacts[l].iter().copied())
            .collect();
        cs.sort_unstable();
        cs.dedup();
        cs
    }
}

/// A family of realizations: which lines share a plane.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Grouping {
    pub groups: Vec<BTreeSet<usize>>,
}

impl Grouping {
    /// Closes a grouping under the coplanarities it forces: groups sharing two
    /// lines are one plane, and a line touching two lines of a group lies in it.
    pub(super) fn close(mut self, inc: &Incidence) -> Self {
        loop {
            let mut changed = false;
            'merge: for i in 0..self.groups.len() {
                for j in i + 1..self.groups.len() {
                    if self.groups[i].intersection(&self.groups[j]).count() >= 2 {
                        let g = self.groups.remove(j);
                        self.groups[i].extend(g);
                        changed = true;
                        break 'merge;
                    }
                }
            }
            for g in &mut self.groups {
                for l in 0..inc.n_lines() {
                    if !g.contains(&l) && inc.touching(l).filter(|m| g.contains(m)).count() >= 2 {
                        g.insert(l);
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        self.groups.sort();
        self.groups.dedup();
        self
    }

    /// The forced grouping: planar bodies and rod triangles, closed.
    pub fn forced(inc: &Incidence) -> Self {
        let mut groups: Vec<BTreeSet<usize>> = inc
            .kinds
            .iter()
            .enumerate()
            .filter(|(_, k)| **k == NodeKind::Planar)
            .map(|(i, _)| inc.node_lines[i].iter().copied().collect())
            .collect();
        let n = inc.n_lines();
        for a in 0..n {
            for b in a + 1..n {
                if !inc.touch(a, b) {
                    continue;
                }
                for c in b + 1..n {
                    if inc.touch(a, c) && inc.touch(b, c) {
                        groups.push([a, b, c].into_iter().collect());
                    }
                }
            }
        }
        Grouping { groups }.close(inc)
    }

    /// Everything in one plane.
    pub fn all_coplanar(inc: &Incidence) -> Self {
        Grouping {
            groups: vec![(0..inc.n_lines()).collect()],
        }
    }

    /// The grouping without its groups of two touching lines: two lines that
    /// meet always share a plane, so such a group constrains nothing.
    pub(super) fn effective(&self, inc: &Incidence) -> Grouping {
        let planar = body_planes(inc);
        Grouping {
            groups: self
                .groups
                .iter()
                .filter(|g| {
                    let v: Vec<usize> = g.iter().copied().collect();
                    !(v.len() == 2 && inc.touch(v[0], v[1])) || planar.contains(g)
                })
                .cloned()
                .collect(),
        }
    }

    pub(super) fn in_group(&self, l: usize) -> bool {
        self.groups.iter().any(|g| g.contains(&l))
    }

    /// A short description, e.g. `planes {0,1,2} {3,4,5}`.
    pub fn describe(&self, inc: &Incidence) -> String {
        if self.groups.len() == 1 && self.groups[0].len() == inc.n_lines() {
            return "all coplanar".into();
        }
        if self.groups.is_empty() {
            return "lines in general position".into();
        }
        let planes: Vec<String> = self
            .groups
            .iter()
            .map(|g| {
                let v: Vec<String> = g.iter().map(|l| l.to_string()).collect();
                format!("{{{}}}", v.join(","))
            })
            .collect();
        format!("planes {}", planes.join(" "))
    }
}

/// The planes a pattern's incidences impose by themselves: its planar bodies.
pub fn body_planes(inc: &Incidence) -> Vec<BTreeSet<usize>> {
    inc.kinds
        .iter()
        .enumerate()
        .filter(|(_, k)| **k == NodeKind::Planar)
        .map(|(i, _)| inc.node_lines[i].iter().copied().collect())
        .collect()
}
