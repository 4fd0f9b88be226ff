//! One Monte Carlo sample: rods, contacts, statistics, K compressions,
//! spanning, and on request the exact rigidity of the whole system.

use nalgebra::Vector3;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

use crate::body::BodyClass;
use crate::contacts::Contact;
use crate::engine::{self, Compression, MotifCounts, RuleSet, certify};
use crate::graph::{self, ContactGraph, ContactStats};
use crate::network::{Network, View};
use crate::rods::ensemble::{Ensemble, Orientation};
use crate::rods::file::Loaded;
use crate::rods::{Periodic, Rod, RodParams, RodSystem, pair_excluded_volume};
use crate::spanning::{self, Criterion, SpanChecker};
use crate::truth::{self, Decision, Truth, TruthOptions};
use crate::usage;
use crate::{Error, Result};

/// Where a sample's rods come from.
#[derive(Clone, Debug)]
pub enum Rods {
    /// Drawn from an ensemble with the sample's seed.
    Generated(Ensemble),
    /// Read from a file and checked ([`crate::rods::file::read`]).
    Read { path: PathBuf, loaded: Loaded },
}

/// What a sample of some rods is estimated to need at its peak.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryEstimate {
    pub rods: usize,
    /// Contacts expected of isotropic rods with these sizes and density
    /// (aligned rods have fewer).
    pub contacts: f64,
    pub bytes: u64,
}

/// Peak bytes per rod of unit length and no radius (rods, contact
/// detection's cell lists, graph, compression), grown by `(1 + 2 r/l)^2`
/// since a thicker rod is listed in more cells.
const ROD_BYTES: f64 = 500.0;
/// Peak bytes per contact (contacts, graph, compression).
const CONTACT_BYTES: f64 = 110.0;

/// The peak memory of `rgc sample` on `rods` rods with `contacts` contacts,
/// of radius `thickness` times their length, bytes, beyond what the process
/// holds before it reads or draws them (about 7 MB). The constants come
/// from the peak resident memory measured on 2 threads for 40,000 to
/// 1,080,000 rods at gamma 5 to 98 and densities 5 to 200 (0.2 to 4.8
/// contacts per rod): the estimate was 0.95 to 1.6 times the measured peak
/// less that of an empty run.
pub fn memory_estimate(rods: usize, contacts: f64, thickness: f64) -> u64 {
    let per_rod = ROD_BYTES * (1.0 + 2.0 * thickness).powi(2);
    (rods as f64 * per_rod + contacts.max(0.0) * CONTACT_BYTES) as u64
}

impl MemoryEstimate {
    /// Refuses the estimate and `more` bytes if they would take the
    /// process past `limit` (see [`Rods::check_memory`]).
    fn check(&self, runs: usize, more: u64, limit: Option<u64>) -> Result<()> {
        usage::reserve(self.bytes + more, 0, limit).map_err(|r| {
            let system = format!(
                "the system of {} rods (about {:.3e} contacts)",
                self.rods, self.contacts
            );
            Error::Memory(match runs {
                0 | 1 => format!("{}; take a smaller box or density", r.describe(&system)),
                _ => format!(
                    "{}; take a smaller box or density, or fewer runs",
                    r.describe(&format!("{system} with {runs} runs"))
                ),
            })
        })?;
        Ok(())
    }
}

impl Rods {
    /// What a sample of these rods is estimated to need, known before any
    /// rod is drawn (or, for rods read, before their contacts are sought).
    pub fn memory_estimate(&self) -> MemoryEstimate {
        let (rods, contacts, thickness) = match self {
            Rods::Generated(e) => {
                let n = e.n_rods();
                let (l, r) = (e.length.mean(), e.radius.mean());
                let mean = Rod::new(Vector3::zeros(), Vector3::x(), l, r);
                let pairs = n as f64 * (n as f64 - 1.0) / 2.0;
                let contacts = pairs * pair_excluded_volume(&mean, &mean) / e.domain.volume();
                (n, contacts, r / l)
            }
            Rods::Read { loaded, .. } => {
                let s = &loaded.system;
                let n = s.len().max(1) as f64;
                let l = s.rods.iter().map(|r| r.length).sum::<f64>() / n;
                let r = s.rods.iter().map(|r| r.radius).sum::<f64>() / n;
                let contacts = 0.5 * s.len() as f64 * s.expected_isotropic_c0();
                (s.len(), contacts, r / l)
            }
        };
        MemoryEstimate {
            rods,
            contacts,
            bytes: memory_estimate(rods, contacts, thickness),
        }
    }

    /// Refuses, before the work, rods whose sample is estimated to take the
    /// process past `limit` (on its resident size; what the machine has
    /// available and an address-space limit are checked without one): one
    /// line with the estimate, what the process holds and the bound,
    /// instead of an allocation failing midway.
    pub fn check_memory(&self, limit: Option<u64>) -> Result<()> {
        self.memory_estimate().check(1, 0, limit)
    }

    /// Each rod's id, when the rods were read from a file that numbers them.
    pub fn ids(&self) -> Option<&[u64]> {
        match self {
            Rods::Generated(_) => None,
            Rods::Read { loaded, .. } => loaded.ids.as_deref(),
        }
    }
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

impl SampleOptions {
    /// [`Rods::check_memory`], with the compressions beyond the first that
    /// run at once and the outcomes of all of them.
    pub fn check_memory(&self, limit: Option<u64>) -> Result<()> {
        let e = self.rods.memory_estimate();
        let (n, m) = (e.rods, e.contacts as usize);
        let runs = engine::runs_memory(n, m, self.runs) - engine::runs_memory(n, m, 1);
        e.check(self.runs, runs, limit)
    }
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
    /// Rods of a file whose centres were wrapped into the box along a
    /// periodic axis.
    pub wrapped: usize,
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
    /// Each rod's id, when the rods were read from a file that numbers them.
    pub ids: Option<Vec<u64>>,
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
    /// The ids of those rods, when the file numbered them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ids: Option<Vec<u64>>,
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
                    ids: self
                        .ids
                        .as_ref()
                        .map(|ids| b.rods.iter().map(|&r| ids[r as usize]).collect()),
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
/// Fails when generated rods are too long for the box (see
/// [`Ensemble::generate`]), and before the work when it would take the
/// process past what the machine (or an address-space limit) leaves
/// ([`SampleOptions::check_memory`] without a limit of its own).
pub fn sample(opts: &SampleOptions) -> Result<Sample> {
    sample_with(opts, &[])
}

/// [`sample`] with loaded motif rules in addition to the base motifs.
pub fn sample_with(opts: &SampleOptions, extra: &[engine::CompiledRule]) -> Result<Sample> {
    opts.check_memory(None)?;
    let start = Instant::now();
    let system = match &opts.rods {
        Rods::Generated(e) => e.generate(opts.seed)?,
        Rods::Read { loaded, .. } => loaded.system.clone(),
    };
    let network = Network::detect(system);
    let view = network.view();
    let View {
        system,
        contacts,
        graph,
        ..
    } = view;
    let seconds_contacts = start.elapsed().as_secs_f64();
    // The statistics and contact spanning take the second core while the
    // (single-threaded) compression runs.
    let measure = || {
        let stats = graph::stats(graph);
        let spanning = spanning::contact_spanning(system, contacts, graph, opts.criterion);
        (stats, spanning)
    };
    let compress = || {
        let t = Instant::now();
        let runs: Vec<Compression> = if opts.rules == RuleSet::Certified {
            // Certified against the truth of this box, not of the bare graph.
            let topo = view.topology();
            engine::Engine::with_rules(RuleSet::Sound, extra)
                .runs(graph, opts.seed, opts.runs)
                .into_iter()
                .enumerate()
                .map(|(k, run)| certify::certify(&topo, run, engine::run_seed(opts.seed, k as u64)))
                .collect()
        } else {
            engine::Engine::with_rules(opts.rules, extra).runs(graph, opts.seed, opts.runs)
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
                .any(|b| checker.spans(system, contacts, graph, &b.rods, opts.criterion))
        })
        .collect();
    let reported_run = spans.iter().position(|&s| s).unwrap_or_else(|| {
        (0..runs.len())
            .max_by_key(|&k| (runs[k].largest_rods(), std::cmp::Reverse(k)))
            .unwrap_or(0)
    });
    let reported = runs.get(reported_run);
    let truth = opts
        .truth
        .then(|| truth::of_system(view, opts.criterion, TruthOptions::seeded(opts.seed)));
    // Truth stopped short of the memory it may take is no answer to report.
    if let Some(t) = truth.as_ref().filter(|t| t.outcome.refused().is_some()) {
        return Err(Error::Memory(format!(
            "truth refused this system: {}",
            t.outcome.reason().unwrap_or_default()
        )));
    }
    let truth_report = truth.as_ref().map(|t| TruthReport {
        method: t.outcome.decision(),
        spanning: t.spanning,
        largest_cluster_rods: t.clusters.first().map_or(0, |c| c.rods.len()),
        clusters: t.clusters.len(),
        dof: t.outcome.dof(),
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
    let (source, ensemble, cut, wrapped) = match &opts.rods {
        Rods::Generated(e) => ("generated".to_string(), Some(*e), 0, 0),
        Rods::Read { path, loaded } => {
            (path.display().to_string(), None, loaded.cut, loaded.wrapped)
        }
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
        wrapped,
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
    let Network {
        system,
        contacts,
        graph,
        ..
    } = network;
    Ok(Sample {
        system,
        ids: opts.rods.ids().map(<[u64]>::to_vec),
        contacts,
        graph,
        runs,
        spans,
        truth,
        report,
    })
}
