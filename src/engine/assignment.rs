//! The assignment of pattern contacts to the host contacts of a complete
//! node map: injective, each node's labelling a function, and (under
//! `sound`) no collinearity the pattern did not assume.

use std::cell::RefCell;

use super::rule::CompiledRule;
use super::ruleset::RuleSet;
use super::state::{Link, NO_PLANE, State};

/// Whether the contacts of the complete node map `map` of `rule` can be
/// assigned (see [`Assignment`]).
pub(super) fn assignable(
    state: &State,
    rule: &CompiledRule,
    map: &[Option<u32>],
    rules: RuleSet,
) -> bool {
    ASSIGNMENT.with(|a| {
        let mut a = a.borrow_mut();
        a.start(state, rule, map);
        a.assign(state, rule, map, 0, 0, rules)
    })
}

/// A contact's (pattern node, rod label) on each of its two sides.
type Sides = [(usize, u8); 2];

impl State<'_> {
    /// The plane a free rod lies in because it touches two rods of it.
    fn touched_plane(&self, rod: u32) -> Option<u32> {
        let mut seen: Vec<u32> = Vec::new();
        for &(nb, _) in self.g.neighbors(rod) {
            let p = self.plane(nb);
            if p != NO_PLANE {
                if seen.contains(&p) {
                    return Some(p);
                }
                seen.push(p);
            }
        }
        None
    }

    /// Under `sound`: three or more chosen contacts between one plane and
    /// another lie on the line the planes share, and the pattern must have
    /// assumed it (all on one rod of one pattern node). Planes are the planar
    /// parts of bodies and the rod triangles among the matched free rods
    /// (extra host contacts can close such triangles).
    fn no_hidden_lines(&self, map: &[Option<u32>], assignment: &Assignment) -> bool {
        let free: Vec<u32> = map
            .iter()
            .flatten()
            .copied()
            .filter(|&x| self.class(x).is_none())
            .collect();
        let triangle_plane = triangle_planes(self.g, &free);
        let plane_of = |rod: u32| -> u32 {
            match self.plane(rod) {
                NO_PLANE => triangle_plane
                    .iter()
                    .find(|(r, _)| *r == rod)
                    .map(|&(_, p)| p)
                    .or_else(|| self.touched_plane(rod))
                    .unwrap_or(NO_PLANE),
                p => p,
            }
        };
        // (plane pair) -> the chosen contacts' (pattern node, label) on each side.
        let mut groups: Vec<((u32, u32), Vec<Sides>)> = Vec::new();
        for &(k, l, (la, lb)) in &assignment.chosen {
            let (a, b, _) = assignment.pairs[k];
            let (pa, pb) = (plane_of(l.own), plane_of(l.other));
            if pa == NO_PLANE || pb == NO_PLANE || pa == pb {
                continue;
            }
            let (key, ends) = if pa < pb {
                ((pa, pb), [(a, la), (b, lb)])
            } else {
                ((pb, pa), [(b, lb), (a, la)])
            };
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, v)) => v.push(ends),
                None => groups.push((key, vec![ends])),
            }
        }
        groups.iter().all(|(_, v)| {
            v.len() < 3 || v.iter().all(|e| e[0] == v[0][0]) || v.iter().all(|e| e[1] == v[0][1])
        })
    }
}

thread_local! {
    static ASSIGNMENT: RefCell<Assignment> = RefCell::new(Assignment::default());
}

/// The search for an injective assignment of pattern contacts to host
/// contacts under which the host has no collinearity the pattern did not
/// assume. Its buffers are flat stacks reused from match to match: the
/// engine completes hundreds of thousands of node maps per system.
#[derive(Default)]
struct Assignment {
    /// The pattern node pairs with contacts, lower node first, and where
    /// their host contacts are in `links`.
    pairs: Vec<(usize, usize, std::ops::Range<usize>)>,
    links: Vec<Link>,
    /// The labels given so far: (pattern node, host rod, pattern label).
    labels: Vec<(usize, u32, u8)>,
    /// The host contacts chosen so far: (pair, contact, labels at its ends).
    chosen: Vec<(usize, Link, (u8, u8))>,
}

impl Assignment {
    /// Lists the host contacts of the pattern's node pairs under `map`.
    fn start(&mut self, state: &State, rule: &CompiledRule, map: &[Option<u32>]) {
        self.pairs.clear();
        self.links.clear();
        self.labels.clear();
        self.chosen.clear();
        let n = map.len();
        for a in 0..n {
            for b in a + 1..n {
                if !rule.between[a][b].is_empty() {
                    let from = self.links.len();
                    state.links_into(
                        map[a].expect("mapped"),
                        map[b].expect("mapped"),
                        &mut self.links,
                    );
                    self.pairs.push((a, b, from..self.links.len()));
                }
            }
        }
    }

    /// Assigns pattern contact `i` of pair `k` and everything after it.
    fn assign(
        &mut self,
        state: &State,
        rule: &CompiledRule,
        map: &[Option<u32>],
        k: usize,
        i: usize,
        rules: RuleSet,
    ) -> bool {
        let Some((a, b, ref range)) = self.pairs.get(k).cloned() else {
            return rules == RuleSet::Paper || state.no_hidden_lines(map, self);
        };
        let wanted = &rule.between[a][b];
        if i == wanted.len() {
            return self.assign(state, rule, map, k + 1, 0, rules);
        }
        let (la, lb) = wanted[i];
        for j in range.clone() {
            let link = self.links[j];
            if self.chosen.iter().any(|&(kk, l, _)| kk == k && l == link)
                || !self.consistent(a, link.own, la)
                || !self.consistent(b, link.other, lb)
            {
                continue;
            }
            let labels = self.labels.len();
            self.labels.push((a, link.own, la));
            self.labels.push((b, link.other, lb));
            self.chosen.push((k, link, (la, lb)));
            if self.assign(state, rule, map, k, i + 1, rules) {
                return true;
            }
            self.chosen.pop();
            self.labels.truncate(labels);
        }
        false
    }

    /// Whether giving host rod `rod` of pattern node `v` label `label` keeps
    /// each node's labelling a function.
    fn consistent(&self, v: usize, rod: u32, label: u8) -> bool {
        self.labels
            .iter()
            .all(|&(w, r, l)| w != v || r != rod || l == label)
    }
}

/// Planes of the rod triangles among `rods` (each rod in the first triangle
/// community found), with ids counting down from below [`NO_PLANE`] so they
/// never meet the ids of bodies' planes.
fn triangle_planes(g: &crate::graph::ContactGraph, rods: &[u32]) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = Vec::new();
    let mut next = NO_PLANE - 1;
    for (i, &a) in rods.iter().enumerate() {
        for (j, &b) in rods.iter().enumerate().skip(i + 1) {
            if g.edge_between(a, b).is_none() {
                continue;
            }
            for &c in &rods[j + 1..] {
                if g.edge_between(a, c).is_none() || g.edge_between(b, c).is_none() {
                    continue;
                }
                let known = [a, b, c]
                    .iter()
                    .find_map(|r| out.iter().find(|(x, _)| x == r).map(|&(_, p)| p));
                let id = known.unwrap_or_else(|| {
                    next -= 1;
                    next + 1
                });
                for r in [a, b, c] {
                    if !out.iter().any(|(x, _)| *x == r) {
                        out.push((r, id));
                    }
                }
            }
        }
    }
    out
}
