//! How far the float rank can be trusted (MODEL §4): the float verdicts
//! (SVD and pivoted QR) against the exact one, at realizations pushed
//! towards degenerate positions and on growing patterns, and the speed of
//! both.
//!
//! Every trial has an exact reference: a degeneracy knob
//! ([`construction::Degeneracy`]) keeps every incidence exact and only moves
//! the free choices `eps` away from a degenerate position, so for `eps > 0`
//! the realization is a generic member of its family and the exact verdict
//! is the right answer. A float verdict is *correct* when its class and
//! degrees of freedom match the exact ones, *undecided* when rgc says so,
//! and *wrong* otherwise. The *naive* answer is what the tolerance alone
//! gives (no grey zone): where it errs and rgc does not is what the grey
//! zone of [`crate::math::float::RankRule`] buys.
//!
//! [`calibrate`] measures where generic spectra sit against the roundoff
//! floor: the evidence behind [`crate::math::float::RankRule::SVD`] and `QR`.

use std::path::Path;
use std::time::Instant;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;

use crate::engine::examples;
use crate::math::float::{FloatRank, rank_qr, rank_svd};
use crate::math::stats::quantile;
use crate::math::{Fp, Matrix, rank_fp};
use crate::output;
use crate::pattern::{NodeKind, Pattern, PatternContact};
use crate::rigidity::construction::{self, Degeneracy, Geometry};
use crate::rigidity::family;
use crate::rigidity::framework::{dof, float_framework, try_framework};
use crate::rigidity::incidence::{Grouping, Incidence};
use crate::rigidity::verdict::{FloatRanks, float_family, float_ranks, float_spectrum};
use crate::rigidity::{self, Ranker, Verdict, check_exact};
use crate::{Error, Result};

/// Seed of the exact reference verdicts.
pub const REFERENCE_SEED: u64 = 7;

/// A rods-only pattern from an edge list (at most 255 rods; the size axis
/// goes past the [`Pattern::validate`] limits on purpose, below the checks
/// that enforce them).
pub fn rods(n: usize, edges: &[(u32, u32)]) -> Pattern {
    Pattern {
        kinds: vec![NodeKind::Rod; n],
        contacts: edges
            .iter()
            .map(|&(a, b)| PatternContact {
                nodes: [a as u8, b as u8],
                rods: [0, 0],
            })
            .collect(),
    }
}

/// The reference patterns: every engine example (rigid, flexible and
/// component-dependent, with bodies), and K_{3,3} and K_{3,4} of rods.
pub fn panel() -> Vec<(String, Pattern)> {
    let mut out: Vec<(String, Pattern)> = examples::all()
        .into_iter()
        .filter_map(|e| {
            let p = Pattern::from_host(&e.graph(), &e.bodies).ok()?;
            Some((e.name.to_string(), p))
        })
        .collect();
    let k = |a: u32, b: u32| -> Vec<(u32, u32)> {
        (0..a)
            .flat_map(|x| (a..a + b).map(move |y| (x, y)))
            .collect()
    };
    out.push(("K_{3,3} of rods".into(), rods(6, &k(3, 3))));
    out.push(("K_{3,4} of rods".into(), rods(7, &k(3, 4))));
    out
}

/// Where generic float spectra sit against the noise a rank decision allows
/// for ([`crate::rigidity::verdict::float_spectrum`]), in units of that noise.
#[derive(Clone, Debug, Serialize)]
pub struct Calibration {
    pub method: Ranker,
    pub matrices: usize,
    /// Largest value that is zero in exact arithmetic.
    pub zero_max: f64,
    /// Its 0.5, 0.99 and 0.999 quantiles.
    pub zero_q: [f64; 3],
    /// Smallest value that is non-zero in exact arithmetic.
    pub nonzero_min: f64,
    /// Its 0.001, 0.01 and 0.5 quantiles.
    pub nonzero_q: [f64; 3],
    /// Where `zero_max` and `nonzero_min` were found: pattern, family, seed.
    pub worst: [String; 2],
}

/// Spectra of float rigidity matrices at generic realizations of every
/// family of the [`panel`], seeds `0..seeds`, against the exact rank of the
/// family (its degrees of freedom are invariant; the float matrix may have
/// other auxiliary points).
pub fn calibrate(method: Ranker, seeds: u64) -> Calibration {
    let per_pattern: Vec<Vec<(f64, f64, String)>> = panel()
        .par_iter()
        .map(|(name, p)| {
            let inc = Incidence::new(p);
            let mut out = Vec::new();
            for seed in 0..seeds {
                let (families, _) = family::families(&inc, 1, seed);
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                for fam in &families {
                    let Some(exact) =
                        try_framework(&inc, &fam.samples[0], &mut || Fp::random(&mut rng))
                    else {
                        continue;
                    };
                    let dof = dof(&exact, rank_fp(&exact.matrix));
                    let Ok(s) =
                        construction::construct_in(&inc, &fam.grouping, &Geometry::generic(), seed)
                    else {
                        continue;
                    };
                    let Some(f) = float_framework(&inc, s, &mut rng) else {
                        continue;
                    };
                    let (v, floor) = float_spectrum(&f, method);
                    let r = (3 * f.points.len()).saturating_sub(dof + f.trivial_dimension());
                    let at = format!("{name}, {}, seed {seed}", fam.grouping.describe(&inc));
                    let zero = v.get(r).map_or(f64::NAN, |x| x / floor);
                    let nonzero = r.checked_sub(1).map_or(f64::NAN, |i| v[i] / floor);
                    out.push((zero, nonzero, at));
                }
            }
            out
        })
        .collect();
    let all: Vec<(f64, f64, String)> = per_pattern.into_iter().flatten().collect();
    let mut zeros: Vec<f64> = all.iter().map(|x| x.0).filter(|x| !x.is_nan()).collect();
    let mut nonzeros: Vec<f64> = all.iter().map(|x| x.1).filter(|x| !x.is_nan()).collect();
    let worst_zero = all
        .iter()
        .filter(|x| !x.0.is_nan())
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let worst_nonzero = all
        .iter()
        .filter(|x| !x.1.is_nan())
        .min_by(|a, b| a.1.total_cmp(&b.1));
    Calibration {
        method,
        matrices: all.len(),
        zero_max: quantile(&mut zeros, 1.0),
        zero_q: [
            quantile(&mut zeros, 0.5),
            quantile(&mut zeros, 0.99),
            quantile(&mut zeros, 0.999),
        ],
        nonzero_min: quantile(&mut nonzeros, 0.0),
        nonzero_q: [
            quantile(&mut nonzeros, 0.001),
            quantile(&mut nonzeros, 0.01),
            quantile(&mut nonzeros, 0.5),
        ],
        worst: [
            worst_zero.map_or(String::new(), |x| x.2.clone()),
            worst_nonzero.map_or(String::new(), |x| x.2.clone()),
        ],
    }
}

/// What the study varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// Rod directions `eps` from parallel ([`Degeneracy::Parallel`]).
    Parallel,
    /// Contact points `eps` apart ([`Degeneracy::Coincident`]).
    Coincident,
    /// Contact points `eps` off one line ([`Degeneracy::Collinear`]).
    Collinear,
    /// Rods-only patterns of growing size at generic realizations.
    Size,
}

impl Axis {
    pub fn name(self) -> &'static str {
        match self {
            Axis::Parallel => "parallel",
            Axis::Coincident => "coincident",
            Axis::Collinear => "collinear",
            Axis::Size => "size",
        }
    }

    fn degeneracy(self) -> Degeneracy {
        match self {
            Axis::Parallel => Degeneracy::Parallel,
            Axis::Coincident => Degeneracy::Coincident,
            Axis::Collinear => Degeneracy::Collinear,
            Axis::Size => Degeneracy::Generic,
        }
    }
}

/// The settings of one study.
#[derive(Clone, Debug, Serialize)]
pub struct StudyConfig {
    /// Distances from the degenerate positions, for the geometric axes.
    pub eps: Vec<f64>,
    /// Numbers of heavy rods for the size axis (see [`ladder`]).
    pub heavy: Vec<usize>,
    /// Seeds per pattern and setting.
    pub seeds: u64,
    pub axes: Vec<Axis>,
    pub methods: Vec<Ranker>,
}

impl StudyConfig {
    /// The study behind `results/rank-stability.csv`: `eps = 1e-1 .. 1e-14`,
    /// ladders of 6 to 60 rods, 10 seeds.
    pub fn full() -> Self {
        StudyConfig {
            eps: (1..=14).map(|k| 10f64.powi(-k)).collect(),
            heavy: (2..=11).collect(),
            seeds: 10,
            axes: vec![
                Axis::Parallel,
                Axis::Coincident,
                Axis::Collinear,
                Axis::Size,
            ],
            methods: vec![Ranker::Svd, Ranker::Qr],
        }
    }

    /// A small version for the test suite.
    pub fn quick() -> Self {
        StudyConfig {
            eps: vec![1e-1, 1e-4, 1e-8, 1e-12, 1e-14],
            heavy: vec![2, 4],
            seeds: 2,
            ..StudyConfig::full()
        }
    }
}

/// One setting of the study, aggregated over its patterns and seeds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StabilityRow {
    pub axis: Axis,
    /// Distance from the degenerate position (geometric axes).
    pub eps: Option<f64>,
    /// Number of rods (size axis).
    pub rods: Option<usize>,
    pub method: Ranker,
    pub trials: usize,
    /// Fractions of the trials: matching the exact verdict, undecided, and
    /// decided but not matching it.
    pub correct: f64,
    pub undecided: f64,
    pub wrong: f64,
    /// Fraction where the tolerance alone (no grey zone, no twin) decides
    /// wrongly: what a plain numerical-rank routine would report.
    pub naive_wrong: f64,
    /// Fraction where the rank rule on one realization (grey zone, no twin)
    /// decides wrongly.
    pub single_wrong: f64,
    /// Median over the trials of the smallest singular-value (or `|R_ii|`) gap.
    pub median_gap: f64,
}

/// How one trial ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outcome {
    Correct,
    Undecided,
    Wrong,
}

struct Trial {
    outcome: Outcome,
    naive_wrong: bool,
    single_wrong: bool,
    gap: f64,
}

/// Runs the study: every axis, setting and method of `config`.
pub fn run(config: &StudyConfig) -> Result<Vec<StabilityRow>> {
    let mut rows = Vec::new();
    for &axis in &config.axes {
        if axis == Axis::Size {
            rows.extend(size_rows(config)?);
            continue;
        }
        let patterns = sensitive_patterns(axis.degeneracy())?;
        let settings: Vec<(f64, Ranker)> = config
            .eps
            .iter()
            .flat_map(|&eps| config.methods.iter().map(move |&m| (eps, m)))
            .collect();
        let out: Vec<Result<StabilityRow>> = settings
            .par_iter()
            .map(|&(eps, method)| {
                let geometry = Geometry {
                    degeneracy: axis.degeneracy(),
                    eps,
                };
                let mut trials = Vec::new();
                for (p, reference) in &patterns {
                    for seed in 0..config.seeds {
                        let ranks = float_ranks(p, method, seed, &geometry)?;
                        trials.push(judge(&ranks, reference));
                    }
                }
                Ok(aggregate(axis, Some(eps), None, method, &trials))
            })
            .collect();
        for row in out {
            rows.push(row?);
        }
    }
    Ok(rows)
}

/// The panel patterns whose degenerate limit along `degeneracy` really is
/// degenerate, with their exact verdicts: built exactly over F_p at
/// `eps = 0`, some component either cannot be realized or has another
/// number of degrees of freedom. The others would only dilute the study.
pub fn sensitive_patterns(degeneracy: Degeneracy) -> Result<Vec<(Pattern, Verdict)>> {
    let limit = Geometry {
        degeneracy,
        eps: Fp::ZERO,
    };
    let mut out = Vec::new();
    for (_, p) in panel() {
        let reference = check_exact(&p, REFERENCE_SEED)?;
        let inc = Incidence::new(&p);
        let (families, _) = family::families(&inc, 1, REFERENCE_SEED);
        let components = family::components(&families);
        let mut rng = ChaCha8Rng::seed_from_u64(REFERENCE_SEED);
        let mut exact_dof = |sample: &construction::Realization<Fp>| {
            try_framework(&inc, sample, &mut || Fp::random(&mut rng))
                .map(|f| dof(&f, rank_fp(&f.matrix)))
        };
        let sensitive = families
            .iter()
            .zip(&components)
            .filter(|(_, c)| **c)
            .any(|(fam, _)| {
                let generic = exact_dof(&fam.samples[0]);
                let degenerate =
                    construction::construct_in(&inc, &fam.grouping, &limit, REFERENCE_SEED)
                        .ok()
                        .and_then(|s| exact_dof(&s));
                degenerate.is_none() || degenerate != generic
            });
        if sensitive {
            out.push((p, reference));
        }
    }
    Ok(out)
}

fn judge(ranks: &FloatRanks, reference: &Verdict) -> Trial {
    let v = ranks.verdict();
    let expected = (reference.class.as_str(), reference.dof);
    let outcome = match v.rigid {
        None => Outcome::Undecided,
        Some(_) if (v.class.as_str(), v.dof) == expected => Outcome::Correct,
        Some(_) => Outcome::Wrong,
    };
    // The same components read from the first realization alone: by the
    // tolerance only (naive), and by the rank rule without the twin (single).
    let read = |decide: &dyn Fn(&Option<FloatRank>) -> bool| -> Vec<Option<usize>> {
        ranks
            .components
            .iter()
            .zip(&ranks.samples)
            .filter(|(c, _)| c.component)
            .map(|(c, s)| decide(&s[0]).then_some(c.dof))
            .collect()
    };
    let wrong = |dofs: Vec<Option<usize>>| {
        let Some(dofs) = dofs.into_iter().collect::<Option<Vec<usize>>>() else {
            return false;
        };
        let class = if dofs.iter().all(|&d| d == 0) {
            "rigid"
        } else if dofs.iter().all(|&d| d > 0) {
            "flexible"
        } else {
            "component-dependent"
        };
        !dofs.is_empty() && (class, dofs.iter().max().copied()) != expected
    };
    Trial {
        outcome,
        naive_wrong: wrong(read(&|s| s.is_some())),
        single_wrong: wrong(read(&|s| s.is_some_and(|fr| fr.rank.is_some()))),
        gap: v.gap.unwrap_or(f64::NAN),
    }
}

fn aggregate(
    axis: Axis,
    eps: Option<f64>,
    rods: Option<usize>,
    method: Ranker,
    trials: &[Trial],
) -> StabilityRow {
    let n = trials.len().max(1) as f64;
    let frac = |o: Outcome| trials.iter().filter(|t| t.outcome == o).count() as f64 / n;
    let mut gaps: Vec<f64> = trials
        .iter()
        .map(|t| t.gap)
        .filter(|g| !g.is_nan())
        .collect();
    StabilityRow {
        axis,
        eps,
        rods,
        method,
        trials: trials.len(),
        correct: frac(Outcome::Correct),
        undecided: frac(Outcome::Undecided),
        wrong: frac(Outcome::Wrong),
        naive_wrong: trials.iter().filter(|t| t.naive_wrong).count() as f64 / n,
        single_wrong: trials.iter().filter(|t| t.single_wrong).count() as f64 / n,
        median_gap: quantile(&mut gaps, 0.5),
    }
}

/// A rods-only "ladder" with `heavy >= 2` long rods: the first two joined by
/// four connector rods (K_{2,4}, rigid), every later heavy rod joined by five
/// connectors to heavy rods placed before it (chosen at random), which makes
/// it rigid again; with `flexible`, the last heavy rod gets one connector
/// fewer (one degree of freedom). Connectors have two contacts and heavy rods never touch, so
/// the lines-first construction realizes it at any size: `6 heavy - 6` rods.
pub fn ladder(heavy: usize, flexible: bool, seed: u64) -> Pattern {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut edges = Vec::new();
    let mut n = heavy as u32;
    let mut connect = |a: u32, b: u32, edges: &mut Vec<(u32, u32)>| {
        edges.push((a, n));
        edges.push((b, n));
        n += 1;
    };
    for j in 1..heavy.max(2) as u32 {
        let count = if j == 1 { 4 } else { 5 } - usize::from(flexible && j + 1 >= heavy as u32);
        for _ in 0..count {
            let to = rng.random_range(0..j);
            connect(to, j, &mut edges);
        }
    }
    rods(n as usize, &edges)
}

/// The size axis: for each ladder size, rigid and flexible ladders, exact
/// rank against float rank on the generic family (the forced grouping; no
/// other family matters for the numerics of size).
fn size_rows(config: &StudyConfig) -> Result<Vec<StabilityRow>> {
    let cases: Vec<(usize, Ranker)> = config
        .heavy
        .iter()
        .flat_map(|&h| config.methods.iter().map(move |&m| (h, m)))
        .collect();
    cases
        .par_iter()
        .map(|&(heavy, method)| {
            let mut trials = Vec::new();
            let mut rods = 0;
            for seed in 0..config.seeds {
                for flexible in [false, true] {
                    let p = ladder(heavy, flexible, seed);
                    rods = rods.max(p.n_rods());
                    trials.push(size_trial(&p, method, seed)?);
                }
            }
            Ok(aggregate(Axis::Size, None, Some(rods), method, &trials))
        })
        .collect()
}

fn size_trial(p: &Pattern, method: Ranker, seed: u64) -> Result<Trial> {
    let inc = Incidence::new(p);
    let grouping = Grouping::forced(&inc);
    let failed = || Error::Parameter("a ladder could not be realized".into());
    let exact = construction::construct(&inc, &grouping, seed).map_err(|_| failed())?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let f = try_framework(&inc, &exact, &mut || Fp::random(&mut rng)).ok_or_else(failed)?;
    let exact_dof = dof(&f, rank_fp(&f.matrix));
    let ranked = float_family(
        &inc,
        &grouping,
        method,
        &Geometry::generic(),
        seed ^ 0xF1,
        &mut rng,
    );
    let outcome = match ranked.dof() {
        None => Outcome::Undecided,
        Some(d) if d == exact_dof => Outcome::Correct,
        Some(_) => Outcome::Wrong,
    };
    Ok(Trial {
        outcome,
        naive_wrong: ranked.base.is_some_and(|(_, d)| d != exact_dof),
        single_wrong: ranked
            .base
            .is_some_and(|(fr, d)| fr.rank.is_some() && d != exact_dof),
        gap: ranked.base.map_or(f64::NAN, |(fr, _)| fr.gap),
    })
}

/// A row of `rank-stability.csv`: fractions to 4 places, the gap in
/// scientific notation, empty cells for absent values.
#[derive(Serialize)]
struct CsvRow {
    axis: &'static str,
    #[serde(serialize_with = "output::cell::sci_opt")]
    eps: Option<f64>,
    rods: Option<usize>,
    method: &'static str,
    trials: usize,
    #[serde(serialize_with = "output::cell::fixed::<4, _>")]
    correct: f64,
    #[serde(serialize_with = "output::cell::fixed::<4, _>")]
    undecided: f64,
    #[serde(serialize_with = "output::cell::fixed::<4, _>")]
    wrong: f64,
    #[serde(serialize_with = "output::cell::fixed::<4, _>")]
    naive_wrong: f64,
    #[serde(serialize_with = "output::cell::fixed::<4, _>")]
    single_wrong: f64,
    #[serde(serialize_with = "output::cell::sci::<4, _>")]
    median_gap: f64,
}

/// Writes the rows as CSV.
pub fn write_csv(rows: &[StabilityRow], path: &Path) -> Result<()> {
    output::write_csv(
        path,
        rows.iter().map(|r| CsvRow {
            axis: r.axis.name(),
            eps: r.eps,
            rods: r.rods,
            method: method_name(r.method),
            trials: r.trials,
            correct: r.correct,
            undecided: r.undecided,
            wrong: r.wrong,
            naive_wrong: r.naive_wrong,
            single_wrong: r.single_wrong,
            median_gap: r.median_gap,
        }),
    )
}

pub fn method_name(m: Ranker) -> &'static str {
    match m {
        Ranker::Exact => "exact",
        Ranker::Svd => "svd",
        Ranker::Qr => "qr",
    }
}

/// Rank speed on one set of matrices.
#[derive(Clone, Debug, Serialize)]
pub struct Throughput {
    /// What was measured, e.g. `rods n=8, forced family`.
    pub set: String,
    pub matrices: usize,
    /// Mean rows and columns.
    pub rows: f64,
    pub cols: f64,
    /// Ranks per second, one thread: exact over F_p, float SVD, float QR
    /// (each including the decision of its rank from the spectrum).
    pub exact_per_s: f64,
    pub svd_per_s: f64,
    pub qr_per_s: f64,
    /// Whole verdicts per second (families, components, every rank):
    /// [`check_exact`] and [`rigidity::check_float`] with SVD and QR.
    pub check_exact_per_s: f64,
    pub check_svd_per_s: f64,
    pub check_qr_per_s: f64,
}

/// Measures rank and verdict throughput on `count` random connected
/// rods-only patterns with `n` rods, minimum degree 2 and Maxwell's count
/// (`3 E >= 5 n - 6`): the candidates the motif enumeration feeds the rank.
/// Each rank is repeated until `min_seconds` have passed.
pub fn throughput(n: usize, count: usize, min_seconds: f64) -> Result<Throughput> {
    if !(3..=crate::pattern::MAX_PATTERN_NODES).contains(&n) || count == 0 {
        return Err(Error::Parameter(format!(
            "throughput needs 3 to {} rods and at least one pattern",
            crate::pattern::MAX_PATTERN_NODES
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(n as u64);
    let mut patterns = Vec::new();
    let mut exact = Vec::new();
    let mut float = Vec::new();
    let mut tries = 0;
    while patterns.len() < count && tries < 1000 * count {
        tries += 1;
        let p = random_candidate(n, &mut rng);
        let inc = Incidence::new(&p);
        let grouping = Grouping::forced(&inc);
        let seed = tries as u64;
        let Ok(e) = construction::construct(&inc, &grouping, seed) else {
            continue;
        };
        let Ok(s) = construction::construct_in(&inc, &grouping, &Geometry::generic(), seed) else {
            continue;
        };
        let (Some(fe), Some(ff)) = (
            try_framework(&inc, &e, &mut || Fp::random(&mut rng)),
            float_framework(&inc, s, &mut rng),
        ) else {
            continue;
        };
        exact.push(fe.matrix);
        float.push(ff.matrix);
        patterns.push(p);
    }
    if patterns.is_empty() {
        return Err(Error::Parameter(format!(
            "no realizable rods-only candidate with {n} rods"
        )));
    }
    let per_s = |f: &mut dyn FnMut()| {
        let start = Instant::now();
        let mut rounds = 0u64;
        while rounds == 0 || start.elapsed().as_secs_f64() < min_seconds {
            f();
            rounds += 1;
        }
        rounds as f64 / start.elapsed().as_secs_f64()
    };
    let k = patterns.len() as f64;
    let mut sink = 0usize;
    let exact_per_s = k * per_s(&mut || exact.iter().for_each(|m| sink ^= rank_fp(m)));
    let svd_per_s = k * per_s(&mut || {
        float
            .iter()
            .for_each(|m| sink ^= rank_svd(m).rank.unwrap_or(0))
    });
    let qr_per_s = k * per_s(&mut || {
        float
            .iter()
            .for_each(|m| sink ^= rank_qr(m).rank.unwrap_or(0))
    });
    let mut check = |f: &dyn Fn(&Pattern) -> Result<Verdict>| -> Result<f64> {
        let mut err = Ok(());
        let rate = per_s(&mut || {
            for p in &patterns {
                match f(p) {
                    Ok(v) => sink ^= v.rank,
                    Err(e) => err = Err(e),
                }
            }
        });
        err.map(|_| k * rate)
    };
    let check_exact_per_s = check(&|p| check_exact(p, 1))?;
    let check_svd_per_s = check(&|p| rigidity::check_float(p, Ranker::Svd, 1))?;
    let check_qr_per_s = check(&|p| rigidity::check_float(p, Ranker::Qr, 1))?;
    std::hint::black_box(sink);
    let mean = |f: &dyn Fn(&Matrix<f64>) -> usize| float.iter().map(f).sum::<usize>() as f64 / k;
    Ok(Throughput {
        set: format!("rods n={n}, min degree 2, Maxwell, forced family"),
        matrices: patterns.len(),
        rows: mean(&|m| m.rows),
        cols: mean(&|m| m.cols),
        exact_per_s,
        svd_per_s,
        qr_per_s,
        check_exact_per_s,
        check_svd_per_s,
        check_qr_per_s,
    })
}

/// A random connected rods-only graph on `n` rods with minimum degree 2 and
/// `3 E >= 5 n - 6`: a random spanning tree, then random extra edges.
fn random_candidate(n: usize, rng: &mut ChaCha8Rng) -> Pattern {
    let target = (5 * n).saturating_sub(6).div_ceil(3) + rng.random_range(0..=2);
    let mut edges: Vec<(u32, u32)> = (1..n as u32).map(|v| (rng.random_range(0..v), v)).collect();
    let mut degree = vec![0usize; n];
    for &(a, b) in &edges {
        degree[a as usize] += 1;
        degree[b as usize] += 1;
    }
    let max_edges = n * (n - 1) / 2;
    while (edges.len() < target || degree.iter().any(|&d| d < 2)) && edges.len() < max_edges {
        let a = rng.random_range(0..n as u32);
        let b = rng.random_range(0..n as u32);
        let e = (a.min(b), a.max(b));
        if a != b && !edges.iter().any(|&(x, y)| (x.min(y), x.max(y)) == e) {
            edges.push(e);
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
    }
    rods(n, &edges)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed table, read back into rows, is written byte for byte.
    #[test]
    fn the_committed_table_is_written_unchanged() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/rank-stability.csv");
        let text = std::fs::read_to_string(&path).unwrap();
        let axes = [
            Axis::Parallel,
            Axis::Coincident,
            Axis::Collinear,
            Axis::Size,
        ];
        let methods = [Ranker::Exact, Ranker::Svd, Ranker::Qr];
        let rows: Vec<StabilityRow> = text
            .lines()
            .skip(1)
            .map(|line| {
                let c: Vec<&str> = line.split(',').collect();
                let f = |k: usize| c[k].parse::<f64>().unwrap();
                StabilityRow {
                    axis: *axes.iter().find(|a| a.name() == c[0]).unwrap(),
                    eps: (!c[1].is_empty()).then(|| f(1)),
                    rods: (!c[2].is_empty()).then(|| c[2].parse().unwrap()),
                    method: *methods.iter().find(|&&m| method_name(m) == c[3]).unwrap(),
                    trials: c[4].parse().unwrap(),
                    correct: f(5),
                    undecided: f(6),
                    wrong: f(7),
                    naive_wrong: f(8),
                    single_wrong: f(9),
                    median_gap: f(10),
                }
            })
            .collect();
        let out = std::env::temp_dir().join(format!("rgc-stability-{}.csv", std::process::id()));
        write_csv(&rows, &out).unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
        std::fs::remove_file(out).unwrap();
    }
}
