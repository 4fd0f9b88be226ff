//! The elastic tensor of a rod system in floats (MODEL §10, elastic
//! moduli).
//!
//! The matrix is truth's ([`crate::truth::matrix`]) with every core rod a
//! part of its own: a forced plane class is rigid in truth because its
//! contacts hold it so, but here those contacts are springs like any other,
//! so a class is elastic and gets no rows of its own. Its rows are the
//! contacts (3 each, a spring each) and each rod's spin about its axis (a
//! gauge: it moves no contact point, so it carries no spring and changes no
//! energy). The strain columns are truth's.
//!
//! The realization is the float one nearest the actual rods
//! ([`projection::nearest`]): contact points on both axes, the forced
//! planes kept, so that it is a member of truth's family and its tensor has
//! the exact strain rank, while its geometry (box side, rod directions,
//! where rods touch) is the rods' own to within the projection. Lengths are
//! in mean rod lengths, so moduli are in `k / L_rod`.
//!
//! Only the 2-core is kept: a rod with one contact turns about it and a
//! free rod moves freely, so neither carries stress at any strain, and
//! removing them (repeatedly) changes no energy.

use std::time::Instant;

use faer::sparse::Triplet;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::{Accum, Mat, Par};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::relax::{self, Relaxation, Solver};
use super::voigt::Voigt;
use crate::graph::Topology;
use crate::math::vec3::{Line, V3, add, distance, foot, norm, scale, sub};
use crate::network::View;
use crate::rods::Periodic;
use crate::truth::planes::{self, Planes};
use crate::truth::realize::Realization;
use crate::truth::{Strain, TruthOptions, matrix, projection, prune, truth};
use crate::usage;
use crate::{Error, Result};

/// What a moduli computation takes.
#[derive(Clone, Copy, Debug)]
pub struct ModuliOptions {
    /// Spring stiffness `k` of a contact, in each direction.
    pub stiffness: f64,
    /// Truth's options, for the exact strain rank.
    pub truth: TruthOptions,
    /// How the springs' least squares is solved.
    pub solver: Solver,
    /// LSMR's iterations per strain column at most: where they run out
    /// the moduli are upper bounds (`Conditioning::settled`).
    pub lsmr_iterations: usize,
}

/// How well posed the solve was.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Conditioning {
    /// The regularization `λ` of the least squares (`R` stacked on
    /// `√λ I`), or with LSMR the shift `μ` of its preconditioner
    /// (`RᵀR + μI`).
    pub regularization: f64,
    /// The largest `|Rᵀ r| / (|R|_F |r|)` left: the least squares'
    /// optimality, at rounding of the affine columns' size when the solve
    /// is well posed (`|b| / |r|` times the precision).
    pub optimality: f64,
    /// Refinement steps taken (LSMR's iterations), and whether the
    /// energies settled (if not, the moduli are upper bounds the solve had
    /// not reached).
    pub steps: usize,
    pub settled: bool,
    /// The solver that relaxed the strain columns (absent in results made
    /// before LSMR: the QR).
    #[serde(default = "Solver::qr")]
    pub solver: Solver,
    /// The smallest eigenvalue kept over the Born tensor's largest (none
    /// when the strain rank is 0).
    pub kept: Option<f64>,
    /// The largest eigenvalue dropped over the Born tensor's largest (none
    /// at rank 6).
    pub dropped: Option<f64>,
}

/// The elastic moduli of a system, in `k / L_rod` (Voigt's notation; the
/// isotropic averages are Voigt's, upper bounds of the Hill and Reuss ones).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Elastic {
    /// The spring stiffness `k`.
    pub stiffness: f64,
    /// The box volume in rod lengths cubed.
    pub volume: f64,
    /// The strains the system resists (exact, from truth).
    pub strain_rank: u8,
    /// The relaxed tensor, kept at the strain rank.
    pub tensor: Voigt,
    /// The affine (Born) tensor: every rod's centre moved with the strain,
    /// no relaxation; an upper bound of `tensor`.
    pub born: Voigt,
    /// Eigenvalues of the relaxed tensor before it is kept at the strain
    /// rank, largest first.
    pub eigenvalues: [f64; 6],
    pub shear: f64,
    pub bulk: f64,
    pub born_shear: f64,
    pub born_bulk: f64,
    /// `1 - G / G_Born`: how much of the affine shear stiffness relaxation
    /// takes away (none where `G_Born` is 0).
    pub nonaffinity: Option<f64>,
    pub conditioning: Conditioning,
    /// Which realization the floats use: `nearest` the rods, or
    /// `projected` from a random start where that did not converge (then
    /// scaled to the box side: the same family and strain rank, not the
    /// rods' own geometry), or `nearest-next`: the one nearest the rods of
    /// a larger system, kept for these rods ([`Floats::prefix`]), so that
    /// the two systems' moduli are those of one geometry.
    pub realization: String,
    /// How far the realization moved the rods, in mean rod lengths: the
    /// root mean square distance of the contact points from the rods' own
    /// (on the first rod's axis), and of the rods' centres from their lines
    /// (none for `projected`).
    pub moved: Option<Moved>,
    pub rods: usize,
    pub contacts: usize,
    /// Rods and contacts of the 2-core, where the springs are.
    pub core_rods: usize,
    pub core_contacts: usize,
    /// Rods in truth's largest rigid cluster (none for a given realization,
    /// where truth was not asked).
    pub largest_cluster: Option<usize>,
    /// The length unit in the rods' own units: their mean length.
    pub length_unit: f64,
    /// Seconds of truth (for the strain rank) and of the whole.
    pub truth_seconds: f64,
    pub seconds: f64,
    /// Seconds of the relaxation alone (the springs' least squares on a
    /// given realization): the part no choice of realization avoids.
    #[serde(default)]
    pub relaxation_seconds: f64,
}

/// No forced planes: every active rod a part of its own.
fn no_planes(topo: &Topology) -> Planes {
    Planes {
        classes: Vec::new(),
        of_rod: vec![Vec::new(); topo.graph.n_nodes()],
        inside: vec![None; topo.graph.n_edges()],
    }
}

/// The velocity gradient of strain column `j` applied to `x`.
fn strained(j: usize, x: V3<f64>) -> V3<f64> {
    let [a, b] = Strain::ALL[j].axes();
    let mut v = [0.0; 3];
    v[a] += x[b];
    if a != b {
        v[b] += x[a];
    }
    v
}

/// The springs of a realization: the contact matrix `R` (3 rows per
/// contact, a spring each, then a spin row per rod, a gauge) by its
/// entries over the parts' columns, and the affine stretches `B` of the
/// six strain columns (truth's, every rod's centre moved with the strain).
#[derive(Clone, Debug)]
pub struct Springs {
    pub rows: usize,
    pub columns: usize,
    pub entries: Vec<Triplet<usize, usize, f64>>,
    pub affine: Mat<f64>,
}

/// The [`Springs`] of the `active` rods of `topo` at `real`, the Born
/// tensor moving `centres`.
pub fn springs(
    topo: &Topology,
    active: &[bool],
    real: &Realization<f64>,
    centres: &[Option<V3<f64>>],
) -> Result<Springs> {
    let none = no_planes(topo);
    let parts = matrix::parts(&none, active);
    let strains = matrix::StrainColumns::new(&parts, &Strain::ALL);
    let rows = matrix::rows(topo, &none, &parts, real, &strains);
    let first = parts.count * matrix::WIDTH;
    let mut entries = Vec::new();
    let mut b = Mat::<f64>::zeros(rows.len(), 6);
    for (i, row) in rows.iter().enumerate() {
        for &(c, v) in row {
            let c = c as usize;
            if c < first {
                entries.push(Triplet::new(i, c, v));
            } else {
                b[(i, c - first)] += v;
            }
        }
    }
    // The affine motion: each rod's centre moved by the strain, no turn.
    let mut u = Mat::<f64>::zeros(first, 6);
    for (r, owner) in parts.owner.iter().enumerate() {
        let (Some((part, _)), Some(c)) = (*owner, centres.get(r).copied().flatten()) else {
            continue;
        };
        for j in 0..6 {
            let t = strained(j, c);
            for k in 0..3 {
                u[(part as usize * matrix::WIDTH + 3 + k, j)] = t[k];
            }
        }
    }
    let r = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(
        rows.len(),
        first,
        &entries,
    )
    .map_err(|e| Error::analysis(format!("the contact matrix: {e:?}")))?;
    let mut affine = b;
    sparse_dense_matmul(
        affine.as_mut(),
        Accum::Add,
        r.as_ref(),
        u.as_ref(),
        1.0,
        Par::Seq,
    );
    Ok(Springs {
        rows: rows.len(),
        columns: first,
        affine,
        entries,
    })
}

/// The moduli of the realization `real` of the `active` rods of a
/// periodic `topo`, kept at the exact `strain_rank`; `centres` (per rod, on
/// its line) move with the strain in the Born tensor; springs of
/// `opts.stiffness`, solved by `opts.solver`. The factor is refused where
/// it would take the process past truth's memory limit (bytes resident).
pub fn of_realization(
    topo: &Topology,
    active: &[bool],
    real: &Realization<f64>,
    centres: &[Option<V3<f64>>],
    strain_rank: u8,
    opts: ModuliOptions,
) -> Result<Elastic> {
    let stiffness = opts.stiffness;
    if topo.periodic != [true; 3] || topo.shifts.is_none() {
        return Err(Error::Parameter(
            "moduli need a box periodic along x, y and z".into(),
        ));
    }
    if !(stiffness.is_finite() && stiffness > 0.0) {
        return Err(Error::Parameter(format!(
            "the spring stiffness k must be positive and finite, not {stiffness}"
        )));
    }
    let start = Instant::now();
    let Springs {
        rows,
        columns,
        entries,
        affine,
    } = springs(topo, active, real, centres)?;
    let Relaxation {
        relaxed,
        affine: born,
        regularization,
        optimality,
        steps,
        settled,
        solver,
    } = relax::relax(
        rows,
        columns,
        &entries,
        &affine,
        opts.solver,
        opts.lsmr_iterations,
        opts.truth.memory_limit,
    )?;
    let volume = real.side.powi(3);
    let raw = Voigt::of_strain_columns(&relaxed, stiffness / volume);
    let born = Voigt::of_strain_columns(&born, stiffness / volume);
    let spectrum = raw.spectrum();
    let eigenvalues: [f64; 6] = std::array::from_fn(|k| spectrum[k].0);
    let s = usize::from(strain_rank);
    // Against the Born tensor's scale: a relaxed tensor of rank 0 is zero
    // to rounding of the affine one, not of itself.
    let top = born.spectrum()[0].0.max(0.0);
    let over = |k: usize| if top > 0.0 { eigenvalues[k] / top } else { 0.0 };
    let kept = (s > 0).then(|| over(s - 1));
    let dropped = (s < 6).then(|| over(s));
    // The exact rank says where the gap is; the floats must show one there.
    if let (Some(k), Some(d)) = (kept, dropped.or(Some(0.0)))
        && k <= d
    {
        return Err(Error::analysis(format!(
            "the float tensor shows no gap at the exact strain rank {s} (kept eigenvalue {}, dropped {} of Born's largest): ill-conditioned",
            crate::error::four(k),
            crate::error::four(d)
        )));
    }
    let tensor = raw.truncated(s);
    let (shear, born_shear) = (tensor.shear(), born.shear());
    let core_rods = active.iter().filter(|&&a| a).count();
    let core_contacts = topo
        .graph
        .edges()
        .iter()
        .filter(|&&[a, b]| active[a as usize] && active[b as usize])
        .count();
    Ok(Elastic {
        stiffness,
        volume,
        strain_rank,
        tensor,
        born,
        eigenvalues,
        shear,
        bulk: tensor.bulk(),
        born_shear,
        born_bulk: born.bulk(),
        nonaffinity: (born_shear > 0.0).then(|| 1.0 - shear / born_shear),
        conditioning: Conditioning {
            regularization,
            optimality,
            steps,
            settled,
            solver,
            kept,
            dropped,
        },
        realization: "given".into(),
        moved: None,
        rods: topo.graph.n_nodes(),
        contacts: topo.graph.n_edges(),
        core_rods,
        core_contacts,
        largest_cluster: None,
        length_unit: 1.0,
        truth_seconds: 0.0,
        seconds: 0.0,
        relaxation_seconds: start.elapsed().as_secs_f64(),
    })
}

/// How far a realization lies from the rods it was projected from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Moved {
    /// Root mean square distance of the contact points.
    pub contacts: f64,
    /// Root mean square distance of the rods' centres from their lines.
    pub centres: f64,
}

impl Moved {
    /// From `rods` (lines through the centres, points on the first rod's
    /// axis) to `real`, in their common unit.
    fn between(rods: &Realization<f64>, real: &Realization<f64>) -> Moved {
        let rms = |d: Vec<f64>| {
            let n = d.len().max(1) as f64;
            (d.iter().map(|x| x * x).sum::<f64>() / n).sqrt()
        };
        let contacts = rods
            .points
            .iter()
            .zip(&real.points)
            .filter_map(|(a, b)| Some(norm(sub((*a)?, (*b)?))))
            .collect();
        let centres = rods
            .lines
            .iter()
            .zip(&real.lines)
            .filter_map(|(a, b)| {
                let (c, l) = ((*a)?.p, (*b)?);
                Some(distance(&l, c))
            })
            .collect();
        Moved {
            contacts: rms(contacts),
            centres: rms(centres),
        }
    }
}

/// Per rod, the mean of its contact points in its own frame.
fn contact_centres(topo: &Topology, real: &Realization<f64>) -> Vec<Option<V3<f64>>> {
    let mut sum = vec![([0.0; 3], 0usize); topo.graph.n_nodes()];
    for (e, &[a, b]) in topo.graph.edges().iter().enumerate() {
        let Some(x) = real.points[e] else { continue };
        let seen = real.lattice(topo.seen(e as u32, a));
        for (r, y) in [(a, x), (b, sub(x, seen))] {
            let s = &mut sum[r as usize];
            *s = (add(s.0, y), s.1 + 1);
        }
    }
    sum.into_iter()
        .map(|(s, n)| (n > 0).then(|| scale(s, 1.0 / n as f64)))
        .collect()
}

/// `real` scaled to the box side `side` (a similarity: no rank changes).
fn scaled(mut real: Realization<f64>, side: f64) -> Realization<f64> {
    let k = side / real.side;
    for l in real.lines.iter_mut().flatten() {
        l.p = scale(l.p, k);
    }
    for x in real.points.iter_mut().flatten() {
        *x = scale(*x, k);
    }
    real.side = side;
    real
}

/// The float realization of a system's 2-core the moduli use.
#[derive(Clone, Debug)]
pub struct Floats {
    /// The 2-core.
    pub active: Vec<bool>,
    pub real: Realization<f64>,
    /// The rods' own lines and contact points it was projected from.
    pub near: Realization<f64>,
    /// Per core rod, the point the Born tensor moves with the strain.
    pub centres: Vec<Option<V3<f64>>>,
    /// `nearest`, `projected` or `nearest-next` ([`Elastic::realization`]).
    pub how: &'static str,
    /// How far it moved the rods (none for `projected`).
    pub moved: Option<Moved>,
    /// The mean rod length, the unit of lengths.
    pub unit: f64,
}

/// Per rod of a prefix's `active` core, `v`'s value (none off the core).
fn on_core<T: Copy>(v: &[Option<T>], active: &[bool]) -> Vec<Option<T>> {
    active
        .iter()
        .zip(v)
        .map(|(&on, x)| x.filter(|_| on))
        .collect()
}

impl Floats {
    /// The same realization for a prefix `network` of the rods it was made
    /// for (the first rods, with the first contacts): lines and points kept
    /// for the prefix's own 2-core, which lies inside this one. Every
    /// incidence of the prefix holds, so it is a realization of the prefix,
    /// though it may be special for it (a plane this system forces and the
    /// prefix does not): the moduli's gap check at the exact strain rank
    /// says so. On one realization the prefix's tensor is at most this
    /// one's, since the prefix's springs are a subset of these.
    pub fn prefix(&self, network: View) -> Floats {
        let core = prune::two_core(network.graph);
        let edges = network.graph.edges();
        let keep = |of: &Realization<f64>| Realization {
            side: of.side,
            lines: on_core(&of.lines, &core.active),
            points: edges
                .iter()
                .enumerate()
                .map(|(e, &[a, b])| {
                    (core.active[a as usize] && core.active[b as usize])
                        .then_some(of.points[e])
                        .flatten()
                })
                .collect(),
        };
        let (real, near) = (keep(&self.real), keep(&self.near));
        let centres = on_core(&self.centres, &core.active);
        Floats {
            moved: self.moved.map(|_| Moved::between(&near, &real)),
            how: if self.how == "nearest" {
                "nearest-next"
            } else {
                self.how
            },
            active: core.active,
            real,
            near,
            centres,
            unit: self.unit,
        }
    }
}

/// A box periodic along every axis and cubic, or why not.
fn check_box(network: View) -> Result<()> {
    let system = network.system;
    if system.domain.periodic != Periodic::Xyz {
        return Err(Error::Parameter(
            "moduli need a box periodic along x, y and z".into(),
        ));
    }
    let [lx, ly, lz] = system.domain.sides;
    if lx != ly || ly != lz {
        return Err(Error::Parameter(format!(
            "moduli need a cubic box, not sides {lx}, {ly}, {lz}"
        )));
    }
    Ok(())
}

/// The float realization of the 2-core of `network` in mean rod lengths:
/// the one nearest the rods, or where that projection does not converge
/// and `random_start` allows it, one from a random start (`seed`) scaled
/// to the box (another member of the family, whose moduli do not compare
/// with those of other systems' nearest realizations). The projection is
/// refused up front where it would take the process past `limit` (bytes
/// resident) or the machine's room.
pub fn floats(network: View, seed: u64, random_start: bool, limit: Option<u64>) -> Result<Floats> {
    check_box(network)?;
    let system = network.system;
    let lx = system.domain.sides[0];
    // The view's rods: a prefix of a sequence's system.
    let rods = &system.rods[..network.graph.n_nodes()];
    let unit = if rods.is_empty() {
        1.0
    } else {
        rods.iter().map(|r| r.length).sum::<f64>() / rods.len() as f64
    };
    let topo = network.topology();
    let core = prune::two_core(network.graph);
    let planes = planes::forced(&topo, &core.active).map_err(|u| {
        Error::analysis(format!(
            "a forced plane of {} rods would contain three lattice directions: no realization",
            u.rods
        ))
    })?;
    let to = |x: nalgebra::Vector3<f64>| [x[0] / unit, x[1] / unit, x[2] / unit];
    let lines: Vec<Option<Line<f64>>> = rods
        .iter()
        .zip(&core.active)
        .map(|(rod, &on)| {
            on.then(|| Line {
                p: to(rod.center),
                d: [rod.axis[0], rod.axis[1], rod.axis[2]],
            })
        })
        .collect();
    let points = network
        .contacts
        .iter()
        .map(|c| {
            let [a, b] = c.rods.map(|r| r as usize);
            let rod = &system.rods[a];
            (core.active[a] && core.active[b]).then(|| to(rod.center + rod.axis * c.params[0]))
        })
        .collect();
    let near = Realization {
        side: lx / unit,
        lines,
        points,
    };
    // The repairs' kicks and the random start draw from streams of their
    // own, so that the start does not depend on how many kicks failed.
    let draws = |stream: u64| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(stream);
        rng
    };
    if let Some(need) = projection::nearest_memory(&topo, &planes, &core.active, &near) {
        usage::reserve(need, 0, limit).map_err(|r| {
            Error::Memory(r.describe(&format!(
                "the projection of the {} core rods onto their line model",
                core.rods()
            )))
        })?;
    }
    let near_rods = projection::nearest(&topo, &planes, &core.active, &near, &mut draws(1));
    let (real, how) = match near_rods {
        Ok(real) => (real, "nearest"),
        Err(why) if !random_start => {
            return Err(Error::analysis(format!(
                "no float realization nearest the rods: {why}"
            )));
        }
        Err(_) => {
            let real = projection::project(&topo, &planes, &core.active, &mut draws(0))
                .map_err(|why| Error::analysis(format!("no float realization: {why}")))?;
            (scaled(real, near.side), "projected")
        }
    };
    // The centres the Born tensor moves: the rods' own on the lines nearest
    // them, else the mean of each rod's contact points.
    let moved = (how == "nearest").then(|| Moved::between(&near, &real));
    let centres: Vec<Option<V3<f64>>> = if moved.is_some() {
        rods.iter()
            .zip(&real.lines)
            .map(|(rod, line)| Some(foot(&(*line)?, to(rod.center))))
            .collect()
    } else {
        contact_centres(&topo, &real)
    };
    Ok(Floats {
        active: core.active,
        real,
        near,
        centres,
        how,
        moved,
        unit,
    })
}

/// What truth says of a rod system before any float: its exact strain
/// rank and largest rigid cluster, and the seconds it took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exact {
    pub strain_rank: u8,
    pub largest_cluster: usize,
    pub seconds: f64,
}

/// Truth of a rod system with its contacts in a cubic periodic box, for
/// the moduli: the exact strain rank they are kept at. Where it is 0 the
/// tensor is zero and no float is needed.
pub fn exact(network: View, opts: ModuliOptions) -> Result<Exact> {
    if !(opts.stiffness.is_finite() && opts.stiffness > 0.0) {
        return Err(Error::Parameter(format!(
            "the spring stiffness k must be positive and finite, not {}",
            opts.stiffness
        )));
    }
    check_box(network)?;
    let topo = network.topology();
    let t = truth(&topo, opts.truth);
    if t.outcome.refused().is_some() {
        return Err(Error::Memory(format!(
            "truth refused this system: {}",
            t.outcome.reason().unwrap_or_default()
        )));
    }
    let strains = t.strains.as_ref().expect("truth reports its strains");
    let Some(rank) = strains.rank else {
        return Err(Error::analysis(format!(
            "the strain rank is unknown: {}",
            strains.reason.as_deref().unwrap_or("truth is undecided")
        )));
    };
    Ok(Exact {
        strain_rank: rank,
        largest_cluster: t.largest_cluster(),
        seconds: t.seconds,
    })
}

/// The moduli of a rod system whose truth is `exact`: the realization
/// nearest the rods ([`floats`], from a random start where that fails and
/// `random_start` allows it), the tensor kept at the exact strain rank.
pub fn of_exact(
    network: View,
    exact: Exact,
    opts: ModuliOptions,
    random_start: bool,
) -> Result<Elastic> {
    let start = Instant::now();
    let f = floats(
        network,
        opts.truth.seed,
        random_start,
        opts.truth.memory_limit,
    )?;
    let mut e = of_floats(network, exact, &f, opts)?;
    e.seconds = exact.seconds + start.elapsed().as_secs_f64();
    Ok(e)
}

/// The moduli of a rod system whose truth is `exact` on the float
/// realization `f` of its 2-core (from [`floats`], or
/// [`Floats::prefix`] of a larger system's), kept at the exact strain rank.
pub fn of_floats(network: View, exact: Exact, f: &Floats, opts: ModuliOptions) -> Result<Elastic> {
    let start = Instant::now();
    let mut e = of_realization(
        &network.topology(),
        &f.active,
        &f.real,
        &f.centres,
        exact.strain_rank,
        opts,
    )?;
    e.realization = f.how.into();
    e.moved = f.moved;
    e.length_unit = f.unit;
    e.truth_seconds = exact.seconds;
    e.largest_cluster = Some(exact.largest_cluster);
    e.seconds = exact.seconds + start.elapsed().as_secs_f64();
    Ok(e)
}

/// The moduli of a rod system with its contacts in a cubic periodic box:
/// truth for the exact strain rank ([`exact`]), then the floats
/// ([`of_exact`]).
pub fn of_system(network: View, opts: ModuliOptions) -> Result<Elastic> {
    let start = Instant::now();
    let mut e = of_exact(network, exact(network, opts)?, opts, true)?;
    e.seconds = start.elapsed().as_secs_f64();
    Ok(e)
}
