//! Which attempts of the rods-only rules a rod task can carry, decided for
//! all rules at once.
//!
//! An attempt puts pattern node `v` of a rule on the task's rod. It can
//! only succeed where the free rods' cores ([`super::cores`]) around the rod
//! hold what the pattern needs there: the rod lies in the core of the
//! pattern's least degree, its neighbours in that core have at least the
//! degrees of `v`'s neighbours (compared as counts over degree thresholds),
//! and the core's rods within `v`'s eccentricity of it have at least the
//! pattern's independent cycles. Attempts with the same requirements share
//! a *key*; a rod task tests its numbers against precomputed bit masks over
//! the keys (one AND per threshold), then marks the attempts of the keys
//! left, in the plain matcher's order.

use super::cores::FAR;
use super::rule::CompiledRule;

/// Degrees are compared at thresholds 1 to this; larger ones count as it.
pub(super) const THRESHOLDS: usize = 8;

/// The largest eccentricity whose cycles a rod task measures.
pub(super) const MAX_RADIUS: usize = 4;

/// What an attempt needs of the rod task.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
struct Key {
    /// The rule's least pattern degree: the core the match lies in.
    order: u8,
    /// The pattern node's eccentricity, and the pattern's cycles.
    eccentricity: u8,
    cycles: u8,
    /// By threshold `t` (from 1): `v`'s neighbours of at least `t` neighbours.
    want: [u8; THRESHOLDS],
    /// `v`'s distance from the nearest triangle, and cycle of at most 4
    /// nodes, of the pattern ([`NONE`] without one).
    short: [u8; 2],
}

/// No short cycle in the pattern.
const NONE: u8 = u8::MAX;

/// Each node's distance from the nearest node on a cycle of at most
/// `length` (3 or 4) nodes of the pattern whose adjacency is `neighbours`.
fn from_short_cycles(neighbours: &[Vec<usize>], length: usize) -> Vec<u8> {
    let n = neighbours.len();
    let adjacent = |a: usize, b: usize| neighbours[a].contains(&b);
    let on: Vec<bool> = (0..n)
        .map(|u| {
            neighbours[u].iter().any(|&a| {
                neighbours[a].iter().any(|&x| {
                    x != u
                        && (adjacent(u, x)
                            || (length == 4
                                && neighbours[x].iter().any(|&b| b != a && adjacent(u, b))))
                })
            })
        })
        .collect();
    let mut distance = vec![NONE; n];
    let mut queue: std::collections::VecDeque<usize> = (0..n).filter(|&u| on[u]).collect();
    for &u in &queue {
        distance[u] = 0;
    }
    while let Some(u) = queue.pop_front() {
        for &w in &neighbours[u] {
            if distance[w] == NONE {
                distance[w] = distance[u] + 1;
                queue.push_back(w);
            }
        }
    }
    distance
}

/// A set of keys or attempts, as bits.
type Words = Vec<u64>;

fn set(bits: &mut [u64], i: usize) {
    bits[i / 64] |= 1 << (i % 64);
}

/// The attempts of the rods-only rules and the masks that select them.
pub(super) struct Sieve {
    /// Attempts (rule, pattern node) by rule, then node; automorphic
    /// repeats of a node tried before are left out (they fail alike).
    pub attempts: Vec<(u32, u8)>,
    /// Each rule's first attempt (`rules + 1` entries).
    first: Vec<u32>,
    /// The attempts of each key.
    by_key: Vec<Vec<u32>>,
    /// Words in a set of keys.
    words: usize,
    /// The least and highest core order of the rules.
    pub low: u8,
    pub high: u8,
    /// The largest eccentricity (up to [`MAX_RADIUS`]) whose cycles are checked.
    pub radius: usize,
    /// The most cycles a key needs.
    pub most_cycles: u8,
    /// By level `l` (from `low`): the keys of order at most `l`.
    level: Vec<Words>,
    /// By order `m` (from `low`), threshold `t` and count `c`: the keys
    /// not of order `m`, or wanting at most `c` neighbours of degree `t`.
    want: Vec<Vec<Vec<Words>>>,
    /// By eccentricity `e` and cycles `y`: the keys not of eccentricity
    /// `e`, or needing at most `y` cycles.
    cycles: Vec<Vec<Words>>,
    /// By eccentricity `e`: the keys of eccentricity `e` or more.
    reach: Vec<Words>,
    /// By cycle length (3, then at most 4) and a rod's distance `f` from
    /// such a cycle of the host (at least [`FAR`] counting as it): the keys
    /// whose node lies at least `f` from one of the pattern ([`NONE`] when
    /// it has none).
    short: [Vec<Words>; 2],
}

impl Sieve {
    pub fn new(rules: &[CompiledRule]) -> Self {
        let mut attempts = Vec::new();
        let mut first = Vec::with_capacity(rules.len() + 1);
        let mut keys: Vec<Key> = Vec::new();
        for (k, rule) in rules.iter().enumerate() {
            first.push(attempts.len() as u32);
            if !rule.rods_only() {
                continue;
            }
            let [short3, short4] = [3, 4].map(|l| from_short_cycles(&rule.neighbours, l));
            for (v, (&s3, &s4)) in short3.iter().zip(&short4).enumerate() {
                if rule.orbit[v] < v {
                    continue;
                }
                let mut want = [0u8; THRESHOLDS];
                for &d in &rule.neighbour_degrees[v] {
                    for w in want.iter_mut().take((d as usize).min(THRESHOLDS)) {
                        *w += 1;
                    }
                }
                keys.push(Key {
                    order: rule.min_degree.min(u8::MAX as usize) as u8,
                    eccentricity: rule.eccentricity[v].min(u8::MAX as usize) as u8,
                    cycles: rule.cycles.clamp(0, u8::MAX as i64) as u8,
                    want,
                    short: [s3, s4],
                });
                attempts.push((k as u32, v as u8));
            }
        }
        first.push(attempts.len() as u32);
        let mut distinct: Vec<Key> = keys.clone();
        distinct.sort_unstable();
        distinct.dedup();
        let mut by_key = vec![Vec::new(); distinct.len()];
        for (i, key) in keys.iter().enumerate() {
            let at = distinct.binary_search(key).expect("a key of its own");
            by_key[at].push(i as u32);
        }
        let low = distinct.iter().map(|k| k.order).min().unwrap_or(1).max(1);
        let high = distinct.iter().map(|k| k.order).max().unwrap_or(1).max(low);
        let radius = distinct
            .iter()
            .map(|k| k.eccentricity as usize)
            .filter(|&e| e <= MAX_RADIUS)
            .max()
            .unwrap_or(0);
        let words = distinct.len().div_ceil(64);
        let mask = |keep: &dyn Fn(&Key) -> bool| {
            let mut bits = vec![0u64; words];
            for (i, key) in distinct.iter().enumerate() {
                if keep(key) {
                    set(&mut bits, i);
                }
            }
            bits
        };
        let level = (low..=high).map(|l| mask(&|k| k.order <= l)).collect();
        let most = distinct.iter().flat_map(|k| k.want).max().unwrap_or(0);
        let want = (low..=high)
            .map(|m| {
                (0..THRESHOLDS)
                    .map(|t| {
                        (0..=most)
                            .map(|c| mask(&|k| k.order != m || k.want[t] <= c))
                            .collect()
                    })
                    .collect()
            })
            .collect();
        let most_cycles = distinct.iter().map(|k| k.cycles).max().unwrap_or(0);
        let cycles = (0..=radius)
            .map(|e| {
                (0..=most_cycles)
                    .map(|y| mask(&|k| k.eccentricity as usize != e || k.cycles <= y))
                    .collect()
            })
            .collect();
        let deepest = distinct.iter().map(|k| k.eccentricity).max().unwrap_or(0);
        let reach = (0..=deepest)
            .map(|e| mask(&|k| k.eccentricity >= e))
            .collect();
        let short = [0, 1].map(|l| (0..=FAR).map(|f| mask(&|k| k.short[l] >= f)).collect());
        Sieve {
            short,
            reach,
            attempts,
            first,
            by_key,
            words,
            low,
            high,
            radius,
            most_cycles,
            level,
            want,
            cycles,
        }
    }

    /// Whether there is any rods-only rule.
    pub fn is_empty(&self) -> bool {
        self.attempts.is_empty()
    }

    /// Words in a set of keys.
    pub fn key_words(&self) -> usize {
        self.words
    }

    /// Words in a set of attempts.
    pub fn attempt_words(&self) -> usize {
        self.attempts.len().div_ceil(64)
    }

    /// The keys a rod at core level `level` (at least `low`) admits, given
    /// `counts[m - low][t]`: its neighbours in the `m`-core with at least
    /// `t + 1` neighbours there (for each order `m` up to `level`), into
    /// `keys`; whether any is left.
    pub fn admit(&self, level: u8, counts: &[[u32; THRESHOLDS]], keys: &mut [u64]) -> bool {
        let level = level.min(self.high);
        keys.copy_from_slice(&self.level[(level - self.low) as usize]);
        for (m, counts) in counts
            .iter()
            .enumerate()
            .take((level - self.low) as usize + 1)
        {
            let tables = &self.want[m];
            for (t, &c) in counts.iter().enumerate() {
                let table = &tables[t];
                let mask = &table[(c as usize).min(table.len() - 1)];
                for (k, m) in keys.iter_mut().zip(mask) {
                    *k &= m;
                }
            }
        }
        keys.iter().any(|&k| k != 0)
    }

    /// Keeps the keys whose short cycles can lie as close to the rod as
    /// the pattern's lie to its node: `from[l]` is its distance from a
    /// triangle (`l` 0) and a cycle of at most 4 rods (`l` 1), up to
    /// [`FAR`]; whether any is left.
    pub fn admit_short(&self, from: [u8; 2], keys: &mut [u64]) -> bool {
        for (l, table) in self.short.iter().enumerate() {
            for (k, m) in keys.iter_mut().zip(&table[from[l] as usize]) {
                *k &= m;
            }
        }
        keys.iter().any(|&k| k != 0)
    }

    /// Keeps the keys whose cycles the rod's surroundings hold: `cycles[e]`
    /// independent cycles among the core's rods within `e` of it; whether
    /// any is left.
    pub fn admit_cycles(&self, cycles: &[i64], keys: &mut [u64]) -> bool {
        for (e, table) in self.cycles.iter().enumerate() {
            let y = cycles[e].clamp(0, table.len() as i64 - 1) as usize;
            for (k, m) in keys.iter_mut().zip(&table[y]) {
                *k &= m;
            }
        }
        keys.iter().any(|&k| k != 0)
    }

    /// The largest eccentricity of `keys`.
    pub fn reach(&self, keys: &[u64]) -> usize {
        (0..self.reach.len())
            .rev()
            .find(|&e| keys.iter().zip(&self.reach[e]).any(|(k, m)| k & m != 0))
            .unwrap_or(0)
    }

    /// Numbers the attempts by their slots (`slot_of`) in [`Sieve::mark`].
    pub fn renumber(&mut self, slot_of: &[u32]) {
        for list in &mut self.by_key {
            for a in list.iter_mut() {
                *a = slot_of[*a as usize];
            }
        }
    }

    /// Marks the attempts of `keys` (by their numbers) in `marked`, cleared first.
    pub fn mark(&self, keys: &[u64], marked: &mut [u64]) {
        marked.fill(0);
        for (w, &word) in keys.iter().enumerate() {
            let mut word = word;
            while word != 0 {
                let b = word.trailing_zeros() as usize;
                word &= word - 1;
                for &a in &self.by_key[64 * w + b] {
                    set(marked, a as usize);
                }
            }
        }
    }

    /// The plain matcher's order from rule `start` on: its first attempt
    /// and the number of attempts (an attempt's place is its number less
    /// the first, cyclically).
    pub fn order_from(&self, start: usize) -> (u32, u32) {
        (self.first[start], self.attempts.len() as u32)
    }

    /// Sorts `attempts` in the plain matcher's order from rule `start` on:
    /// by rule cyclically, then by node.
    pub fn sort_from(&self, start: usize, attempts: &mut [u32]) {
        let split = self.first[start];
        let n = self.attempts.len() as u32;
        attempts.sort_unstable_by_key(|&a| (a + n - split) % n.max(1));
    }
}
