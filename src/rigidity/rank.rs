//! Exact rank over F_p of a rigidity matrix by its structure (MODEL §4).
//!
//! The matrix ([`super::framework::Structure`]) is `A ⊗ I_3` stacked on bar
//! rows: each affine row of a part acts the same way on the x, y and z
//! velocities, and only bars mix coordinates. So its kernel is the kernel
//! of the bars restricted to `ker A ⊗ R^3`, and
//!
//! ```text
//! rank = 3 rank(A) + rank(B K),
//! ```
//!
//! where `A` is the scalar matrix of the affine rows (one row per affine
//! point, one column per point), `K` a basis of its kernel and `B K` the
//! bars on that basis (one row per bar, three columns per basis vector).
//! Both factors are small: `A` has a column per point instead of three, and
//! `ker A` has about `2 rods - contacts` dimensions for rods-only patterns.
//! This is an identity, not an estimate: the rank equals that of the dense
//! matrix at every realization, and the tests check it against
//! [`crate::math::rank_fp`].

use std::cell::RefCell;

use super::framework::{Row, Structure};
use crate::math::Fp;

/// Buffers a thread reuses across ranks: a verdict takes thousands of small
/// ranks, and the audit millions of verdicts.
#[derive(Default)]
struct Work {
    a: Vec<Fp>,
    pivots: Vec<usize>,
    basis: Vec<Fp>,
    b: Vec<Fp>,
    nonzero: Vec<(usize, Fp)>,
}

thread_local! {
    static WORK: RefCell<Work> = RefCell::new(Work::default());
}

/// The rank of the rigidity matrix that `s` stands for: the rank
/// [`crate::math::rank_fp`] gives for [`super::framework::try_framework`]'s matrix.
pub fn structured_rank(s: &Structure<Fp>) -> usize {
    WORK.with(|w| rank_in(s, &mut w.borrow_mut()))
}

fn rank_in(s: &Structure<Fp>, w: &mut Work) -> usize {
    let n = s.points.len();
    let affine = s
        .rows
        .iter()
        .filter(|r| matches!(r, Row::Affine { .. }))
        .count();
    w.a.clear();
    w.a.resize(affine * n, Fp::ZERO);
    let mut i = 0;
    for row in &s.rows {
        if let Row::Affine { c, terms, len } = *row {
            let r = &mut w.a[i * n..(i + 1) * n];
            r[c] = r[c] + Fp::ONE;
            for &(t, coef) in &terms[..len] {
                r[t] = r[t] + coef;
            }
            i += 1;
        }
    }
    let rank_a = reduce(&mut w.a, affine, n, &mut w.pivots, &mut w.nonzero, true);
    // A kernel basis: one vector per free column f, 1 at f and minus the
    // reduced rows' entries at their pivots.
    let k = n - rank_a;
    w.basis.clear();
    w.basis.resize(n * k, Fp::ZERO);
    let mut j = 0;
    let mut next_pivot = 0;
    for f in 0..n {
        if w.pivots.get(next_pivot) == Some(&f) {
            next_pivot += 1;
            continue;
        }
        w.basis[f * k + j] = Fp::ONE;
        for (r, &p) in w.pivots.iter().enumerate() {
            w.basis[p * k + j] = -w.a[r * n + f];
        }
        j += 1;
    }
    let bars = s.rows.len() - affine;
    let cols = 3 * k;
    w.b.clear();
    w.b.resize(bars * cols, Fp::ZERO);
    let mut r = 0;
    for row in &s.rows {
        if let Row::Bar { a, b, d } = *row {
            let out = &mut w.b[r * cols..(r + 1) * cols];
            for j in 0..k {
                let x = w.basis[a * k + j] - w.basis[b * k + j];
                if !x.is_zero() {
                    for (o, &dk) in out[3 * j..3 * j + 3].iter_mut().zip(&d) {
                        *o = x * dk;
                    }
                }
            }
            r += 1;
        }
    }
    let rank_b = reduce(&mut w.b, bars, cols, &mut w.pivots, &mut w.nonzero, false);
    3 * rank_a + rank_b
}

/// Row-reduces the dense `rows x cols` matrix `a` in place and returns its
/// rank, with `pivots` the pivot column of each of the first `rank` rows.
/// With `full`, the result is the reduced row echelon form (pivots 1, zero
/// above and below); else only entries below the pivots are cleared.
fn reduce(
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
        let inv = a[rank * cols + c].inv().expect("a pivot is non-zero");
        let pivot = &mut a[rank * cols..(rank + 1) * cols];
        nonzero.clear();
        for (k, x) in pivot.iter_mut().enumerate() {
            if !x.is_zero() && k != c {
                if full {
                    *x = *x * inv;
                }
                nonzero.push((k, *x));
            }
        }
        if full {
            pivot[c] = Fp::ONE;
        }
        let first = if full { 0 } else { rank + 1 };
        for r in first..rows {
            if r == rank {
                continue;
            }
            let x = a[r * cols + c];
            if x.is_zero() {
                continue;
            }
            let f = if full { x } else { x * inv };
            let row = &mut a[r * cols..(r + 1) * cols];
            row[c] = Fp::ZERO;
            for &(k, v) in nonzero.iter() {
                row[k] = row[k] - f * v;
            }
        }
        pivots.push(c);
        rank += 1;
    }
    rank
}
