//! Numerical projection onto realization families (MODEL §3): it finds
//! realizations of families that do have exact constructions (and agrees
//! with the exact verdict there), and it decides the rods-only candidates
//! whose most generic family has no exact construction. Those candidates on
//! 9 rods are pinned in `graphs/undecided-9.g6`, written by the ignored
//! `collect_undecided_9` and found afresh by `undecided_candidates_are_found_afresh`.

use std::path::Path;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use rgc::engine::examples;
use rgc::enumerate::{GraphFilter, connected_small_graphs};
use rgc::graph::ContactGraph;
use rgc::graph::io::{read_graph6_file, to_graph6};
use rgc::math::vec3::{distance, dot, norm, sub};
use rgc::pattern::Pattern;
use rgc::rigidity::construction::Realization;
use rgc::rigidity::family;
use rgc::rigidity::framework::float_framework;
use rgc::rigidity::incidence::{Grouping, Incidence};
use rgc::rigidity::projection::{float_local_dimension, project};
use rgc::rigidity::verdict::float_spectrum;
use rgc::rigidity::{Ranker, Verdict, check_exact, check_float};

fn rods(n: usize, edges: &[(u32, u32)]) -> Pattern {
    let g = ContactGraph::new(n, edges.iter().map(|&(a, b)| [a, b]).collect()).unwrap();
    Pattern::from_graph(&g).unwrap()
}

fn k(a: std::ops::Range<u32>, b: std::ops::Range<u32>) -> Vec<(u32, u32)> {
    a.flat_map(|x| b.clone().map(move |y| (x, y))).collect()
}

fn prism() -> Pattern {
    rods(6, &examples::PRISM)
}

fn example(name: &str) -> Pattern {
    let e = examples::all()
        .into_iter()
        .find(|e| e.name == name)
        .unwrap();
    Pattern::from_host(&e.graph(), &e.bodies).unwrap()
}

/// The largest relative violation of the incidences of `grouping` at `s`:
/// contact points off their lines, group contact points off their planes.
fn violation(inc: &Incidence, grouping: &Grouping, s: &Realization<f64>) -> f64 {
    let mut worst: f64 = 0.0;
    for (c, &[a, b]) in inc.contact_lines.iter().enumerate() {
        for l in [a, b] {
            worst = worst.max(distance(&s.lines[l], s.points[c]));
        }
    }
    for (g, pl) in grouping.groups.iter().zip(&s.group_planes) {
        let pl = pl.unwrap();
        let n = pl.normal();
        for &l in g {
            for &c in &inc.line_contacts[l] {
                worst = worst.max(dot(n, sub(s.points[c], pl.q)).abs() / norm(n));
            }
        }
    }
    worst
}

/// Degrees of freedom of the float rigidity matrix at a projected sample,
/// when its rank is decided.
fn float_dof(inc: &Incidence, s: &Realization<f64>) -> Option<usize> {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let f = float_framework(inc, s.clone(), &mut rng)?;
    let (values, noise) = float_spectrum(&f, Ranker::Svd);
    let fr = rgc::math::float::decide_rank_above(&values, noise, rgc::math::float::RankRule::SVD);
    Some(rgc::rigidity::framework::dof(&f, fr.rank?))
}

#[test]
fn projection_finds_families_that_have_exact_constructions() {
    let cases = [
        ("K_{2,4}", rods(6, &k(0..2, 2..6))),
        ("rod prism", prism()),
        ("3D6", example("3D6 K_{2,4} of rods")),
        ("K_{3,3}", rods(6, &k(0..3, 3..6))),
    ];
    for (name, p) in cases {
        let inc = Incidence::new(&p);
        let forced = Grouping::forced(&inc);
        let exact = check_exact(&p, 7).unwrap();
        let on_forced = exact
            .components
            .iter()
            .find(|c| c.built == forced.describe(&inc))
            .unwrap_or_else(|| panic!("{name}: {exact:?}"));
        for seed in 0..3 {
            let s = project(&inc, &forced, seed).unwrap_or_else(|| panic!("{name} seed {seed}"));
            assert!(violation(&inc, &forced, &s) < 1e-10, "{name} seed {seed}");
            let dim = float_local_dimension(&inc, &forced.groups, &s.points);
            assert_eq!(dim, Some(on_forced.dimension), "{name} seed {seed}");
            assert_eq!(
                float_dof(&inc, &s),
                Some(on_forced.dof),
                "{name} seed {seed}"
            );
        }
    }
}

#[test]
fn projection_is_deterministic_for_a_seed() {
    let p = prism();
    let inc = Incidence::new(&p);
    let forced = Grouping::forced(&inc);
    let a = project(&inc, &forced, 5).unwrap();
    let b = project(&inc, &forced, 5).unwrap();
    assert_eq!(a.points, b.points);
}

#[test]
fn exact_verdicts_without_projection_are_unchanged() {
    for p in [rods(6, &k(0..2, 2..6)), prism(), rods(6, &k(0..3, 3..6))] {
        let v = check_exact(&p, 7).unwrap();
        assert!(v.components.iter().all(|c| !c.projected));
        let json = serde_json::to_string(&v).unwrap();
        assert!(!json.contains("projected"), "{json}");
        let float = check_float(&p, Ranker::Svd, 7).unwrap();
        assert_eq!((float.class, float.dof), (v.class, v.dof));
    }
}

/// The rods-only candidates on 9 rods (connected, minimum degree 2,
/// Maxwell) that exact constructions leave undecided, one graph6 line each
/// in enumeration order. Written by [`collect_undecided_9`] (`cargo test
/// --release -- --ignored collect_undecided_9`), which runs the same search
/// as [`undecided_candidates_are_found_afresh`]; see `graphs/README.md`.
const UNDECIDED_9: &str = "graphs/undecided-9.g6";

/// Whether the pattern was undecided before projection: its most generic
/// family has no exact construction, and every exactly built component is rigid.
fn undecided_without_projection(p: &Pattern, v: &Verdict) -> bool {
    let inc = Incidence::new(p);
    let (families, forced_built) = family::families(&inc, 2, 7);
    let flags = family::components(&families);
    !forced_built
        && flags
            .iter()
            .zip(&v.components)
            .all(|(&flag, c)| !flag || c.dof == 0)
}

/// Searches every candidate on 9 rods (196,904) for those exact
/// constructions leave undecided, in enumeration order. One construction of
/// the forced grouping screens them first (it succeeds on all but 23, and
/// only those get the family search and the exact verdict); the seed is the
/// one `family::families(_, _, 7)` builds its first forced sample with.
fn search_undecided_9() -> Vec<(String, Pattern)> {
    use rayon::prelude::*;
    use rgc::rigidity::construction::construct;
    let filter = GraphFilter::maxwell_rods(9).with_min_degree(2);
    let graphs = connected_small_graphs(9, &filter).unwrap();
    assert_eq!(graphs.len(), 196_904);
    graphs
        .par_iter()
        .filter_map(|g| {
            let g = g.to_contact_graph();
            let p = Pattern::from_graph(&g).unwrap();
            let inc = Incidence::new(&p);
            if construct(&inc, &Grouping::forced(&inc), 1007).is_ok() {
                return None;
            }
            let v = check_exact(&p, 7).unwrap();
            undecided_without_projection(&p, &v).then(|| (to_graph6(&g), p))
        })
        .collect()
}

/// Writes `graphs/undecided-9.g6` from a fresh search.
#[test]
#[ignore = "writes graphs/undecided-9.g6 (the file the projection tests read); run with --ignored to regenerate it"]
fn collect_undecided_9() {
    let mut out = String::new();
    for (g6, _) in search_undecided_9() {
        out.push_str(&g6);
        out.push('\n');
    }
    std::fs::write(UNDECIDED_9, out).unwrap();
}

/// The candidates on 9 rods that exact constructions leave undecided.
fn undecided_9() -> Vec<(String, Pattern)> {
    read_graph6_file(Path::new(UNDECIDED_9))
        .unwrap()
        .iter()
        .map(|g| (to_graph6(g), Pattern::from_graph(g).unwrap()))
        .collect()
}

/// Of the 11, projection finds the forced family of 10 with a clear float
/// rank (8 rigid on it, 2 not: component-dependent); on the last every start
/// converges to coincident contact points, so it stays undecided.
fn check_projected(candidates: &[(String, Pattern)]) {
    assert_eq!(candidates.len(), 11);
    let mut counts: std::collections::BTreeMap<String, usize> = Default::default();
    for (g6, p) in candidates {
        let v = check_exact(p, 7).unwrap();
        assert!(undecided_without_projection(p, &v), "{g6}");
        let real: Vec<_> = v.components.iter().filter(|c| c.component).collect();
        let projected: Vec<_> = v.components.iter().filter(|c| c.projected).collect();
        assert!(projected.len() <= 1, "{g6}: {v:?}");
        match v.class.as_str() {
            "rigid" => assert!(real.iter().all(|c| c.dof == 0), "{g6}: {v:?}"),
            "flexible" => assert!(real.iter().all(|c| c.dof > 0), "{g6}: {v:?}"),
            "component-dependent" => {
                assert!(real.iter().any(|c| c.dof == 0) && real.iter().any(|c| c.dof > 0))
            }
            _ => {
                assert_eq!(v.class, "undecided");
                assert!(projected.is_empty(), "{g6}: {v:?}");
                assert!(
                    v.note.as_deref().unwrap().contains("projection"),
                    "{g6}: {v:?}"
                );
            }
        }
        if v.class != "undecided" {
            assert_eq!(projected.len(), 1, "{g6}: {v:?}");
            assert!(projected[0].built.ends_with("numerical projection"));
            assert!(projected[0].dimension <= 3 * Incidence::new(p).n_contacts());
            assert_eq!(v.dof, real.iter().map(|c| c.dof).max(), "{g6}");
        }
        let inc = Incidence::new(p);
        let forced = Grouping::forced(&inc);
        if let Some(s) = project(&inc, &forced, 7) {
            assert!(violation(&inc, &forced, &s) < 1e-10, "{g6}");
        }
        let again = check_exact(p, 7).unwrap();
        assert_eq!(again, v, "{g6}: not deterministic");
        *counts.entry(v.class.clone()).or_default() += 1;
    }
    let count = |class: &str| counts.get(class).copied().unwrap_or(0);
    assert_eq!(
        [
            count("rigid"),
            count("flexible"),
            count("component-dependent"),
            count("undecided")
        ],
        [8, 0, 2, 1],
        "{counts:?}"
    );
}

#[test]
fn projection_decides_the_undecided_candidates_on_9_rods() {
    check_projected(&undecided_9());
}

/// The search behind `graphs/undecided-9.g6`, run afresh over every
/// candidate on 9 rods: it finds the pinned candidates, in the same order,
/// and they behave as the pinned ones do.
#[test]
fn undecided_candidates_are_found_afresh() {
    let fresh = search_undecided_9();
    let g6 = |c: &[(String, Pattern)]| c.iter().map(|(g, _)| g.clone()).collect::<Vec<_>>();
    assert_eq!(g6(&fresh), g6(&undecided_9()));
    check_projected(&fresh);
}

#[test]
fn projected_verdicts_do_not_depend_on_the_seed() {
    for (g6, p) in undecided_9() {
        let a = check_exact(&p, 7).unwrap();
        for seed in [0, 1, 2, 3, 4, 5, 99] {
            let b = check_exact(&p, seed).unwrap();
            assert_eq!((&a.class, a.dof), (&b.class, b.dof), "{g6} seed {seed}");
        }
    }
}
