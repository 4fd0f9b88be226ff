//! How truth decides a system: the 2-core, the forced planes, an exact
//! construction order, two twin realizations ranked in two primes, and the
//! rigid clusters; the float fallback where no exact order exists.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

use super::answer::{Outcome, Spans, Truth, TruthOptions};
use super::planes::Planes;
use super::{clusters, contract, fallback, matrix, order, planes, prune, realize};
use crate::graph::Topology;
use crate::math::{Field, Q1, Q2, sparse};
use crate::network::View;
use crate::spanning::{Criterion, SpanChecker};

/// Random kernel vectors drawn for the clusters: a relation that holds on
/// all of them holds on the whole kernel except with probability `1/q^2`.
const KERNEL_VECTORS: usize = 2;

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
    let mut out = Truth::unranked(graph, topo.trivial_motions());
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
            out.undecide(format!(
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
                    out.rows = f.rows;
                    let reason = format!("{why}; decided in floats");
                    out.decide(f.rank, core.pruned_motions(), f.clusters, |rank, dof| {
                        Outcome::Float {
                            rank,
                            dof,
                            gap: f.gap,
                            reason,
                        }
                    });
                }
                Err(w) => out.undecide(format!("{why}; in floats undecided: {w}")),
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
            stopped(&mut out, stop, opts.memory_limit);
            return finish(out);
        }
    };
    out.rows = first.rows.len();
    out.largest_front = Some(first.elim.largest_front);
    let clusters = clusters::clusters(topo, &parts, &first.real, &first.elim.kernel);
    if !opts.twins {
        out.decide(first.elim.rank, pruned, clusters, exact(None));
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
            stopped(&mut out, stop, opts.memory_limit);
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
            out.decide(first.elim.rank, pruned, clusters, exact(Some(true)));
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
    let agree = exact(Some(whole.rank == first.elim.rank));
    if whole.rank > first.elim.rank {
        match twin.eliminate(&rows, Some(&mut draws)) {
            Ok(elim) => {
                out.largest_front = Some(elim.largest_front);
                let clusters = clusters::clusters(topo, &parts, &real, &elim.kernel);
                out.decide(elim.rank, pruned, clusters, agree);
            }
            Err(e) => out.refuse(e, opts.memory_limit),
        }
    } else {
        out.decide(first.elim.rank, pruned, clusters, agree);
    }
    finish(out)
}

/// An exact outcome, with whether the twins agreed (`None` without twins).
fn exact(twins_agree: Option<bool>) -> impl FnOnce(usize, usize) -> Outcome {
    move |rank, dof| Outcome::Exact {
        rank,
        dof,
        twins_agree,
    }
}

/// What every realization of one system shares.
struct Twin<'a> {
    topo: &'a Topology<'a>,
    planes: &'a Planes,
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

/// Records why a twin stopped short of an answer.
fn stopped(out: &mut Truth, stop: Stop, limit: Option<u64>) {
    match stop {
        Stop::Memory(e) => out.refuse(e, limit),
        Stop::Degenerate(why) => out.undecide(why),
    }
}

/// One exact realization over a field, its matrix and their elimination.
struct Ranked<F> {
    real: realize::Realization<F>,
    rows: Vec<sparse::SparseRow<F>>,
    elim: sparse::Elimination<F>,
}

impl Twin<'_> {
    /// Bytes a realization and its matrix hold per core rod (its line, its
    /// spin rows) and per core contact (its point, three rows of up to
    /// twelve entries): resident growth measured over them was 350 to 450
    /// bytes per contact (rods included) at gamma 23 to 98.
    const ROD_BYTES: usize = 120;
    const CONTACT_BYTES: usize = 420;

    /// Builds a realization over `F` (redrawn while it lands on a
    /// degenerate position) and its matrix; `Err` says why no realization
    /// could be built.
    /// Refused before anything is built if the realization and its matrix
    /// would take the process past its memory limit.
    fn realize<F: Field>(
        &self,
        rng: &mut ChaCha8Rng,
    ) -> std::result::Result<(realize::Realization<F>, Vec<sparse::SparseRow<F>>), Stop> {
        let graph = self.topo.graph;
        let rods = self.active.iter().filter(|&&a| a).count();
        let contacts = graph
            .edges()
            .iter()
            .filter(|&&[a, b]| self.active[a as usize] && self.active[b as usize])
            .count();
        let need = (rods * Self::ROD_BYTES + contacts * Self::CONTACT_BYTES) as u64;
        crate::usage::reserve(need, 0, self.memory_limit).map_err(|refusal| {
            Stop::Memory(sparse::Refused {
                refusal,
                step: sparse::Step::Rows,
            })
        })?;
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

/// The truth of a rod system with its contacts, with the spanning of every
/// cluster under both criteria and whether one spans under `criterion`.
pub fn of_system(network: View, criterion: Criterion, opts: TruthOptions) -> Truth {
    let start = Instant::now();
    let View {
        system,
        contacts,
        graph,
        ..
    } = network;
    let mut t = truth(&network.topology(), opts);
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
