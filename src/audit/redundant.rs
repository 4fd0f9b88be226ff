//! Rules that smaller rules make redundant: a rule whose pattern the engine
//! compresses to one node with the smaller rules of the same set loaded, in
//! some motif order, adds nothing the engine could not do without it. The
//! audit keeps a missed motif only when it is not reduced so
//! ([`super::funnel`]); this asks the same question of any rule files
//! (`rgc rules --check`), whoever made them.

use serde::Serialize;

use super::funnel::reduced_by;
use crate::Result;
use crate::engine::{CompiledRule, Motif, RuleSet};
use crate::pattern::Pattern;
use crate::progress::Progress;
use crate::rule_file::Rule;

/// A rule the smaller rules make redundant, and how the engine compressed it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Redundant {
    pub id: String,
    /// Its nodes and contacts: the size the smaller rules are below.
    pub nodes: usize,
    pub contacts: usize,
    /// The first motif order (seed) that compressed it to one node.
    pub run: u64,
    /// The motifs that run applied, in order (`rule` for a loaded rule).
    pub sequence: Vec<Motif>,
}

/// Rules checked between two progress reports.
const CHUNK: usize = 32;

/// How large a rule is: its nodes, then its contacts. A rule another rule
/// can be found in is larger in this order (more nodes, or as many nodes
/// and more contacts), so a rule is judged only against those that could
/// be part of it, and two rules never make each other redundant.
fn size(p: &Pattern) -> (usize, usize) {
    (p.n_nodes(), p.contacts.len())
}

/// Every rule of `rules` that the engine (`base`, `runs` motif orders)
/// compresses to one node with the smaller rules of `rules` added, in the
/// order of `rules`. The audit's own rule files have none among rules of
/// different node counts by construction; rules of one node count it does
/// not compare, and files from elsewhere (mined, hand made, or sets joined)
/// may have any. `progress` counts the rules checked.
pub fn redundant(
    rules: &[Rule],
    base: RuleSet,
    runs: u64,
    progress: &dyn Progress,
) -> Result<Vec<Redundant>> {
    progress.start("rules", rules.len() as u64);
    let mut order: Vec<usize> = (0..rules.len()).collect();
    order.sort_by_key(|&k| size(&rules[k].pattern));
    let compiled: Vec<CompiledRule> = order
        .iter()
        .map(|&k| CompiledRule::new(&rules[k]))
        .collect();
    let mut found: Vec<(usize, Redundant)> = Vec::new();
    // Rules of one size, a chunk at a time, against the smaller ones: a
    // prefix of `compiled`.
    let mut start = 0;
    while start < order.len() {
        let here = size(&rules[order[start]].pattern);
        let end = start
            + order[start..]
                .iter()
                .take_while(|&&k| size(&rules[k].pattern) == here)
                .count();
        for chunk in order[start..end].chunks(CHUNK) {
            let patterns: Vec<&Pattern> = chunk.iter().map(|&k| &rules[k].pattern).collect();
            let reduced = reduced_by(&patterns, base, &compiled[..start], runs)?;
            progress.advance(chunk.len() as u64);
            for (&k, r) in chunk.iter().zip(reduced) {
                if let Some((run, c)) = r {
                    let id = rules[k].id.clone();
                    let (nodes, contacts) = here;
                    let sequence = c.sequence;
                    found.push((
                        k,
                        Redundant {
                            id,
                            nodes,
                            contacts,
                            run,
                            sequence,
                        },
                    ));
                }
            }
        }
        start = end;
    }
    progress.finish();
    found.sort_by_key(|(k, _)| *k);
    Ok(found.into_iter().map(|(_, r)| r).collect())
}
