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
//! `ker A` holds the affine functions of space (1, x, y, z on the points)
//! and, for most candidates, nothing else; then `B K` is the matrices
//! `d d^T` of the bar directions, six columns. These are identities, not
//! estimates: the rank equals that of the dense matrix at every
//! realization, and the tests check it against [`crate::math::rank_fp`].

use std::cell::RefCell;

use super::framework::{Row, Structure};
use crate::math::Fp;
use crate::math::vec3::{V3, cross, dot, is_null, sub};

/// Buffers a thread reuses across ranks: a verdict takes thousands of small
/// ranks, and the audit millions of verdicts.
#[derive(Default)]
struct Work {
    a: Vec<Fp>,
    pivots: Vec<usize>,
    basis: Vec<Fp>,
    scale: Vec<Fp>,
    b: Vec<Fp>,
    nonzero: Vec<(usize, Fp)>,
    support: Vec<u128>,
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
    fill_affine(s, n, affine, &mut w.a);
    if let Some(rank_a) = sparse_rank(&mut w.a, affine, n, &mut w.support) {
        // The affine functions of space restricted to the points (1, x, y,
        // z) always lie in ker A: every affine row puts a point at the same
        // affine combination of its anchors. When they span it, the bars
        // act on `x_j`, and bar (a, b) with `d = p_a - p_b` reads `d_j d_k`
        // in column (j, k): the rank of the bars on `ker A ⊗ R^3` is that of
        // the matrices `d d^T` (the classical conic condition).
        if n - rank_a == affine_span(&s.points) + 1 {
            return 3 * rank_a + conic_rank(s, &mut w.b, &mut w.support);
        }
        fill_affine(s, n, affine, &mut w.a);
    }
    let rank_a = reduce(&mut w.a, affine, n, &mut w.pivots, &mut w.nonzero, true);
    // A kernel basis: one vector per free column f. Row r of the reduced
    // matrix reads `q_r x_(p_r) + sum_f a_rf x_f = 0` with its pivot `q_r`
    // not scaled to 1, so the vector with `x_f = D`, `D` the product of the
    // pivots, has `x_(p_r) = -a_rf D / q_r`: products of the other pivots,
    // and no inverse (an inverse costs as much as dozens of products).
    let k = n - rank_a;
    w.scale.clear();
    w.scale.resize(rank_a, Fp::ONE);
    let mut prefix = Fp::ONE;
    for (r, &p) in w.pivots.iter().enumerate() {
        w.scale[r] = prefix;
        prefix = prefix * w.a[r * n + p];
    }
    let product = prefix;
    let mut suffix = Fp::ONE;
    for (r, &p) in w.pivots.iter().enumerate().rev() {
        w.scale[r] = w.scale[r] * suffix;
        suffix = suffix * w.a[r * n + p];
    }
    w.basis.clear();
    w.basis.resize(n * k, Fp::ZERO);
    let mut j = 0;
    let mut next_pivot = 0;
    for f in 0..n {
        if w.pivots.get(next_pivot) == Some(&f) {
            next_pivot += 1;
            continue;
        }
        w.basis[f * k + j] = product;
        for (r, &p) in w.pivots.iter().enumerate() {
            let x = w.a[r * n + f];
            if !x.is_zero() {
                w.basis[p * k + j] = -(x * w.scale[r]);
            }
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

/// Writes the affine rows of `s` as the dense `affine x n` matrix `A`.
fn fill_affine(s: &Structure<Fp>, n: usize, affine: usize, a: &mut Vec<Fp>) {
    a.clear();
    a.resize(affine * n, Fp::ZERO);
    let mut i = 0;
    for row in &s.rows {
        if let Row::Affine { c, terms, len } = *row {
            let r = &mut a[i * n..(i + 1) * n];
            r[c] = r[c] + Fp::ONE;
            for &(t, coef) in &terms[..len] {
                r[t] = r[t] + coef;
            }
            i += 1;
        }
    }
}

/// The dimension of the affine span of `points` (0 to 3).
fn affine_span(points: &[V3<Fp>]) -> usize {
    let Some(&p0) = points.first() else {
        return 0;
    };
    let e = |p: &V3<Fp>| sub(*p, p0);
    let Some(e1) = points.iter().map(e).find(|v| !is_null(*v)) else {
        return 0;
    };
    let Some(n) = points
        .iter()
        .map(|p| cross(e1, e(p)))
        .find(|v| !is_null(*v))
    else {
        return 1;
    };
    if points.iter().all(|p| dot(n, e(p)).is_zero()) {
        2
    } else {
        3
    }
}

/// The rank of the matrices `d d^T` of the bars of `s`, as rows of their
/// six distinct entries.
fn conic_rank(s: &Structure<Fp>, b: &mut Vec<Fp>, support: &mut Vec<u128>) -> usize {
    b.clear();
    let mut bars = 0;
    for row in &s.rows {
        if let Row::Bar { d, .. } = *row {
            b.extend([
                d[0] * d[0],
                d[0] * d[1],
                d[0] * d[2],
                d[1] * d[1],
                d[1] * d[2],
                d[2] * d[2],
            ]);
            bars += 1;
        }
    }
    sparse_rank(b, bars, 6, support).expect("six columns fit a mask")
}

/// The rank of the dense `rows x cols` matrix `a` (destroyed), or `None`
/// when it has more than 128 rows or columns. Elimination follows each
/// row's non-zero columns (bit masks) and picks the sparsest row holding
/// the pivot column, so it costs what the non-zeros and their fill cost,
/// not `rows x cols` per pivot; fraction free (see [`reduce`]).
fn sparse_rank(a: &mut [Fp], rows: usize, cols: usize, support: &mut Vec<u128>) -> Option<usize> {
    if rows > 128 || cols > 128 {
        return None;
    }
    support.clear();
    support.extend((0..rows).map(|r| {
        a[r * cols..(r + 1) * cols]
            .iter()
            .enumerate()
            .filter(|(_, x)| !x.is_zero())
            .fold(0u128, |m, (k, _)| m | 1 << k)
    }));
    let mut free_rows: u128 = if rows == 128 {
        u128::MAX
    } else {
        (1 << rows) - 1
    };
    let mut rank = 0;
    let mut order: [(u32, u8); 128] = [(0, 0); 128];
    for (c, o) in order[..cols].iter_mut().enumerate() {
        let count = support.iter().filter(|&&m| m >> c & 1 == 1).count();
        *o = (count as u32, c as u8);
    }
    order[..cols].sort_unstable();
    for &(_, c) in &order[..cols] {
        let c = c as usize;
        let bit = 1u128 << c;
        let holding = |free: u128| {
            let mut m = 0u128;
            for r in mask_bits(free) {
                if support[r] & bit != 0 {
                    m |= 1 << r;
                }
            }
            m
        };
        let rows_c = holding(free_rows);
        let Some(p) = mask_bits(rows_c).min_by_key(|&r| support[r].count_ones()) else {
            continue;
        };
        free_rows &= !(1 << p);
        rank += 1;
        let q = a[p * cols + c];
        let sp = support[p] & !bit;
        for r in mask_bits(rows_c & !(1 << p)) {
            let x = a[r * cols + c];
            let row_start = r * cols;
            a[row_start + c] = Fp::ZERO;
            for k in mask_bits(support[r] & !sp & !bit) {
                a[row_start + k] = a[row_start + k] * q;
            }
            let mut sr = (support[r] | sp) & !bit;
            for k in mask_bits(sp) {
                let y = a[row_start + k] * q - x * a[p * cols + k];
                a[row_start + k] = y;
                if y.is_zero() {
                    sr &= !(1 << k);
                }
            }
            support[r] = sr;
        }
    }
    Some(rank)
}

/// The set bits of a mask, ascending.
fn mask_bits(mut m: u128) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (m != 0).then(|| {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            k
        })
    })
}

/// Row-reduces the dense `rows x cols` matrix `a` in place and returns its
/// rank, with `pivots` the pivot column of each of the first `rank` rows.
/// Fraction free: a row is cleared at a pivot column `c` by `q row - x
/// pivot_row`, with `q` the pivot and `x` its entry at `c`, which scales
/// the row by a non-zero factor and changes neither rank nor row space. With
/// `full`, entries above the pivots are cleared too (an echelon form whose
/// pivots are not 1); else only those below.
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
