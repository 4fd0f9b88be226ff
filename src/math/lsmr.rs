//! Least squares where the sparse QR does not fit: faer's LSMR on `A`
//! itself, right-preconditioned by the Cholesky factor of `AᵀA + μI`.
//!
//! The factor of the normal equations takes a tenth of the QR's memory on
//! the moduli's spring matrices (1.24 GiB against 11.1 GiB at gamma 23,
//! L = 8), but squares `A`'s singular values, so on its own it cannot see
//! a mode with `σ² < μ` (MODEL, elastic moduli). LSMR never forms `AᵀA`:
//! it works with `A` and `Aᵀ` apart, as the QR does, and the factor only
//! makes `A M` near an isometry on the modes above `√μ`; each mode below
//! costs it iterations. So where it converges it solves the same least
//! squares as the QR, and where those modes are many it does not converge
//! within its cap and says so.
//!
//! The columns (the moduli's six strains) are independent solves and run
//! in parallel, each on one thread, so no digit depends on the thread count.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::matrix_free::InitialGuessStatus;
use faer::matrix_free::lsmr::{LsmrError, LsmrParams, lsmr, lsmr_scratch};
use faer::sparse::linalg::matmul::sparse_sparse_matmul;
use faer::sparse::{SparseColMat, SparseColMatRef, Triplet};
use faer::{Mat, MatRef, Par};
use rayon::prelude::*;

use super::cholesky::Llt;
use super::qr::Failure;
use crate::usage;

/// The shift `μ` of the normal equations over their largest diagonal,
/// first: near the rounding of `AᵀA` (a smaller one leaves it
/// indefinite in floats).
pub const SHIFT: f64 = 1e-13;

/// The shift grows by this factor each time the factor fails.
const SHIFT_GROWTH: f64 = 100.0;

/// The largest shift tried.
const SHIFT_MAX: f64 = 1e-5;

/// The least squares `min |A x - b|` of each column of `b`.
#[derive(Clone, Debug)]
pub struct Solution {
    pub x: Mat<f64>,
    /// LSMR's iterations, over all columns.
    pub iterations: usize,
    /// Whether every column reached `|(A M)ᵀ r| <= tolerance |(A M)ᵀ b|`.
    pub converged: bool,
    /// The largest of those ratios at the end.
    pub optimality: f64,
    /// The shift `μ` the factor took, over `AᵀA`'s largest diagonal.
    pub shift: f64,
}

/// Solves `min |A x - b|` for each column of `b` by LSMR, stopping a
/// column at `tolerance` or after `max_iterations`; the preconditioner's
/// factor is refused where it would take the process past `limit` (bytes
/// resident), with faer's symbolic step sizing it first.
pub fn least_squares(
    a: SparseColMatRef<'_, usize, f64>,
    b: MatRef<'_, f64>,
    tolerance: f64,
    max_iterations: usize,
    limit: Option<u64>,
) -> Result<Solution, Failure> {
    let n = a.ncols();
    // The normal equations before they exist: at most the squares of the
    // rows' counts, held as `Aᵀ` (16 bytes an entry of `A`), `AᵀA` (16 an
    // entry), and its shifted lower half as triplets and as a matrix (40).
    let mut per_row = vec![0_u64; a.nrows()];
    for &i in a.row_idx() {
        per_row[i] += 1;
    }
    let products: u64 = per_row.iter().map(|c| c * c).sum();
    let held = 16 * a.compute_nnz() as u64 + 16 * products + 40 * (products / 2 + n as u64);
    usage::reserve(held, 0, limit).map_err(Failure::Memory)?;
    let at = a.transpose().to_col_major().map_err(alloc)?;
    let normal = sparse_sparse_matmul(at.as_ref(), a, 1.0, Par::Seq).map_err(alloc)?;
    drop(at);
    let top = (0..n)
        .map(|j| normal.as_ref().get(j, j).copied().unwrap_or(0.0))
        .fold(0.0_f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let shifted = |mu: f64| -> Result<SparseColMat<usize, f64>, Failure> {
        let mut entries: Vec<Triplet<usize, usize, f64>> =
            Vec::with_capacity(normal.compute_nnz() / 2 + n);
        for j in 0..n {
            let rows = normal.as_ref().row_idx_of_col(j);
            let values = normal.as_ref().val_of_col(j);
            entries.extend(
                rows.zip(values)
                    .filter(|(i, _)| *i >= j)
                    .map(|(i, &v)| Triplet::new(i, j, v)),
            );
            entries.push(Triplet::new(j, j, mu * top));
        }
        SparseColMat::try_new_from_triplets(n, n, &entries)
            .map_err(|e| Failure::Unsound(format!("the shifted normal equations: {e:?}")))
    };
    let mut mu = SHIFT;
    let first = shifted(mu)?;
    let need = Llt::need(first.symbolic()).ok_or_else(|| no_order(n))?;
    usage::reserve(need, 0, limit).map_err(Failure::Memory)?;
    let mut llt = Llt::analyse(first.symbolic()).ok_or_else(|| no_order(n))?;
    let mut matrix = first;
    while !llt.factor(matrix.as_ref()) {
        mu *= SHIFT_GROWTH;
        if mu > SHIFT_MAX {
            return Err(Failure::Unsound(format!(
                "the normal equations of the {} x {n} matrix stay indefinite with a shift of {SHIFT_MAX:e} of their largest diagonal",
                a.nrows()
            )));
        }
        matrix = shifted(mu)?;
    }
    drop(matrix);
    drop(normal);
    let root = llt.root().expect("factored above");
    // Each running column holds its own workspace.
    let scratch = lsmr_scratch(root, a, 1, Par::Seq);
    let running = rayon::current_num_threads().min(b.ncols()).max(1) as u64;
    usage::reserve(running * scratch.size_bytes() as u64, 0, limit).map_err(Failure::Memory)?;
    let params = LsmrParams {
        initial_guess: InitialGuessStatus::Zero,
        abs_tolerance: 0.0,
        rel_tolerance: tolerance,
        max_iters: max_iterations,
        ..Default::default()
    };
    let mut x = Mat::<f64>::zeros(n, b.ncols());
    let columns: Vec<Column> = x
        .par_col_chunks_mut(1)
        .enumerate()
        .map(|(j, x)| {
            let mut mem = MemBuffer::new(scratch);
            let out = lsmr(
                x,
                root,
                a,
                b.subcols(j, 1),
                params,
                |_| {},
                Par::Seq,
                MemStack::new(&mut mem),
            );
            match out {
                Ok(info) => Column {
                    iterations: info.iter_count,
                    converged: true,
                    residual: info.rel_residual,
                },
                Err(LsmrError::NoConvergence { rel_residual, .. }) => Column {
                    iterations: max_iterations,
                    converged: false,
                    residual: rel_residual,
                },
            }
        })
        .collect();
    Ok(Solution {
        x,
        iterations: columns.iter().map(|c| c.iterations).sum(),
        converged: columns.iter().all(|c| c.converged),
        optimality: columns.iter().map(|c| c.residual).fold(0.0, f64::max),
        shift: mu,
    })
}

/// How one column's LSMR ended: its iterations, whether it stopped at the
/// tolerance, and `|(A M)ᵀ r| / |(A M)ᵀ b|` where it stopped.
struct Column {
    iterations: usize,
    converged: bool,
    residual: f64,
}

fn alloc(e: faer::sparse::FaerError) -> Failure {
    Failure::Unsound(format!("the normal equations: {e:?}"))
}

fn no_order(n: usize) -> Failure {
    Failure::Unsound(format!(
        "no Cholesky order for the {n} x {n} normal equations"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::SolveLstsq;

    #[test]
    fn the_preconditioned_lsmr_solves_the_dense_least_squares() {
        // 60 rows over 20 unknowns, a few entries per row.
        let (m, n) = (60, 20);
        let mut entries = Vec::new();
        let mut dense = Mat::<f64>::zeros(m, n);
        for i in 0..m {
            for k in 0..3 {
                let j = (i * 7 + k * 5) % n;
                let v = 1.0 + ((i * 13 + k * 3) % 11) as f64 / 7.0;
                entries.push(Triplet::new(i, j, v));
                dense[(i, j)] += v;
            }
        }
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(m, n, &entries).unwrap();
        let b = Mat::from_fn(m, 2, |i, j| ((i * 3 + j * 5) % 7) as f64 - 3.0);
        let out = least_squares(a.as_ref(), b.as_ref(), 1e-12, 200, None).unwrap();
        assert!(out.converged, "{out:?}");
        let reference = dense.qr().solve_lstsq(&b);
        let err = (&out.x - &reference).norm_l2() / reference.norm_l2();
        assert!(err < 1e-10, "relative error {err:e}");
        // A near-exact preconditioner: a handful of iterations per column.
        assert!(out.iterations <= 10, "{} iterations", out.iterations);
    }

    #[test]
    fn the_solution_does_not_depend_on_the_thread_count() {
        // Six right-hand sides, as the moduli's strains, on a matrix with a
        // soft mode below the preconditioner's shift (its last column the
        // one before it, changed by 1e-8), which costs iterations.
        let (m, n) = (90, 30);
        let mut entries: Vec<Triplet<usize, usize, f64>> = (0..m)
            .flat_map(|i| {
                (0..3).map(move |k| {
                    let v = 1.0 + ((i * 17 + k * 5) % 13) as f64 / 3.0;
                    Triplet::new(i, (i * 11 + k * 7) % (n - 1), v)
                })
            })
            .collect();
        let twin: Vec<_> = entries
            .iter()
            .filter(|t| t.col == n - 2)
            .map(|t| Triplet::new(t.row, n - 1, t.val * (1.0 + 1e-8 * (t.row % 3) as f64)))
            .collect();
        entries.extend(twin);
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(m, n, &entries).unwrap();
        let b = Mat::from_fn(m, 6, |i, j| ((i * (j + 2)) % 9) as f64 - 4.0);
        let on = |threads: usize, cap: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| least_squares(a.as_ref(), b.as_ref(), 1e-14, cap, None).unwrap())
        };
        for cap in [2, 2000] {
            let (one, three) = (on(1, cap), on(3, cap));
            let bits = |x: &Mat<f64>| -> Vec<u64> {
                (0..6)
                    .flat_map(|j| x.col(j).iter().map(|v| v.to_bits()).collect::<Vec<_>>())
                    .collect()
            };
            assert_eq!(bits(&one.x), bits(&three.x), "cap {cap}");
            assert_eq!(
                (one.iterations, one.converged, one.optimality.to_bits()),
                (
                    three.iterations,
                    three.converged,
                    three.optimality.to_bits()
                )
            );
            // The small cap leaves columns unsettled; the large one none.
            assert_eq!(one.converged, cap == 2000, "cap {cap}: {one:?}");
        }
    }
}
