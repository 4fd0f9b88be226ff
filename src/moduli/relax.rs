//! The non-affine relaxation of every strain column: `min_u |R u + b|` for
//! the six columns `b` of `B` at once, whose residuals `r = (I - R R⁺) b`
//! give the tensor as their Gram matrix.
//!
//! `R` has a kernel (the box's translations, the floppy motions), and near
//! the threshold singular values far below the square root of the rounding.
//! The normal equations `RᵀR` square them, so a regularization `λ` there
//! must stand above the rounding of `RᵀR`, and every mode with `σ² ≲ λ`
//! stays unrelaxed: at gamma 23, L = 5, on both sides of the critical rod
//! of the solid study's sequence 31 (4,295 rods), `RᵀR + λI` with `λ`
//! 1e-12, 1e-14 and 1e-16 of its largest diagonal gave G = 2.8e-6, 7.3e-7
//! and 4.8e-7 at the rod, and at 1e-12 a larger G below the rod than at
//! it, which springs added to one geometry cannot give. So the least
//! squares is solved by faer's sparse QR ([`crate::math::qr`]) of `R`
//! stacked on `√λ I`, which never squares `R`, with `λ` [`REGULARIZATION`]
//! of the largest squared column norm. There G = 2.0775e-7 at the rod and
//! 1.7328e-7 below it, the same to five digits for `λ` from 1e-26 to
//! 1e-22, and the tensor below, of exact strain rank 5, has its sixth
//! eigenvalue at 1e-20 against 3.2e-10 for its fifth. A smaller `λ` loses
//! the kernel to rounding (the factor's diagonal there is `√λ`): at 1e-26
//! a hand-derived lattice modulus was off by 5e-12 and at 1e-30 by 4e-4,
//! where 1e-24 to 1e-20 give it within 1e-12. The solution is refined with
//! the same factor (iterated Tikhonov) until no residual's energy changes
//! by more than [`SETTLED`] of itself.
//!
//! Where the QR does not fit in memory (at gamma 98 from density 190 on
//! this machine), or when asked, LSMR solves the same least squares
//! without squaring `R` ([`crate::math::lsmr`]), preconditioned by the
//! normal equations' factor, a tenth of the QR's size. Where both ran they
//! agree to 1e-13 in G (the six systems of `rgc bench --moduli`); near the
//! threshold, where the QR's 8 refinements have not settled, LSMR relaxes
//! further (MODEL, elastic moduli).

use faer::sparse::linalg::matmul::{dense_sparse_matmul, sparse_dense_matmul};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Accum, Mat, MatRef, Par};
use serde::{Deserialize, Serialize};

use crate::math::lsmr;
use crate::math::qr::{Failure, Qr};
use crate::{Error, Result};

/// `λ` over the largest squared column norm of `R`: singular values
/// below 1e-12 of the largest column count as kernel.
pub const REGULARIZATION: f64 = 1e-24;

/// The relative change of every residual's energy below which the
/// refinement stops: above their rounding noise, about 1e-10 of
/// themselves (3 and 4 steps on the system above).
pub const SETTLED: f64 = 1e-8;

/// Refinement steps at most (each one least-squares solve with six
/// columns).
pub const MAX_STEPS: usize = 8;

/// LSMR's tolerance on `|(R M)ᵀ r| / |(R M)ᵀ b|` per strain column.
pub const LSMR_TOLERANCE: f64 = 1e-10;

/// LSMR's iterations per strain column at most, unless asked otherwise:
/// near the threshold at gamma 23, L = 5 and 6, all 40 sides that 1,000
/// left unsettled settled within 10,000, their G up to 65% below the bound
/// 1,000 gave (MODEL, elastic moduli).
pub const LSMR_ITERATIONS: usize = 10_000;

/// The cap before it was a choice: sides and specs that do not say theirs
/// were relaxed under it.
pub const FIRST_LSMR_ITERATIONS: usize = 1000;

/// The largest cap accepted: a typo's cap would run for days.
pub const MAX_LSMR_ITERATIONS: usize = 1_000_000;

/// How the least squares is solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Solver {
    /// The sparse QR where it fits in memory, else LSMR.
    #[default]
    Auto,
    /// faer's sparse QR of the springs' matrix R over √λ I, refined.
    Qr,
    /// LSMR on R, preconditioned by the Cholesky factor of RᵀR + μI: a
    /// tenth of the QR's memory.
    Lsmr,
}

impl Solver {
    /// The QR: what results made before the choice were solved by.
    pub fn qr() -> Self {
        Solver::Qr
    }

    pub fn is_qr(&self) -> bool {
        *self == Solver::Qr
    }
}

/// The relaxed strain columns.
#[derive(Clone, Debug)]
pub struct Relaxation {
    /// `r_i . r_j` over the relaxed residuals.
    pub relaxed: [[f64; 6]; 6],
    /// `b_i . b_j` over the columns as given (the affine stretches).
    pub affine: [[f64; 6]; 6],
    /// `λ` used (the QR), or the preconditioner's shift `μ` (LSMR).
    pub regularization: f64,
    /// The largest `|Rᵀ r| / (|R|_F |r|)` over the columns left (0 when
    /// every residual vanishes).
    pub optimality: f64,
    /// Refinement steps taken (LSMR's iterations over the six columns).
    pub steps: usize,
    /// Whether the energies settled within [`MAX_STEPS`] (LSMR: every
    /// column converged); if not, the relaxed energies (and the moduli)
    /// are upper bounds still falling.
    pub settled: bool,
    /// The solver used: [`Solver::Qr`] or [`Solver::Lsmr`].
    pub solver: Solver,
}

/// The Gram matrix of the columns of `m`.
fn gram(m: &Mat<f64>) -> [[f64; 6]; 6] {
    let g = m.transpose() * m;
    std::array::from_fn(|i| std::array::from_fn(|j| g[(i, j)]))
}

/// Relaxes the six columns `b` (rows of `r`) over the `columns` unknowns
/// of the sparse matrix given by `entries` (row, column, value) with
/// `solver` (LSMR at most `lsmr_iterations` per column), refusing a factor
/// that would take the process past `limit` (bytes resident).
pub fn relax(
    rows: usize,
    columns: usize,
    entries: &[Triplet<usize, usize, f64>],
    b: &Mat<f64>,
    solver: Solver,
    lsmr_iterations: usize,
    limit: Option<u64>,
) -> Result<Relaxation> {
    let r = SparseColMat::<usize, f64>::try_new_from_triplets(rows, columns, entries)
        .map_err(|e| Error::analysis(format!("the contact matrix: {e:?}")))?;
    let mut norms = vec![0.0; columns];
    for t in entries {
        norms[t.col] += t.val * t.val;
    }
    let top = norms.iter().copied().fold(0.0_f64, f64::max);
    let frobenius = norms.iter().sum::<f64>().sqrt();
    let lambda = REGULARIZATION * top.max(f64::MIN_POSITIVE);
    let failure = |f: Failure, what: String| match f {
        Failure::Memory(refusal) => Error::Memory(refusal.describe(&what)),
        Failure::Unsound(why) => Error::analysis(why),
    };
    let by_qr = || {
        refined(&r, entries, b, lambda, limit).map_err(|f| {
            let stacked = rows + columns;
            failure(
                f,
                format!("the sparse QR of the {stacked} x {columns} spring matrix"),
            )
        })
    };
    let by_lsmr = || {
        lsmr::least_squares(
            r.as_ref(),
            b.as_ref(),
            LSMR_TOLERANCE,
            lsmr_iterations,
            limit,
        )
        .map(|s| {
            let fit = s.x;
            (
                b - times(&r, fit.as_ref()),
                s.iterations,
                s.converged,
                s.shift * top,
                Solver::Lsmr,
            )
        })
        .map_err(|f| {
            failure(
                f,
                format!("LSMR's preconditioner for the {rows} x {columns} spring matrix"),
            )
        })
    };
    let (res, steps, settled, regularization, solver) = match solver {
        Solver::Qr => by_qr()?,
        Solver::Lsmr => by_lsmr()?,
        Solver::Auto => match by_qr() {
            Err(Error::Memory(_)) => by_lsmr()?,
            other => other?,
        },
    };
    let last: [f64; 6] = std::array::from_fn(|j| res.col(j).squared_norm_l2());
    // A non-finite residual is no modulus: say so rather than record it
    // (serialized, NaN would read as a missing value).
    if !last.iter().all(|e| e.is_finite()) {
        return Err(Error::analysis(format!(
            "the relaxation of the {rows} x {columns} spring matrix gave non-finite energies {last:?}"
        )));
    }
    // `(resᵀ R)ᵀ = Rᵀ res`, without a transposed copy of `R`.
    let mut gt = Mat::<f64>::zeros(6, columns);
    dense_sparse_matmul(
        gt.as_mut(),
        Accum::Replace,
        res.transpose(),
        r.as_ref(),
        1.0,
        Par::Seq,
    );
    let g = gt.transpose();
    let optimality = (0..6)
        .filter_map(|j| {
            let rn = res.col(j).norm_l2();
            (rn > 0.0).then(|| g.col(j).norm_l2() / (frobenius * rn))
        })
        .fold(0.0, f64::max);
    Ok(Relaxation {
        relaxed: gram(&res),
        affine: gram(b),
        regularization,
        optimality,
        steps,
        settled,
        solver,
    })
}

/// `m x` for sparse `m`, on one thread.
fn times(m: &SparseColMat<usize, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    let mut y = Mat::<f64>::zeros(m.nrows(), x.ncols());
    sparse_dense_matmul(y.as_mut(), Accum::Replace, m.as_ref(), x, 1.0, Par::Seq);
    y
}

/// The QR's relaxation: the residuals, steps, whether they settled, `λ`.
fn refined(
    r: &SparseColMat<usize, f64>,
    entries: &[Triplet<usize, usize, f64>],
    b: &Mat<f64>,
    lambda: f64,
    limit: Option<u64>,
) -> std::result::Result<(Mat<f64>, usize, bool, f64, Solver), Failure> {
    let (rows, columns) = (r.nrows(), r.ncols());
    // `R` over `√λ I`: full column rank, and its least squares is the
    // regularized one without squaring `R`.
    let mut stacked = entries.to_vec();
    stacked.extend((0..columns).map(|c| Triplet::new(rows + c, c, lambda.sqrt())));
    let stacked =
        SparseColMat::<usize, f64>::try_new_from_triplets(rows + columns, columns, &stacked)
            .map_err(|e| Failure::Unsound(format!("the regularized contact matrix: {e:?}")))?;
    let mut qr = Qr::factor(stacked.as_ref(), 6, limit)?;
    let energies =
        |res: &Mat<f64>| -> [f64; 6] { std::array::from_fn(|j| res.col(j).squared_norm_l2()) };
    let mut u = Mat::<f64>::zeros(columns, 6);
    let mut res = b.clone();
    let mut last = energies(&res);
    let (mut steps, mut settled) = (0, false);
    while steps < MAX_STEPS {
        let mut step = Mat::<f64>::zeros(rows + columns, 6);
        step.subrows_mut(0, rows).copy_from(&res);
        qr.solve(step.as_mut());
        u -= step.subrows(0, columns);
        res = b + times(r, u.as_ref());
        steps += 1;
        let now = energies(&res);
        settled = now
            .iter()
            .zip(&last)
            .all(|(e, l)| (e - l).abs() <= SETTLED * e.max(*l));
        last = now;
        if settled {
            break;
        }
    }
    Ok((res, steps, settled, lambda, Solver::Qr))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_column_in_the_range_relaxes_away_and_one_across_it_stays() {
        // R = [1 0; 0 1; 0 0] (with a kernel column 2): b = (1, 2, 0)
        // lies in its range, b = (0, 0, 3) is orthogonal to it.
        let entries = [Triplet::new(0, 0, 1.0), Triplet::new(1, 1, 1.0)];
        let mut b = Mat::<f64>::zeros(3, 6);
        b[(0, 0)] = 1.0;
        b[(1, 0)] = 2.0;
        b[(2, 1)] = 3.0;
        b[(0, 2)] = 1.0;
        b[(2, 2)] = 1.0;
        let out = relax(3, 3, &entries, &b, Solver::Qr, LSMR_ITERATIONS, None).unwrap();
        assert!(out.relaxed[0][0].abs() < 1e-18, "{:?}", out.relaxed);
        assert!((out.relaxed[1][1] - 9.0).abs() < 1e-12);
        assert!((out.relaxed[2][2] - 1.0).abs() < 1e-12);
        assert!((out.relaxed[1][2] - 3.0).abs() < 1e-12);
        assert_eq!(out.affine[0][0], 5.0);
        assert!(out.optimality <= 1e-15, "{}", out.optimality);
        assert!(out.settled && out.steps < MAX_STEPS, "{} steps", out.steps);
    }

    #[test]
    fn lsmr_relaxes_as_the_qr_does() {
        // R = [1 0; 0 1; 1/2 0], six columns b, by both solvers.
        let entries = [
            Triplet::new(0, 0, 1.0),
            Triplet::new(1, 1, 1.0),
            Triplet::new(2, 0, 0.5),
        ];
        let b = Mat::<f64>::from_fn(3, 6, |i, j| ((i + 2 * j) % 5) as f64 - 1.5);
        let qr = relax(3, 2, &entries, &b, Solver::Qr, LSMR_ITERATIONS, None).unwrap();
        let lsmr = relax(3, 2, &entries, &b, Solver::Lsmr, LSMR_ITERATIONS, None).unwrap();
        assert_eq!((qr.solver, lsmr.solver), (Solver::Qr, Solver::Lsmr));
        assert!(lsmr.settled, "{lsmr:?}");
        for i in 0..6 {
            for j in 0..6 {
                let (a, b) = (qr.relaxed[i][j], lsmr.relaxed[i][j]);
                assert!((a - b).abs() < 1e-12, "{i} {j}: {a} against {b}");
            }
        }
        // R's one left null vector is w = (-1/2, 0, 1): a residual is b's
        // part along w, of energy (w . b)² / |w|². Column 0 is
        // b = (-3/2, -1/2, 1/2): (5/4)² / (5/4) = 5/4.
        assert!(
            (lsmr.relaxed[0][0] - 1.25).abs() < 1e-12,
            "{:?}",
            lsmr.relaxed
        );
    }

    #[test]
    fn a_mode_at_the_regularization_relaxes_by_half_a_step_and_does_not_settle() {
        // R = diag(1, 1e-12): λ = 1e-24 puts σ² = λ for the second column,
        // which each refinement relaxes by λ / (σ² + λ) = 1/2.
        let entries = [Triplet::new(0, 0, 1.0), Triplet::new(1, 1, 1e-12)];
        let mut b = Mat::<f64>::zeros(2, 6);
        b[(1, 0)] = 1.0;
        let out = relax(2, 2, &entries, &b, Solver::Qr, LSMR_ITERATIONS, None).unwrap();
        assert_eq!((out.steps, out.settled), (MAX_STEPS, false));
        let expected = 0.25_f64.powi(MAX_STEPS as i32);
        assert!(
            (out.relaxed[0][0] / expected - 1.0).abs() < 1e-6,
            "{:e}",
            out.relaxed[0][0]
        );
    }

    #[test]
    fn a_non_finite_relaxation_is_an_error_not_a_modulus() {
        let entries = [Triplet::new(0, 0, f64::NAN), Triplet::new(1, 1, 1.0)];
        let mut b = Mat::<f64>::zeros(3, 6);
        b[(0, 0)] = 1.0;
        let Err(e) = relax(3, 2, &entries, &b, Solver::Qr, LSMR_ITERATIONS, None) else {
            panic!("a NaN spring gave a relaxation");
        };
        assert!(e.to_string().contains("non-finite energies"), "{e}");
    }
}
