//! The second twin's check: the first twin's rigid clusters contracted to
//! one part each keep the kernel's dimension, and a set that is not rigid
//! does not.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rgc::math::{Q2, sparse};
use rgc::spanning::Criterion;
use rgc::truth::contract::{self, Contraction};
use rgc::truth::matrix::{self, Parts, WIDTH};
use rgc::truth::{Topology, TruthOptions, order, planes, prune, realize};

/// A generated periodic system, its truth and a fresh realization over the
/// second prime: the parts, the contact shifts and the matrix.
struct Case {
    graph: rgc::graph::ContactGraph,
    shifts: Vec<[i32; 3]>,
    clusters: Vec<Vec<u32>>,
    dof: usize,
}

fn case(gamma: f64, box_len: f64, rho: f64, seed: u64) -> Case {
    let net = crate::truth::system(gamma, box_len, rho, seed);
    let t = rgc::truth::of_system(net.view(), Criterion::Wrap, TruthOptions::default());
    crate::truth::assert_exact_twins(&t, "the system");
    assert_eq!(t.spanning, Some(true), "a spanning cluster crosses the box");
    Case {
        shifts: net.shifts,
        clusters: t.clusters.into_iter().map(|c| c.rods).collect(),
        dof: t.outcome.dof().unwrap(),
        graph: net.graph,
    }
}

/// The kernel dimensions of the whole matrix and of `contracted(parts)`
/// at one realization over the second prime. The whole kernel is checked
/// against truth's DOF on the way (less the pruned rods' motions, plus the
/// 3 translations).
fn kernels(
    c: &Case,
    contracted: impl Fn(&Topology, &Parts) -> Contraction,
) -> (usize, usize, Contraction) {
    let topo = Topology::periodic(&c.graph, &c.shifts).unwrap();
    let core = prune::two_core(&c.graph);
    let planes = planes::forced(&topo, &core.active).unwrap();
    let order = order::order(&topo, &planes, &core.active).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let real = realize::build::<Q2>(&topo, &planes, &core.active, &order, &mut rng).unwrap();
    let parts = matrix::parts(&planes, &core.active);
    let rows = matrix::rows(
        &topo,
        &planes,
        &parts,
        &real,
        &matrix::StrainColumns::none(),
    );
    let whole = sparse::rank(&rows, sparse::Layout::plain(parts.count, WIDTH), None).unwrap();
    assert_eq!(
        parts.count * WIDTH - whole.rank + core.pruned_motions(),
        c.dof + 3
    );
    let k = contracted(&topo, &parts);
    let small = sparse::rank(
        &k.rows(&real, &rows),
        sparse::Layout::plain(k.count, WIDTH),
        None,
    )
    .unwrap();
    (
        parts.count * WIDTH - whole.rank,
        k.count * WIDTH - small.rank,
        k,
    )
}

#[test]
fn contracting_true_clusters_keeps_the_kernel() {
    for (gamma, box_len, rho, seed) in [(23.0, 4.0, 38.0, 3), (98.0, 3.0, 170.0, 1)] {
        let c = case(gamma, box_len, rho, seed);
        let (whole, small, k) = kernels(&c, |topo, parts| {
            contract::of_clusters(topo, parts, &c.clusters)
        });
        assert_eq!(whole, small, "gamma {gamma}: {} bodies", k.bodies);
        // The contraction did something, across the periodic boundary too.
        assert!(k.bodies > 0 && k.crossing > 0, "gamma {gamma}: {k:?}");
    }
}

#[test]
fn contracting_a_set_that_is_not_rigid_shrinks_the_kernel() {
    let c = case(23.0, 4.0, 38.0, 3);
    // Two touching rods, each a part of its own, that share no cluster.
    let together = |a: u32, b: u32| c.clusters.iter().any(|k| k.contains(&a) && k.contains(&b));
    let (whole, small, k) = kernels(&c, |topo, parts| {
        let own =
            |r: u32| parts.owner[r as usize].is_some_and(|(p, _)| p as usize >= parts.classes);
        let (a, b) = c
            .graph
            .edges()
            .iter()
            .map(|&[a, b]| (a, b))
            .find(|&(a, b)| own(a) && own(b) && !together(a, b))
            .expect("a flexible contact between two rod parts");
        contract::of_clusters(topo, parts, &[vec![a, b]])
    });
    assert_eq!(k.bodies, 1);
    assert!(small < whole, "{small} against {whole}");
    // And the true clusters themselves keep it, at this realization too.
    let (whole, small, _) = kernels(&c, |topo, parts| {
        contract::of_clusters(topo, parts, &c.clusters)
    });
    assert_eq!(whole, small);
}
