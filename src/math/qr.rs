//! faer's sparse QR, on one thread: least squares without the normal
//! equations, whose squared condition number hides every singular value
//! below the square root of the rounding. One thread for the reasons of
//! [`super::cholesky`]: a factor must not depend on the thread count.
//!
//! The faer built here is 0.24.4 with its supernodal factor mended
//! (`vendor/README.md`): as published it loses columns after a gap in a
//! front's staircase, and its fronts' dense QR drops a column whose
//! remainder falls below a rank threshold, which shifts the front's rows
//! (NaN energies at gamma 98, where the regularization's `√λ` is all a
//! column keeps).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::qr::{QrRef, QrSymbolicParams, SymbolicQr, factorize_symbolic_qr};
use faer::{Conj, MatMut, Par};

use crate::usage::{self, Refusal};

/// Why a matrix got no factor.
#[derive(Clone, Debug)]
pub enum Failure {
    /// The factor and its workspace would take the process past its
    /// memory bound (faer's symbolic step sizes them before they exist).
    Memory(Refusal),
    /// Fewer rows than unknowns, or no symbolic factor.
    Unsound(String),
}

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
    /// sides at once, or says why it cannot (more columns than rows, or
    /// no factor that fits within `limit` on the resident size and what
    /// the machine has room for).
    pub fn factor(
        a: SparseColMatRef<'_, usize, f64>,
        columns: usize,
        limit: Option<u64>,
    ) -> Result<Self, Failure> {
        Self::factor_with(a, columns, SupernodalThreshold::AUTO, limit)
    }

    /// [`Self::factor`], choosing faer's supernodal or simplicial factor
    /// by `supernodal` (faer's flop ratio; automatic outside tests).
    fn factor_with(
        a: SparseColMatRef<'_, usize, f64>,
        columns: usize,
        supernodal: SupernodalThreshold,
        limit: Option<u64>,
    ) -> Result<Self, Failure> {
        if a.nrows() < a.ncols() {
            return Err(Failure::Unsound(format!(
                "least squares of {} rows in {} unknowns: fewer rows than unknowns",
                a.nrows(),
                a.ncols()
            )));
        }
        let params = QrSymbolicParams {
            supernodal_flop_ratio_threshold: supernodal,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_qr(a.symbolic(), params).map_err(|e| {
            Failure::Unsound(format!(
                "no QR of the {} x {} matrix: {e:?}",
                a.nrows(),
                a.ncols()
            ))
        })?;
        let scratch = symbolic
            .factorize_numeric_qr_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(columns.max(1), Par::Seq));
        let need = (symbolic.len_idx() + symbolic.len_val()) * 8 + scratch.size_bytes();
        usage::reserve(need as u64, 0, limit).map_err(Failure::Memory)?;
        let mut mem = MemBuffer::new(scratch);
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
        Ok(Qr {
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
        let qr = unsafe { QrRef::new_unchecked(&self.symbolic, &self.indices, &self.values) };
        qr.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut self.mem));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;
    use faer::linalg::solvers::SolveLstsq;
    use faer::sparse::{SparseColMat, Triplet};

    fn matrix(t: &[(usize, usize, f64)], rows: usize, cols: usize) -> SparseColMat<usize, f64> {
        let entries: Vec<_> = t.iter().map(|&(i, j, v)| Triplet::new(i, j, v)).collect();
        SparseColMat::try_new_from_triplets(rows, cols, &entries).unwrap()
    }

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
        let a = matrix(&t, 4, 2);
        let mut qr = Qr::factor(a.as_ref(), 1, None).unwrap();
        let b = [1.0, 2.0, 3.0, 4.0];
        let mut x = Mat::from_fn(4, 1, |i, _| b[i]);
        qr.solve(x.as_mut());
        // AᵀA = [[3, -1], [-1, 5]], Aᵀb = [7, 2]: x = [37, 13] / 14.
        assert!((x[(0, 0)] - 37.0 / 14.0).abs() < 1e-14, "{:?}", x[(0, 0)]);
        assert!((x[(1, 0)] - 13.0 / 14.0).abs() < 1e-14, "{:?}", x[(1, 0)]);
        let wide = matrix(&[], 1, 2);
        let Err(Failure::Unsound(refused)) = Qr::factor(wide.as_ref(), 1, None) else {
            panic!("a wide matrix has a least-squares factor");
        };
        assert!(refused.contains("fewer rows than unknowns"), "{refused}");
        // A limit below what the process holds refuses the factor, sized
        // by the symbolic step: at least its values and indices.
        if usage::held().is_some() {
            let Err(Failure::Memory(refusal)) = Qr::factor(a.as_ref(), 1, Some(1)) else {
                panic!("a factor beyond the memory limit");
            };
            assert_eq!((refusal.bound, refusal.limit), (usage::Bound::Limit, 1));
            assert!(refusal.need >= 8 * 5, "{refusal:?}");
        }
    }

    /// 96 rows of ones over 117 columns, shrunk from a random matrix on
    /// which faer 0.24.4 as published loses a column of a supernodal front
    /// (found by search) and does not solve it.
    const GAP: [&[usize]; 96] = [
        &[27, 104, 115],
        &[38, 39, 80],
        &[67, 105],
        &[56, 71, 114],
        &[14, 15, 82],
        &[13, 60, 77],
        &[8, 113],
        &[91, 96, 116],
        &[95, 110, 114],
        &[32, 62, 86, 95],
        &[36, 84],
        &[74, 90, 98],
        &[38, 58],
        &[63, 75, 85],
        &[12, 59],
        &[28, 70, 100],
        &[35, 114],
        &[26, 52],
        &[45, 115],
        &[63, 92],
        &[20, 23, 69],
        &[10, 20, 35, 79],
        &[60, 62],
        &[92, 110],
        &[3, 7, 44],
        &[48, 111],
        &[10, 83, 116],
        &[25, 36, 47],
        &[33, 65],
        &[29, 47, 66],
        &[40, 79],
        &[31, 88],
        &[5, 102, 106],
        &[55, 60],
        &[61, 88],
        &[34, 91, 108],
        &[81, 98],
        &[43, 73, 76, 104],
        &[37, 51, 53, 84],
        &[8, 61, 79],
        &[4, 90],
        &[1, 54, 94],
        &[59, 65, 95],
        &[0, 6],
        &[19, 24, 37, 101],
        &[17, 103],
        &[32, 40],
        &[17, 106],
        &[36, 97],
        &[15, 39, 41],
        &[24, 107],
        &[0, 109],
        &[27, 61, 70],
        &[21, 30],
        &[33, 92, 106],
        &[99, 109],
        &[6, 77],
        &[85, 89],
        &[23, 25],
        &[42, 50, 57],
        &[12, 44, 80, 100],
        &[112, 116],
        &[30, 32],
        &[49, 90],
        &[8, 46, 68, 81],
        &[9, 51],
        &[66, 93, 113],
        &[16, 64, 93, 105],
        &[16, 75, 94, 101],
        &[28, 71, 96],
        &[72, 113],
        &[3, 5, 18, 67],
        &[22, 43],
        &[2, 72],
        &[13, 68, 76],
        &[11, 14, 99],
        &[2, 11, 54],
        &[58, 63, 74],
        &[13, 111],
        &[45, 50],
        &[65, 86, 107],
        &[34, 41, 103],
        &[21, 82, 83],
        &[1, 52],
        &[26, 57],
        &[78, 87, 89, 97],
        &[4, 46, 55],
        &[42, 85, 102],
        &[22, 31],
        &[49, 53, 108],
        &[48, 112],
        &[7, 10, 58, 81],
        &[9, 69],
        &[56, 80],
        &[19, 27, 29, 99],
        &[21, 91],
    ];

    /// faer's dense QR drops a column whose remainder is below
    /// `16 (m - row) eps` of its norm, a rank threshold the supernodal
    /// fronts cannot follow: their rows then shift, and the published solve
    /// returned NaN here (and on a spring matrix of the gamma 98 study).
    #[test]
    fn a_column_below_the_dense_rank_threshold_keeps_its_row() {
        use rand::{RngExt, SeedableRng};
        let (rows, n) = (1200, 40);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let mut dense =
            nalgebra::DMatrix::<f64>::from_fn(rows + n, n, |_, _| rng.random::<f64>() - 0.5);
        // Column 1 a copy of column 0: its remainder is the regularization's.
        let first = dense.column(0).into_owned();
        dense.set_column(1, &first);
        let top = dense
            .rows(0, rows)
            .column_iter()
            .map(|c| c.norm_squared())
            .fold(0.0, f64::max);
        let mut lower = dense.rows_mut(rows, n);
        lower.fill(0.0);
        lower.fill_diagonal((1e-24 * top).sqrt());
        let t: Vec<(usize, usize, f64)> = (0..n)
            .flat_map(|j| (0..rows + n).map(move |i| (i, j)))
            .filter(|&(i, j)| dense[(i, j)] != 0.0)
            .map(|(i, j)| (i, j, dense[(i, j)]))
            .collect();
        let a = matrix(&t, rows + n, n);
        let mut qr =
            Qr::factor_with(a.as_ref(), 1, SupernodalThreshold::FORCE_SUPERNODAL, None).unwrap();
        let b = nalgebra::DVector::<f64>::from_fn(rows + n, |i, _| {
            if i < rows {
                ((i * 7) % 5) as f64 - 2.0
            } else {
                0.0
            }
        });
        let mut x = Mat::from_fn(rows + n, 1, |i, _| b[i]);
        qr.solve(x.as_mut());
        let x = nalgebra::DVector::from_fn(n, |j, _| x[(j, 0)]);
        // The reference: nalgebra's Householder QR, which has no threshold.
        let reference = dense.clone().qr();
        let qtb = reference.q().transpose() * &b;
        let expected = reference.r().solve_upper_triangular(&qtb).unwrap();
        let energy =
            |x: &nalgebra::DVector<f64>| (b.rows(0, rows) - dense.rows(0, rows) * x).norm_squared();
        let (got, want) = (energy(&x), energy(&expected));
        // 1.3e-11 measured; the published factor gave NaN.
        assert!((got - want).abs() < 1e-9 * want, "{got:e} against {want:e}");
    }

    #[test]
    fn a_gap_in_a_front_is_solved_exactly() {
        let n = 117;
        let mut t: Vec<(usize, usize, f64)> = GAP
            .iter()
            .enumerate()
            .flat_map(|(i, row)| row.iter().map(move |&j| (i, j, 1.0)))
            .collect();
        t.extend((0..n).map(|j| (GAP.len() + j, j, 1e-3)));
        let m = GAP.len() + n;
        let a = matrix(&t, m, n);
        let mut qr =
            Qr::factor_with(a.as_ref(), 2, SupernodalThreshold::FORCE_SUPERNODAL, None).unwrap();
        let b = Mat::from_fn(m, 2, |i, j| ((i * 5 + j * 3) % 7) as f64 - 3.0);
        let mut x = b.clone();
        qr.solve(x.as_mut());
        let expected: Mat<f64> = a.to_dense().qr().solve_lstsq(&b);
        let error = (x.subrows(0, n) - &expected).norm_l2() / expected.norm_l2();
        // 1.9e-13 measured.
        assert!(error < 1e-11, "{error:e}");
    }
}
