//! Motif rules loaded from files, matched in the compression state
//! (MODEL §6).
//!
//! A match maps pattern nodes to distinct host nodes and pattern contacts to
//! distinct host contacts. It is valid when every host node is at least as
//! generic as its pattern node (a rod for a rod, any body for a planar
//! body, a spatial body for a spatial one), the host has at least the
//! pattern's contacts between matched nodes, and the host has no
//! collinearity the pattern did not assume: host contacts of a node on one
//! rod carry one pattern rod label, and (under `sound`) three or more host
//! contacts between one plane of each side carry one label on a side
//! (`assignment` assigns the contacts of a complete node map).
//! Searches start from what changed: a rod at the start (rods-only rules),
//! or a pair of nodes whose relation a merge changed, mapped onto a pattern
//! contact.
//!
//! Four backtracking searches, each kept for a reason:
//! * [`State::extend`], the plain search, defines the answer: which match
//!   is met first, and so which merge a motif order makes. Everything else
//!   must find the same first match, and `Matching::Unindexed` runs it
//!   alone, so tests can compare.
//! * `survey` counts the complete maps, up to two, in the cheapest order:
//!   the plain order may walk a body's thousands of neighbours where
//!   another order reaches the same nodes through a rod. Most attempts end
//!   here with none.
//! * `extend_indexed` replays the plain order on the index's cached
//!   neighbour lists when the survey found two or more maps, since only the
//!   plain order says which of them comes first.
//! * [`super::ball::Ball::search`] is the same replay for rods-only rules
//!   with bit operations on the free rods around a rod task: the hot path of
//!   a dense system, where cached lists would be rebuilt for every task.

use super::assignment::assignable;
use super::demand::{accepts, fits};
use super::index::Index;
use super::rule::{CompiledRule, Step};
use super::ruleset::RuleSet;
use super::state::State;
use crate::body::BodyClass;

/// Neighbour lists longer than this are walked only after the later steps
/// are checked on shorter ones.
const LOOK_AHEAD: usize = 16;

impl State<'_> {
    /// Nodes adjacent to node `x`.
    fn adjacent(&mut self, x: u32) -> Vec<u32> {
        if self.class(x).is_some() {
            // Distinct already; the map's order is deterministic (Fx hashing,
            // one thread per compression), and bodies can have thousands.
            return self.neighbours(x).collect();
        }
        let g = self.g;
        let mut v: Vec<u32> = g.neighbors(x).iter().map(|&(nb, _)| nb).collect();
        for y in &mut v {
            *y = self.find(*y);
        }
        v.sort_unstable();
        v.dedup();
        v
    }

    /// A match of `rule` with pattern node `a` on host node `x` (and, when
    /// given, pattern node `b` on host node `y`).
    pub fn match_rule(
        &mut self,
        rule: &CompiledRule,
        a: usize,
        x: u32,
        b: Option<(usize, u32)>,
        rules: RuleSet,
        index: Option<&mut Index>,
    ) -> Option<(Vec<u32>, BodyClass)> {
        let n = rule.kinds.len();
        if !fits(rule.kinds[a], self.class(x)) {
            return None;
        }
        if self.degree(x) < rule.neighbours[a].len() {
            return None;
        }
        // Small patterns map on the stack: attempts are many, matches few.
        let (mut small, mut large) = ([None; 16], Vec::new());
        let map: &mut [Option<u32>] = if n <= small.len() {
            &mut small[..n]
        } else {
            large.resize(n, None);
            &mut large
        };
        map[a] = Some(x);
        if let Some((b, y)) = b {
            if b == a
                || x == y
                || !fits(rule.kinds[b], self.class(y))
                || !self.counts_fit(rule, map, b, y)
            {
                return None;
            }
            map[b] = Some(y);
        }
        let found = match index {
            Some(ix) => {
                let plan = match b {
                    None => rule.plans[a].as_ref(),
                    Some((b, _)) => rule.pair_plans[a][b].as_ref(),
                };
                plan.is_some_and(|plan| self.search_indexed(ix, rule, plan, map, rules))
            }
            None => self.extend(rule, map, rules),
        };
        if !found {
            return None;
        }
        let parts: Vec<u32> = map.iter().map(|m| m.expect("complete match")).collect();
        Some(self.matched(rule, parts))
    }

    /// [`State::match_rule`] for rods-only `rule` with pattern node `v` on
    /// the rod of the index's rod task, searched in the task's ball: the
    /// same complete maps in the same order, so the same match. `None` when
    /// the ball cannot be used.
    pub(super) fn match_in_ball(
        &mut self,
        ix: &mut Index,
        rule: &CompiledRule,
        v: usize,
        rules: RuleSet,
    ) -> Option<Option<(Vec<u32>, BodyClass)>> {
        let Some(plan) = &rule.plans[v] else {
            return Some(None);
        };
        let mut found = None;
        let searched = ix.search_ball(
            v,
            rule.eccentricity[v],
            rule.min_degree,
            plan,
            rule.kinds.len(),
            &mut |map| {
                let done = self.complete(rule, map, rules);
                if done {
                    found = Some(map.iter().map(|m| m.expect("complete map")).collect());
                }
                done
            },
        )?;
        debug_assert_eq!(searched, found.is_some());
        Some(found.map(|parts| self.matched(rule, parts)))
    }

    /// A complete match's parts and the class of the body they form.
    fn matched(&self, rule: &CompiledRule, parts: Vec<u32>) -> (Vec<u32>, BodyClass) {
        let planar = rule.planar
            && parts
                .iter()
                .all(|&p| self.class(p) != Some(BodyClass::Spatial));
        (
            parts,
            if planar {
                BodyClass::Planar
            } else {
                BodyClass::Spatial
            },
        )
    }

    /// Whether `rule` matches exactly the host nodes `parts`, in some order.
    pub fn matches_nodes(&mut self, rule: &CompiledRule, parts: &[u32], rules: RuleSet) -> bool {
        let n = rule.kinds.len();
        if n != parts.len() {
            return false;
        }
        let mut map: Vec<Option<u32>> = vec![None; n];
        self.place(rule, parts, 0, &mut map, rules)
    }

    /// Tries every host node of `parts` not yet used on pattern node `v`, then the next.
    fn place(
        &mut self,
        rule: &CompiledRule,
        parts: &[u32],
        v: usize,
        map: &mut [Option<u32>],
        rules: RuleSet,
    ) -> bool {
        if v == map.len() {
            return self.complete(rule, map, rules);
        }
        for &y in parts {
            if fits(rule.kinds[v], self.class(y)) && self.counts_fit(rule, map, v, y) {
                map[v] = Some(y);
                if self.place(rule, parts, v + 1, map, rules) {
                    return true;
                }
                map[v] = None;
            }
        }
        false
    }

    /// Whether host node `y` has at least the pattern's contacts with every
    /// mapped node that pattern node `v` touches.
    fn counts_fit(&mut self, rule: &CompiledRule, map: &[Option<u32>], v: usize, y: u32) -> bool {
        // A host node with fewer neighbours than the pattern node cannot carry it.
        if self.degree(y) < rule.neighbours[v].len() || map.contains(&Some(y)) {
            return false;
        }
        for &w in &rule.neighbours[v] {
            if let Some(hw) = map[w]
                && self.multiplicity(y, hw) < rule.between[v][w].len()
            {
                return false;
            }
        }
        true
    }

    /// Maps the remaining pattern nodes by backtracking over host neighbours,
    /// then assigns contacts.
    fn extend(&mut self, rule: &CompiledRule, map: &mut [Option<u32>], rules: RuleSet) -> bool {
        let Some(v) = rule.next_node(|v| map[v].is_some()) else {
            return map.iter().all(|m| m.is_some()) && self.complete(rule, map, rules);
        };
        // Candidates come from the mapped neighbour with the fewest neighbours.
        let anchor = rule.neighbours[v]
            .iter()
            .filter_map(|&w| map[w])
            .min_by_key(|&h| self.degree(h))
            .expect("v touches a mapped node");
        for y in self.adjacent(anchor) {
            if fits(rule.kinds[v], self.class(y)) && self.counts_fit(rule, map, v, y) {
                map[v] = Some(y);
                if self.extend(rule, map, rules) {
                    return true;
                }
                map[v] = None;
            }
        }
        false
    }

    /// [`State::extend`] with the index: the complete maps are first
    /// counted, up to two, in the cheapest order (the plain order may walk a
    /// body's thousands of neighbours where another reaches the same nodes
    /// through a rod). None: no match. One: the plain search would check
    /// that one alone. More: the plain order decides which is met first.
    fn search_indexed(
        &mut self,
        ix: &mut Index,
        rule: &CompiledRule,
        plan: &[Step],
        map: &mut [Option<u32>],
        rules: RuleSet,
    ) -> bool {
        let mut found = ix.take_maps();
        found.clear();
        self.survey(ix, rule, map, 2, &mut found);
        let n = map.len();
        ix.no_map = found.is_empty();
        let matched = match found.len() / n {
            0 => false,
            1 => {
                map.copy_from_slice(&found);
                self.complete(rule, map, rules)
            }
            _ => self.extend_indexed(ix, rule, plan, map, rules),
        };
        ix.give_maps(found);
        matched
    }

    /// Appends the complete maps extending `map` to `out` until it holds
    /// `limit` of them (then true), mapping next, among the pattern nodes
    /// with the most mapped neighbours, one with a host among them of the
    /// fewest neighbours, whose list is walked.
    fn survey(
        &mut self,
        ix: &mut Index,
        rule: &CompiledRule,
        map: &mut [Option<u32>],
        limit: usize,
        out: &mut Vec<Option<u32>>,
    ) -> bool {
        let n = map.len();
        let mut degrees = [0usize; 16];
        for (w, m) in map.iter().enumerate().take(16) {
            if let Some(h) = m {
                degrees[w] = self.degree(*h);
            }
        }
        let mut best: Option<((usize, usize), usize, usize)> = None;
        for v in (0..n).filter(|&v| map[v].is_none()) {
            let (mut m, mut d, mut at) = (0, usize::MAX, 0);
            for &w in &rule.neighbours[v] {
                if let Some(h) = map[w] {
                    m += 1;
                    let dw = degrees.get(w).copied().unwrap_or_else(|| self.degree(h));
                    if dw < d {
                        (d, at) = (dw, w);
                    }
                }
            }
            if m == 0 {
                continue;
            }
            let key = (usize::MAX - m, d);
            if best.is_none_or(|(c, _, _)| key < c) {
                best = Some((key, v, at));
            }
        }
        let Some((_, v, w)) = best else {
            if map.iter().all(Option::is_some) {
                out.extend_from_slice(map);
            }
            return out.len() >= limit * n;
        };
        let anchor = map[w].expect("mapped");
        let fits_v = accepts(rule.kinds[v]);
        let (need, degree) = (rule.between[v][w].len(), rule.neighbours[v].len());
        for i in 0..ix.n_neighbours(self, anchor) {
            let y = ix.neighbour(anchor, i);
            if !fits_v[y.class as usize] || (y.mult as usize) < need {
                continue;
            }
            let y = y.node;
            if self.degree(y) < degree
                || map.contains(&Some(y))
                || rule.neighbours[v].iter().any(|&u| {
                    u != w
                        && map[u]
                            .is_some_and(|hu| self.multiplicity(y, hu) < rule.between[v][u].len())
                })
                || !ix.profile(self, y).admits(&rule.needs[v])
            {
                continue;
            }
            map[v] = Some(y);
            let full = self.survey(ix, rule, map, limit, out);
            map[v] = None;
            if full {
                return true;
            }
        }
        false
    }

    /// [`State::extend`] on the index's cached neighbour lists, along the
    /// steps it would take (`plan`): the same candidates in the same order,
    /// so the same complete maps in the same order, except under a
    /// candidate whose neighbours cannot carry its pattern node's (no
    /// complete map there).
    fn extend_indexed(
        &mut self,
        ix: &mut Index,
        rule: &CompiledRule,
        plan: &[Step],
        map: &mut [Option<u32>],
        rules: RuleSet,
    ) -> bool {
        let Some((step, rest)) = plan.split_first() else {
            return self.complete(rule, map, rules);
        };
        let v = step.node;
        // The anchor as `extend` picks it: the first mapped neighbour of least degree.
        let w = *step
            .back
            .iter()
            .min_by_key(|&&w| self.degree(map[w].expect("mapped")))
            .expect("a step has a mapped neighbour");
        let anchor = map[w].expect("mapped");
        let fits_v = accepts(rule.kinds[v]);
        let (need, degree) = (rule.between[v][w].len(), step.degree as usize);
        let len = ix.n_neighbours(self, anchor);
        if len > LOOK_AHEAD && !self.later_steps_possible(ix, rule, rest, map) {
            return false;
        }
        for i in 0..len {
            let y = ix.neighbour(anchor, i);
            if !fits_v[y.class as usize] || (y.mult as usize) < need {
                continue;
            }
            let y = y.node;
            if self.degree(y) < degree
                || map.contains(&Some(y))
                || step.back.iter().any(|&u| {
                    u != w
                        && self.multiplicity(y, map[u].expect("mapped")) < rule.between[v][u].len()
                })
                || !ix.profile(self, y).admits(&rule.needs[v])
            {
                continue;
            }
            map[v] = Some(y);
            if self.extend_indexed(ix, rule, rest, map, rules) {
                return true;
            }
            map[v] = None;
        }
        false
    }

    /// Whether each of the later steps `rest` that touches a mapped node
    /// on a short list still has a host there (else no map completes);
    /// checked before a long list is walked.
    fn later_steps_possible(
        &mut self,
        ix: &mut Index,
        rule: &CompiledRule,
        rest: &[Step],
        map: &[Option<u32>],
    ) -> bool {
        rest.iter().all(|step| {
            let v = step.node;
            let Some((w, h, degree)) = step
                .back
                .iter()
                .filter_map(|&w| map[w].map(|h| (w, h, self.degree(h))))
                .min_by_key(|t| t.2)
            else {
                return true;
            };
            // A rod's contacts bound its neighbours: long lists stay unbuilt.
            if degree > LOOK_AHEAD {
                return true;
            }
            let len = ix.n_neighbours(self, h);
            let fits_v = accepts(rule.kinds[v]);
            (0..len).any(|i| {
                let y = ix.neighbour(h, i);
                fits_v[y.class as usize]
                    && y.mult as usize >= rule.between[v][w].len()
                    && self.degree(y.node) >= step.degree as usize
                    && !map.contains(&Some(y.node))
                    && step.back.iter().all(|&u| {
                        u == w
                            || map[u].is_none_or(|hu| {
                                self.multiplicity(y.node, hu) >= rule.between[v][u].len()
                            })
                    })
            })
        })
    }

    /// Whether a complete node mapping is a match: its contacts can be
    /// assigned and, under `sound`, the pattern its nodes induce is rigid.
    fn complete(&mut self, rule: &CompiledRule, map: &[Option<u32>], rules: RuleSet) -> bool {
        let assigned = assignable(self, rule, map, rules);
        if !assigned {
            return false;
        }
        let parts: Vec<u32> = map.iter().flatten().copied().collect();
        rules == RuleSet::Paper || self.induced_rigid(&parts)
    }
}
