//! The exact field and rank that every rigidity verdict rests on.

use proptest::prelude::*;
use rgc::math::{Fp, Matrix, P, rank_fp};

/// Rank by the textbook dense elimination with Fermat inverses: slow, plain,
/// and independent of the sparse elimination `rank_fp` uses.
fn dense_rank(m: &Matrix<Fp>) -> usize {
    let mut a: Vec<Vec<Fp>> = (0..m.rows)
        .map(|r| (0..m.cols).map(|c| m.get(r, c)).collect())
        .collect();
    let mut rank = 0;
    for c in 0..m.cols {
        let Some(p) = (rank..m.rows).find(|&r| !a[r][c].is_zero()) else {
            continue;
        };
        a.swap(rank, p);
        let inv = a[rank][c].pow(P - 2);
        for r in 0..m.rows {
            if r != rank && !a[r][c].is_zero() {
                let f = a[r][c] * inv;
                let pivot = a[rank].clone();
                for (x, &p) in a[r].iter_mut().zip(&pivot).take(m.cols) {
                    *x = *x - f * p;
                }
            }
        }
        rank += 1;
    }
    rank
}

#[test]
fn inverses_are_inverses() {
    assert_eq!(Fp::ZERO.inv(), None);
    for v in [1, 2, 3, -1, -2, 1 << 40, (1 << 61) - 2, 123_456_789_012_345] {
        let a = Fp::new(v);
        let inv = a.inv().unwrap();
        assert_eq!(a * inv, Fp::ONE, "{v}");
        assert_eq!(inv, a.pow(P - 2), "{v}: Euclid and Fermat disagree");
    }
}

proptest! {
    /// Sparse matrices of small rank deficiency, built as sums of outer
    /// products, with dependent and zero rows: the sparse elimination
    /// agrees with the dense one.
    #[test]
    fn sparse_rank_equals_dense_rank(
        rows in 1usize..14,
        cols in 1usize..14,
        entries in prop::collection::vec((0usize..14, 0usize..14, -3i64..4), 0..60),
        copies in prop::collection::vec((0usize..14, 0usize..14, -2i64..3), 0..4),
    ) {
        let mut m = Matrix::zeros(rows, cols);
        for (r, c, v) in entries {
            m.add_to(r % rows, c % cols, Fp::new(v));
        }
        for (from, to, f) in copies {
            let (from, to) = (from % rows, to % rows);
            for c in 0..cols {
                let v = m.get(from, c);
                m.add_to(to, c, Fp::new(f) * v);
            }
        }
        prop_assert_eq!(rank_fp(&m), dense_rank(&m));
    }
}
