//! The non-affine relaxation of every strain column: `min_u |R u + b|` for
//! the six columns `b` of `B` at once, whose residuals `r = (I - R R⁺) b`
//! give the tensor as their Gram matrix.
//!
//! `R` has a kernel (the box's translations, the floppy motions), so the
//! normal equations are regularized, `(RᵀR + λ I) δ = Rᵀ r`, with `λ` a
//! small multiple of the largest diagonal entry, factored once by faer's
//! sparse Cholesky on one thread ([`crate::math::cholesky`]); the solution is then refined with the same factor
//! (iterated Tikhonov): each step divides a mode of singular value `σ` by
//! `1 + σ²/λ`, and never touches the kernel, since `Rᵀ r` has no part
//! there. The steps stop once `Rᵀ r` (the optimality of the least
//! squares) is at rounding, or stalls: modes below `√λ` then count as
//! kernel, which the caller's rank check against the exact strain rank
//! catches.

use faer::sparse::linalg::matmul::{sparse_dense_matmul, sparse_sparse_matmul};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Accum, Mat, MatRef, Par};

use crate::math::cholesky::Llt;

/// `λ` over the largest diagonal entry of `RᵀR`.
pub const REGULARIZATION: f64 = 1e-12;

/// The optimality `|Rᵀ r| / (|R| |r|)` at which the refinement stops.
pub const OPTIMAL: f64 = 1e-13;

/// Steps without a tenth less `|Rᵀ r|` after which the refinement stops.
pub const STALL: usize = 5;

/// Refinement steps at most (each two triangular solves with six columns).
pub const MAX_STEPS: usize = 60;

/// The relaxed strain columns.
#[derive(Clone, Debug)]
pub struct Relaxation {
    /// `r_i . r_j` over the relaxed residuals.
    pub relaxed: [[f64; 6]; 6],
    /// `b_i . b_j` over the columns as given (the affine stretches).
    pub affine: [[f64; 6]; 6],
    /// `λ` used.
    pub regularization: f64,
    /// The largest `|Rᵀ r| / (|R|_F |r|)` over the columns left (0 when
    /// every residual vanishes).
    pub optimality: f64,
    /// Refinement steps taken.
    pub steps: usize,
}

/// The Gram matrix of the columns of `m`.
fn gram(m: &Mat<f64>) -> [[f64; 6]; 6] {
    let g = m.transpose() * m;
    std::array::from_fn(|i| std::array::from_fn(|j| g[(i, j)]))
}

/// Relaxes the six columns `b` (rows of `r`) over the `columns` unknowns
/// of the sparse matrix given by `entries` (row, column, value).
pub fn relax(
    rows: usize,
    columns: usize,
    entries: &[Triplet<usize, usize, f64>],
    b: &Mat<f64>,
) -> Result<Relaxation, String> {
    let affine = gram(b);
    let r = SparseColMat::<usize, f64>::try_new_from_triplets(rows, columns, entries)
        .map_err(|e| format!("the contact matrix: {e:?}"))?;
    let transposed: Vec<Triplet<usize, usize, f64>> = entries
        .iter()
        .map(|t| Triplet::new(t.col, t.row, t.val))
        .collect();
    let rt = SparseColMat::<usize, f64>::try_new_from_triplets(columns, rows, &transposed)
        .map_err(|e| format!("the contact matrix: {e:?}"))?;
    let normal = sparse_sparse_matmul(rt.as_ref(), r.as_ref(), 1.0, Par::Seq)
        .map_err(|e| format!("the normal equations: {e:?}"))?;
    let top = (0..columns)
        .filter_map(|c| normal.get(c, c).copied())
        .fold(0.0_f64, f64::max);
    let frobenius = entries.iter().map(|t| t.val * t.val).sum::<f64>().sqrt();
    let lambda = REGULARIZATION * top.max(f64::MIN_POSITIVE);
    let shift: Vec<Triplet<usize, usize, f64>> =
        (0..columns).map(|c| Triplet::new(c, c, lambda)).collect();
    let shift = SparseColMat::<usize, f64>::try_new_from_triplets(columns, columns, &shift)
        .map_err(|e| format!("the regularization: {e:?}"))?;
    let regularized = normal + shift;
    let mut llt = Llt::analyse(regularized.symbolic())
        .ok_or("the regularized normal equations: no Cholesky ordering")?;
    if !llt.factor(regularized.as_ref()) {
        return Err("the regularized normal equations are not positive definite".into());
    }
    // `m x` for sparse `m`, on one thread.
    let times = |m: &SparseColMat<usize, f64>, x: MatRef<'_, f64>| {
        let mut y = Mat::<f64>::zeros(m.nrows(), x.ncols());
        sparse_dense_matmul(y.as_mut(), Accum::Replace, m.as_ref(), x, 1.0, Par::Seq);
        y
    };
    let mut u = Mat::<f64>::zeros(columns, 6);
    let mut res = b.clone();
    let mut steps = 0;
    let mut optimality = f64::INFINITY;
    let mut best = 0;
    loop {
        let g = times(&rt, res.as_ref());
        let worst = (0..6)
            .filter_map(|j| {
                let rn = res.col(j).norm_l2();
                (rn > 0.0).then(|| g.col(j).norm_l2() / (frobenius * rn))
            })
            .fold(0.0, f64::max);
        // Stalled: the modes left lie below the regularization.
        if worst < 0.9 * optimality {
            (optimality, best) = (worst, steps);
        }
        if worst <= OPTIMAL || steps == MAX_STEPS || steps >= best + STALL {
            break;
        }
        let mut delta = g;
        llt.solve(delta.as_mut());
        u -= &delta;
        res = b + times(&r, u.as_ref());
        steps += 1;
    }
    Ok(Relaxation {
        relaxed: gram(&res),
        affine,
        regularization: lambda,
        optimality: if optimality.is_finite() {
            optimality
        } else {
            0.0
        },
        steps,
    })
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
        let out = relax(3, 3, &entries, &b).unwrap();
        assert!(out.relaxed[0][0].abs() < 1e-18, "{:?}", out.relaxed);
        assert!((out.relaxed[1][1] - 9.0).abs() < 1e-12);
        assert!((out.relaxed[2][2] - 1.0).abs() < 1e-12);
        assert!((out.relaxed[1][2] - 3.0).abs() < 1e-12);
        assert_eq!(out.affine[0][0], 5.0);
        assert!(out.optimality <= OPTIMAL);
    }
}
