//! What the index knows of a rule set before any host: the rods-only
//! rules' sieve and trie, and the pattern contacts of the rules with bodies
//! by class pair with their shared conditions. Built once per distinct rule
//! set in a process and shared by every compression with it (building it
//! for 1,569 rules takes tens of milliseconds, more than compressing a small
//! system).

use std::sync::{Arc, LazyLock, Mutex};

use super::demand::{CommonNeeds, Needs, accepts};
use super::rule::CompiledRule;
use super::sieve::Sieve;
use super::trie::Trie;

/// A pattern contact of a rule with bodies whose ends fit a class pair, and
/// the numbers of its conditions in the [`Catalog`]'s tables.
#[derive(Clone, Copy, Debug)]
pub(super) struct PairEntry {
    pub a: usize,
    pub b: usize,
    /// Pattern contacts between `a` and `b`: the host pair needs as many.
    pub mult: usize,
    pub need_a: usize,
    pub need_b: usize,
    pub common: usize,
}

/// The pattern contacts of all rules that share their conditions, for one
/// class pair: the rules that have one, as bits. A class pair's list is
/// sorted by contacts between the ends, then by the conditions on `x`, then
/// on `y`, and `skip_a`, `skip_b` are where the run of the same contacts
/// and condition on `x` (and on `y`) ends, so a failed condition skips its run.
#[derive(Clone, Debug)]
pub(super) struct Shared {
    pub entry: PairEntry,
    pub rules: Vec<u64>,
    pub skip_a: usize,
    pub skip_b: usize,
}

/// A rule set's tables for matching all its rules at once.
pub(super) struct Catalog {
    /// Each rule's digest, in order: what identifies the rule set.
    digests: Vec<u64>,
    pub sieve: Sieve,
    pub trie: Trie,
    /// By rule, by class pair (`3 * class x + class y`), the pattern
    /// contacts in the order the plain matcher tries them.
    pub entries: Vec<[Vec<PairEntry>; 9]>,
    /// By class pair, the distinct conditions of the entries.
    pub shared: [Vec<Shared>; 9],
    /// Distinct [`Needs`] and [`CommonNeeds`] of all entries.
    pub needs: Vec<Needs>,
    pub commons: Vec<CommonNeeds>,
    /// Whether some rule has a body.
    pub has_pair_rules: bool,
}

/// Rule sets whose catalogs are kept, most recently used first.
const KEPT: usize = 8;

static CATALOGS: LazyLock<Mutex<Vec<Arc<Catalog>>>> = LazyLock::new(Default::default);

/// Finds `item` in `list`, appending it if new; its position.
fn intern<T: PartialEq + Clone>(list: &mut Vec<T>, item: &T) -> usize {
    list.iter().position(|x| x == item).unwrap_or_else(|| {
        list.push(item.clone());
        list.len() - 1
    })
}

/// Builds the catalog of `rules` now (or finds it built), so that the
/// first compression with them does not pay for it: what loading a rule
/// set costs besides reading and verifying it.
pub fn prepare(rules: &[CompiledRule]) {
    Catalog::of(rules);
}

impl Catalog {
    /// The catalog of `rules`, built unless one of the same rules (by their
    /// digests, in order) was built before.
    pub fn of(rules: &[CompiledRule]) -> Arc<Catalog> {
        let same = |c: &Catalog| {
            c.digests.len() == rules.len()
                && c.digests.iter().zip(rules).all(|(&d, r)| d == r.digest)
        };
        {
            let mut kept = CATALOGS.lock().expect("catalog cache");
            if let Some(at) = kept.iter().position(|c| same(c)) {
                let c = kept.remove(at);
                kept.insert(0, Arc::clone(&c));
                return c;
            }
        }
        let built = Arc::new(Catalog::new(rules));
        let mut kept = CATALOGS.lock().expect("catalog cache");
        kept.insert(0, Arc::clone(&built));
        kept.truncate(KEPT);
        built
    }

    fn new(rules: &[CompiledRule]) -> Self {
        let mut sieve = Sieve::new(rules);
        let trie = Trie::new(rules, &sieve.attempts);
        sieve.renumber(&trie.slot_of);
        let (mut needs, mut commons) = (Vec::new(), Vec::new());
        let entries = rules
            .iter()
            .map(|rule| {
                let mut by_class: [Vec<PairEntry>; 9] = Default::default();
                if rule.rods_only() {
                    return by_class;
                }
                for a in 0..rule.n_nodes() {
                    for &b in &rule.neighbours[a] {
                        let entry = PairEntry {
                            a,
                            b,
                            mult: rule.between[a][b].len(),
                            need_a: intern(&mut needs, &rule.needs[a]),
                            need_b: intern(&mut needs, &rule.needs[b]),
                            common: intern(&mut commons, &rule.common[a][b]),
                        };
                        let (ka, kb) = (accepts(rule.kinds[a]), accepts(rule.kinds[b]));
                        for cx in 0..3 {
                            for cy in 0..3 {
                                if ka[cx] && kb[cy] {
                                    by_class[3 * cx + cy].push(entry);
                                }
                            }
                        }
                    }
                }
                by_class
            })
            .collect::<Vec<_>>();
        let words = rules.len().div_ceil(64);
        let mut shared: [Vec<Shared>; 9] = Default::default();
        for (k, by_class) in entries.iter().enumerate() {
            for (c, list) in by_class.iter().enumerate() {
                for e in list {
                    let same = |s: &Shared| {
                        let f = &s.entry;
                        (f.mult, f.need_a, f.need_b, f.common)
                            == (e.mult, e.need_a, e.need_b, e.common)
                    };
                    let at = match shared[c].iter().position(same) {
                        Some(at) => at,
                        None => {
                            shared[c].push(Shared {
                                entry: *e,
                                rules: vec![0; words],
                                skip_a: 0,
                                skip_b: 0,
                            });
                            shared[c].len() - 1
                        }
                    };
                    shared[c][at].rules[k / 64] |= 1 << (k % 64);
                }
            }
        }
        for list in &mut shared {
            let key = |s: &Shared| (s.entry.mult, s.entry.need_a, s.entry.need_b, s.entry.common);
            list.sort_by_key(key);
            for i in (0..list.len()).rev() {
                let (m, a, b, _) = key(&list[i]);
                let next = list.get(i + 1).map(key);
                list[i].skip_a = match next {
                    Some((m2, a2, _, _)) if (m2, a2) == (m, a) => list[i + 1].skip_a,
                    _ => i + 1,
                };
                list[i].skip_b = match next {
                    Some((m2, a2, b2, _)) if (m2, a2, b2) == (m, a, b) => list[i + 1].skip_b,
                    _ => i + 1,
                };
            }
        }
        Catalog {
            digests: rules.iter().map(|r| r.digest).collect(),
            sieve,
            trie,
            entries,
            shared,
            needs,
            commons,
            has_pair_rules: rules.iter().any(|r| !r.rods_only()),
        }
    }
}
