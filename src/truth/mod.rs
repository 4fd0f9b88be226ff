//! Truth: the exact rigidity of a whole contact graph (MODEL §10).
//!
//! 3D-RGC compresses local motifs, which is fast but neither sound on whole
//! graphs (a motif can be forced into a flexible special position by rods
//! outside it) nor complete. Truth decides the rigidity of the whole system
//! on one stated realization family: planes only where the contacts force
//! them, distinct contact points, everything else in general position. The
//! steps, each in its module:
//!
//! * [`prune`] — the 2-core: a rod held by one contact turns about it, so
//!   it neither is rigid with anything nor holds anything;
//! * [`planes`] — the forced plane classes, each also a rigid body;
//! * [`order`] — an order in which every line can be placed rationally;
//! * [`realize`] — an exact realization over F_p in that order;
//! * [`matrix`] — the rigidity matrix in body frames, six columns per part;
//! * [`crate::math::sparse`] — its exact rank and random kernel vectors;
//! * [`clusters`] — the rigid clusters those vectors imply;
//! * [`contract`] — those clusters contracted, for the second twin's check.
//!
//! Two independent realizations (twins) are ranked; the generic rank is the
//! larger (Schwartz–Zippel), and they agree except with probability about
//! `1/p`. The second twin confirms the first's kernel dimension with the
//! first's clusters contracted, and ranks the whole matrix only where the
//! two differ. Where no rational construction order exists, [`fallback`] decides
//! in floats: twin realizations by numerical projection ([`projection`]),
//! the same matrix ranked by its singular values where they show a clear
//! gap, clusters from the kernel basis ([`Method::Float`]). Where that is
//! not clear either, truth answers "undecided" and says why: never a guess.

pub mod clusters;
pub mod contract;
pub mod fallback;
pub mod matrix;
pub mod order;
pub mod planes;
pub mod projection;
pub mod prune;
pub mod realize;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::time::Instant;

use crate::contacts::Contact;
use crate::graph::ContactGraph;
use crate::math::{Field, Q1, Q2, sparse};
use crate::rods::{Domain, Periodic, RodSystem};
use crate::spanning::{Criterion, SpanChecker};
use crate::{Error, Result};
use planes::Offset;

/// The contacts of a system, and for a periodic box the image of each.
#[derive(Clone, Copy, Debug)]
pub struct Topology<'a> {
    pub graph: &'a ContactGraph,
    /// Per edge `[a, b]`: `a` touches the image of `b` shifted by this many
    /// box sides. `None`: a finite framework (a graph read from a file).
    pub shifts: Option<&'a [Offset]>,
}

impl<'a> Topology<'a> {
    /// A finite framework.
    pub fn finite(graph: &'a ContactGraph) -> Self {
        Topology {
            graph,
            shifts: None,
        }
    }

    /// A periodic system with a fixed box.
    pub fn periodic(graph: &'a ContactGraph, shifts: &'a [Offset]) -> Result<Self> {
        if shifts.len() != graph.n_edges() {
            return Err(Error::Parameter(format!(
                "{} image shifts for {} contacts",
                shifts.len(),
                graph.n_edges()
            )));
        }
        Ok(Topology {
            graph,
            shifts: Some(shifts),
        })
    }

    /// The contacts of a system in `domain`: periodic along some axis, or a
    /// finite framework when every side is a wall (the walls hold nothing).
    pub fn of_domain(graph: &'a ContactGraph, shifts: &'a [Offset], domain: &Domain) -> Self {
        debug_assert_eq!(shifts.len(), graph.n_edges(), "one shift per contact");
        Topology {
            graph,
            shifts: (domain.periodic != Periodic::None).then_some(shifts),
        }
    }

    /// The image offset at which rod `r` sees the other rod of edge `e`.
    pub fn seen(&self, e: u32, r: u32) -> Offset {
        let Some(shifts) = self.shifts else {
            return [0; 3];
        };
        let s = shifts[e as usize];
        if self.graph.edges()[e as usize][0] == r {
            s
        } else {
            s.map(|k| -k)
        }
    }

    /// Rigid motions of the whole system that are no deformation: 6 for a
    /// finite framework (5 for a lone rod, which has no spin), 3
    /// translations in a fixed periodic box.
    pub fn trivial_motions(&self) -> usize {
        match (self.shifts, self.graph.n_nodes()) {
            (_, 0) => 0,
            (Some(_), _) => 3,
            (None, 1) => 5,
            (None, _) => 6,
        }
    }
}

/// Random kernel vectors drawn for the clusters: a relation that holds on
/// all of them holds on the whole kernel except with probability `1/q^2`.
const KERNEL_VECTORS: usize = 2;

/// How truth was decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Exact F_p rank at exact twin realizations.
    Exact,
    /// No construction order exists: float rank with a clear singular-value
    /// gap at twin float realizations that agree ([`fallback`]).
    Float,
    /// No realization could be built, or its float rank was unclear;
    /// nothing is claimed.
    Undecided,
}

impl std::fmt::Display for Method {
    /// The name in files.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Exact => "exact",
            Method::Float => "float",
            Method::Undecided => "undecided",
        })
    }
}

/// Options of a truth evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TruthOptions {
    pub seed: u64,
    /// Redraws of a realization that lands on a degenerate position (the
    /// float fallback draws [`fallback::DRAWS_PER_ATTEMPT`] times as many).
    pub attempts: usize,
    /// Rank a second, independent realization too (the generic rank is the
    /// larger). One realization already proves what it finds rigid; the twin
    /// guards the flexible answers against an unlucky draw. The float
    /// fallback proves nothing from one realization and always ranks twins.
    pub twins: bool,
    /// Stop an elimination before a dense front that would take it past
    /// this many bytes; the answer is then undecided ([`Truth::refused`]).
    pub memory_limit: Option<u64>,
}

impl TruthOptions {
    /// The default options with realizations drawn from `seed`.
    pub fn seeded(seed: u64) -> Self {
        TruthOptions {
            seed,
            ..TruthOptions::default()
        }
    }
}

impl Default for TruthOptions {
    fn default() -> Self {
        TruthOptions {
            seed: 1,
            attempts: 8,
            twins: true,
            memory_limit: None,
        }
    }
}

/// The rigidity of a whole system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    pub method: Method,
    /// Why the answer is undecided, if it is; for a float answer, why it
    /// is in floats.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    pub n_rods: usize,
    pub n_contacts: usize,
    /// Rods and contacts of the 2-core, the part that can be rigid.
    pub core_rods: usize,
    pub core_contacts: usize,
    /// Forced plane classes, and the rods in the largest (MODEL §10: where
    /// it percolates, the line model forces the system flat).
    pub plane_classes: usize,
    pub largest_plane_class: usize,
    /// Rigid parts of the matrix (classes and the other core rods), its
    /// columns, rows and rank.
    pub parts: usize,
    pub columns: usize,
    pub rows: usize,
    pub rank: Option<usize>,
    /// Rigid motions not counted as deformations.
    pub trivial_motions: usize,
    /// Internal degrees of freedom of the whole system.
    pub dof: Option<usize>,
    /// Whether the twin realizations gave the same rank (`None` without twins).
    pub twins_agree: Option<bool>,
    /// Float answers only: the smaller singular-value gap of the twins (the
    /// smallest value counted over the largest one not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<f64>,
    /// Rigid clusters of two or more rods, largest first.
    pub clusters: Vec<Cluster>,
    /// The largest dense front of the elimination, rows times columns: what
    /// the cost of truth grows with.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_front: Option<(usize, usize)>,
    /// Set when the elimination stopped for the memory limit, with the
    /// front that would have passed it (the answer is then undecided).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refused: Option<sparse::Refused>,
    /// For a generated system: whether a rigid cluster spans under the
    /// criterion asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub criterion: Option<Criterion>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spanning: Option<bool>,
    pub seconds: f64,
}

/// A rigid cluster: rods with no relative motion.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Cluster {
    /// Member rods, sorted.
    pub rods: Vec<u32>,
    /// Whether it spans the box under each criterion (generated systems only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spans: Option<Spans>,
}

/// Spanning of one cluster under both criteria.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Spans {
    pub wrap: bool,
    pub faces: bool,
}

impl Spans {
    /// Whether it spans under `criterion`.
    pub fn under(self, criterion: Criterion) -> bool {
        match criterion {
            Criterion::Wrap => self.wrap,
            Criterion::Faces => self.faces,
        }
    }
}

impl Truth {
    /// Nothing decided yet about the system `graph`, whose rigid motions
    /// that are no deformation number `trivial_motions`.
    fn undecided(graph: &ContactGraph, trivial_motions: usize) -> Truth {
        Truth {
            method: Method::Undecided,
            reason: None,
            n_rods: graph.n_nodes(),
            n_contacts: graph.n_edges(),
            core_rods: 0,
            core_contacts: 0,
            plane_classes: 0,
            largest_plane_class: 0,
            parts: 0,
            columns: 0,
            rows: 0,
            rank: None,
            trivial_motions,
            dof: None,
            twins_agree: None,
            gap: None,
            clusters: Vec::new(),
            largest_front: None,
            refused: None,
            criterion: None,
            spanning: None,
            seconds: 0.0,
        }
    }

    /// Rods in the largest rigid cluster (0 when there is none).
    pub fn largest_cluster(&self) -> usize {
        self.clusters.first().map_or(0, |c| c.rods.len())
    }

    pub fn decided(&self) -> bool {
        self.method != Method::Undecided
    }

    /// Records an elimination stopped for the memory limit: undecided,
    /// with the front that would pass it.
    fn refuse(&mut self, e: sparse::Refused, limit: Option<u64>) {
        let limit = limit.expect("a refusal needs a limit");
        self.reason = Some(format!(
            "its elimination reached a dense front of {} x {} that would take it to about {}, over the memory limit of {}",
            e.front.0,
            e.front.1,
            gib(e.bytes),
            gib(limit)
        ));
        self.refused = Some(e);
    }

    /// Records why a twin stopped short of an answer.
    fn stop(&mut self, stop: Stop, limit: Option<u64>) {
        match stop {
            Stop::Memory(e) => self.refuse(e, limit),
            Stop::Degenerate(why) => self.reason = Some(why),
        }
    }

    /// Records a decided rank of the matrix, the degrees of freedom it
    /// leaves (its kernel, plus the `pruned` motions of what the 2-core
    /// removed, less the trivial motions) and the rigid clusters.
    /// Fewer motions than the trivial ones would mean a wrong matrix (the
    /// trivial motions lie in its kernel): the answer is then undecided,
    /// with the reason, never a clamped DOF.
    fn decide(&mut self, method: Method, rank: usize, pruned: usize, clusters: Vec<Vec<u32>>) {
        self.rank = Some(rank);
        let motions = self.columns - rank + pruned;
        let Some(dof) = motions.checked_sub(self.trivial_motions) else {
            self.method = Method::Undecided;
            self.reason = Some(format!(
                "{motions} motions, fewer than the {} trivial ones: the rigidity matrix is wrong",
                self.trivial_motions
            ));
            return;
        };
        self.method = method;
        self.dof = Some(dof);
        self.clusters = clusters
            .into_iter()
            .map(|rods| Cluster { rods, spans: None })
            .collect();
    }
}

/// The exact rigidity of the system `topo` (in floats where no exact
/// construction exists).
pub fn truth(topo: &Topology, opts: TruthOptions) -> Truth {
    evaluate(topo, opts, false)
}

/// [`truth`] by the float fallback even where a construction order exists:
/// for tests that compare the two paths.
#[doc(hidden)]
pub fn truth_in_floats(topo: &Topology, opts: TruthOptions) -> Truth {
    evaluate(topo, opts, true)
}

fn evaluate(topo: &Topology, opts: TruthOptions, floats: bool) -> Truth {
    let start = Instant::now();
    let graph = topo.graph;
    let core = prune::two_core(graph);
    let mut out = Truth::undecided(graph, topo.trivial_motions());
    out.core_rods = core.rods();
    out.core_contacts = core.contacts(graph);
    let finish = |mut out: Truth| {
        out.seconds = start.elapsed().as_secs_f64();
        out
    };
    let planes = match planes::forced(topo, &core.active) {
        Ok(p) => p,
        Err(u) => {
            // The periodic closure stops at the contradiction; the closure
            // without images runs to the end and sizes the whole class.
            out.largest_plane_class = planes::forced(&Topology::finite(graph), &core.active)
                .map_or(u.rods, |p| p.largest());
            out.reason = Some(format!(
                "a forced plane class of {} rods would contain three independent box directions: \
                 the line model has no realization in this box",
                u.rods
            ));
            return finish(out);
        }
    };
    out.plane_classes = planes.classes.len();
    out.largest_plane_class = planes.largest();
    let parts = matrix::parts(&planes, &core.active);
    out.parts = parts.count;
    out.columns = parts.count * matrix::WIDTH;
    let order = if floats {
        Err(None)
    } else {
        order::order(topo, &planes, &core.active).map_err(Some)
    };
    let order = match order {
        Ok(o) => o,
        Err(stuck) => {
            let why = stuck.map_or("asked for floats".to_string(), |s| {
                format!(
                    "no rational construction order: {} rods are each held by more placed lines than a rational step can meet",
                    s.rods.len()
                )
            });
            match fallback::decide(topo, &planes, &core.active, &parts, opts) {
                Ok(f) => {
                    out.reason = Some(format!("{why}; decided in floats"));
                    out.rows = f.rows;
                    out.twins_agree = Some(true);
                    out.gap = Some(f.gap);
                    out.decide(Method::Float, f.rank, core.pruned_motions(), f.clusters);
                }
                Err(w) => out.reason = Some(format!("{why}; in floats undecided: {w}")),
            }
            return finish(out);
        }
    };
    // Each twin draws its realization from its own stream, and kernel
    // vectors come from a third, so that nothing depends on how many draws
    // came before.
    let stream = |k| {
        let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
        rng.set_stream(k);
        rng
    };
    let (mut rng1, mut rng2, mut draws) = (stream(0), stream(2), stream(1));
    let twin = Twin {
        topo,
        planes: &planes,
        active: &core.active,
        order: &order,
        parts: &parts,
        attempts: opts.attempts.max(1),
        memory_limit: opts.memory_limit,
    };
    let pruned = core.pruned_motions();
    let first = match twin.rank::<Q1>(&mut rng1, Some(&mut draws)) {
        Ok(f) => f,
        Err(stop) => {
            out.stop(stop, opts.memory_limit);
            return finish(out);
        }
    };
    out.rows = first.rows.len();
    out.largest_front = Some(first.elim.largest_front);
    let clusters = clusters::clusters(topo, &parts, &first.real, &first.elim.kernel);
    if !opts.twins {
        out.decide(Method::Exact, first.elim.rank, pruned, clusters);
        return finish(out);
    }
    // The twin, in the other prime, checks the kernel's dimension with the
    // first twin's clusters contracted: that is all it needs to confirm
    // (MODEL §10). Only where the two differ does it rank the whole matrix,
    // and then the larger rank wins.
    let contraction = contract::of_clusters(topo, &parts, &clusters);
    let kernel = |rank: usize, count: usize| count * matrix::WIDTH - rank;
    let second = match twin.realize::<Q2>(&mut rng2) {
        Ok(s) => s,
        Err(stop) => {
            out.stop(stop, opts.memory_limit);
            return finish(out);
        }
    };
    let contracted = contraction.rows(&second.0, &second.1);
    let checked = sparse::rank(
        &contracted,
        contraction.count,
        matrix::WIDTH,
        opts.memory_limit,
    );
    match checked {
        Ok(c) if kernel(c.rank, contraction.count) == kernel(first.elim.rank, parts.count) => {
            out.twins_agree = Some(true);
            out.decide(Method::Exact, first.elim.rank, pruned, clusters);
            return finish(out);
        }
        Ok(_) => {}
        Err(e) => {
            out.refuse(e, opts.memory_limit);
            return finish(out);
        }
    }
    let (real, rows) = second;
    let whole = match twin.eliminate::<Q2>(&rows, None) {
        Ok(w) => w,
        Err(e) => {
            out.refuse(e, opts.memory_limit);
            return finish(out);
        }
    };
    out.twins_agree = Some(whole.rank == first.elim.rank);
    if whole.rank > first.elim.rank {
        match twin.eliminate(&rows, Some(&mut draws)) {
            Ok(elim) => {
                out.largest_front = Some(elim.largest_front);
                let clusters = clusters::clusters(topo, &parts, &real, &elim.kernel);
                out.decide(Method::Exact, elim.rank, pruned, clusters);
            }
            Err(e) => out.refuse(e, opts.memory_limit),
        }
    } else {
        out.decide(Method::Exact, first.elim.rank, pruned, clusters);
    }
    finish(out)
}

/// What every realization of one system shares.
struct Twin<'a> {
    topo: &'a Topology<'a>,
    planes: &'a planes::Planes,
    active: &'a [bool],
    order: &'a [u32],
    parts: &'a matrix::Parts,
    attempts: usize,
    /// Bytes an elimination may use.
    memory_limit: Option<u64>,
}

/// Why a twin stopped short of an elimination.
enum Stop {
    /// Every realization landed on a degenerate position.
    Degenerate(String),
    /// The elimination stopped before a front that would pass the limit.
    Memory(sparse::Refused),
}

/// Bytes in GiB, for messages.
fn gib(bytes: u64) -> String {
    format!("{:.2} GiB", bytes as f64 / (1u64 << 30) as f64)
}

/// One exact realization over a field, its matrix and their elimination.
struct Ranked<F> {
    real: realize::Realization<F>,
    rows: Vec<sparse::SparseRow<F>>,
    elim: sparse::Elimination<F>,
}

impl Twin<'_> {
    /// Builds a realization over `F` (redrawn while it lands on a
    /// degenerate position) and its matrix; `Err` says why no realization
    /// could be built.
    fn realize<F: Field>(
        &self,
        rng: &mut ChaCha8Rng,
    ) -> std::result::Result<(realize::Realization<F>, Vec<sparse::SparseRow<F>>), Stop> {
        let mut why = String::new();
        for _ in 0..self.attempts {
            match realize::build::<F>(self.topo, self.planes, self.active, self.order, rng) {
                Ok(real) => {
                    let rows = matrix::rows(self.topo, self.planes, self.parts, &real);
                    return Ok((real, rows));
                }
                Err(realize::Failure::Degenerate(w)) => why = w,
                Err(realize::Failure::Broken(why)) => panic!("truth construction: {why}"),
            }
        }
        Err(Stop::Degenerate(format!(
            "every one of {} realizations landed on a degenerate position (the last: {why})",
            self.attempts
        )))
    }

    /// [`Twin::realize`], and the elimination of its matrix with kernel
    /// vectors drawn from `draws` if given.
    fn rank<F: Field>(
        &self,
        rng: &mut ChaCha8Rng,
        draws: Option<&mut ChaCha8Rng>,
    ) -> std::result::Result<Ranked<F>, Stop> {
        let (real, rows) = self.realize(rng)?;
        let elim = self.eliminate(&rows, draws).map_err(Stop::Memory)?;
        Ok(Ranked { real, rows, elim })
    }

    /// Eliminates `rows`, with kernel vectors drawn from `draws` if given,
    /// within the memory limit.
    fn eliminate<F: Field>(
        &self,
        rows: &[sparse::SparseRow<F>],
        draws: Option<&mut ChaCha8Rng>,
    ) -> std::result::Result<sparse::Elimination<F>, sparse::Refused> {
        let (width, groups, limit) = (matrix::WIDTH, self.parts.count, self.memory_limit);
        match draws {
            Some(d) => sparse::eliminate(rows, groups, width, KERNEL_VECTORS, d, limit),
            None => sparse::rank(rows, groups, width, limit),
        }
    }
}

/// The truth of a rod system (`graph` built from
/// `contacts`), with the spanning of every cluster under both criteria and
/// whether one spans under `criterion`.
pub fn of_system(
    system: &RodSystem,
    contacts: &[Contact],
    graph: &ContactGraph,
    criterion: Criterion,
    opts: TruthOptions,
) -> Truth {
    let start = Instant::now();
    let shifts: Vec<Offset> = contacts.iter().map(|c| c.shift).collect();
    let topo = Topology::of_domain(graph, &shifts, &system.domain);
    let mut t = truth(&topo, opts);
    let mut checker = SpanChecker::new();
    for c in &mut t.clusters {
        let mut spans = |k| checker.spans(system, contacts, graph, &c.rods, k);
        c.spans = Some(Spans {
            wrap: spans(Criterion::Wrap),
            faces: spans(Criterion::Faces),
        });
    }
    t.criterion = Some(criterion);
    t.spanning = t.decided().then(|| {
        t.clusters
            .iter()
            .any(|c| c.spans.expect("set above").under(criterion))
    });
    t.seconds = start.elapsed().as_secs_f64();
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fewer_motions_than_the_trivial_ones_are_undecided_not_clamped() {
        let graph = ContactGraph::new(2, vec![[0, 1]]).unwrap();
        let mut t = Truth::undecided(&graph, 6);
        t.columns = 12;
        t.decide(Method::Exact, 9, 0, Vec::new());
        assert_eq!((t.method, t.dof), (Method::Undecided, None));
        assert!(
            t.reason
                .unwrap()
                .contains("3 motions, fewer than the 6 trivial ones")
        );
        let mut t = Truth::undecided(&graph, 6);
        t.columns = 12;
        t.decide(Method::Exact, 5, 1, vec![vec![0, 1]]);
        assert_eq!((t.method, t.dof, t.rank), (Method::Exact, Some(2), Some(5)));
        assert_eq!(t.largest_cluster(), 2);
    }
}
