//! What the index knows of a rule set before any host: the rods-only
//! rules' sieve and trie, and the pattern contacts of the rules with bodies
//! by class pair with their shared conditions. Built once per distinct rule
//! set in a process and shared by every compression with it (building it
//! for 1,569 rules takes tens of milliseconds, more than compressing a small
//! system).

use std::sync::{Arc, LazyLock, Mutex};

use rayon::prelude::*;

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
    /// The number of the rule's pattern contact `a`, `b` among all rules'
    /// ([`Catalog::implies`]).
    pub id: u32,
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
    /// By pattern contact ([`PairEntry::id`]): itself and the pattern
    /// contacts of other rules (or of the same rule under another map)
    /// that a host pair carries only if it carries this one
    /// ([`contained`]), as bits by word (each word once, with its bits):
    /// a pair task marks them all dead with a few word operations.
    pub implies: Vec<Vec<(u32, u64)>>,
}

/// The maps of every node of rule `a`'s pattern to distinct nodes of rule
/// `b`'s under which `b`'s pattern contains `a`'s: each node of `b` at
/// least as specific (a rod for a rod, a spatial body for a spatial one)
/// and at least as many contacts between each pair of nodes. A node map of
/// `b` into the host restricted to the images is then one of `a`,
/// meeting everything the matcher asks of `a` (classes, contacts, degrees,
/// the Hall conditions of the demands, which only grow); so where `a`
/// has no node map from pattern contact (`u`, `w`), `b` has none from
/// (`sigma[u]`, `sigma[w]`).
fn contained(a: &CompiledRule, b: &CompiledRule) -> Vec<Vec<usize>> {
    fn place(
        a: &CompiledRule,
        b: &CompiledRule,
        sigma: &mut Vec<usize>,
        used: &mut [bool],
        out: &mut Vec<Vec<usize>>,
    ) {
        let i = sigma.len();
        if i == a.n_nodes() {
            out.push(sigma.clone());
            return;
        }
        let (ka, di) = (accepts(a.kinds[i]), a.neighbours[i].len());
        for j in 0..b.n_nodes() {
            let kb = accepts(b.kinds[j]);
            let fits = !used[j]
                && (0..3).all(|c| !kb[c] || ka[c])
                && b.neighbours[j].len() >= di
                && (0..i).all(|u| a.between[i][u].len() <= b.between[j][sigma[u]].len());
            if fits {
                sigma.push(j);
                used[j] = true;
                place(a, b, sigma, used, out);
                used[j] = false;
                sigma.pop();
            }
        }
    }
    let mut out = Vec::new();
    let mut used = vec![false; b.n_nodes()];
    place(a, b, &mut Vec::new(), &mut used, &mut out);
    out
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
        // Every pattern contact of the rules with bodies, numbered.
        let mut ids = Vec::with_capacity(rules.len());
        let mut n_ids = 0u32;
        for rule in rules {
            let n = rule.n_nodes();
            let mut id = vec![vec![u32::MAX; n]; n];
            if !rule.rods_only() {
                for (a, row) in id.iter_mut().enumerate() {
                    for &b in &rule.neighbours[a] {
                        row[b] = n_ids;
                        n_ids += 1;
                    }
                }
            }
            ids.push(id);
        }
        let with_bodies: Vec<usize> = (0..rules.len())
            .filter(|&k| !rules[k].rods_only())
            .collect();
        // Each rule's contacts, and its degrees sorted (a rule contains
        // another only if it has as many and each degree in order as large).
        let shape: Vec<(usize, Vec<usize>)> = rules
            .iter()
            .map(|r| {
                let mut d: Vec<usize> = r.neighbours.iter().map(Vec::len).collect();
                d.sort_unstable_by(|x, y| y.cmp(x));
                (r.between.iter().flatten().map(Vec::len).sum(), d)
            })
            .collect();
        let within = |i: usize, j: usize| {
            let ((ci, di), (cj, dj)) = (&shape[i], &shape[j]);
            ci <= cj && di.len() <= dj.len() && di.iter().zip(dj).all(|(x, y)| x <= y)
        };
        let found: Vec<Vec<(u32, u32)>> = with_bodies
            .par_iter()
            .map(|&i| {
                let mut pairs = Vec::new();
                for &j in with_bodies.iter().filter(|&&j| within(i, j)) {
                    for sigma in contained(&rules[i], &rules[j]) {
                        if i == j && sigma.iter().enumerate().all(|(u, &w)| u == w) {
                            continue;
                        }
                        for a in 0..rules[i].n_nodes() {
                            for &b in &rules[i].neighbours[a] {
                                pairs.push((ids[i][a][b], ids[j][sigma[a]][sigma[b]]));
                            }
                        }
                    }
                }
                pairs
            })
            .collect();
        let mut implied: Vec<Vec<u32>> = (0..n_ids).map(|id| vec![id]).collect();
        for (from, to) in found.into_iter().flatten() {
            implied[from as usize].push(to);
        }
        let implies = implied
            .into_iter()
            .map(|mut ids| {
                ids.sort_unstable();
                let mut words: Vec<(u32, u64)> = Vec::new();
                for id in ids {
                    let (w, bit) = (id / 64, 1u64 << (id % 64));
                    match words.last_mut() {
                        Some((last, bits)) if *last == w => *bits |= bit,
                        _ => words.push((w, bit)),
                    }
                }
                words
            })
            .collect();
        let entries = rules
            .iter()
            .zip(&ids)
            .map(|(rule, ids)| {
                let mut by_class: [Vec<PairEntry>; 9] = Default::default();
                if rule.rods_only() {
                    return by_class;
                }
                for (a, ids) in ids.iter().enumerate() {
                    for &b in &rule.neighbours[a] {
                        let entry = PairEntry {
                            a,
                            b,
                            mult: rule.between[a][b].len(),
                            need_a: intern(&mut needs, &rule.needs[a]),
                            need_b: intern(&mut needs, &rule.needs[b]),
                            common: intern(&mut commons, &rule.common[a][b]),
                            id: ids[b],
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
            implies,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// mixed-4-22 is mixed-4-4 with a third contact between nodes 1 and
    /// 2: the smaller pattern lies in the larger by the identity (and no
    /// other way round), and each of its contacts rules out the same one
    /// of the larger.
    #[test]
    fn a_pattern_with_a_contact_more_contains_the_smaller() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs/mixed-4.json");
        let rules: Vec<CompiledRule> = crate::rule_file::load_rules(&[path])
            .unwrap()
            .iter()
            .map(CompiledRule::new)
            .collect();
        let find = |id: &str| rules.iter().position(|r| r.id == id).unwrap();
        let (small, large) = (find("mixed-4-4"), find("mixed-4-22"));
        let maps = contained(&rules[small], &rules[large]);
        assert!(maps.contains(&vec![0, 1, 2, 3]), "{maps:?}");
        assert!(contained(&rules[large], &rules[small]).is_empty());
        let catalog = Catalog::new(&rules);
        let id = |k: usize, a: usize, b: usize| {
            catalog.entries[k]
                .iter()
                .flatten()
                .find(|e| (e.a, e.b) == (a, b))
                .unwrap()
                .id
        };
        let implies = |from: u32, to: u32| {
            catalog.implies[from as usize]
                .iter()
                .any(|&(w, bits)| w == to / 64 && bits & (1 << (to % 64)) != 0)
        };
        for (a, b) in [(0, 2), (2, 0), (1, 2), (2, 3), (3, 1)] {
            assert!(implies(id(small, a, b), id(large, a, b)));
            assert!(!implies(id(large, a, b), id(small, a, b)));
            assert!(implies(id(large, a, b), id(large, a, b)));
        }
    }
}
