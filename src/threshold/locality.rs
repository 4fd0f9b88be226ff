//! How far the rigidity 3D-RGC misses reaches, at the true threshold: on
//! the sequences of finished truth studies, at each one's true critical
//! number, the spanning true cluster set against the bodies of one `sound`
//! compression (with the rules asked for), and the minimal rigid sets that
//! hold two of the compression's nodes together inside that cluster, grown
//! over the compression's quotient one layer at a time and cut down to a
//! minimal set (the search of `rgc mine`, with caps of its own).
//!
//! A motif can only merge what a pattern of its size holds rigid. So the
//! sizes of these minimal sets, and the share of pairs that no ball within
//! the caps holds together, are the length scale a motif set would need to
//! see the rigidity the engine misses. Each sequence is one line of
//! `locality.jsonl` (a [`journal`]), so a killed run resumes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::journal;
use super::sequence::{Record, Sequence};
use super::study::MotifSet;
use crate::engine::{CompiledRule, Engine, RuleSet, run_seed};
use crate::math::stats;
use crate::mine::{Search, mine};
use crate::progress::Progress;
use crate::spanning::Criterion;
use crate::truth::{self, TruthOptions};
use crate::{Error, Result, output};

/// What a measurement probes: which studies, boxes and sequences, the
/// compression's rules and the search's caps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalitySpec {
    /// Truth study directories, as given.
    pub studies: Vec<String>,
    /// Boxes of each study (all when empty).
    pub boxes: Vec<f64>,
    /// The first this many sequences of each box.
    pub sequences: u64,
    /// The rules the compression adds to the base motifs.
    pub motifs: MotifSet,
    #[serde(flatten)]
    pub search: Search,
}

/// One minimal set: how many quotient nodes and rods it has, and the ball
/// radius (quotient layers around the pair) at which the pair was first
/// rigid together.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetSize {
    pub nodes: usize,
    pub rods: usize,
    pub radius: usize,
}

/// One sequence at its true critical number: one line of `locality.jsonl`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SequenceLocality {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub index: u64,
    /// Rods at the true critical number.
    pub rods: usize,
    /// Rods of the spanning true cluster; of them, those in a body of the
    /// compression (two rods or more); its largest body inside the cluster.
    pub cluster_rods: usize,
    pub covered_rods: usize,
    pub largest_body: usize,
    /// The compression's nodes (bodies and free rods) lying whole in the
    /// cluster: what one motif would have to merge to see it whole.
    pub cluster_nodes: usize,
    /// Seed pairs (adjacent nodes of the cluster) tried, the distinct
    /// minimal sets they gave, and the pairs no ball within the caps held
    /// together (radius, rods) or whose cluster ran out of nodes first.
    pub pairs: usize,
    pub found: usize,
    pub sets: Vec<SetSize>,
    pub beyond_radius: usize,
    pub beyond_rods: usize,
    pub exhausted: usize,
    pub truth_calls: usize,
    pub seconds: f64,
}

/// The locality of one box of one aspect ratio.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LocalitySummary {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub sequences: usize,
    /// Means over the sequences: rods at the critical number, of the
    /// spanning true cluster, its share covered by bodies, its largest
    /// body's share, and the nodes it holds whole.
    pub rods: f64,
    pub cluster_rods: f64,
    pub covered_share: f64,
    pub largest_body_share: f64,
    pub cluster_nodes: f64,
    /// Seed pairs, and the share of them held together within the caps.
    pub pairs: usize,
    pub found_share: f64,
    pub beyond_radius: usize,
    pub beyond_rods: usize,
    pub exhausted: usize,
    /// The distinct minimal sets: how many, and the median and largest of
    /// their quotient nodes, rods and radii.
    pub sets: usize,
    pub median_nodes: f64,
    pub max_nodes: usize,
    pub median_rods: f64,
    pub max_rods: usize,
    pub median_radius: f64,
    pub max_radius: usize,
    /// Sets of more than 10 quotient nodes: beyond the largest motifs rgc
    /// enumerates.
    pub beyond_ten_nodes: usize,
}

/// The directory's spec file and lines.
fn files(out: &Path) -> (PathBuf, PathBuf) {
    (out.join("locality.json"), out.join("locality.jsonl"))
}

/// Probes the chosen sequences of the truth studies `dirs` into `out`
/// (resuming what is there), compressing with the base motifs and `rules`,
/// and summarizes per aspect ratio and box.
pub fn run(
    dirs: &[PathBuf],
    spec: &LocalitySpec,
    rules: &[CompiledRule],
    out: &Path,
    progress: &dyn Progress,
) -> Result<Vec<LocalitySummary>> {
    spec.search.validate()?;
    let decided = journal::decided_truth_records(
        dirs,
        &spec.boxes,
        spec.sequences,
        "the locality of missed rigidity",
    )?;
    output::check_dir(out)?;
    let (spec_file, lines) = files(out);
    let engine = Engine::with_rules(RuleSet::Sound, rules);
    let all = journal::measure(
        (&spec_file, spec, "locality spec"),
        &lines,
        &decided,
        progress,
        |gamma, r| probe(gamma, r, &engine, &spec.search),
    )?;
    Ok(summarize(&all))
}

/// The sequences probed so far.
pub fn read(lines: &Path) -> Result<Vec<SequenceLocality>> {
    journal::read(lines, "locality")
}

/// One sequence at its true critical number: truth as the study evaluated
/// it there (the same realizations), one compression seeded as the study's
/// step at that number, and the search in the spanning cluster.
fn probe(gamma: f64, r: &Record, engine: &Engine, search: &Search) -> Result<SequenceLocality> {
    let start = Instant::now();
    let n = r.rigid_critical.expect("chosen records are decided");
    let seq = Sequence::new(gamma, r.box_len, n, r.seed)?;
    let graph = seq.graph(n);
    let view = seq.view(n, &graph);
    let seed = run_seed(r.seed, n as u64);
    let t = truth::of_system(view, Criterion::Wrap, TruthOptions::seeded(seed));
    let Some(spanning) = t
        .clusters
        .iter()
        .find(|c| c.spans.is_some_and(|s| s.wrap))
        .cloned()
    else {
        return Err(Error::Analysis(format!(
            "truth of the first {n} rods of the sequence seeded {} has no spanning cluster, \
             although its study found them critical",
            r.seed
        )));
    };
    let run = engine.compress(&graph, &[], run_seed(seed, 0))?;
    let in_cluster = |rods: &[u32]| rods.iter().all(|x| spanning.rods.binary_search(x).is_ok());
    let bodies: Vec<usize> = run
        .bodies
        .iter()
        .filter(|b| in_cluster(&b.rods))
        .map(|b| b.rods.len())
        .collect();
    let covered: usize = bodies.iter().sum();
    let cluster_rods = spanning.rods.len();
    let only_spanning = truth::Truth {
        clusters: vec![spanning],
        ..t
    };
    let topo = view.topology();
    let mined = mine(&topo, &run, &only_spanning, seed, search);
    let c = &mined.counts;
    Ok(SequenceLocality {
        gamma,
        box_len: r.box_len,
        index: r.index,
        rods: n,
        cluster_rods,
        covered_rods: covered,
        largest_body: bodies.iter().copied().max().unwrap_or(0),
        cluster_nodes: bodies.len() + cluster_rods - covered,
        pairs: c.pairs,
        found: c.found,
        sets: mined
            .sets
            .iter()
            .map(|s| SetSize {
                nodes: s.nodes.len(),
                rods: s.rods.len(),
                radius: s.radius,
            })
            .collect(),
        beyond_radius: c.beyond_radius,
        beyond_rods: c.beyond_rods,
        exhausted: c.exhausted,
        truth_calls: c.truth_calls,
        seconds: start.elapsed().as_secs_f64(),
    })
}

impl journal::Line for SequenceLocality {
    fn key(&self) -> (f64, f64, u64) {
        (self.gamma, self.box_len, self.index)
    }
}

/// Per aspect ratio and box, in that order.
pub fn summarize(all: &[SequenceLocality]) -> Vec<LocalitySummary> {
    let mut keys: Vec<(f64, f64)> = all.iter().map(|s| (s.gamma, s.box_len)).collect();
    keys.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
    keys.dedup();
    keys.into_iter()
        .map(|(gamma, box_len)| {
            let of: Vec<&SequenceLocality> = all
                .iter()
                .filter(|s| (s.gamma, s.box_len) == (gamma, box_len))
                .collect();
            let mean = |f: &dyn Fn(&SequenceLocality) -> f64| {
                of.iter().map(|s| f(s)).sum::<f64>() / of.len() as f64
            };
            let sets: Vec<SetSize> = of.iter().flat_map(|s| s.sets.iter().copied()).collect();
            let median = |f: &dyn Fn(&SetSize) -> usize| {
                let mut v: Vec<f64> = sets.iter().map(|s| f(s) as f64).collect();
                if v.is_empty() {
                    f64::NAN
                } else {
                    stats::median(&mut v)
                }
            };
            let max = |f: &dyn Fn(&SetSize) -> usize| sets.iter().map(f).max().unwrap_or(0);
            let pairs: usize = of.iter().map(|s| s.pairs).sum();
            let found: usize = of.iter().map(|s| s.found).sum();
            LocalitySummary {
                gamma,
                box_len,
                sequences: of.len(),
                rods: mean(&|s| s.rods as f64),
                cluster_rods: mean(&|s| s.cluster_rods as f64),
                covered_share: mean(&|s| s.covered_rods as f64 / s.cluster_rods as f64),
                largest_body_share: mean(&|s| s.largest_body as f64 / s.cluster_rods as f64),
                cluster_nodes: mean(&|s| s.cluster_nodes as f64),
                pairs,
                found_share: found as f64 / pairs.max(1) as f64,
                beyond_radius: of.iter().map(|s| s.beyond_radius).sum(),
                beyond_rods: of.iter().map(|s| s.beyond_rods).sum(),
                exhausted: of.iter().map(|s| s.exhausted).sum(),
                sets: sets.len(),
                median_nodes: median(&|s| s.nodes),
                max_nodes: max(&|s| s.nodes),
                median_rods: median(&|s| s.rods),
                max_rods: max(&|s| s.rods),
                median_radius: median(&|s| s.radius),
                max_radius: max(&|s| s.radius),
                beyond_ten_nodes: sets.iter().filter(|s| s.nodes > 10).count(),
            }
        })
        .collect()
}

/// Writes `PREFIX.json` (with the command that made it) and `PREFIX.csv`,
/// one row per aspect ratio and box.
pub fn write(prefix: &Path, summaries: &[LocalitySummary], command: &str) -> Result<Vec<PathBuf>> {
    let with = |ext: &str| output::with_extension(prefix, ext);
    let (json, csv) = (with("json"), with("csv"));
    let doc = serde_json::json!({ "command": command, "boxes": summaries });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("summaries serialize"),
    )?;
    output::write_csv(&csv, summaries)?;
    Ok(vec![json, csv])
}
