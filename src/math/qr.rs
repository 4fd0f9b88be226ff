//! faer's sparse QR, on one thread: least squares without the normal
//! equations, whose squared condition number hides every singular value
//! below the square root of the rounding. One thread for the reasons of
//! [`super::cholesky`]: a factor must not depend on the thread count.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::qr::{SymbolicQr, factorize_symbolic_qr};
use faer::{Conj, MatMut, Par};

/// The QR factorization of a sparse matrix with at least as many rows as
/// columns, its columns permuted to limit fill (COLAMD).
pub struct Qr {
    symbolic: SymbolicQr<usize>,
    indices: Vec<usize>,
    values: Vec<f64>,
    mem: MemBuffer,
}

impl Qr {
    /// Factors `a` for least squares with up to `columns` right-hand
    /// sides at once, or `None` when faer cannot (more columns than rows).
    pub fn factor(a: SparseColMatRef<'_, usize, f64>, columns: usize) -> Option<Self> {
        if a.nrows() < a.ncols() {
            return None;
        }
        let symbolic = factorize_symbolic_qr(a.symbolic(), Default::default()).ok()?;
        let mut mem = MemBuffer::new(
            symbolic
                .factorize_numeric_qr_scratch::<f64>(Par::Seq, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(columns, Par::Seq)),
        );
        let mut indices = vec![0; symbolic.len_idx()];
        let mut values = vec![0.0; symbolic.len_val()];
        symbolic.factorize_numeric_qr(
            &mut indices,
            &mut values,
            a,
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        );
        Some(Qr {
            symbolic,
            indices,
            values,
            mem,
        })
    }

    /// Overwrites the first `ncols` rows of `rhs` (of `nrows` rows) with
    /// the least-squares solution of `A x = rhs`, column by column.
    pub fn solve(&mut self, rhs: MatMut<'_, f64>) {
        // The factor's parts as faer numbered them when it was made.
        let qr = unsafe {
            faer::sparse::linalg::qr::QrRef::new_unchecked(
                &self.symbolic,
                &self.indices,
                &self.values,
            )
        };
        qr.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut self.mem));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;
    use faer::sparse::{SparseColMat, Triplet};

    #[test]
    fn least_squares_leaves_the_residual_orthogonal_to_the_columns() {
        // 4 x 2: the normal equations' solution of a full-rank problem.
        let t = [
            (0, 0, 1.0),
            (1, 0, 1.0),
            (2, 1, 2.0),
            (3, 0, 1.0),
            (3, 1, -1.0),
        ];
        let entries: Vec<_> = t.iter().map(|&(i, j, v)| Triplet::new(i, j, v)).collect();
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(4, 2, &entries).unwrap();
        let mut qr = Qr::factor(a.as_ref(), 1).unwrap();
        let b = [1.0, 2.0, 3.0, 4.0];
        let mut x = Mat::from_fn(4, 1, |i, _| b[i]);
        qr.solve(x.as_mut());
        // AᵀA = [[3, -1], [-1, 5]], Aᵀb = [7, 2]: x = [37, 13] / 14.
        assert!((x[(0, 0)] - 37.0 / 14.0).abs() < 1e-14, "{:?}", x[(0, 0)]);
        assert!((x[(1, 0)] - 13.0 / 14.0).abs() < 1e-14, "{:?}", x[(1, 0)]);
        let wide = SparseColMat::<usize, f64>::try_new_from_triplets(1, 2, &[]).unwrap();
        assert!(Qr::factor(wide.as_ref(), 1).is_none());
    }
}
