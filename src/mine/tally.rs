//! The minimal sets of every system counted by pattern, and the systems
//! summarized per density.

use rustc_hash::{FxHashMap, FxHashSet};
use serde::{Deserialize, Serialize};

use super::parameters::Parameters;
use super::search::{Counts, MinimalSet};
use super::system::SystemReport;
use crate::pattern::{NodeKind, Pattern};
use crate::rule_file::Frequency;

/// One distinct pattern, over every system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MinedMotif {
    /// 1 for the most frequent.
    pub rank: usize,
    pub canonical: String,
    /// The canonical pattern (not in the JSON: [`MinedMotif::canonical`]
    /// spells it, kinds then contacts `a.i-b.j`, and the rule file holds the rules').
    #[serde(skip, default = "no_pattern")]
    pub pattern: Pattern,
    pub nodes: usize,
    pub rod_nodes: usize,
    pub planar: usize,
    pub spatial: usize,
    pub contacts: usize,
    /// The exact verdict on every realization component, and its largest DOF.
    pub class: String,
    pub dof: Option<usize>,
    /// Whether the `sound` engine compresses it to one node in some of the orders tried.
    pub sound_compresses: bool,
    /// The same with the extended rule files (when any were given).
    pub extended_compresses: Option<bool>,
    /// Rigid on every component and missed by `sound`: a rule candidate.
    pub candidate: bool,
    /// Its id in the rule file written, if it is one of the top candidates.
    pub rule: Option<String>,
    /// Distinct minimal sets with this pattern, and the systems holding one.
    pub occurrences: u64,
    pub systems: u64,
    /// Of the occurrences, those that were one rigid cluster, and those wrapping the box.
    pub whole: u64,
    pub wrapping: u64,
    pub per_density: Vec<Frequency>,
    /// The first occurrence: its system and rods.
    pub example: Example,
}

fn no_pattern() -> Pattern {
    Pattern {
        kinds: Vec::new(),
        contacts: Vec::new(),
    }
}

/// Where a pattern was first found: the system, the rods of the set, and,
/// when the set is not whole, those the pair's cluster holds. Rods are
/// written as one space-separated string, which keeps the JSON short.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Example {
    pub density: f64,
    pub seed: u64,
    #[serde(with = "super::spaced")]
    pub rods: Vec<u32>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "super::spaced::serialize_opt",
        deserialize_with = "super::spaced::deserialize_opt"
    )]
    pub held_rods: Option<Vec<u32>>,
}

/// One density summarized.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DensitySummary {
    pub density: f64,
    pub systems: usize,
    pub truth_spans: usize,
    pub sound_spans: usize,
    pub mean_nodes: f64,
    pub missed_clusters: usize,
    pub mean_missed_rods: f64,
    pub pairs: usize,
    pub found: usize,
    /// Pairs not rigid together within the caps (every reason).
    pub not_local: usize,
    pub sets: usize,
    pub too_large: usize,
    pub not_whole: usize,
    /// Quotient nodes per distinct minimal set: mean and largest.
    pub mean_set_nodes: f64,
    pub max_set_nodes: usize,
    /// Distinct patterns at this density, and the rule candidates among them.
    pub patterns: usize,
    pub candidates: usize,
}

/// Counts the patterns of every system (in job order), most frequent first;
/// the verdicts are filled in later.
pub(super) fn tally(
    params: &Parameters,
    mined: &[(SystemReport, Vec<MinimalSet>)],
) -> Vec<MinedMotif> {
    let mut index: FxHashMap<String, usize> = FxHashMap::default();
    let mut motifs: Vec<MinedMotif> = Vec::new();
    for (system, sets) in mined {
        let d = params
            .densities
            .iter()
            .position(|&rho| rho == system.density)
            .expect("a system of a mined density");
        let mut seen_here: FxHashSet<usize> = FxHashSet::default();
        for set in sets {
            let (Some(pattern), Some(canonical)) = (&set.pattern, &set.canonical) else {
                continue;
            };
            let k = *index.entry(canonical.clone()).or_insert_with(|| {
                motifs.push(new_motif(params, system, set, pattern, canonical));
                motifs.len() - 1
            });
            let m = &mut motifs[k];
            m.occurrences += 1;
            m.whole += u64::from(set.whole);
            m.wrapping += u64::from(set.wraps);
            m.per_density[d].occurrences += 1;
            if seen_here.insert(k) {
                m.systems += 1;
                m.per_density[d].systems += 1;
            }
        }
    }
    motifs.sort_by(|a, b| {
        b.occurrences
            .cmp(&a.occurrences)
            .then(b.systems.cmp(&a.systems))
            .then(a.canonical.cmp(&b.canonical))
    });
    for (k, m) in motifs.iter_mut().enumerate() {
        m.rank = k + 1;
    }
    motifs
}

fn new_motif(
    params: &Parameters,
    system: &SystemReport,
    set: &MinimalSet,
    pattern: &Pattern,
    canonical: &str,
) -> MinedMotif {
    let count = |k: NodeKind| pattern.kinds.iter().filter(|&&x| x == k).count();
    MinedMotif {
        rank: 0,
        canonical: canonical.to_string(),
        pattern: pattern.clone(),
        nodes: pattern.n_nodes(),
        rod_nodes: count(NodeKind::Rod),
        planar: count(NodeKind::Planar),
        spatial: count(NodeKind::Spatial),
        contacts: pattern.contacts.len(),
        class: String::new(),
        dof: None,
        sound_compresses: false,
        extended_compresses: None,
        candidate: false,
        rule: None,
        occurrences: 0,
        systems: 0,
        whole: 0,
        wrapping: 0,
        per_density: params
            .densities
            .iter()
            .map(|&density| Frequency {
                density,
                occurrences: 0,
                systems: 0,
                of_systems: params.systems,
            })
            .collect(),
        example: Example {
            density: system.density,
            seed: system.seed,
            rods: set.rods.clone(),
            held_rods: (!set.whole).then(|| set.held_rods.clone()),
        },
    }
}

pub(super) fn summaries(
    params: &Parameters,
    mined: &[(SystemReport, Vec<MinimalSet>)],
    motifs: &[MinedMotif],
) -> Vec<DensitySummary> {
    params
        .densities
        .iter()
        .enumerate()
        .map(|(d, &density)| {
            let here: Vec<&SystemReport> = mined
                .iter()
                .map(|(s, _)| s)
                .filter(|s| s.density == density)
                .collect();
            let set_nodes: Vec<usize> = mined
                .iter()
                .filter(|(s, _)| s.density == density)
                .flat_map(|(_, sets)| sets.iter().map(|m| m.nodes.len()))
                .collect();
            let n = here.len().max(1) as f64;
            let sum =
                |f: &dyn Fn(&Counts) -> usize| here.iter().map(|s| f(&s.counts)).sum::<usize>();
            let present = || motifs.iter().filter(|m| m.per_density[d].occurrences > 0);
            DensitySummary {
                density,
                systems: here.len(),
                truth_spans: here.iter().filter(|s| s.truth_spans == Some(true)).count(),
                sound_spans: here.iter().filter(|s| s.sound_spans).count(),
                mean_nodes: sum(&|c| c.nodes) as f64 / n,
                missed_clusters: sum(&|c| c.missed_clusters),
                mean_missed_rods: sum(&|c| c.missed_rods) as f64 / n,
                pairs: sum(&|c| c.pairs),
                found: sum(&|c| c.found),
                not_local: sum(&|c| c.beyond_radius + c.beyond_rods + c.exhausted),
                sets: sum(&|c| c.sets),
                too_large: sum(&|c| c.too_large),
                not_whole: sum(&|c| c.not_whole),
                mean_set_nodes: set_nodes.iter().sum::<usize>() as f64
                    / set_nodes.len().max(1) as f64,
                max_set_nodes: set_nodes.iter().copied().max().unwrap_or(0),
                patterns: present().count(),
                candidates: present().filter(|m| m.candidate).count(),
            }
        })
        .collect()
}
