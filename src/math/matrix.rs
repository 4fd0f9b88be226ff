//! A dense row-major matrix over a [`Scalar`], and its exact rank over F_p
//! by fraction-free Gaussian elimination.

use super::field::{Field, Fp, Scalar};

/// A dense row-major matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix<S> {
    pub rows: usize,
    pub cols: usize,
    pub data: Vec<S>,
}

impl<S: Scalar> Matrix<S> {
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Matrix {
            rows,
            cols,
            data: vec![S::zero(); rows * cols],
        }
    }

    /// Appends a zero row and returns its index.
    pub fn push_row(&mut self) -> usize {
        self.data.extend(std::iter::repeat_n(S::zero(), self.cols));
        self.rows += 1;
        self.rows - 1
    }

    pub fn get(&self, r: usize, c: usize) -> S {
        self.data[r * self.cols + c]
    }

    pub fn set(&mut self, r: usize, c: usize, v: S) {
        self.data[r * self.cols + c] = v;
    }

    /// Adds `v` to entry `(r, c)`.
    pub fn add_to(&mut self, r: usize, c: usize, v: S) {
        let x = &mut self.data[r * self.cols + c];
        *x = *x + v;
    }

    /// `self * x` for a column vector `x`.
    pub fn apply(&self, x: &[S]) -> Vec<S> {
        (0..self.rows)
            .map(|r| {
                self.data[r * self.cols..(r + 1) * self.cols]
                    .iter()
                    .zip(x)
                    .fold(S::zero(), |acc, (&a, &b)| acc + a * b)
            })
            .collect()
    }
}

/// Exact rank over F_p by Gaussian elimination of a copy.
pub fn rank_fp(m: &Matrix<Fp>) -> usize {
    let mut a = m.data.clone();
    reduce_fp(
        &mut a,
        m.rows,
        m.cols,
        &mut Vec::new(),
        &mut Vec::new(),
        false,
    )
}

/// Exact rank over any prime field by textbook Gaussian elimination of a
/// copy: the plain reference the fast kernels are tested against.
pub fn rank_exact<F: Field>(m: &Matrix<F>) -> usize {
    let (rows, cols) = (m.rows, m.cols);
    let mut a = m.data.clone();
    let mut rank = 0;
    for c in 0..cols {
        let Some(p) = (rank..rows).find(|&i| a[i * cols + c] != F::zero()) else {
            continue;
        };
        for k in 0..cols {
            a.swap(rank * cols + k, p * cols + k);
        }
        let inv = a[rank * cols + c].inverse().expect("non-zero pivot");
        for i in rank + 1..rows {
            let f = a[i * cols + c] * inv;
            if f == F::zero() {
                continue;
            }
            for k in c..cols {
                let v = a[rank * cols + k];
                a[i * cols + k] = a[i * cols + k] - f * v;
            }
        }
        rank += 1;
    }
    rank
}

/// Row-reduces the dense `rows x cols` matrix `a` in place and returns its
/// rank, with `pivots` the pivot column of each of the first `rank` rows.
/// Fraction free: a row is cleared at a pivot column `c` by `q row - x
/// pivot_row`, with `q` the pivot and `x` its entry at `c`, which scales
/// the row by a non-zero factor and changes neither rank nor row space. With
/// `full`, entries above the pivots are cleared too (an echelon form whose
/// pivots are not 1); else only those below. `nonzero` is scratch space,
/// passed in so that callers ranking many matrices allocate it once.
/// Rigidity and Jacobian rows have a handful of non-zeros: each row update
/// touches the pivot row's non-zeros and only scales the rest.
pub fn reduce_fp(
    a: &mut [Fp],
    rows: usize,
    cols: usize,
    pivots: &mut Vec<usize>,
    nonzero: &mut Vec<(usize, Fp)>,
    full: bool,
) -> usize {
    pivots.clear();
    let mut rank = 0;
    for c in 0..cols {
        if rank == rows {
            break;
        }
        let Some(p) = (rank..rows).find(|&r| !a[r * cols + c].is_zero()) else {
            continue;
        };
        if p != rank {
            let (top, bottom) = a.split_at_mut(p * cols);
            top[rank * cols..(rank + 1) * cols].swap_with_slice(&mut bottom[..cols]);
        }
        let q = a[rank * cols + c];
        nonzero.clear();
        nonzero.extend(
            a[rank * cols..(rank + 1) * cols]
                .iter()
                .enumerate()
                .filter(|&(k, x)| k != c && !x.is_zero())
                .map(|(k, &x)| (k, x)),
        );
        let first = if full { 0 } else { rank + 1 };
        for r in first..rows {
            if r == rank {
                continue;
            }
            let x = a[r * cols + c];
            if x.is_zero() {
                continue;
            }
            let row = &mut a[r * cols..(r + 1) * cols];
            row[c] = Fp::ZERO;
            // Entries outside the pivot row's support only scale (most are zero).
            let mut k0 = 0;
            for &(k, v) in nonzero.iter() {
                scale_nonzero(&mut row[k0..k], q);
                row[k] = row[k] * q - x * v;
                k0 = k + 1;
            }
            scale_nonzero(&mut row[k0..], q);
        }
        pivots.push(c);
        rank += 1;
    }
    rank
}

fn scale_nonzero(row: &mut [Fp], q: Fp) {
    for y in row.iter_mut().filter(|y| !y.is_zero()) {
        *y = *y * q;
    }
}
