//! A loaded rule compiled for matching (MODEL §6): its pattern's contacts
//! and neighbours, what each node demands of its host, its automorphisms
//! and the plain matcher's search plans.

use super::demand::{CommonNeeds, Needs, fits};
use super::motif::Motif;
use crate::body::BodyClass;
use crate::pattern::{NodeKind, Pattern};
use crate::rigidity::incidence::{Grouping, Incidence};
use crate::rule_file::Rule;

/// A rule prepared for matching.
#[derive(Clone, Debug)]
pub struct CompiledRule {
    pub id: String,
    /// A hash of the id and pattern: rule sets with the same digests in the
    /// same order share their catalog ([`super::catalog`]).
    pub(super) digest: u64,
    /// The base motif a base rule writes out, else [`Motif::Rule`].
    pub motif: Motif,
    pub(super) kinds: Vec<NodeKind>,
    /// Pattern contacts between each pair of nodes, as (label at the lower node, label at the higher).
    pub(super) between: Vec<Vec<Vec<(u8, u8)>>>,
    pub(super) neighbours: Vec<Vec<usize>>,
    rods_only: bool,
    /// Whether every realization of the pattern is planar (a triangle, a
    /// rod touching a planar body twice): the merged body is then planar
    /// when its host bodies are.
    pub(super) planar: bool,
    /// What each pattern node's neighbours demand of its host's neighbours.
    pub(super) needs: Vec<Needs>,
    /// Each pattern node's neighbours' degrees, largest first.
    pub(super) neighbour_degrees: Vec<Vec<u32>>,
    /// Each pattern node's largest distance to another.
    pub(super) eccentricity: Vec<usize>,
    /// Adjacent pairs of pattern nodes − nodes + 1: the independent cycles.
    pub(super) cycles: i64,
    /// The fewest neighbours of a pattern node: a rods-only match lies in
    /// the free rods' core of that order.
    pub(super) min_degree: usize,
    /// The plain matcher's search from each pattern node, and from each
    /// pattern contact (by its ends), if it reaches every node.
    pub(super) plans: Vec<Option<Vec<Step>>>,
    pub(super) pair_plans: Vec<Vec<Option<Vec<Step>>>>,
    /// The least pattern node an automorphism maps each node to, and the
    /// least pattern contact (ends in order) each contact: a search from an
    /// automorphic start finds the matches of the earlier one, permuted.
    pub(super) orbit: Vec<usize>,
    pub(super) pair_orbit: Vec<Vec<(usize, usize)>>,
    /// What the pattern nodes touching both `a` and `b` demand of the
    /// common neighbours of their hosts, for each pattern contact `a`, `b`.
    pub(super) common: Vec<Vec<CommonNeeds>>,
}

impl CompiledRule {
    pub fn new(rule: &Rule) -> Self {
        let p: &Pattern = &rule.pattern;
        let n = p.n_nodes();
        let mut between = vec![vec![Vec::new(); n]; n];
        for c in &p.contacts {
            let (a, b) = (c.nodes[0] as usize, c.nodes[1] as usize);
            between[a][b].push((c.rods[0], c.rods[1]));
            between[b][a].push((c.rods[1], c.rods[0]));
        }
        let neighbours: Vec<Vec<usize>> = (0..n)
            .map(|a| (0..n).filter(|&b| !between[a][b].is_empty()).collect())
            .collect();
        let inc = Incidence::new(p);
        let forced = Grouping::forced(&inc);
        let planar = !p.kinds.contains(&NodeKind::Spatial)
            && forced.groups.len() == 1
            && forced.groups[0].len() == inc.n_lines();
        let motif = [
            ("3D3C", Motif::Community),
            ("3D2B", Motif::D2B),
            ("3D2A", Motif::D2A),
            ("3D3A", Motif::D3A),
            ("3D3B", Motif::D3B),
            ("3D4", Motif::D4),
            ("3D6", Motif::D6),
        ]
        .into_iter()
        .find(|(name, _)| rule.id.starts_with(&format!("base-{name}-")))
        .map_or(Motif::Rule, |(_, m)| m);
        let needs = (0..n)
            .map(|a| {
                let demands: Vec<(NodeKind, usize)> = neighbours[a]
                    .iter()
                    .map(|&b| (p.kinds[b], between[a][b].len()))
                    .collect();
                Needs::new(&demands)
            })
            .collect();
        let neighbour_degrees = (0..n)
            .map(|a| {
                let mut d: Vec<u32> = neighbours[a]
                    .iter()
                    .map(|&b| neighbours[b].len() as u32)
                    .collect();
                d.sort_unstable_by(|x, y| y.cmp(x));
                d
            })
            .collect();
        let common = (0..n)
            .map(|a| {
                (0..n)
                    .map(|b| {
                        CommonNeeds::new(
                            (0..n)
                                .filter(|&c| {
                                    c != a
                                        && c != b
                                        && !between[a][c].is_empty()
                                        && !between[b][c].is_empty()
                                })
                                .map(|c| (p.kinds[c], between[a][c].len(), between[b][c].len()))
                                .collect(),
                        )
                    })
                    .collect()
            })
            .collect();
        let eccentricity = (0..n)
            .map(|a| {
                let mut dist = vec![usize::MAX; n];
                dist[a] = 0;
                let mut queue = std::collections::VecDeque::from([a]);
                while let Some(u) = queue.pop_front() {
                    for &w in &neighbours[u] {
                        if dist[w] == usize::MAX {
                            dist[w] = dist[u] + 1;
                            queue.push_back(w);
                        }
                    }
                }
                dist.into_iter().max().unwrap_or(0)
            })
            .collect();
        let pairs: usize = neighbours.iter().map(Vec::len).sum::<usize>() / 2;
        let cycles = pairs as i64 - n as i64 + 1;
        let min_degree = neighbours.iter().map(Vec::len).min().unwrap_or(0);
        let digest = {
            use std::hash::{Hash, Hasher};
            let mut h = rustc_hash::FxHasher::default();
            (&rule.id, p).hash(&mut h);
            h.finish()
        };
        let mut compiled = CompiledRule {
            id: rule.id.clone(),
            digest,
            motif,
            kinds: p.kinds.clone(),
            between,
            neighbours,
            rods_only: p.kinds.iter().all(|k| *k == NodeKind::Rod),
            planar,
            needs,
            neighbour_degrees,
            eccentricity,
            cycles,
            min_degree,
            plans: Vec::new(),
            pair_plans: Vec::new(),
            orbit: (0..n).collect(),
            pair_orbit: (0..n).map(|a| (0..n).map(|b| (a, b)).collect()).collect(),
            common,
        };
        for sigma in compiled.automorphisms() {
            for a in 0..n {
                compiled.orbit[a] = compiled.orbit[a].min(sigma[a]);
                for b in 0..n {
                    let image = (sigma[a], sigma[b]);
                    compiled.pair_orbit[a][b] = compiled.pair_orbit[a][b].min(image);
                }
            }
        }
        compiled.plans = (0..n).map(|v| compiled.plan(&[v])).collect();
        compiled.pair_plans = (0..n)
            .map(|a| {
                (0..n)
                    .map(|b| {
                        (!compiled.between[a][b].is_empty())
                            .then(|| compiled.plan(&[a, b]))
                            .flatten()
                    })
                    .collect()
            })
            .collect();
        compiled
    }

    /// The pattern node to map next: the most mapped neighbours, then the
    /// most neighbours (a fixed order would explore far more partial maps);
    /// `None` when no unmapped node touches a mapped one.
    pub(super) fn next_node(&self, mapped: impl Fn(usize) -> bool) -> Option<usize> {
        (0..self.kinds.len())
            .filter(|&v| !mapped(v))
            .map(|v| {
                let m = self.neighbours[v].iter().filter(|&&w| mapped(w)).count();
                (m, self.neighbours[v].len(), std::cmp::Reverse(v))
            })
            .filter(|t| t.0 > 0)
            .max()
            .map(|t| t.2.0)
    }

    /// The automorphisms of the pattern that keep every rod label (node `a`
    /// goes to `sigma[a]`), or only the identity if there are too many to
    /// list cheaply. Matches map to matches under them.
    fn automorphisms(&self) -> Vec<Vec<usize>> {
        fn place(
            rule: &CompiledRule,
            between: &[Vec<Vec<(u8, u8)>>],
            a: usize,
            sigma: &mut Vec<usize>,
            used: &mut [bool],
            found: &mut Vec<Vec<usize>>,
            budget: &mut usize,
        ) -> bool {
            let n = rule.kinds.len();
            if a == n {
                found.push(sigma.clone());
                return true;
            }
            for b in 0..n {
                if *budget == 0 {
                    return false;
                }
                *budget -= 1;
                let fits = !used[b]
                    && rule.kinds[a] == rule.kinds[b]
                    && rule.neighbours[a].len() == rule.neighbours[b].len()
                    && (0..a).all(|c| between[a][c] == between[b][sigma[c]]);
                if fits {
                    sigma.push(b);
                    used[b] = true;
                    let ok = place(rule, between, a + 1, sigma, used, found, budget);
                    used[b] = false;
                    sigma.pop();
                    if !ok {
                        return false;
                    }
                }
            }
            true
        }
        let n = self.kinds.len();
        // Contacts as label multisets, comparable whatever their order.
        let mut between = self.between.clone();
        between.iter_mut().flatten().for_each(|v| v.sort_unstable());
        let mut found = Vec::new();
        let mut budget = 100_000;
        let (mut sigma, mut used) = (Vec::new(), vec![false; n]);
        if place(
            self,
            &between,
            0,
            &mut sigma,
            &mut used,
            &mut found,
            &mut budget,
        ) {
            found
        } else {
            vec![(0..n).collect()]
        }
    }

    /// The steps of the plain matcher's search from the pattern nodes
    /// `starts` (the order depends on the pattern alone), if it reaches
    /// every node.
    fn plan(&self, starts: &[usize]) -> Option<Vec<Step>> {
        let n = self.kinds.len();
        // The number of steps done when each node is mapped.
        let mut done = vec![None; n];
        for &v in starts {
            done[v] = Some(0);
        }
        let mut steps: Vec<Step> = Vec::new();
        while let Some(v) = self.next_node(|w| done[w].is_some()) {
            let back: Vec<usize> = self.neighbours[v]
                .iter()
                .copied()
                .filter(|&w| done[w].is_some())
                .collect();
            steps.push(Step {
                node: v,
                ready: back.iter().filter_map(|&w| done[w]).max().unwrap_or(0),
                back,
                degree: self.neighbours[v].len() as u32,
                distance: 0,
            });
            done[v] = Some(steps.len());
        }
        if done.contains(&None) {
            return None;
        }
        // Pattern distances from the starts, by breadth first.
        let mut dist = vec![u8::MAX; n];
        let mut queue = std::collections::VecDeque::new();
        for &v in starts {
            dist[v] = 0;
            queue.push_back(v);
        }
        while let Some(u) = queue.pop_front() {
            for &w in &self.neighbours[u] {
                if dist[w] == u8::MAX {
                    dist[w] = dist[u] + 1;
                    queue.push_back(w);
                }
            }
        }
        for step in &mut steps {
            step.distance = dist[step.node];
        }
        Some(steps)
    }

    pub fn rods_only(&self) -> bool {
        self.rods_only
    }

    pub fn n_nodes(&self) -> usize {
        self.kinds.len()
    }

    /// Ordered pairs of pattern nodes joined by a contact, that host nodes of
    /// classes `x` and `y` with `m` contacts between them could carry.
    pub fn contact_pairs(
        &self,
        x: Option<BodyClass>,
        y: Option<BodyClass>,
        m: usize,
    ) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.kinds.len()).flat_map(move |a| {
            self.neighbours[a]
                .iter()
                .filter(move |&&b| {
                    fits(self.kinds[a], x)
                        && fits(self.kinds[b], y)
                        && self.between[a][b].len() <= m
                })
                .map(move |&b| (a, b))
        })
    }
}

/// One step of the plain matcher's search: the pattern node it maps next,
/// its mapped neighbours, its degree, its distance from the start, and how
/// many steps are done when all its neighbours in `back` are mapped.
#[derive(Clone, Debug)]
pub(super) struct Step {
    pub node: usize,
    pub back: Vec<usize>,
    pub degree: u32,
    pub distance: u8,
    pub ready: usize,
}
