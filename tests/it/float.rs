//! The float rank (SVD and pivoted QR at float realizations) against the
//! exact verdict, and its refusal to guess at degenerate realizations.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use rgc::engine::examples;
use rgc::graph::ContactGraph;
use rgc::math::float::{RankRule, decide_rank, qr_diagonal, rank_qr, rank_svd, singular_values};
use rgc::math::{Fp, Matrix, rank_fp};
use rgc::pattern::Pattern;
use rgc::rigidity::construction::{self, Degeneracy, Geometry};
use rgc::rigidity::family;
use rgc::rigidity::framework::{float_framework, trivial_residual};
use rgc::rigidity::incidence::Incidence;
use rgc::rigidity::verdict::check_float_in;
use rgc::rigidity::{Ranker, check_exact, check_float};

fn rods(n: usize, edges: &[(u32, u32)]) -> Pattern {
    let g = ContactGraph::new(n, edges.iter().map(|&(a, b)| [a, b]).collect()).unwrap();
    Pattern::from_graph(&g).unwrap()
}

fn k(a: std::ops::Range<u32>, b: std::ops::Range<u32>) -> Vec<(u32, u32)> {
    a.flat_map(|x| b.clone().map(move |y| (x, y))).collect()
}

/// Every engine example, and the rods-only patterns of tests/rigidity.rs.
fn patterns() -> Vec<(String, Pattern)> {
    let mut out: Vec<(String, Pattern)> = examples::all()
        .into_iter()
        .map(|e| {
            let p = Pattern::from_host(&e.graph(), &e.bodies).unwrap();
            (e.name.to_string(), p)
        })
        .collect();
    out.push(("K_{3,3}".into(), rods(6, &k(0..3, 3..6))));
    out.push(("K_{2,4}".into(), rods(6, &k(0..2, 2..6))));
    out.push(("rod prism".into(), rods(6, &examples::PRISM)));
    out.push(("4-cycle".into(), rods(4, &[(0, 1), (1, 2), (2, 3), (3, 0)])));
    out
}

#[test]
fn svd_and_qr_agree_with_the_exact_verdict_at_generic_realizations() {
    let mut classes = std::collections::BTreeSet::new();
    for (name, p) in patterns() {
        let exact = check_exact(&p, 7).unwrap();
        classes.insert(exact.class.clone());
        // The reference patterns' known verdicts.
        let known = match name.as_str() {
            "K_{3,3}" | "rod prism" => Some(("component-dependent", Some(1))),
            "K_{2,4}" => Some(("rigid", Some(0))),
            "4-cycle" => Some(("flexible", Some(2))),
            _ => None,
        };
        if let Some(known) = known {
            assert_eq!((exact.class.as_str(), exact.dof), known, "{name}");
        }
        for method in [Ranker::Svd, Ranker::Qr] {
            for seed in 0..3 {
                let v = check_float(&p, method, seed).unwrap();
                assert_eq!(
                    (&v.class, v.dof),
                    (&exact.class, exact.dof),
                    "{name} {method:?} seed {seed}: {v:?}"
                );
                assert_eq!(v.method, method);
                let gap = v.gap.expect("a float verdict reports its gap");
                assert!(gap > RankRule::SVD.grey, "{name}: gap {gap}");
            }
        }
    }
    // The floats were checked on rigid, flexible and component-dependent patterns.
    assert_eq!(
        classes.into_iter().collect::<Vec<_>>(),
        ["component-dependent", "flexible", "rigid"]
    );
}

#[test]
fn the_trivial_motions_lie_in_every_float_kernel() {
    for (name, p) in patterns() {
        let inc = Incidence::new(&p);
        let (families, _) = family::families(&inc, 1, 5);
        assert!(!families.is_empty(), "{name}: no realization family");
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for fam in &families {
            for seed in 0..2 {
                let s = construction::construct_in(&inc, &fam.grouping, &Geometry::generic(), seed)
                    .unwrap();
                let f = float_framework(&inc, s, &mut rng).unwrap();
                // Rows have unit length: the residual is relative.
                let r = trivial_residual(&f);
                assert!(r < 1e-12, "{name}, {}: {r}", fam.grouping.describe(&inc));
            }
        }
    }
}

/// Exactly parallel directions, coincident points, collinear points
/// (`eps = 0` in floats): undecided or right, never a wrong decided verdict.
#[test]
fn degenerate_float_realizations_are_undecided_or_right() {
    let mut undecided = 0;
    for (name, p) in patterns() {
        let exact = check_exact(&p, 7).unwrap();
        for degeneracy in [
            Degeneracy::Parallel,
            Degeneracy::Coincident,
            Degeneracy::Collinear,
        ] {
            let geometry = Geometry {
                degeneracy,
                eps: 0.0,
            };
            for method in [Ranker::Svd, Ranker::Qr] {
                let v = check_float_in(&p, method, 1, &geometry).unwrap();
                match v.rigid {
                    None => {
                        undecided += 1;
                        assert_eq!(v.class, "undecided");
                        assert!(v.note.is_some());
                    }
                    Some(_) => assert_eq!(
                        (&v.class, v.dof),
                        (&exact.class, exact.dof),
                        "{name} {degeneracy:?} {method:?}: {v:?}"
                    ),
                }
            }
        }
    }
    assert!(undecided > 20, "only {undecided} undecided");
}

/// Over F_p, `eps = 0` builds the degenerate limit itself: two parallel
/// heavy rods put K_{2,4} in one plane, where it flexes.
#[test]
fn the_parallel_limit_of_k24_is_its_flexible_special_position() {
    let p = rods(6, &k(0..2, 2..6));
    let inc = Incidence::new(&p);
    let grouping = rgc::rigidity::incidence::Grouping::forced(&inc);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut dof = |eps: Fp| {
        let g = Geometry {
            degeneracy: Degeneracy::Parallel,
            eps,
        };
        let s = construction::construct_in(&inc, &grouping, &g, 3).unwrap();
        let f = rgc::rigidity::framework::framework(&inc, &s, &mut || Fp::random(&mut rng));
        rgc::rigidity::framework::dof(&f, rank_fp(&f.matrix))
    };
    assert_eq!(dof(Fp::new(10).pow(12).inv().unwrap()), 0);
    assert!(dof(Fp::ZERO) > 0);
}

fn matrix(rows: usize, cols: usize, data: &[f64]) -> Matrix<f64> {
    Matrix {
        rows,
        cols,
        data: data.to_vec(),
    }
}

#[test]
fn singular_values_and_qr_diagonal_are_descending_spectra() {
    let m = matrix(3, 3, &[0.0, 0.0, 1.0, 0.0, 3.0, 0.0, 2.0, 0.0, 0.0]);
    let s = singular_values(&m).unwrap();
    for (got, want) in s.iter().zip([3.0, 2.0, 1.0]) {
        assert!((got - want).abs() < 1e-14, "{s:?}");
    }
    // Rank 2: the third row is the sum of the first two.
    let r = matrix(
        3,
        4,
        &[1.0, 2.0, 0.5, -1.0, 0.3, -0.7, 2.0, 1.0, 1.3, 1.3, 2.5, 0.0],
    );
    let s = singular_values(&r).unwrap();
    let q = qr_diagonal(&r).unwrap();
    for v in [&s, &q] {
        assert_eq!(v.len(), 3);
        assert!(v.windows(2).all(|w| w[0] >= w[1]), "{v:?}");
        assert!(v[1] > 0.1 && v[2] < 1e-14, "{v:?}");
    }
    assert_eq!(rank_svd(&r).rank, Some(2));
    assert_eq!(rank_qr(&r).rank, Some(2));
    let mut bad = r.clone();
    bad.data[0] = f64::NAN;
    assert!(singular_values(&bad).is_none() && qr_diagonal(&bad).is_none());
    assert_eq!(rank_svd(&bad).rank, None);
}

#[test]
fn a_value_in_the_grey_zone_leaves_the_rank_undecided() {
    let rule = RankRule::SVD;
    let floor = 10.0 * f64::EPSILON;
    let decide = |last: f64| decide_rank(&[1.0, 0.5, last, 1e-17], 10, 4, rule);
    // Clear gaps either way.
    let clear = decide(1e-3);
    assert_eq!((clear.rank, clear.counted), (Some(3), 3));
    assert!((clear.gap - 1e-3 / f64::EPSILON).abs() < 1.0, "{clear:?}");
    let zero = decide(floor);
    assert_eq!((zero.rank, zero.counted), (Some(2), 2));
    // Between the tolerance and the top of the grey zone: undecided.
    let grey = decide(floor * rule.safety * 10.0);
    assert_eq!((grey.rank, grey.counted), (None, 3));
    assert!((grey.tolerance - floor * rule.safety).abs() < 1e-20);
    // Degenerate spectra.
    assert_eq!(decide_rank(&[0.0, 0.0], 2, 2, rule).rank, Some(0));
    assert_eq!(decide_rank(&[], 0, 0, rule).rank, Some(0));
    assert_eq!(decide_rank(&[1.0, f64::NAN], 2, 2, rule).rank, None);
}
