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
use crate::math::vec3::{V3, cross, dot, is_null, sub};
use crate::math::{Fp, reduce_fp};

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
    parts: Vec<(u128, u128, bool)>,
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
    // The affine functions of space restricted to the points (1, x, y, z)
    // always lie in ker A: every affine row puts a point at the same affine
    // combination of its anchors. When they span it, the bars act on `x_j`,
    // and bar (a, b) with `d = p_a - p_b` reads `d_j d_k` in column (j, k):
    // the rank of the bars on `ker A ⊗ R^3` is that of the matrices `d d^T`
    // (the classical conic condition). They span it when as many points as
    // they have dimensions determine every point (`spanned_by_affine`), or
    // else when the rank of A says so.
    let affine_dimension = affine_span(&s.points) + 1;
    if spanned_by_affine(s, affine_dimension, &mut w.parts) {
        return 3 * (n - affine_dimension) + conic_rank(s);
    }
    fill_affine(s, n, affine, &mut w.a);
    if let Some(rank_a) = sparse_rank(&mut w.a, affine, n, &mut w.support) {
        if n - rank_a == affine_dimension {
            return 3 * rank_a + conic_rank(s);
        }
        fill_affine(s, n, affine, &mut w.a);
    }
    let rank_a = reduce_fp(&mut w.a, affine, n, &mut w.pivots, &mut w.nonzero, true);
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
    let rank_b = reduce_fp(&mut w.b, bars, cols, &mut w.pivots, &mut w.nonzero, false);
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

/// Whether `ker A` is at most `dimension`-dimensional because the values
/// at `dimension` points determine those at every point. A function in
/// `ker A` is affine along each rod, so its values at two points of a rod
/// give all the rod's (the points of a rod are distinct and the rows put
/// them at distinct parameters); and a body's points are fixed combinations
/// of its anchors. Seeds are chosen greedily: two points of the rod with the
/// most points, then, while points are unknown, one point of the rod (or
/// one anchor of the body) whose closure knows the most. `false` when the
/// seeds run past `dimension`, or beyond 128 points. Since `ker A` holds the
/// `dimension` affine functions, `true` means `ker A` is exactly their
/// span: a certificate without arithmetic.
fn spanned_by_affine(
    s: &Structure<Fp>,
    dimension: usize,
    parts: &mut Vec<(u128, u128, bool)>,
) -> bool {
    let n = s.points.len();
    if n > 128 || s.parts.is_empty() {
        return false;
    }
    // (anchors, points, rod) of each part.
    parts.clear();
    for part in &s.parts {
        let anchors = part.anchors[..part.n_anchors]
            .iter()
            .fold(0u128, |m, &a| m | 1 << a);
        let points = s.rows[part.rows.clone()]
            .iter()
            .fold(anchors, |m, row| match *row {
                Row::Affine { c, .. } => m | 1 << c,
                Row::Bar { .. } => m,
            });
        parts.push((anchors, points, part.rod));
    }
    let close = |mut known: u128| loop {
        let before = known;
        for &(anchors, points, rod) in parts.iter() {
            let fixed = if rod {
                (known & points).count_ones() >= 2
            } else {
                known & anchors == anchors
            };
            if fixed {
                known |= points;
            }
        }
        if known == before {
            return known;
        }
    };
    let all = if n == 128 {
        u128::MAX
    } else {
        (1u128 << n) - 1
    };
    let Some(&(_, first, _)) = parts
        .iter()
        .filter(|p| p.2)
        .max_by_key(|p| p.1.count_ones())
    else {
        return false;
    };
    let mut seeds = 2;
    let mut known = close(first);
    while known != all {
        seeds += 1;
        if seeds > dimension {
            return false;
        }
        // One more seed: the unknown point that makes the most known.
        let mut best = known;
        for &(anchors, points, rod) in parts.iter() {
            let candidates = if rod { points } else { anchors } & !known;
            if candidates == 0 || (rod && known & points == 0) {
                continue;
            }
            let grown = close(known | candidates & candidates.wrapping_neg());
            if grown.count_ones() > best.count_ones() {
                best = grown;
            }
        }
        if best == known {
            return false;
        }
        known = best;
    }
    seeds == dimension
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
fn conic_rank(s: &Structure<Fp>) -> usize {
    // Rows go into an echelon basis one at a time, and at six (the most
    // there can be) the rest need not be looked at.
    let mut basis: [([Fp; 6], usize); 6] = [([Fp::ZERO; 6], 0); 6];
    let mut rank = 0;
    for row in &s.rows {
        let Row::Bar { d, .. } = *row else {
            continue;
        };
        let mut v = [
            d[0] * d[0],
            d[0] * d[1],
            d[0] * d[2],
            d[1] * d[1],
            d[1] * d[2],
            d[2] * d[2],
        ];
        // Clear v at each pivot of the basis (fraction free, as in `reduce_fp`).
        for (b, p) in &basis[..rank] {
            let x = v[*p];
            if !x.is_zero() {
                let q = b[*p];
                for (vk, &bk) in v.iter_mut().zip(b) {
                    *vk = *vk * q - x * bk;
                }
            }
        }
        if let Some(p) = v.iter().position(|x| !x.is_zero()) {
            basis[rank] = (v, p);
            rank += 1;
            if rank == 6 {
                break;
            }
        }
    }
    rank
}

/// The rank of the dense `rows x cols` matrix `a` (destroyed), or `None`
/// when it has more than 128 rows or columns. Elimination follows bit masks
/// of each row's non-zero columns and each column's non-zero rows: the next
/// pivot column is the one fewest remaining rows hold (minimum degree, to
/// keep the fill small), its row the sparsest of them. So it costs what the
/// non-zeros and their fill cost, not `rows x cols` per pivot. Fraction free
/// (see [`reduce_fp`]).
fn sparse_rank(a: &mut [Fp], rows: usize, cols: usize, support: &mut Vec<u128>) -> Option<usize> {
    if rows > 128 || cols > 128 {
        return None;
    }
    let mut col_rows = [0u128; 128];
    support.clear();
    for r in 0..rows {
        let mut m = 0u128;
        for (k, x) in a[r * cols..(r + 1) * cols].iter().enumerate() {
            if !x.is_zero() {
                m |= 1 << k;
                col_rows[k] |= 1 << r;
            }
        }
        support.push(m);
    }
    let all = |n: usize| {
        if n == 128 {
            u128::MAX
        } else {
            (1u128 << n) - 1
        }
    };
    let mut free_rows = all(rows);
    let mut left_cols = all(cols);
    let mut rank = 0;
    loop {
        let mut best: Option<(u32, usize)> = None;
        for c in mask_bits(left_cols) {
            let held = (col_rows[c] & free_rows).count_ones();
            if held == 0 {
                left_cols &= !(1 << c);
            } else if best.is_none_or(|(fewest, _)| held < fewest) {
                best = Some((held, c));
                if held == 1 {
                    break;
                }
            }
        }
        let Some((_, c)) = best else {
            return Some(rank);
        };
        left_cols &= !(1 << c);
        let bit = 1u128 << c;
        let rows_c = col_rows[c] & free_rows;
        let p = mask_bits(rows_c)
            .min_by_key(|&r| support[r].count_ones())
            .expect("the column is held");
        free_rows &= !(1 << p);
        rank += 1;
        let q = a[p * cols + c];
        let sp = support[p] & !bit;
        for r in mask_bits(rows_c & !(1 << p)) {
            let x = a[r * cols + c];
            let start = r * cols;
            a[start + c] = Fp::ZERO;
            col_rows[c] &= !(1 << r);
            for k in mask_bits(support[r] & !sp & !bit) {
                a[start + k] = a[start + k] * q;
            }
            let mut sr = (support[r] | sp) & !bit;
            for k in mask_bits(sp) {
                let y = a[start + k] * q - x * a[p * cols + k];
                a[start + k] = y;
                if y.is_zero() {
                    sr &= !(1 << k);
                    col_rows[k] &= !(1 << r);
                } else {
                    col_rows[k] |= 1 << r;
                }
            }
            support[r] = sr;
        }
    }
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
