//! How truth decides a system: the 2-core, the forced planes, an exact
//! construction order, two twin realizations ranked in two primes, and the
//! rigid clusters; the float fallback where no exact order exists.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

use super::answer::{Outcome, Spans, Strain, Strains, Truth, TruthOptions};
use super::planes::Planes;
use super::{clusters, contract, fallback, matrix, order, planes, prune, realize};
use crate::graph::Topology;
use crate::math::sparse::Deferred;
use crate::math::{Field, Fr, prime, sparse, with_prime};
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
    let (mut out, found) = ranked(topo, opts, floats);
    out.strains = Some(strains(&out, topo, opts, found));
    out
}

/// The strains of the box `out` resists: the Schur complement `found` of
/// the strain columns of the realization kept, read against the strains of
/// the periodic axes; unknown, with the reason, wherever that is not exact.
fn strains(out: &Truth, topo: &Topology, opts: TruthOptions, found: Option<Deferred>) -> Strains {
    let considered = Strain::of_box(topo.periodic);
    if considered.is_empty() {
        return Strains::unknown(
            considered,
            "no periodic axis: a finite framework has no box to strain",
        );
    }
    if !opts.strain {
        return Strains::unknown(considered, "not asked for");
    }
    match (&out.outcome, found) {
        (Outcome::Exact { .. }, Some(d)) => Strains {
            resisted: considered
                .iter()
                .copied()
                .filter(|c| d.nonzero[c.index()])
                .collect(),
            considered,
            rank: Some(d.rank as u8),
            reason: None,
        },
        (Outcome::Float { .. }, _) => Strains::unknown(
            considered,
            "decided in floats: only the exact elimination ranks the strain columns",
        ),
        _ => Strains::unknown(considered, "truth is undecided"),
    }
}

/// Truth without its strains, and the strain columns' Schur complement at
/// the realization kept (exact answers only).
fn ranked(topo: &Topology, opts: TruthOptions, floats: bool) -> (Truth, Option<Deferred>) {
    let start = Instant::now();
    let graph = topo.graph;
    let core = prune::two_core(graph);
    let mut out = Truth::unranked(graph, topo.trivial_motions());
    out.core_rods = core.rods();
    out.core_contacts = core.contacts(graph);
    let finish = |mut out: Truth| {
        out.seconds = start.elapsed().as_secs_f64();
        (out, None)
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
    let mut realizations = Realizations::new(opts);
    let twin = Twin::new(topo, &planes, &core.active, &order, &parts, opts);
    let pruned = core.pruned_motions();
    let first = match realizations.first(&twin) {
        Ok(f) => f,
        Err(stop) => {
            stopped(&mut out, stop, opts.memory_limit);
            return finish(out);
        }
    };
    out.rows = first.rows;
    out.largest_front = Some(first.largest_front);
    out.primes.push(first.prime);
    if realizations.count() == 1 {
        out.decide(first.rank, pruned, first.clusters, exact(None));
        return (finish(out).0, first.strain);
    }
    // Each later realization, in a prime of its own, checks the kernel's
    // dimension with the best clusters so far contracted: that is all it
    // needs to confirm (MODEL §10). Only where the two differ does it rank
    // its whole matrix, and then the larger rank wins.
    let (mut best, mut agree) = (first, true);
    for k in 1..realizations.count() {
        match realizations.check(k, &twin, &best) {
            Ok(Check::Confirmed { prime }) => out.primes.push(prime),
            Ok(Check::Whole {
                prime,
                rank,
                strain,
                larger,
            }) => {
                out.primes.push(prime);
                agree &= rank == best.rank;
                if let Some(l) = larger {
                    out.largest_front = Some(l.largest_front);
                    best = l;
                } else if rank == best.rank {
                    // Both realizations have the rank kept: each strain
                    // rank is a lower bound, so the larger is kept.
                    best.strain = larger_strain(best.strain.take(), strain);
                }
            }
            Err(stop) => {
                stopped(&mut out, stop, opts.memory_limit);
                return finish(out);
            }
        }
    }
    out.decide(best.rank, pruned, best.clusters, exact(Some(agree)));
    (finish(out).0, best.strain)
}

/// The Schur complement of the larger strain rank.
fn larger_strain(a: Option<Deferred>, b: Option<Deferred>) -> Option<Deferred> {
    match (a, b) {
        (Some(a), Some(b)) => Some(if b.rank > a.rank { b } else { a }),
        (a, b) => a.or(b),
    }
}

/// The whole rank of each of `opts.realizations` exact realizations of
/// `topo`, with its prime, before any contraction: what the measurement of
/// unlucky draws compares (`threshold::twins`). `None` where truth would
/// not rank exactly: no realization of the line model in the box, no
/// construction order, a degenerate draw every time, or the memory limit.
pub fn realization_ranks(topo: &Topology, opts: TruthOptions) -> Option<Vec<(u32, usize)>> {
    let core = prune::two_core(topo.graph);
    let planes = planes::forced(topo, &core.active).ok()?;
    let parts = matrix::parts(&planes, &core.active);
    let order = order::order(topo, &planes, &core.active).ok()?;
    let twin = Twin::new(topo, &planes, &core.active, &order, &parts, opts);
    Realizations::new(opts).ranks(&twin).ok()
}

/// An exact outcome, with whether the twins agreed (`None` without twins).
fn exact(twins_agree: Option<bool>) -> impl FnOnce(usize, usize) -> Outcome {
    move |rank, dof| Outcome::Exact {
        rank,
        dof,
        twins_agree,
    }
}

/// The most realizations one evaluation ranks.
pub const MAX_REALIZATIONS: usize = 3;

/// The random streams of the realizations, the kernel vectors and the
/// primes of one evaluation.
const REALIZATION_STREAMS: [u64; MAX_REALIZATIONS] = [0, 2, 4];
const KERNEL_STREAM: u64 = 1;
const PRIME_STREAM: u64 = 3;

/// One random stream of an evaluation seeded `seed`.
fn stream(seed: u64, k: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(k);
    rng
}

/// The realizations of one evaluation: each from its own random stream and
/// in its own prime, so that nothing depends on how many draws came before.
struct Realizations {
    seed: u64,
    primes: Vec<u32>,
    /// Kernel vectors come from a stream of their own.
    draws: ChaCha8Rng,
}

/// The best rank so far, with the clusters of its kernel.
struct Best {
    rank: usize,
    prime: u32,
    rows: usize,
    largest_front: (usize, usize),
    clusters: Vec<Vec<u32>>,
    /// The strain columns' Schur complement, if they were ranked.
    strain: Option<Deferred>,
}

/// What a later realization found.
enum Check {
    /// Its contracted matrix has the kernel the best rank predicts.
    Confirmed { prime: u32 },
    /// It did not: its whole rank with its strain columns' Schur
    /// complement, and what it found if that is larger.
    Whole {
        prime: u32,
        rank: usize,
        strain: Option<Deferred>,
        larger: Option<Best>,
    },
}

impl Realizations {
    fn new(opts: TruthOptions) -> Self {
        let count = opts.realizations.clamp(1, MAX_REALIZATIONS);
        let primes = match opts.primes {
            Some(fixed) => fixed[..count].to_vec(),
            None => {
                let mut rng = stream(opts.seed, PRIME_STREAM);
                let mut primes: Vec<u32> = Vec::with_capacity(count);
                while primes.len() < count {
                    let q = prime::draw(&mut rng);
                    if !primes.contains(&q) {
                        primes.push(q);
                    }
                }
                primes
            }
        };
        Realizations {
            seed: opts.seed,
            primes,
            draws: stream(opts.seed, KERNEL_STREAM),
        }
    }

    fn count(&self) -> usize {
        self.primes.len()
    }

    fn rng(&self, k: usize) -> ChaCha8Rng {
        stream(self.seed, REALIZATION_STREAMS[k])
    }

    /// The first realization ranked whole, with its clusters.
    fn first(&mut self, twin: &Twin) -> std::result::Result<Best, Stop> {
        let (prime, mut rng, draws) = (self.primes[0], self.rng(0), &mut self.draws);
        with_prime(prime, || {
            let r = twin.rank::<Fr>(&mut rng, Some(draws))?;
            Ok(Best {
                rank: r.elim.rank,
                prime,
                rows: r.rows.len(),
                largest_front: r.elim.largest_front,
                clusters: clusters::clusters(twin.topo, twin.parts, &r.real, &r.elim.kernel),
                strain: r.elim.deferred,
            })
        })
    }

    /// Realization `k` checks `best`: its matrix with `best`'s clusters
    /// contracted, and its whole matrix where the kernels differ.
    fn check(&mut self, k: usize, twin: &Twin, best: &Best) -> std::result::Result<Check, Stop> {
        let (prime, mut rng, draws) = (self.primes[k], self.rng(k), &mut self.draws);
        let contraction = contract::of_clusters(twin.topo, twin.parts, &best.clusters);
        let kernel = |rank: usize, count: usize| count * matrix::WIDTH - rank;
        with_prime(prime, || {
            let (real, rows) = twin.realize::<Fr>(&mut rng)?;
            let contracted = contraction.rows(&real, &rows);
            let layout = sparse::Layout::plain(contraction.count, matrix::WIDTH);
            let checked =
                sparse::rank(&contracted, layout, twin.memory_limit).map_err(Stop::Memory)?;
            if kernel(checked.rank, contraction.count) == kernel(best.rank, twin.parts.count) {
                return Ok(Check::Confirmed { prime });
            }
            let whole = twin.eliminate::<Fr>(&rows, None).map_err(Stop::Memory)?;
            let larger = if whole.rank > best.rank {
                let elim = twin.eliminate(&rows, Some(draws)).map_err(Stop::Memory)?;
                Some(Best {
                    rank: elim.rank,
                    prime,
                    rows: rows.len(),
                    largest_front: elim.largest_front,
                    clusters: clusters::clusters(twin.topo, twin.parts, &real, &elim.kernel),
                    strain: elim.deferred,
                })
            } else {
                None
            };
            Ok(Check::Whole {
                prime,
                rank: whole.rank,
                strain: whole.deferred,
                larger,
            })
        })
    }

    /// The whole rank of every realization, each in its prime: what the
    /// twins' measurement compares (no contraction, no clusters).
    fn ranks(&self, twin: &Twin) -> std::result::Result<Vec<(u32, usize)>, Stop> {
        (0..self.count())
            .map(|k| {
                let (prime, mut rng) = (self.primes[k], self.rng(k));
                with_prime(prime, || {
                    let (_, rows) = twin.realize::<Fr>(&mut rng)?;
                    let e = twin.eliminate::<Fr>(&rows, None).map_err(Stop::Memory)?;
                    Ok((prime, e.rank))
                })
            })
            .collect()
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
    /// The strains with columns (none unless asked for in a periodic box).
    strains: Vec<Strain>,
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

impl<'a> Twin<'a> {
    /// Bytes a realization and its matrix hold per core rod (its line, its
    /// spin rows) and per core contact (its point, three rows of up to
    /// twelve entries): resident growth measured over them was 350 to 450
    /// bytes per contact (rods included) at gamma 23 to 98.
    const ROD_BYTES: usize = 120;
    const CONTACT_BYTES: usize = 420;

    fn new(
        topo: &'a Topology<'a>,
        planes: &'a Planes,
        active: &'a [bool],
        order: &'a [u32],
        parts: &'a matrix::Parts,
        opts: TruthOptions,
    ) -> Self {
        Twin {
            topo,
            planes,
            active,
            order,
            parts,
            attempts: opts.attempts.max(1),
            memory_limit: opts.memory_limit,
            strains: if opts.strain {
                Strain::of_box(topo.periodic)
            } else {
                Vec::new()
            },
        }
    }

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
                    let strain = matrix::StrainColumns::new(self.parts, &self.strains);
                    let rows = matrix::rows(self.topo, self.planes, self.parts, &real, &strain);
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
        // The strain columns, one group after the parts', ranked last.
        let layout = if self.strains.is_empty() {
            sparse::Layout::plain(groups, width)
        } else {
            sparse::Layout::deferring(groups + 1, width)
        };
        match draws {
            Some(d) => sparse::eliminate(rows, layout, KERNEL_VECTORS, d, limit),
            None => sparse::rank(rows, layout, limit),
        }
    }
}

/// The truth of a rod system with its contacts, with the spanning of every
/// cluster under both criteria and whether one spans under `criterion`
/// (under `Solid`, whether the strain rank reaches the strains considered).
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
    t.spanning = if criterion == Criterion::Solid {
        t.strains
            .as_ref()
            .and_then(|s| Some(usize::from(s.rank?) == s.considered.len()))
    } else {
        t.decided().then(|| {
            t.clusters
                .iter()
                .any(|c| c.spans.expect("set above").under(criterion))
        })
    };
    t.seconds = start.elapsed().as_secs_f64();
    t
}
