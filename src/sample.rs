//! One Monte Carlo sample: rods, contacts, statistics, K compressions,
//! spanning, and on request the exact rigidity of the whole system.

use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

use crate::Result;
use crate::body::BodyClass;
use crate::contacts::{self, Contact};
use crate::engine::{self, Compression, MotifCounts, RuleSet, certify};
use crate::graph::{self, ContactGraph, ContactStats};
use crate::rods::ensemble::{Ensemble, Orientation};
use crate::rods::file::Loaded;
use crate::rods::{Periodic, RodParams, RodSystem};
use crate::spanning::{self, Criterion, SpanChecker};
use crate::truth::{self, Decision, Topology, Truth, TruthOptions};

/// Where a sample's rods come from.
#[derive(Clone, Debug)]
pub enum Rods {
    /// Drawn from an ensemble with the sample's seed.
    Generated(Ensemble),
    /// Read from a file and checked ([`crate::rods::file::read`]).
    Read { path: PathBuf, loaded: Loaded },
}

impl From<RodParams> for Rods {
    /// The paper's ensemble.
    fn from(params: RodParams) -> Self {
        Rods::Generated(Ensemble::paper(params))
    }
}

/// What to sample and how to compress it.
#[derive(Clone, Debug)]
pub struct SampleOptions {
    pub rods: Rods,
    /// Seed of the rods (when generated) and of the motif orders.
    pub seed: u64,
    /// Independent compressions (random motif orders); a system is
    /// rigid-spanning if any of them finds a spanning body.
    pub runs: usize,
    pub rules: RuleSet,
    pub criterion: Criterion,
    /// Also decide the exact rigidity of the whole system (MODEL §10).
    pub truth: bool,
}

/// The exact rigidity of a sample's system, as `rgc sample --truth` reports it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TruthReport {
    pub method: Decision,
    /// Whether a true rigid cluster spans (none when undecided).
    pub spanning: Option<bool>,
    /// Rods in the largest true rigid cluster.
    pub largest_cluster_rods: usize,
    /// True rigid clusters of two or more rods.
    pub clusters: usize,
    /// Internal degrees of freedom, trivial motions not counted.
    pub dof: Option<usize>,
    pub seconds: f64,
}

/// The figures of one sample, as printed by `rgc sample --json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SampleReport {
    /// `generated`, or the rods file.
    pub source: String,
    /// The recipe of generated rods.
    pub ensemble: Option<Ensemble>,
    /// The aspect ratio `l / (2r)` when every rod has the same length and radius.
    pub gamma: Option<f64>,
    pub mean_length: f64,
    pub mean_radius: f64,
    /// The box sides.
    #[serde(rename = "box")]
    pub sides: [f64; 3],
    pub periodic: Periodic,
    /// Rods per unit volume, `N / V`.
    pub density: f64,
    /// Rods of a file whose cores were cut at a wall.
    pub cut: usize,
    pub seed: u64,
    pub runs: usize,
    pub rules: RuleSet,
    pub criterion: Criterion,
    pub n_rods: usize,
    pub n_contacts: usize,
    pub c0: f64,
    /// The expected `c0` of isotropic rods with these sizes in a periodic
    /// box (the pair average of the excluded volume over the volume; for
    /// equal rods Philipse's `rho V_ex (N-1)/N`), for generated isotropic
    /// systems in a periodic box; otherwise none is known in closed form.
    pub c0_expected: Option<f64>,
    pub c1: f64,
    pub c2: f64,
    pub clustering: f64,
    pub contact_spanning: bool,
    /// Whether any run found a spanning body (the union rule).
    pub rigid_spanning: bool,
    /// How many of the runs found a spanning body.
    pub runs_spanning: usize,
    /// Rods in the largest body of any run.
    pub largest_body_rods: usize,
    /// Bodies in the reported run: the first spanning one, else the one with the largest body.
    pub n_bodies: usize,
    /// Nodes left (bodies and free rods) in the reported run.
    pub components: usize,
    /// Index of the reported run.
    pub reported_run: usize,
    /// Motifs compressed in the reported run.
    pub motifs: MotifCounts,
    /// The exact rigidity, when asked for.
    pub truth: Option<TruthReport>,
    pub seconds: f64,
    pub seconds_contacts: f64,
    pub seconds_compression: f64,
}

/// Everything a sample produced, for callers that need more than the report.
pub struct Sample {
    pub system: RodSystem,
    pub contacts: Vec<Contact>,
    pub graph: ContactGraph,
    pub runs: Vec<Compression>,
    /// Per run, whether it found a spanning body.
    pub spans: Vec<bool>,
    /// The exact rigidity, when asked for.
    pub truth: Option<Truth>,
    pub report: SampleReport,
}

/// A body of the reported run, as written by `rgc sample --save-bodies`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReportedBody {
    pub rods: Vec<u32>,
    pub class: BodyClass,
    pub spans: bool,
}

/// The bodies of the reported run, largest first, under `criterion`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReportedBodies {
    pub run: usize,
    pub criterion: Criterion,
    pub bodies: Vec<ReportedBody>,
}

impl Sample {
    /// The bodies of the reported run with whether each spans.
    pub fn reported_bodies(&self, criterion: Criterion) -> ReportedBodies {
        let run = self.report.reported_run;
        let mut checker = SpanChecker::new();
        let bodies = self.runs.get(run).map_or_else(Vec::new, |c| {
            c.bodies
                .iter()
                .map(|b| ReportedBody {
                    rods: b.rods.clone(),
                    class: b.class,
                    spans: checker.spans(
                        &self.system,
                        &self.contacts,
                        &self.graph,
                        &b.rods,
                        criterion,
                    ),
                })
                .collect()
        });
        ReportedBodies {
            run,
            criterion,
            bodies,
        }
    }
}

/// Generates (or takes), detects, compresses and measures one rod system.
/// Fails only when generated rods are too long for the box (see
/// [`Ensemble::generate`]).
pub fn sample(opts: &SampleOptions) -> Result<Sample> {
    sample_with(opts, &[])
}

/// [`sample`] with loaded motif rules in addition to the base motifs.
pub fn sample_with(opts: &SampleOptions, extra: &[engine::CompiledRule]) -> Result<Sample> {
    let start = Instant::now();
    let system = match &opts.rods {
        Rods::Generated(e) => e.generate(opts.seed)?,
        Rods::Read { loaded, .. } => loaded.system.clone(),
    };
    let contacts = contacts::detect(&system);
    let graph = ContactGraph::from_contacts(system.len(), &contacts);
    let seconds_contacts = start.elapsed().as_secs_f64();
    // The statistics and contact spanning take the second core while the
    // (single-threaded) compression runs.
    let measure = || {
        let stats = graph::stats(&graph);
        let spanning = spanning::contact_spanning(&system, &contacts, &graph, opts.criterion);
        (stats, spanning)
    };
    let compress = || {
        let t = Instant::now();
        let runs: Vec<Compression> = if opts.rules == RuleSet::Certified {
            // Certified against the truth of this box, not of the bare graph.
            let shifts: Vec<_> = contacts.iter().map(|c| c.shift).collect();
            let topo = Topology::of_domain(&graph, &shifts, &system.domain);
            engine::Engine::with_rules(RuleSet::Sound, extra)
                .runs(&graph, opts.seed, opts.runs)
                .into_iter()
                .enumerate()
                .map(|(k, run)| certify::certify(&topo, run, engine::run_seed(opts.seed, k as u64)))
                .collect()
        } else {
            engine::Engine::with_rules(opts.rules, extra).runs(&graph, opts.seed, opts.runs)
        };
        (runs, t.elapsed().as_secs_f64())
    };
    let ((stats, contact_spanning), (runs, seconds_compression)) = rayon::join(measure, compress);
    let ContactStats {
        c0,
        c1,
        c2,
        clustering,
    } = stats;
    let mut checker = SpanChecker::new();
    let spans: Vec<bool> = runs
        .iter()
        .map(|run| {
            run.bodies
                .iter()
                .any(|b| checker.spans(&system, &contacts, &graph, &b.rods, opts.criterion))
        })
        .collect();
    let reported_run = spans.iter().position(|&s| s).unwrap_or_else(|| {
        (0..runs.len())
            .max_by_key(|&k| (runs[k].largest_rods(), std::cmp::Reverse(k)))
            .unwrap_or(0)
    });
    let reported = runs.get(reported_run);
    let truth = opts.truth.then(|| {
        truth::of_system(
            &system,
            &contacts,
            &graph,
            opts.criterion,
            TruthOptions::seeded(opts.seed),
        )
    });
    let truth_report = truth.as_ref().map(|t| TruthReport {
        method: t.method,
        spanning: t.spanning,
        largest_cluster_rods: t.clusters.first().map_or(0, |c| c.rods.len()),
        clusters: t.clusters.len(),
        dof: t.dof,
        seconds: t.seconds,
    });
    let n = system.len().max(1) as f64;
    let first = system.rods.first();
    let equal = first.is_some_and(|f| {
        system
            .rods
            .iter()
            .all(|r| r.length == f.length && r.radius == f.radius)
    });
    let (source, ensemble, cut) = match &opts.rods {
        Rods::Generated(e) => ("generated".to_string(), Some(*e), 0),
        Rods::Read { path, loaded } => (path.display().to_string(), None, loaded.cut),
    };
    let c0_expected = ensemble
        .filter(|e| e.orientation == Orientation::Isotropic && e.domain.periodic == Periodic::Xyz)
        .map(|_| system.expected_isotropic_c0());
    let report = SampleReport {
        source,
        ensemble,
        gamma: first.filter(|_| equal).map(|f| f.length / (2.0 * f.radius)),
        mean_length: system.rods.iter().map(|r| r.length).sum::<f64>() / n,
        mean_radius: system.rods.iter().map(|r| r.radius).sum::<f64>() / n,
        sides: system.domain.sides,
        periodic: system.domain.periodic,
        density: system.density(),
        cut,
        seed: opts.seed,
        runs: opts.runs,
        rules: opts.rules,
        criterion: opts.criterion,
        n_rods: system.len(),
        n_contacts: contacts.len(),
        c0,
        c0_expected,
        c1,
        c2,
        clustering,
        contact_spanning,
        rigid_spanning: spans.iter().any(|&s| s),
        runs_spanning: spans.iter().filter(|&&s| s).count(),
        largest_body_rods: runs
            .iter()
            .map(Compression::largest_rods)
            .max()
            .unwrap_or(0),
        n_bodies: reported.map_or(0, |r| r.bodies.len()),
        components: reported.map_or(system.len(), |r| r.components),
        reported_run,
        motifs: reported.map(|r| r.motifs).unwrap_or_default(),
        truth: truth_report,
        seconds: start.elapsed().as_secs_f64(),
        seconds_contacts,
        seconds_compression,
    };
    Ok(Sample {
        system,
        contacts,
        graph,
        runs,
        spans,
        truth,
        report,
    })
}
