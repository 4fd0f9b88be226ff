//! Compression runs: the [`Engine`] and its worklist. A run repeatedly
//! finds a rigid motif and merges its nodes into one body, drawing tasks in
//! random order: every rod first (for the rods-only motifs), then every
//! pair of nodes whose relation a merge changed (for the motifs with
//! bodies).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::base::Found;
use super::certify;
use super::compression::Compression;
use super::index::Index;
use super::motif::{Motif, MotifCounts};
use super::rule::CompiledRule;
use super::ruleset::RuleSet;
use super::state::State;
use crate::body::Body;
use crate::graph::ContactGraph;
use crate::{Error, Result};

/// Something to examine: a rod (rods-only motifs) or a body and a node whose
/// relation to it changed (motifs with bodies).
#[derive(Clone, Copy, Debug)]
enum Task {
    Rod(u32),
    Pair(u32, u32),
}

/// What one compression did besides its outcome: its tasks, the searches
/// of loaded rules they made, and its merges (a measure of work apart from
/// time, for `rgc bench`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Work {
    /// Rod tasks on a rod still free.
    pub rod_tasks: u64,
    /// Pair tasks on two distinct nodes.
    pub pair_tasks: u64,
    /// Searches of a loaded rule from a task: the attempts the index left.
    pub attempts: u64,
    /// Merges, and those of them that loaded rules made.
    pub merges: u64,
    pub rule_merges: u64,
    /// Nanoseconds spent matching loaded rules (and keeping their index),
    /// when timed: the rest is the base engine's work.
    pub rule_nanos: u64,
    #[serde(skip)]
    timed: bool,
}

impl Work {
    /// Runs `f`, adding its time to [`Work::rule_nanos`] when timed.
    fn rules<T>(&mut self, f: impl FnOnce(&mut Work) -> T) -> T {
        if !self.timed {
            return f(self);
        }
        let t = std::time::Instant::now();
        let out = f(self);
        self.rule_nanos += t.elapsed().as_nanos() as u64;
        out
    }
}

/// What the engine compresses with: the rule set, whether the built-in base
/// motifs are on, and rules loaded from files.
#[derive(Clone, Copy, Debug)]
pub struct Engine<'r> {
    pub rules: RuleSet,
    /// The built-in base motifs (off only to test the same motifs given as rules).
    pub base: bool,
    pub extra: &'r [CompiledRule],
}

impl<'r> Engine<'r> {
    /// The built-in base motifs only.
    pub fn base(rules: RuleSet) -> Self {
        Engine {
            rules,
            base: true,
            extra: &[],
        }
    }

    /// The base motifs plus loaded rules.
    pub fn with_rules(rules: RuleSet, extra: &'r [CompiledRule]) -> Self {
        Engine {
            rules,
            base: true,
            extra,
        }
    }

    /// `runs` independent compressions of `graph` (rayon), in run order.
    pub fn runs(&self, graph: &ContactGraph, seed: u64, runs: usize) -> Vec<Compression> {
        (0..runs as u64)
            .into_par_iter()
            .map(|k| {
                self.compress(graph, &[], run_seed(seed, k))
                    .expect("no declared bodies to reject")
            })
            .collect()
    }

    /// Compresses `graph` once, starting from `bodies` declared rigid (rods of
    /// a body need no contacts among them: the host of a mixed motif), with
    /// the order of motif application drawn from `seed`.
    pub fn compress(
        &self,
        graph: &ContactGraph,
        bodies: &[Body],
        seed: u64,
    ) -> Result<Compression> {
        if self.rules == RuleSet::Certified {
            let sound = Engine {
                rules: RuleSet::Sound,
                ..*self
            };
            let run = compress_engine(
                &sound,
                graph,
                bodies,
                seed,
                Matching::Indexed,
                &mut Work::default(),
            )?;
            // A graph without geometry is a finite framework; a generated
            // system certifies with its box (`certify::certify`).
            let topo = crate::truth::Topology::finite(graph);
            return Ok(certify::certify(&topo, run, seed));
        }
        compress_engine(
            self,
            graph,
            bodies,
            seed,
            Matching::Indexed,
            &mut Work::default(),
        )
    }

    /// [`Engine::compress`] from no bodies (`sound` or `paper`), with what
    /// it did, and (when `timed`) the time it spent on loaded rules, which
    /// the clock's own cost inflates.
    pub fn compress_measured(
        &self,
        graph: &ContactGraph,
        seed: u64,
        timed: bool,
    ) -> (Compression, Work) {
        let mut work = Work {
            timed,
            ..Work::default()
        };
        let engine = Engine {
            rules: match self.rules {
                RuleSet::Certified => RuleSet::Sound,
                r => r,
            },
            ..*self
        };
        let run = compress_engine(&engine, graph, &[], seed, Matching::Indexed, &mut work)
            .expect("no declared bodies to reject");
        (run, work)
    }

    /// [`Engine::compress`] with the loaded rules matched as `matching`
    /// says: the unindexed and audited matchers are references the indexed
    /// one must reproduce exactly (tests only).
    #[doc(hidden)]
    pub fn compress_matching(
        &self,
        graph: &ContactGraph,
        bodies: &[Body],
        seed: u64,
        matching: Matching,
    ) -> Result<Compression> {
        let engine = Engine {
            rules: match self.rules {
                RuleSet::Certified => RuleSet::Sound,
                r => r,
            },
            ..*self
        };
        let run = compress_engine(&engine, graph, bodies, seed, matching, &mut Work::default())?;
        Ok(match self.rules {
            RuleSet::Certified => {
                certify::certify(&crate::truth::Topology::finite(graph), run, seed)
            }
            _ => run,
        })
    }
}

/// How loaded rules are matched (tests compare them; the engine indexes).
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Matching {
    /// Every rule at every pattern node or contact: the plain backtracking.
    Unindexed,
    /// Attempts the index shows cannot match are skipped.
    Indexed,
    /// As indexed, and every skipped attempt is matched anyway, panicking
    /// if it would have matched.
    Audited,
}

/// Compresses `graph` once, with the order of motif application drawn from `seed`.
pub fn compress(graph: &ContactGraph, rules: RuleSet, seed: u64) -> Compression {
    compress_from(graph, &[], rules, seed).expect("no declared bodies to reject")
}

/// Compresses `graph` once, starting from `bodies` declared rigid.
pub fn compress_from(
    graph: &ContactGraph,
    bodies: &[Body],
    rules: RuleSet,
    seed: u64,
) -> Result<Compression> {
    Engine::base(rules).compress(graph, bodies, seed)
}

/// One compression, with loaded rules matched as `matching` says (the same
/// result every way).
fn compress_engine(
    engine: &Engine,
    graph: &ContactGraph,
    bodies: &[Body],
    seed: u64,
    matching: Matching,
    work: &mut Work,
) -> Result<Compression> {
    let rules = engine.rules;
    check_bodies(graph, bodies)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut state = State::new(graph);
    let mut counts = MotifCounts::default();
    let mut sequence = Vec::new();
    let mut tasks: Vec<Task> = Vec::new();
    let declared: Vec<u32> = bodies
        .iter()
        .map(|body| {
            let node = state.merge(&body.rods, body.class).0;
            for plane in &body.planes {
                state.put_in_plane(plane);
            }
            node
        })
        .collect();
    // Every declared body with every neighbour, independently of what the
    // merges reported as changed: a restart from a finished run's bodies is
    // then an exhaustive check that the run left no motif behind.
    for b in declared {
        let b = state.find(b);
        tasks.extend(state.neighbours(b).map(|y| Task::Pair(b, y)));
    }
    let mut index = work.rules(|_| {
        (matching != Matching::Unindexed && !engine.extra.is_empty())
            .then(|| Index::new(&mut state, engine.extra, matching == Matching::Audited))
    });
    tasks.extend(
        (0..graph.n_nodes() as u32)
            .filter(|&r| graph.degree(r) >= 2)
            .map(Task::Rod),
    );
    let mut buf = Vec::new();
    while !tasks.is_empty() {
        let task = tasks.swap_remove(rng.random_range(0..tasks.len()));
        let found = match task {
            Task::Rod(r) => {
                if !state.is_free_rod(r) {
                    continue;
                }
                work.rod_tasks += 1;
                let rules_first = rng.random::<bool>();
                let base = |state: &mut State, rng: &mut ChaCha8Rng| {
                    if !engine.base {
                        None
                    } else if rng.random::<bool>() {
                        state.community(r).or_else(|| state.k24(r))
                    } else {
                        state.k24(r).or_else(|| state.community(r))
                    }
                };
                let mut rules = |state: &mut State, rng: &mut ChaCha8Rng| {
                    work.rules(|work| {
                        let hit = rod_rules(state, engine, r, rng, index.as_mut(), work);
                        if hit.is_none()
                            && let Some(ix) = index.as_mut()
                        {
                            ix.leave(state, r);
                        }
                        hit
                    })
                };
                if rules_first {
                    rules(&mut state, &mut rng).or_else(|| base(&mut state, &mut rng))
                } else {
                    base(&mut state, &mut rng).or_else(|| rules(&mut state, &mut rng))
                }
            }
            Task::Pair(x, y) => {
                let (x, y) = (state.find(x), state.find(y));
                if x == y {
                    continue;
                }
                work.pair_tasks += 1;
                let mut loaded = |state: &mut State, rng: &mut ChaCha8Rng| {
                    work.rules(|work| pair_rules(state, engine, x, y, rng, index.as_mut(), work))
                };
                let mut base = |state: &mut State, rng: &mut ChaCha8Rng| {
                    engine
                        .base
                        .then(|| examine_pair(state, x, y, rules, rng, &mut buf))
                        .flatten()
                };
                if rng.random::<bool>() {
                    loaded(&mut state, &mut rng).or_else(|| base(&mut state, &mut rng))
                } else {
                    base(&mut state, &mut rng).or_else(|| loaded(&mut state, &mut rng))
                }
            }
        };
        if let Some(Found {
            motif,
            parts,
            class,
        }) = found
        {
            counts.add(motif);
            sequence.push(motif);
            work.merges += 1;
            work.rule_merges += u64::from(motif == Motif::Rule);
            let leaving: Vec<u32> = match index {
                Some(_) => parts
                    .iter()
                    .copied()
                    .filter(|&p| state.is_free_rod(p))
                    .collect(),
                None => Vec::new(),
            };
            let (node, changed) = state.merge(&parts, class);
            if let Some(index) = index.as_mut() {
                work.rules(|_| {
                    for &r in &leaving {
                        index.leave(&state, r);
                    }
                    // The parts (the merged node among them) and every node
                    // whose neighbours changed (`State::merge` reports them).
                    for &x in parts.iter().chain(&changed) {
                        index.invalidate(x);
                    }
                });
            }
            tasks.extend(changed.into_iter().map(|y| Task::Pair(node, y)));
        }
    }
    let mut bodies: Vec<Body> = state
        .bodies()
        .map(|(rods, class, planes)| {
            let mut rods = rods.to_vec();
            rods.sort_unstable();
            Body {
                rods,
                class,
                planes,
            }
        })
        .collect();
    bodies.sort_by(|a, b| {
        b.rods
            .len()
            .cmp(&a.rods.len())
            .then(a.rods[0].cmp(&b.rods[0]))
    });
    Ok(Compression {
        bodies,
        components: state.n_nodes(),
        motifs: counts,
        sequence,
        refuted: 0,
        undecided: false,
    })
}

/// Declared bodies must have two or more rods each, in range, and be disjoint.
fn check_bodies(graph: &ContactGraph, bodies: &[Body]) -> Result<()> {
    let mut owner = vec![usize::MAX; graph.n_nodes()];
    for (k, body) in bodies.iter().enumerate() {
        if body.rods.len() < 2 {
            return Err(Error::Parameter(format!(
                "declared body {k} has {} rod(s); a body has at least two",
                body.rods.len()
            )));
        }
        for &r in &body.rods {
            let slot = owner.get_mut(r as usize).ok_or_else(|| {
                Error::Parameter(format!(
                    "declared body {k} names rod {r}, outside 0..{}",
                    graph.n_nodes()
                ))
            })?;
            if *slot != usize::MAX {
                return Err(Error::Parameter(format!(
                    "rod {r} is declared in body {} and body {k}",
                    *slot
                )));
            }
            *slot = k;
        }
        let mut in_plane = std::collections::HashSet::new();
        for plane in &body.planes {
            for &r in plane {
                if !body.rods.contains(&r) || !in_plane.insert(r) {
                    return Err(Error::Parameter(format!(
                        "declared body {k}: plane rod {r} is not a rod of the body, or is in two planes"
                    )));
                }
            }
        }
    }
    Ok(())
}

/// Tries the rods-only loaded rules with rod `r` on each pattern node, from
/// a random rule on, skipping the nodes `index` shows `r` cannot carry.
/// (Kept out of the worklist's loop, which the base engine runs alone.)
#[inline(never)]
fn rod_rules(
    state: &mut State,
    engine: &Engine,
    r: u32,
    rng: &mut ChaCha8Rng,
    index: Option<&mut Index>,
    work: &mut Work,
) -> Option<Found> {
    let n = engine.extra.len();
    if n == 0 {
        return None;
    }
    let start = rng.random_range(0..n);
    let Some(ix) = index else {
        for k in 0..n {
            let rule = &engine.extra[(start + k) % n];
            if !rule.rods_only() {
                continue;
            }
            for v in 0..rule.n_nodes() {
                work.attempts += 1;
                if let Some(hit) = state.match_rule(rule, v, r, None, engine.rules, None) {
                    return Some(Found::of_rule(rule, hit));
                }
            }
        }
        return None;
    };
    let admitted = ix.start_rod(state, r, start, ix.audit);
    if ix.audit {
        return audited_rod_rules(state, engine, r, start, ix, admitted);
    }
    if !admitted {
        return None;
    }
    while let Some((k, v)) = ix.next_rod_attempt() {
        let rule = &engine.extra[k];
        work.attempts += 1;
        let hit = match state.match_in_ball(ix, rule, v, engine.rules) {
            Some(hit) => hit,
            None => state.match_rule(rule, v, r, None, engine.rules, Some(&mut *ix)),
        };
        if let Some(hit) = hit {
            return Some(Found::of_rule(rule, hit));
        }
    }
    None
}

/// [`rod_rules`] with every attempt the index skips matched anyway
/// (panicking if it would have matched), and every attempt it makes
/// matched plainly too, to compare.
fn audited_rod_rules(
    state: &mut State,
    engine: &Engine,
    r: u32,
    start: usize,
    ix: &mut Index,
    admitted: bool,
) -> Option<Found> {
    let n = engine.extra.len();
    let attempts: Vec<(usize, usize)> = if admitted {
        ix.rod_attempts().collect()
    } else {
        Vec::new()
    };
    for k in (0..n).map(|k| (start + k) % n) {
        let rule = &engine.extra[k];
        if !rule.rods_only() {
            continue;
        }
        for v in 0..rule.n_nodes() {
            let plain = state.match_rule(rule, v, r, None, engine.rules, None);
            if !attempts.contains(&(k, v)) {
                assert!(
                    plain.is_none(),
                    "the index skipped a match of rule {} at rod {r}",
                    rule.id
                );
                continue;
            }
            let hit = match state.match_in_ball(ix, rule, v, engine.rules) {
                Some(hit) => hit,
                None => state.match_rule(rule, v, r, None, engine.rules, Some(&mut *ix)),
            };
            assert_eq!(hit, plain, "rule {} at rod {r}", rule.id);
            if let Some(hit) = hit {
                return Some(Found::of_rule(rule, hit));
            }
        }
    }
    None
}

/// Tries the loaded rules with bodies on the changed pair `x`, `y` mapped
/// onto each pattern contact, from a random rule on, skipping the contacts
/// `index` shows the pair cannot carry (kept out of the loop too).
#[inline(never)]
fn pair_rules(
    state: &mut State,
    engine: &Engine,
    x: u32,
    y: u32,
    rng: &mut ChaCha8Rng,
    mut index: Option<&mut Index>,
    work: &mut Work,
) -> Option<Found> {
    let n = engine.extra.len();
    if n == 0 {
        return None;
    }
    let (cx, cy) = (state.class(x), state.class(y));
    let m = state.multiplicity(x, y);
    let start = rng.random_range(0..n);
    if let Some(ix) = index.as_deref_mut() {
        if !ix.has_pair_rules() {
            return None;
        }
        ix.start_pair(state, x, y, m);
    }
    let Some(ix) = index else {
        for k in 0..n {
            let rule = &engine.extra[(start + k) % n];
            if rule.rods_only() {
                continue;
            }
            let hit = rule.contact_pairs(cx, cy, m).find_map(|(a, b)| {
                work.attempts += 1;
                state.match_rule(rule, a, x, Some((b, y)), engine.rules, None)
            });
            if let Some(hit) = hit {
                return Some(Found::of_rule(rule, hit));
            }
        }
        return None;
    };
    // The audit walks every rule, to match each skipped attempt anyway.
    let rules: Vec<usize> = if ix.audit {
        (0..n).map(|k| (start + k) % n).collect()
    } else {
        ix.candidates(start).collect()
    };
    for k in rules {
        let rule = &engine.extra[k];
        for j in 0..ix.entries(k, cx, cy).len() {
            let e = ix.entries(k, cx, cy)[j];
            let (a, b) = (e.a, e.b);
            if e.mult > m {
                continue;
            }
            let skip = rule.pair_orbit[a][b] < (a, b)
                || ix.dead(&e)
                || !ix.pair_could_match(state, &e) && {
                    ix.kill(&e);
                    true
                };
            if skip {
                assert!(
                    !ix.audit
                        || state
                            .match_rule(rule, a, x, Some((b, y)), engine.rules, None)
                            .is_none(),
                    "the index skipped a match of rule {} at nodes {x}, {y}",
                    rule.id
                );
                continue;
            }
            work.attempts += 1;
            // No node map unless the search finds one.
            ix.no_map = true;
            let hit = state.match_rule(rule, a, x, Some((b, y)), engine.rules, Some(&mut *ix));
            if hit.is_none() && ix.no_map {
                ix.kill(&e);
            }
            if ix.audit {
                let plain = state.match_rule(rule, a, x, Some((b, y)), engine.rules, None);
                assert_eq!(hit, plain, "rule {} at nodes {x}, {y}", rule.id);
            }
            if let Some(hit) = hit {
                return Some(Found::of_rule(rule, hit));
            }
        }
    }
    None
}

/// Tries, in random order, every motif with bodies that contains both `x` and `y`.
fn examine_pair(
    state: &mut State,
    x: u32,
    y: u32,
    rules: RuleSet,
    rng: &mut ChaCha8Rng,
    buf: &mut Vec<u32>,
) -> Option<Found> {
    let (body, other) = match (state.class(x), state.class(y)) {
        (Some(_), _) => (x, y),
        (None, Some(_)) => (y, x),
        (None, None) => return None,
    };
    let start = rng.random_range(0..3usize);
    if state.class(other).is_some() {
        (0..3).find_map(|k| match (start + k) % 3 {
            0 => state.d2a(body, other, rules),
            1 => state.d3a(body, other, rules),
            _ => state.d3b_bodies(body, other, rules, buf),
        })
    } else {
        (0..3).find_map(|k| match (start + k) % 3 {
            0 => state.d2b(body, other, buf),
            1 => state.d3b_rod(body, other, rules, buf),
            _ => state.d4(body, other, rules, buf),
        })
    }
}

/// The seed of run `k` of a sample seeded with `seed` (SplitMix64 of both),
/// so runs are independent and the same whatever the thread count.
pub fn run_seed(seed: u64, k: u64) -> u64 {
    let mut z = seed ^ k.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The most independent compressions one call makes (`rgc sample --runs`,
/// the Python module's `runs`): it keeps the runs' answers within memory.
pub const MAX_RUNS: u64 = 100_000;

/// Bytes one run's state holds per node and per contact while it runs,
/// and its outcome per node after (its bodies): measured at 60 to 70, 75
/// and 13 bytes on gamma 23 graphs of 320,000 rods and on isolated nodes.
const RUN_NODE_BYTES: u64 = 64;
const RUN_CONTACT_BYTES: u64 = 80;
const OUTCOME_NODE_BYTES: u64 = 16;

/// What `runs` compressions of a graph of `nodes` nodes and `contacts`
/// contacts hold at their peak, bytes: the state of the runs in flight (one
/// per worker thread) and the outcomes of all of them.
pub fn runs_memory(nodes: usize, contacts: usize, runs: usize) -> u64 {
    let (n, m, runs) = (nodes as u64, contacts as u64, runs as u64);
    let in_flight = runs.min(rayon::current_num_threads() as u64);
    in_flight * (RUN_NODE_BYTES * n + RUN_CONTACT_BYTES * m) + runs * OUTCOME_NODE_BYTES * n
}

/// Refuses, before any run, `runs` compressions of a graph of this size
/// that would take the process past `limit` (or what the machine or an
/// address-space limit leaves), with `more` bytes still to come before
/// them (the graph itself, where it is not built yet).
pub fn check_runs_memory(
    nodes: usize,
    contacts: usize,
    runs: usize,
    more: u64,
    limit: Option<u64>,
) -> Result<()> {
    let need = runs_memory(nodes, contacts, runs) + more;
    crate::usage::reserve(need, 0, limit).map_err(|r| {
        let what = format!("{runs} compression(s) of {nodes} rods and {contacts} contacts");
        Error::Memory(r.describe(&what))
    })?;
    Ok(())
}

/// `runs` independent compressions of `graph` (rayon), in run order.
pub fn compress_runs(
    graph: &ContactGraph,
    rules: RuleSet,
    seed: u64,
    runs: usize,
) -> Vec<Compression> {
    Engine::base(rules).runs(graph, seed, runs)
}
