//! A dense row-major matrix over a [`Scalar`], and its exact rank over F_p
//! by sparse Gaussian elimination.

use super::field::{Fp, Scalar};

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

/// Exact rank over F_p by Gaussian elimination (consumes a copy).
pub fn rank_fp(m: &Matrix<Fp>) -> usize {
    let mut a = m.data.clone();
    let (rows, cols) = (m.rows, m.cols);
    // Rigidity and Jacobian rows have a handful of non-zeros: eliminating
    // with the pivot row's non-zeros only is several times faster than dense.
    let mut pivot_row: Vec<(usize, Fp)> = Vec::with_capacity(cols);
    let mut rank = 0;
    for c in 0..cols {
        if rank == rows {
            break;
        }
        let Some(pivot) = (rank..rows).find(|&r| !a[r * cols + c].is_zero()) else {
            continue;
        };
        if pivot != rank {
            let (top, bottom) = a.split_at_mut(pivot * cols);
            top[rank * cols..(rank + 1) * cols].swap_with_slice(&mut bottom[..cols]);
        }
        let inv = a[rank * cols + c].inv().expect("pivot is non-zero");
        pivot_row.clear();
        pivot_row.extend(
            (c + 1..cols)
                .map(|k| (k, a[rank * cols + k]))
                .filter(|(_, v)| !v.is_zero()),
        );
        for r in rank + 1..rows {
            let f = a[r * cols + c];
            if f.is_zero() {
                continue;
            }
            let f = f * inv;
            let row = &mut a[r * cols..(r + 1) * cols];
            row[c] = Fp::ZERO;
            for &(k, v) in &pivot_row {
                row[k] = row[k] - f * v;
            }
        }
        rank += 1;
    }
    rank
}
