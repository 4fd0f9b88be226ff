//! The plain search plans of all rods-only attempts as one trie, searched
//! once per rod task for which attempts have a complete map of their nodes.
//!
//! An attempt's plan ([`super::rule::Step`]s) maps one pattern node after
//! another onto ball rods that touch the rods its mapped neighbours are on;
//! written with step numbers instead of pattern nodes, the plans of
//! different rules and starts share their first steps. The trie searches
//! each shared prefix once, for all attempts below it, and leaves a subtree
//! once every attempt the task admits below it has a complete map. Which
//! complete map the plain search meets first, and whether it passes the
//! contact assignment and the induced rigidity, is left to each attempt's
//! own search: the trie only says which attempts can match at all.

use super::ball::{Ball, Bits, MAX_CORE, MAX_DEGREE, Set};
use super::rule::CompiledRule;

/// One step of a plan, by step numbers: the earlier steps (0 is the start)
/// whose rods it must touch, its pattern degree (up to [`MAX_DEGREE`]) and
/// its pattern distance from the start.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Key {
    back: Vec<u8>,
    degree: u8,
    distance: u8,
}

/// The class of a step of pattern degree `degree` (up to [`MAX_DEGREE`])
/// and distance `distance` from the start: its index in [`Tables::class`].
fn class(degree: u8, distance: u8) -> u8 {
    distance * (MAX_DEGREE as u8 + 1) + degree
}

/// A trie node: the last step of its prefix (its back steps and
/// [`class`]), its children (contiguous), the slots of the attempts below
/// it (and, where they lie in one word of a set of slots, that word and
/// their bits, else `u32::MAX`) and of those whose plans end here, and its
/// checks (in [`Trie::checks`]).
#[derive(Clone, Debug)]
struct Node {
    back: (u32, u8),
    class: u8,
    children: (u32, u32),
    slots: (u32, u32),
    word: (u32, u64),
    ends: (u32, u32),
    checks: (u32, u32),
}

/// A later step that every plan below a trie node has, with all the steps
/// it must touch in the node's prefix: once the prefix is mapped, a rod
/// must be left for it (its back steps in [`Trie::backs`]).
#[derive(Clone, Copy, Debug)]
struct Check {
    back: (u32, u8),
    class: u8,
}

/// The attempts' plans as a trie per group of attempts that search the
/// same rods (the same eccentricity and core order).
pub(super) struct Trie {
    nodes: Vec<Node>,
    backs: Vec<u8>,
    checks: Vec<Check>,
    /// By group: the eccentricity, the core order and the root node.
    groups: Vec<(u8, u8, u32)>,
    /// Each attempt's slot: attempts numbered in the trie's order, so a
    /// subtree's attempts are a range of slots.
    pub slot_of: Vec<u32>,
    pub attempt_of: Vec<u32>,
}

/// The state of one trie search: when only the first attempt in the plain
/// order is wanted, that order (where the cycle of attempts starts, and
/// their number); how many times the pending attempts changed; and the
/// ball's tables as one word (balls of at most 64 rods), two (at most
/// 128) or [`Bits`].
#[derive(Default)]
pub(super) struct Walk {
    first: Option<(u32, u32)>,
    changes: u32,
    small: Tables<u64>,
    medium: Tables<u128>,
    large: Tables<Bits>,
}

/// A ball's rows, the rods a step of each [`class`] can use (those of
/// `within` at most its distance from the root with at least its degree
/// of neighbours in the ball), and the ball rod of each step and the rods
/// used so far.
#[derive(Default)]
struct Tables<S> {
    rows: Vec<S>,
    class: Vec<S>,
    local: [u8; 32],
    used: S,
}

impl<S: Set> Tables<S> {
    /// Takes `within` as the rods a match can use, starting at the root,
    /// and (when `rows`) the rows of `ball`.
    fn start(&mut self, ball: &Ball, within: Bits, rows: bool) {
        if rows {
            self.rows.clear();
            self.rows.extend(ball.rows.iter().map(|&r| S::of(r)));
        }
        self.class.clear();
        for near in &ball.near {
            for wide in &ball.wide {
                self.class.push(S::of(within & *near & *wide));
            }
        }
        self.local[0] = ball.root as u8;
        self.used = S::default();
        self.used.insert(ball.root);
    }
}

impl Walk {
    /// The searches want the first attempt with a complete map in the
    /// plain order that starts at attempt `split` (of `n`), and leave the
    /// later ones unknown; or (`None`) every attempt with one.
    pub fn want_first(&mut self, first: Option<(u32, u32)>) {
        self.first = first;
    }
}

impl Trie {
    /// Stores a step's back steps in [`Trie::backs`]: where they start and
    /// how many.
    fn push_back(&mut self, back: &[u8]) -> (u32, u8) {
        let at = (self.backs.len() as u32, back.len() as u8);
        self.backs.extend_from_slice(back);
        at
    }

    /// The trie of the plans of `attempts` (rule, pattern node), whose
    /// plans exist and have at most 31 steps.
    pub fn new(rules: &[CompiledRule], attempts: &[(u32, u8)]) -> Self {
        let mut plans: Vec<((u8, u8), Vec<Key>, u32)> = attempts
            .iter()
            .enumerate()
            .map(|(a, &(k, v))| {
                let rule = &rules[k as usize];
                let v = v as usize;
                let plan = rule.plans[v]
                    .as_ref()
                    .expect("a rods-only rule is connected");
                let mut number = vec![0u8; rule.n_nodes()];
                let keys = plan
                    .iter()
                    .enumerate()
                    .map(|(i, step)| {
                        number[step.node] = i as u8 + 1;
                        let mut back: Vec<u8> = step
                            .back
                            .iter()
                            .map(|&w| if w == v { 0 } else { number[w] })
                            .collect();
                        back.sort_unstable();
                        Key {
                            back,
                            degree: (step.degree as usize).min(MAX_DEGREE) as u8,
                            distance: step.distance,
                        }
                    })
                    .collect();
                let group = (
                    rule.eccentricity[v].min(u8::MAX as usize) as u8,
                    rule.min_degree.min(MAX_CORE) as u8,
                );
                (group, keys, a as u32)
            })
            .collect();
        plans.sort_unstable();
        let attempt_of: Vec<u32> = plans.iter().map(|p| p.2).collect();
        let mut slot_of = vec![0u32; attempts.len()];
        for (s, &a) in attempt_of.iter().enumerate() {
            slot_of[a as usize] = s as u32;
        }
        let mut trie = Trie {
            nodes: Vec::new(),
            backs: Vec::new(),
            checks: Vec::new(),
            groups: Vec::new(),
            slot_of,
            attempt_of,
        };
        let mut lo = 0;
        while lo < plans.len() {
            let group = plans[lo].0;
            let hi = lo + plans[lo..].partition_point(|p| p.0 == group);
            let root = trie.nodes.len() as u32;
            trie.nodes.push(Node {
                back: (0, 0),
                class: 0,
                children: (0, 0),
                slots: (lo as u32, hi as u32),
                word: word(lo, hi),
                ends: (lo as u32, lo as u32),
                checks: (0, 0),
            });
            trie.grow(&plans, root, 0);
            trie.groups.push((group.0, group.1, root));
            lo = hi;
        }
        trie
    }

    /// Adds the children of `node`, whose prefix is the first `depth` steps
    /// of the plans in its slots, and their subtrees.
    fn grow(&mut self, plans: &[((u8, u8), Vec<Key>, u32)], node: u32, depth: usize) {
        let (lo, hi) = self.nodes[node as usize].slots;
        let (lo, hi) = (lo as usize, hi as usize);
        // Plans that end here sort first.
        let mut at = lo + plans[lo..hi].partition_point(|p| p.1.len() == depth);
        self.nodes[node as usize].ends = (lo as u32, at as u32);
        // The steps after the next that every plan below has and that touch
        // only the prefix (none where a plan ends here).
        if at == lo {
            let ready = |p: &'_ ((u8, u8), Vec<Key>, u32)| -> Vec<Key> {
                p.1.iter()
                    .skip(depth + 1)
                    .filter(|k| k.back.iter().all(|&b| usize::from(b) <= depth))
                    .cloned()
                    .collect()
            };
            let mut common = ready(&plans[lo]);
            for p in &plans[lo + 1..hi] {
                if common.is_empty() {
                    break;
                }
                let theirs = ready(p);
                common.retain(|k| theirs.contains(k));
            }
            common.sort_unstable();
            common.dedup();
            let from = self.checks.len() as u32;
            for k in common {
                let back = self.push_back(&k.back);
                self.checks.push(Check {
                    back,
                    class: class(k.degree, k.distance),
                });
            }
            self.nodes[node as usize].checks = (from, self.checks.len() as u32);
        }
        let first = self.nodes.len() as u32;
        while at < hi {
            let key = &plans[at].1[depth];
            let end = at + plans[at..hi].partition_point(|p| &p.1[depth] == key);
            let back = self.push_back(&key.back);
            self.nodes.push(Node {
                back,
                class: class(key.degree, key.distance),
                children: (0, 0),
                slots: (at as u32, end as u32),
                word: word(at, end),
                ends: (at as u32, at as u32),
                checks: (0, 0),
            });
            at = end;
        }
        let last = self.nodes.len() as u32;
        self.nodes[node as usize].children = (first, last);
        for child in first..last {
            self.grow(plans, child, depth + 1);
        }
    }

    /// The place of slot `s` in the plain order that starts at attempt
    /// `split` of `n`.
    pub fn rank(&self, s: u32, (split, n): (u32, u32)) -> u32 {
        (self.attempt_of[s as usize] + n - split) % n
    }

    /// Finds, among the attempts whose slots are set in `pending`, those
    /// with a complete map of their nodes into `ball` from its root, whose
    /// eccentricity is at most `radius`: clears their slots and appends
    /// them to `found`. When `walk` wants the first one only, each one
    /// found also clears the slots later than it in the plain order, which
    /// are then left unknown; those earlier than the first found and still
    /// set have no complete map.
    pub fn search(
        &self,
        ball: &mut Ball,
        radius: usize,
        pending: &mut [u64],
        found: &mut Vec<u32>,
        walk: &mut Walk,
    ) {
        let size = ball.rods.len();
        let mut rows = false;
        for &(eccentricity, order, root) in &self.groups {
            let node = &self.nodes[root as usize];
            if eccentricity as usize > radius || !any(pending, node.slots) {
                continue;
            }
            let within = ball.within(eccentricity as usize, order as usize);
            if !within.has(ball.root) {
                continue;
            }
            let first = walk.first;
            let changes = &mut walk.changes;
            if size <= 64 {
                walk.small.start(ball, within, !rows);
                self.explore(root, 0, &mut walk.small, first, changes, pending, found);
            } else if size <= 128 {
                walk.medium.start(ball, within, !rows);
                self.explore(root, 0, &mut walk.medium, first, changes, pending, found);
            } else {
                walk.large.start(ball, within, !rows);
                self.explore(root, 0, &mut walk.large, first, changes, pending, found);
            }
            rows = true;
        }
    }

    /// Searches below `node`, whose prefix maps its `depth + 1` steps to
    /// `t.local`: whether the later steps every plan below has can still
    /// be mapped, then each child's candidates in turn. A subtree is left
    /// once none of its attempts is pending (`changes` counts the times
    /// the pending attempts changed, which only then are looked at again).
    #[allow(clippy::too_many_arguments)]
    fn explore<S: Set>(
        &self,
        node: u32,
        depth: usize,
        t: &mut Tables<S>,
        first: Option<(u32, u32)>,
        changes: &mut u32,
        pending: &mut [u64],
        found: &mut Vec<u32>,
    ) {
        let here = &self.nodes[node as usize];
        let free = !t.used;
        let (from, to) = here.checks;
        for check in &self.checks[from as usize..to as usize] {
            if self.candidates(check.back, check.class, free, t).is_empty() {
                return;
            }
        }
        let (first_child, last_child) = here.children;
        for c in first_child..last_child {
            let child = &self.nodes[c as usize];
            if !live(pending, child) {
                continue;
            }
            let mut bits = self.candidates(child.back, child.class, free, t);
            if bits.is_empty() {
                continue;
            }
            let mut seen = *changes;
            for s in child.ends.0..child.ends.1 {
                let (w, b) = (s as usize / 64, s % 64);
                if pending[w] & (1 << b) != 0 {
                    pending[w] &= !(1 << b);
                    found.push(s);
                    if let Some(order) = first {
                        self.clear_later(s, order, pending);
                    }
                    *changes = changes.wrapping_add(1);
                }
            }
            if child.children.0 == child.children.1 {
                continue;
            }
            while let Some(i) = bits.pop() {
                if *changes != seen {
                    if !live(pending, child) {
                        break;
                    }
                    seen = *changes;
                }
                t.local[depth + 1] = i as u8;
                t.used.insert(i);
                self.explore(c, depth + 1, t, first, changes, pending, found);
                t.used.remove(i);
            }
        }
    }
}

impl Trie {
    /// The rods left of `free` for a step of [`class`] `class` that touches
    /// the rods of the steps `back` (in [`Trie::backs`]).
    #[inline]
    fn candidates<S: Set>(&self, (at, len): (u32, u8), class: u8, free: S, t: &Tables<S>) -> S {
        let mut bits = free & t.class[class as usize];
        for &b in &self.backs[at as usize..at as usize + len as usize] {
            bits &= t.rows[t.local[b as usize] as usize];
        }
        bits
    }

    /// Clears the slots of `pending` later than slot `s` in `order`.
    fn clear_later(&self, s: u32, order: (u32, u32), pending: &mut [u64]) {
        let rank = self.rank(s, order);
        for (w, word) in pending.iter_mut().enumerate() {
            let mut bits = *word;
            while bits != 0 {
                let b = bits.trailing_zeros();
                bits &= bits - 1;
                if self.rank(64 * w as u32 + b, order) > rank {
                    *word &= !(1 << b);
                }
            }
        }
    }
}

/// The word of a set of slots that holds the slots `lo..hi` (not empty),
/// and their bits there, if one does (else `u32::MAX`).
fn word(lo: usize, hi: usize) -> (u32, u64) {
    if lo / 64 != (hi - 1) / 64 {
        return (u32::MAX, 0);
    }
    let bits = (u64::MAX << (lo % 64)) & (u64::MAX >> (63 - (hi - 1) % 64));
    ((lo / 64) as u32, bits)
}

/// Whether any slot below `node` is set in `pending`.
#[inline(always)]
fn live(pending: &[u64], node: &Node) -> bool {
    match node.word {
        (u32::MAX, _) => any(pending, node.slots),
        (w, bits) => pending[w as usize] & bits != 0,
    }
}

/// Whether any bit of `bits` in `lo..hi` is set.
#[inline(always)]
fn any(bits: &[u64], (lo, hi): (u32, u32)) -> bool {
    let (lo, hi) = (lo as usize, hi as usize);
    if lo >= hi {
        return false;
    }
    let (first, last) = (lo / 64, (hi - 1) / 64);
    let head = u64::MAX << (lo % 64);
    let tail = u64::MAX >> (63 - (hi - 1) % 64);
    if first == last {
        return bits[first] & head & tail != 0;
    }
    bits[first] & head != 0
        || bits[first + 1..last].iter().any(|&w| w != 0)
        || bits[last] & tail != 0
}
