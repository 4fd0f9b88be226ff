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

/// Every rods-only candidate up to 7 rods and every mixed candidate up to
/// 3 components: the candidates the audit classifies.
fn candidates() -> Vec<rgc::pattern::Pattern> {
    use rgc::enumerate::{GraphFilter, TypedFilter, connected_graphs, typed_patterns};
    let mut out = Vec::new();
    for n in 3..=7 {
        for g in connected_graphs(n, &GraphFilter::maxwell_rods(n).with_min_degree(2)).unwrap() {
            out.push(rgc::pattern::Pattern::from_graph(&g).unwrap());
        }
    }
    for k in 2..=3 {
        let filter = TypedFilter {
            maxwell: true,
            ..TypedFilter::new(k)
        };
        out.extend(typed_patterns(&filter).unwrap());
    }
    out
}

/// The rank by the matrix's structure (`3 rank A + rank B K`) is the rank
/// of the matrix itself, on every sample of every family of the audit's
/// small candidates, bodies and auxiliary points included.
#[test]
fn structured_rank_is_the_matrix_rank() {
    use rand::SeedableRng;
    use rgc::rigidity::family::families;
    use rgc::rigidity::framework::{structure, try_framework};
    use rgc::rigidity::incidence::Incidence;
    use rgc::rigidity::rank::structured_rank;
    let mut checked = 0;
    for p in candidates() {
        let inc = Incidence::new(&p);
        for fam in families(&inc, 2, 11).0 {
            for s in &fam.samples {
                let mut a = rand_chacha::ChaCha8Rng::seed_from_u64(3);
                let mut b = a.clone();
                let dense = try_framework(&inc, s, &mut || Fp::random(&mut a)).unwrap();
                let structured = structure(&inc, s, &mut || Fp::random(&mut b)).unwrap();
                assert_eq!(dense.points, structured.points);
                rows_hold_at_the_points(&structured);
                assert_eq!(
                    structured_rank(&structured),
                    rank_fp(&dense.matrix),
                    "{p:?}, {}",
                    fam.grouping.describe(&inc)
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

/// Each row of an exact rigidity matrix states a fact about the points: a
/// bar's direction is the difference of its points, and an affine point is
/// the combination its coefficients give (`p_c + sum coef p_t = 0`, the
/// coefficients summing to -1).
fn rows_hold_at_the_points(s: &rgc::rigidity::framework::Structure<Fp>) {
    use rgc::rigidity::framework::Row;
    for row in &s.rows {
        match *row {
            Row::Bar { a, b, d } => {
                for (k, &dk) in d.iter().enumerate() {
                    assert_eq!(dk, s.points[a][k] - s.points[b][k]);
                }
            }
            Row::Affine { c, terms, len } => {
                let sum = terms[..len].iter().fold(Fp::ZERO, |acc, t| acc + t.1);
                assert_eq!(sum, -Fp::ONE);
                for k in 0..3 {
                    let at = terms[..len].iter().fold(s.points[c][k], |acc, &(t, coef)| {
                        acc + coef * s.points[t][k]
                    });
                    assert_eq!(at, Fp::ZERO);
                }
            }
        }
    }
}

/// The audit's class is the full verdict's class on every small candidate.
#[test]
fn exact_class_is_the_verdicts_class() {
    use rgc::rigidity::{check_exact, exact_class};
    for p in candidates() {
        for seed in [1, rgc::rule_file::RULE_SEED] {
            assert_eq!(
                exact_class(&p, seed).unwrap(),
                check_exact(&p, seed).unwrap().class,
                "{p:?}"
            );
        }
    }
}
