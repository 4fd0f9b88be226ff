//! The base motifs of 3D-RGC (MODEL §5, paper §3.2 and appendix), each found
//! from an anchor: a rod for the rods-only motifs (3-clique communities, 3D6),
//! a pair of nodes whose relation just changed for the motifs with bodies.
//!
//! A contact set is "on one rod" when all its contacts share a rod of either
//! side; the non-degeneracy conditions of the theorems exclude exactly that.

use rustc_hash::{FxHashMap, FxHashSet};

use super::motif::Motif;
use super::rule::CompiledRule;
use super::ruleset::RuleSet;
use super::sound::sound_rules;
use super::state::{Link, NO_PLANE, State};
use crate::body::BodyClass;

/// A motif instance ready to be compressed.
pub(super) struct Found {
    pub motif: Motif,
    pub parts: Vec<u32>,
    pub class: BodyClass,
}

impl Found {
    /// A match of a loaded rule: the host nodes and the merged body's class.
    pub fn of_rule(rule: &CompiledRule, (parts, class): (Vec<u32>, BodyClass)) -> Self {
        Found {
            motif: rule.motif,
            parts,
            class,
        }
    }
}

impl State<'_> {
    /// Under `sound`, whether a candidate of 3D3A, 3D3B or 3D4 matches a
    /// verified base rule: the published conditions admit variants with
    /// planar bodies that exact rank refutes. (The matcher then also checks
    /// the induced pattern, see [`State::induced_rigid`].)
    fn verified(&mut self, motif: Motif, parts: &[u32], rules: RuleSet) -> bool {
        rules == RuleSet::Paper
            || sound_rules()
                .iter()
                .filter(|r| r.motif == motif)
                .any(|r| self.matches_nodes(r, parts, rules))
    }
}

/// Whether all `links` share one rod on the same side.
fn on_one_rod(links: &[Link]) -> bool {
    let Some(first) = links.first() else {
        return true;
    };
    links.iter().all(|l| l.own == first.own) || links.iter().all(|l| l.other == first.other)
}

impl State<'_> {
    /// Whether all `links` lie on one line: on one rod, or (under `sound`)
    /// between one plane on each side, where they sit on the line the two
    /// planes share — wherever those planar parts now belong.
    fn on_one_line(&self, links: &[Link], rules: RuleSet) -> bool {
        if on_one_rod(links) {
            return true;
        }
        let one_plane = |rod: fn(&Link) -> u32| {
            let p = self.plane(rod(&links[0]));
            p != NO_PLANE && links.iter().all(|l| self.plane(rod(l)) == p)
        };
        rules == RuleSet::Sound && one_plane(|l| l.own) && one_plane(|l| l.other)
    }
}

/// Pairs `{p, q}` of `links` (first side = `R_i`, second side = `R_3`) that
/// avoid sharing the rod `avoid` on the first side, summarized for 3D3A:
/// whether any exists, whether one has two different third-side rods, and
/// the third-side rods of the pairs that have the same one.
struct PairChoices {
    any: bool,
    split: bool,
    same: Vec<u32>,
}

fn pair_choices(links: &[Link], avoid: u32, scratch: &mut Vec<(u32, bool)>) -> PairChoices {
    let free = links.iter().any(|l| l.own != avoid);
    scratch.clear();
    scratch.extend(links.iter().map(|l| (l.other, l.own != avoid)));
    scratch.sort_unstable();
    let mut same = Vec::new();
    let mut groups = 0;
    let mut i = 0;
    while i < scratch.len() {
        let z = scratch[i].0;
        let mut j = i;
        let mut free_in_group = false;
        while j < scratch.len() && scratch[j].0 == z {
            free_in_group |= scratch[j].1;
            j += 1;
        }
        if j - i >= 2 && free_in_group {
            same.push(z);
        }
        groups += 1;
        i = j;
    }
    PairChoices {
        any: links.len() >= 2 && free,
        split: groups >= 2 && free,
        same,
    }
}

impl State<'_> {
    /// 3D3C grown to a 3-clique community: the rods reachable from a rod
    /// triangle through `r` by triangles sharing an edge, all still free rods.
    pub fn community(&mut self, r: u32) -> Option<Found> {
        let g = self.g;
        let free_common = |s: &Self, a: u32, b: u32, out: &mut Vec<u32>| {
            out.clear();
            let (na, nb) = (g.neighbors(a), g.neighbors(b));
            let (mut i, mut j) = (0, 0);
            while i < na.len() && j < nb.len() {
                match na[i].0.cmp(&nb[j].0) {
                    std::cmp::Ordering::Less => i += 1,
                    std::cmp::Ordering::Greater => j += 1,
                    std::cmp::Ordering::Equal => {
                        if s.is_free_rod(na[i].0) {
                            out.push(na[i].0);
                        }
                        i += 1;
                        j += 1;
                    }
                }
            }
        };
        let mut common = Vec::new();
        let seed = g
            .neighbors(r)
            .iter()
            .map(|&(u, _)| u)
            .filter(|&u| self.is_free_rod(u))
            .find_map(|u| {
                free_common(self, r, u, &mut common);
                common.first().map(|&w| (u, w))
            })?;
        let (u, w) = seed;
        let mut members = vec![r, u, w];
        let mut in_community: FxHashSet<u32> = members.iter().copied().collect();
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        let mut seen: FxHashSet<(u32, u32)> =
            [key(r, u), key(r, w), key(u, w)].into_iter().collect();
        let mut queue = vec![(r, u), (r, w), (u, w)];
        while let Some((a, b)) = queue.pop() {
            free_common(self, a, b, &mut common);
            for &c in &common {
                if in_community.insert(c) {
                    members.push(c);
                }
                for e in [(a, c), (b, c)] {
                    if seen.insert(key(e.0, e.1)) {
                        queue.push(e);
                    }
                }
            }
        }
        Some(Found {
            motif: Motif::Community,
            parts: members,
            class: BodyClass::Planar,
        })
    }

    /// 3D6: rods `r` and `s`, not touching, both touching the same four rods.
    pub fn k24(&mut self, r: u32) -> Option<Found> {
        let g = self.g;
        if g.degree(r) < 4 {
            return None;
        }
        let mut second: Vec<(u32, u32)> = Vec::new();
        for &(u, _) in g.neighbors(r) {
            if !self.is_free_rod(u) {
                continue;
            }
            for &(s, _) in g.neighbors(u) {
                if s != r && self.is_free_rod(s) {
                    second.push((s, u));
                }
            }
        }
        second.sort_unstable();
        second
            .chunk_by(|a, b| a.0 == b.0)
            .find(|c| c.len() >= 4 && g.edge_between(r, c[0].0).is_none())
            .map(|c| {
                let mut parts = vec![r, c[0].0];
                parts.extend(c[..4].iter().map(|&(_, u)| u));
                Found {
                    motif: Motif::D6,
                    parts,
                    class: BodyClass::Spatial,
                }
            })
    }

    /// 3D2B: rod `r` touching body `b` at two or more contacts.
    pub fn d2b(&mut self, b: u32, r: u32, buf: &mut Vec<u32>) -> Option<Found> {
        self.rod_contacts_with(r, b, buf);
        (buf.len() >= 2).then(|| Found {
            motif: Motif::D2B,
            parts: vec![b, r],
            class: self.class(b).expect("3D2B anchors at a body"),
        })
    }

    /// 3D2A: bodies `x`, `y` with three or more contacts not all on one rod;
    /// under `sound` not all between one plane of each (two planar bodies, or
    /// planar parts of larger ones: a hinge about the line the planes share).
    pub fn d2a(&self, x: u32, y: u32, rules: RuleSet) -> Option<Found> {
        let links = self.body_links(x, y);
        (links.len() >= 3 && !self.on_one_line(links, rules)).then(|| Found {
            motif: Motif::D2A,
            parts: vec![x, y],
            class: BodyClass::Spatial,
        })
    }

    /// 3D3A through bodies `x` and `y`: a third body `z` touching both, in any
    /// assignment of the roles R1, R2, R3 (R3 being the one with two contacts to each).
    pub fn d3a(&mut self, x: u32, y: u32, rules: RuleSet) -> Option<Found> {
        let (small, large) = if self.nodes[x as usize].adj.len() <= self.nodes[y as usize].adj.len()
        {
            (x, y)
        } else {
            (y, x)
        };
        let mut scratch = Vec::new();
        let mut z_candidates: Vec<u32> = self.nodes[small as usize]
            .adj
            .keys()
            .copied()
            .filter(|&z| {
                z != large
                    && self.class(z).is_some()
                    && self.nodes[large as usize].adj.contains_key(&z)
            })
            .collect();
        z_candidates.sort_unstable();
        z_candidates.into_iter().find_map(|z| {
            let rigid = [(x, y, z), (x, z, y), (y, z, x)]
                .into_iter()
                .any(|(r1, r2, r3)| self.d3a_roles(r1, r2, r3, &mut scratch))
                && self.verified(Motif::D3A, &[x, y, z], rules);
            rigid.then(|| Found {
                motif: Motif::D3A,
                parts: vec![x, y, z],
                class: BodyClass::Spatial,
            })
        })
    }

    /// The 3D3A conditions with the roles fixed: some p1 in R1∩R2, {p2, p3} in
    /// R1∩R3, {p4, p5} in R2∩R3 with {p1,p2,p3} and {p1,p4,p5} not on one rod
    /// and {p2,p3,p4,p5} not on one rod.
    fn d3a_roles(&self, r1: u32, r2: u32, r3: u32, scratch: &mut Vec<(u32, bool)>) -> bool {
        let c12 = self.body_links(r1, r2);
        let c13 = self.body_links(r1, r3);
        let c23 = self.body_links(r2, r3);
        if c12.is_empty() || c13.len() < 2 || c23.len() < 2 {
            return false;
        }
        let mut tried: Vec<(u32, u32)> = Vec::new();
        c12.iter().any(|p1| {
            if tried.contains(&(p1.own, p1.other)) {
                return false;
            }
            tried.push((p1.own, p1.other));
            // p2, p3 share a rod with p1 only on R1's side; likewise p4, p5 on R2's.
            let a = pair_choices(c13, p1.own, scratch);
            let b = pair_choices(c23, p1.other, scratch);
            a.any
                && b.any
                && (a.split || b.split || a.same.iter().any(|q| b.same.iter().any(|w| q != w)))
        })
    }

    /// 3D3B through bodies `x` and `y` (two or more contacts): a rod touching both.
    pub fn d3b_bodies(
        &mut self,
        x: u32,
        y: u32,
        rules: RuleSet,
        buf: &mut Vec<u32>,
    ) -> Option<Found> {
        if self.body_links(x, y).len() < 2 {
            return None;
        }
        let (small, large) = if self.nodes[x as usize].adj.len() <= self.nodes[y as usize].adj.len()
        {
            (x, y)
        } else {
            (y, x)
        };
        let mut rods: Vec<u32> = self.nodes[small as usize]
            .adj
            .keys()
            .copied()
            .filter(|&r| self.class(r).is_none() && self.nodes[large as usize].adj.contains_key(&r))
            .collect();
        rods.sort_unstable();
        rods.into_iter().find_map(|r| self.d3b(x, y, r, rules, buf))
    }

    /// 3D3B through body `x` and rod `r`: another body `y` with two or more
    /// contacts with `x` that `r` also touches.
    pub fn d3b_rod(&mut self, x: u32, r: u32, rules: RuleSet, buf: &mut Vec<u32>) -> Option<Found> {
        let g = self.g;
        let mut bodies: Vec<u32> = Vec::new();
        for &(nb, _) in g.neighbors(r) {
            let y = self.find(nb);
            if y != x && self.class(y).is_some() && self.body_links(x, y).len() >= 2 {
                bodies.push(y);
            }
        }
        bodies.sort_unstable();
        bodies.dedup();
        bodies
            .into_iter()
            .find_map(|y| self.d3b(x, y, r, rules, buf))
    }

    /// The 3D3B conditions for bodies `x`, `y` and rod `r`: contacts p1, p2 of
    /// x with y, p3 of r with x, p4 of r with y, such that neither p3 nor p4 is
    /// on one rod with both p1 and p2.
    fn d3b(&mut self, x: u32, y: u32, r: u32, rules: RuleSet, buf: &mut Vec<u32>) -> Option<Found> {
        self.rod_contacts_with(r, x, buf);
        let on_x = std::mem::take(buf);
        self.rod_contacts_with(r, y, buf);
        let c12 = self.body_links(x, y);
        let m = c12.len();
        let pairs = |k: usize| k * k.saturating_sub(1) / 2;
        // A pair of c12 is bad when both sit on x's rod u (p3 collinear with them)
        // or both on y's rod v (p4 collinear with them); no pair does both,
        // since u and v touch at most once.
        let ok = on_x.iter().any(|&u| {
            let a = c12.iter().filter(|l| l.own == u).count();
            buf.iter().any(|&v| {
                let b = c12.iter().filter(|l| l.other == v).count();
                pairs(m) > pairs(a) + pairs(b)
            })
        });
        *buf = on_x;
        (ok && self.verified(Motif::D3B, &[x, y, r], rules)).then(|| Found {
            motif: Motif::D3B,
            parts: vec![x, y, r],
            class: BodyClass::Spatial,
        })
    }

    /// 3D4 through body `x` and rod `r`: rods a–b–c in a path, each touching
    /// `x`, with `r` among them and the three body contacts not all on one rod of `x`.
    /// Under `sound`, when a and c touch too the rods form a triangle, a planar
    /// body; if the three body contacts all sit in one plane of `x`, the pair
    /// is the rod prism's hinge (the contacts on the line the planes share).
    pub fn d4(&mut self, x: u32, r: u32, rules: RuleSet, buf: &mut Vec<u32>) -> Option<Found> {
        let g = self.g;
        // Rods around r that touch x, with the rods of x they touch.
        let mut touching: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
        let mut touches = |s: &mut Self, rod: u32, buf: &mut Vec<u32>| -> bool {
            if let Some(v) = touching.get(&rod) {
                return !v.is_empty();
            }
            s.rod_contacts_with(rod, x, buf);
            touching.insert(rod, buf.clone());
            !buf.is_empty()
        };
        if !touches(self, r, buf) {
            return None;
        }
        let free_nbrs = |s: &Self, a: u32| -> Vec<u32> {
            g.neighbors(a)
                .iter()
                .map(|&(v, _)| v)
                .filter(|&v| s.is_free_rod(v))
                .collect()
        };
        let mut paths: Vec<[u32; 3]> = Vec::new();
        let around = free_nbrs(self, r);
        let around: Vec<u32> = around
            .into_iter()
            .filter(|&v| touches(self, v, buf))
            .collect();
        // r in the middle.
        for (i, &a) in around.iter().enumerate() {
            for &c in &around[i + 1..] {
                paths.push([a, r, c]);
            }
        }
        // r at an end.
        for &b in &around {
            for c in free_nbrs(self, b) {
                if c != r && touches(self, c, buf) {
                    paths.push([r, b, c]);
                }
            }
        }
        let path = paths.into_iter().find(|p| {
            let parts = [x, p[0], p[1], p[2]];
            let rods: Vec<u32> = p.iter().flat_map(|v| touching[v].iter().copied()).collect();
            let plane = self.plane(rods[0]);
            let in_one_plane = plane != NO_PLANE && rods.iter().all(|&q| self.plane(q) == plane);
            let hinge =
                rules == RuleSet::Sound && in_one_plane && g.edge_between(p[0], p[2]).is_some();
            rods.iter().any(|&q| q != rods[0]) && !hinge && self.verified(Motif::D4, &parts, rules)
        })?;
        let mut parts = vec![x];
        parts.extend(path);
        Some(Found {
            motif: Motif::D4,
            parts,
            class: BodyClass::Spatial,
        })
    }
}
