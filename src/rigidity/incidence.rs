//! The incidence model of a pattern (MODEL §3): one line per rod, one
//! point per contact on both its lines, and plane groupings, the families of
//! realizations in which chosen lines share a plane.

use std::collections::BTreeSet;

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
    /// The lines touching each line as a bit mask, when there are at most
    /// [`MASK_LINES`] lines and no two contacts join the same two lines
    /// (else empty): the plane closure runs on masks.
    touch: Vec<u128>,
}

/// Most lines whose touching sets fit a mask.
const MASK_LINES: usize = 128;

impl Incidence {
    pub fn new(p: &Pattern) -> Self {
        // Lines by (node, rod label): a rod node has rod 0 only, a body its
        // labels in use and 0 (see `Pattern::rods_of`), in that order.
        let mut keys: Vec<(u8, u8)> = Vec::with_capacity(p.kinds.len() + 2 * p.contacts.len());
        keys.extend((0..p.kinds.len() as u8).map(|i| (i, 0)));
        for c in &p.contacts {
            for side in 0..2 {
                if p.kinds[c.nodes[side] as usize].is_body() {
                    keys.push((c.nodes[side], c.rods[side]));
                }
            }
        }
        keys.sort_unstable();
        keys.dedup();
        let line_of = |node: u8, label: u8| -> usize {
            keys.binary_search(&(node, label))
                .expect("a rod node's contacts are on its rod 0")
        };
        let line_node: Vec<u8> = keys.iter().map(|&(node, _)| node).collect();
        let mut node_lines = vec![Vec::new(); p.kinds.len()];
        for (l, &node) in line_node.iter().enumerate() {
            node_lines[node as usize].push(l);
        }
        let contact_lines: Vec<[usize; 2]> = p
            .contacts
            .iter()
            .map(|c| {
                [
                    line_of(c.nodes[0], c.rods[0]),
                    line_of(c.nodes[1], c.rods[1]),
                ]
            })
            .collect();
        let mut line_contacts = vec![Vec::new(); line_node.len()];
        for (k, &[a, b]) in contact_lines.iter().enumerate() {
            line_contacts[a].push(k);
            line_contacts[b].push(k);
        }
        let mut touch = Vec::new();
        if line_node.len() <= MASK_LINES {
            touch = vec![0u128; line_node.len()];
            for &[a, b] in &contact_lines {
                if a == b || touch[a] >> b & 1 == 1 {
                    touch.clear();
                    break;
                }
                touch[a] |= 1 << b;
                touch[b] |= 1 << a;
            }
        }
        Incidence {
            line_node,
            contact_lines,
            line_contacts,
            node_lines,
            kinds: p.kinds.clone(),
            touch,
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

    /// How many distinct lines touching `l` are `placed`.
    pub(super) fn placed_touching(&self, l: usize, placed: impl Fn(usize) -> bool) -> usize {
        if self.touch.is_empty() {
            let mut m: Vec<usize> = self.touching(l).filter(|&m| placed(m)).collect();
            m.sort_unstable();
            m.dedup();
            return m.len();
        }
        // The lines touching `l` are distinct when there are masks.
        self.touching(l).filter(|&m| placed(m)).count()
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
    ///
    /// Both rules only grow groups, so the closure is the one fixed point
    /// whatever the order they are applied in: a group of one closure lies
    /// in a group of the other (by induction over its merges and additions),
    /// and groups of a closure share at most one line. Masks and sets give
    /// the same groups.
    pub(super) fn close(self, inc: &Incidence) -> Self {
        if inc.touch.is_empty() {
            return self.close_sets(inc);
        }
        let masks = self.groups.iter().map(mask).collect();
        Grouping::from_masks(close_masks(&inc.touch, masks))
    }

    /// [`Grouping::close`] on sets, for incidences without masks.
    fn close_sets(mut self, inc: &Incidence) -> Self {
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

    /// The grouping of closed masks: sets sorted, duplicates dropped.
    fn from_masks(masks: Vec<u128>) -> Self {
        let mut groups: Vec<BTreeSet<usize>> = masks.into_iter().map(set).collect();
        groups.sort();
        groups.dedup();
        Grouping { groups }
    }

    /// The forced grouping: planar bodies and rod triangles, closed.
    pub fn forced(inc: &Incidence) -> Self {
        let planar = inc
            .kinds
            .iter()
            .enumerate()
            .filter(|(_, k)| **k == NodeKind::Planar)
            .map(|(i, _)| &inc.node_lines[i]);
        if !inc.touch.is_empty() {
            let mut groups: Vec<u128> = planar
                .map(|lines| lines.iter().fold(0, |m, &l| m | 1 << l))
                .collect();
            for (a, &ta) in inc.touch.iter().enumerate() {
                for b in bits(ta >> a >> 1 << a << 1) {
                    for c in bits(ta & inc.touch[b] >> b >> 1 << b << 1) {
                        groups.push(1 << a | 1 << b | 1 << c);
                    }
                }
            }
            return Grouping::from_masks(close_masks(&inc.touch, groups));
        }
        let mut groups: Vec<BTreeSet<usize>> = planar
            .map(|lines| lines.iter().copied().collect())
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
        Grouping { groups }.close_sets(inc)
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

/// A set of lines (below [`MASK_LINES`]) as a mask.
fn mask(g: &BTreeSet<usize>) -> u128 {
    g.iter().fold(0, |m, &l| m | 1 << l)
}

/// The lines of a mask, ascending.
fn bits(mut m: u128) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (m != 0).then(|| {
            let l = m.trailing_zeros() as usize;
            m &= m - 1;
            l
        })
    })
}

fn set(m: u128) -> BTreeSet<usize> {
    bits(m).collect()
}

/// [`Grouping::close`] on masks, `touch` the lines touching each line.
fn close_masks(touch: &[u128], mut groups: Vec<u128>) -> Vec<u128> {
    loop {
        let mut changed = false;
        let mut i = 0;
        while i < groups.len() {
            let mut j = i + 1;
            while j < groups.len() {
                if (groups[i] & groups[j]).count_ones() >= 2 {
                    let g = groups.swap_remove(j);
                    groups[i] |= g;
                    changed = true;
                    j = i + 1;
                } else {
                    j += 1;
                }
            }
            i += 1;
        }
        let all = if touch.len() == 128 {
            u128::MAX
        } else {
            (1u128 << touch.len()) - 1
        };
        for g in &mut groups {
            loop {
                let joining = bits(all & !*g)
                    .filter(|&l| (touch[l] & *g).count_ones() >= 2)
                    .fold(0, |m, l| m | 1 << l);
                if joining == 0 {
                    break;
                }
                *g |= joining;
                changed = true;
            }
        }
        if !changed {
            return groups;
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::PatternContact;
    use rand::{RngExt, SeedableRng};

    /// A random valid pattern: rods, planar and spatial bodies, contacts
    /// on random rods of the bodies, two rods touching at most once.
    fn random_pattern(rng: &mut impl rand::Rng) -> Pattern {
        let n = rng.random_range(3..10usize);
        let kinds: Vec<NodeKind> = (0..n)
            .map(|_| match rng.random_range(0..6) {
                0 => NodeKind::Planar,
                1 => NodeKind::Spatial,
                _ => NodeKind::Rod,
            })
            .collect();
        let mut contacts: Vec<PatternContact> = Vec::new();
        for _ in 0..rng.random_range(n..3 * n) {
            let (a, b) = (rng.random_range(0..n), rng.random_range(0..n));
            let label = |k: usize, rng: &mut dyn rand::Rng| {
                if kinds[k].is_body() {
                    rng.random_range(0..3u8)
                } else {
                    0
                }
            };
            let c = PatternContact {
                nodes: [a as u8, b as u8],
                rods: [label(a, rng), label(b, rng)],
            };
            let key = |c: &PatternContact| {
                let (x, y) = ((c.nodes[0], c.rods[0]), (c.nodes[1], c.rods[1]));
                (x.min(y), x.max(y))
            };
            if a != b && contacts.iter().all(|d| key(d) != key(&c)) {
                contacts.push(c);
            }
        }
        let p = Pattern { kinds, contacts };
        p.validate().unwrap();
        p
    }

    /// The closure on masks is the closure on sets: for the forced grouping
    /// and for random groupings of random patterns.
    #[test]
    fn closure_on_masks_is_closure_on_sets() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for _ in 0..2000 {
            let inc = Incidence::new(&random_pattern(&mut rng));
            assert!(!inc.touch.is_empty());
            let mut sets = inc.clone();
            sets.touch.clear();
            assert_eq!(Grouping::forced(&inc), Grouping::forced(&sets));
            let n = inc.n_lines();
            let groups: Vec<BTreeSet<usize>> = (0..rng.random_range(0..4))
                .map(|_| {
                    (0..rng.random_range(1..4))
                        .map(|_| rng.random_range(0..n))
                        .collect()
                })
                .collect();
            let g = Grouping { groups };
            assert_eq!(g.clone().close(&inc), g.close(&sets));
        }
    }
}
