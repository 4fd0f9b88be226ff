//! The rigid motions truth must see in its matrix, by the shape of the box:
//! every rigid motion of a closed box, the translations of a slab or a
//! periodic box and no rotation where contacts or planes wrap; and truth
//! does not depend on how the rods are numbered.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rgc::contacts::Contact;
use rgc::graph::ContactGraph;
use rgc::math::Fp;
use rgc::rods::ensemble::Ensemble;
use rgc::rods::{Domain, Periodic, RodParams, RodSystem};
use rgc::truth::Offset;
use rgc::truth::matrix::{self, Parts};
use rgc::truth::planes::Planes;
use rgc::truth::realize::Realization;
use rgc::truth::{Decision, Topology, TruthOptions, order, planes, prune, realize, truth};

type Row = Vec<(u32, Fp)>;

/// The matrix of `topo` at one exact realization, with what built it.
fn build(topo: &Topology, seed: u64) -> (Planes, Parts, Realization, Vec<Row>) {
    let core = prune::two_core(topo.graph);
    let planes = planes::forced(topo, &core.active).expect("realizable planes");
    let order = order::order(topo, &planes, &core.active).expect("a construction order");
    let real = realize::build(
        topo,
        &planes,
        &core.active,
        &order,
        &mut ChaCha8Rng::seed_from_u64(seed),
    )
    .expect("a generic realization");
    let parts = matrix::parts(&planes, &core.active);
    let rows = matrix::rows(topo, &planes, &parts, &real, &matrix::StrainColumns::none());
    (planes, parts, real, rows)
}

/// The rows that `x` does not satisfy exactly.
fn violated(rows: &[Row], x: &[Fp]) -> Vec<usize> {
    (0..rows.len())
        .filter(|&k| {
            !rows[k]
                .iter()
                .fold(Fp::ZERO, |a, &(c, v)| a + v * x[c as usize])
                .is_zero()
        })
        .collect()
}

const ZERO: [Fp; 3] = [Fp::ZERO; 3];

fn random3(rng: &mut ChaCha8Rng) -> [Fp; 3] {
    [0; 3].map(|_| Fp::random(rng))
}

fn unit(k: usize) -> [Fp; 3] {
    let mut v = ZERO;
    v[k] = Fp::ONE;
    v
}

/// A generated system of the paper's rods (gamma 23) in a cube of side
/// `box_len` with the periodic axes `periodic`.
fn generated(
    box_len: f64,
    rho: f64,
    periodic: Periodic,
    seed: u64,
) -> (RodSystem, Vec<Contact>, ContactGraph, Vec<Offset>) {
    let mut e = Ensemble::paper(RodParams::new(23.0, box_len, rho).unwrap());
    e.domain = Domain::new([box_len; 3], periodic).unwrap();
    let system = e.generate(seed).unwrap();
    let contacts = rgc::contacts::detect(&system);
    let graph = ContactGraph::from_contacts(system.len(), &contacts);
    let shifts = contacts.iter().map(|c| c.shift).collect();
    (system, contacts, graph, shifts)
}

/// A motion that is no rigid motion (one column moved) violates some row:
/// the kernel checks below can fail.
fn assert_bent_fails(rows: &[Row], parts: &Parts, real: &Realization, rng: &mut ChaCha8Rng) {
    let mut bent = matrix::rigid_motion(parts, real, random3(rng), random3(rng));
    let k = bent.len() - 1;
    bent[k] = bent[k] + Fp::ONE;
    assert!(!violated(rows, &bent).is_empty(), "a bent motion passed");
}

/// Walls hold nothing: in a closed box every rigid motion, rotations
/// included, is in the kernel of the rigidity matrix.
#[test]
fn rotations_of_a_closed_box_are_in_the_kernel() {
    for seed in [2, 3] {
        let (system, _, graph, shifts) = generated(3.0, 38.0, Periodic::None, seed);
        let topo = Topology::of_domain(&graph, &shifts, &system.domain);
        assert!(topo.shifts.is_none(), "a closed box is a finite framework");
        let (_, parts, real, rows) = build(&topo, seed);
        assert!(parts.count > 10 && rows.len() > 100, "a real core");
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for k in 0..3 {
            let r = matrix::rigid_motion(&parts, &real, unit(k), ZERO);
            assert_eq!(
                violated(&rows, &r),
                Vec::<usize>::new(),
                "rotation about axis {k}"
            );
        }
        let (w, t) = (random3(&mut rng), random3(&mut rng));
        assert!(violated(&rows, &matrix::rigid_motion(&parts, &real, w, ZERO)).is_empty());
        assert!(violated(&rows, &matrix::rigid_motion(&parts, &real, w, t)).is_empty());
        assert_bent_fails(&rows, &parts, &real, &mut rng);
        // Six independent rigid motions lie in the kernel: truth's rank
        // leaves at least six columns free, and it counts six as trivial.
        let t = truth(&topo, TruthOptions::seeded(seed));
        assert_eq!(
            t.outcome.decision(),
            Decision::Exact,
            "{:?}",
            t.outcome.reason()
        );
        assert_eq!(t.trivial_motions, 6);
        assert!(t.columns - t.outcome.rank().unwrap() >= 6, "{t:?}");
    }
}

/// A slab (periodic along x and y, walls at z = 0 and z = L) keeps the
/// three translations; a rotation about z would move the images of a
/// contact across the box apart.
#[test]
fn translations_of_a_slab_are_in_the_kernel_and_rotations_are_not() {
    for seed in [2, 3] {
        let (system, _, graph, shifts) = generated(3.0, 38.0, Periodic::Xy, seed);
        let topo = Topology::of_domain(&graph, &shifts, &system.domain);
        assert!(topo.shifts.is_some(), "a slab is periodic");
        assert!(shifts.iter().all(|s| s[2] == 0), "nothing crosses a wall");
        assert!(
            shifts.iter().any(|s| *s != [0; 3]),
            "contacts across the periodic sides"
        );
        let (_, parts, real, rows) = build(&topo, seed);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for k in 0..3 {
            let t = matrix::rigid_motion(&parts, &real, ZERO, unit(k));
            assert_eq!(
                violated(&rows, &t),
                Vec::<usize>::new(),
                "translation along axis {k}"
            );
        }
        let t = random3(&mut rng);
        assert!(violated(&rows, &matrix::rigid_motion(&parts, &real, ZERO, t)).is_empty());
        for k in 0..3 {
            let r = matrix::rigid_motion(&parts, &real, unit(k), ZERO);
            assert!(!violated(&rows, &r).is_empty(), "rotation about axis {k}");
        }
        assert_bent_fails(&rows, &parts, &real, &mut rng);
    }
}

/// In a periodic box with a rigid cluster wrapping it, no rotation is a
/// motion: it violates the rows of the contacts across the box, which the
/// same graph taken as a finite framework does not have.
#[test]
fn a_rotation_breaks_a_periodic_system_with_a_wrapping_cluster() {
    let (system, contacts, graph, shifts) = generated(3.0, 44.0, Periodic::Xyz, 4);
    let view = rgc::network::View {
        system: &system,
        contacts: &contacts,
        graph: &graph,
        shifts: &shifts,
    };
    let t = rgc::truth::of_system(
        view,
        rgc::spanning::Criterion::Wrap,
        TruthOptions::default(),
    );
    assert_eq!(t.spanning, Some(true), "a true cluster wraps the box");
    let topo = Topology::periodic(&graph, &shifts).unwrap();
    let (_, parts, real, rows) = build(&topo, 4);
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let t = random3(&mut rng);
    assert!(violated(&rows, &matrix::rigid_motion(&parts, &real, ZERO, t)).is_empty());
    for k in 0..3 {
        let r = matrix::rigid_motion(&parts, &real, unit(k), ZERO);
        let bad = violated(&rows, &r);
        assert!(!bad.is_empty(), "rotation about axis {k}");
    }
    // The bare graph closes its loops through the box on themselves: there
    // every rotation is a motion.
    let finite = Topology::finite(&graph);
    let (_, parts, real, rows) = build(&finite, 4);
    let r = matrix::rigid_motion(&parts, &real, random3(&mut rng), ZERO);
    assert!(violated(&rows, &r).is_empty());
}

/// A strip of rod triangles (rod i touches i+1 and i+2, cyclically) whose
/// last triangles close through the box along x: one forced plane class
/// that contains the lattice direction x. Its only rows are `omega x w = 0`,
/// which every rotation about another axis breaks.
#[test]
fn a_plane_wrapping_the_box_fixes_every_rotation_but_about_its_direction() {
    let m = 6u32;
    let mut edges = Vec::new();
    let mut shifts: Vec<Offset> = Vec::new();
    for i in 0..m {
        for step in [1, 2] {
            let j = (i + step) % m;
            // Rod i sees rod j one box along x when the strip wraps past the end.
            let wraps = i + step >= m;
            let s = if wraps { [1, 0, 0] } else { [0; 3] };
            edges.push([i, j]);
            shifts.push(s);
        }
    }
    let graph = ContactGraph::new(m as usize, edges).unwrap();
    let topo = Topology::periodic(&graph, &shifts).unwrap();
    let (planes, parts, real, rows) = build(&topo, 1);
    assert_eq!(planes.classes.len(), 1, "{planes:?}");
    assert_eq!(planes.classes[0].rods.len(), m as usize);
    // The direction x, whichever its sign.
    let wraps = &planes.classes[0].wraps;
    assert!(wraps == &[[1, 0, 0]] || wraps == &[[-1, 0, 0]], "{wraps:?}");
    assert_eq!(parts.count, 1);
    // omega x (+-1, 0, 0) = +-(0, omega_z, -omega_y): two rows.
    assert_eq!(rows.len(), 2, "{rows:?}");
    for k in 0..3 {
        let t = matrix::rigid_motion(&parts, &real, ZERO, unit(k));
        assert!(violated(&rows, &t).is_empty(), "translation along axis {k}");
    }
    let about_x = matrix::rigid_motion(&parts, &real, unit(0), ZERO);
    assert!(violated(&rows, &about_x).is_empty());
    for k in [1, 2] {
        let r = matrix::rigid_motion(&parts, &real, unit(k), ZERO);
        assert_eq!(violated(&rows, &r).len(), 1, "rotation about axis {k}");
    }
    // So the band keeps one motion: turning about x.
    let t = truth(&topo, TruthOptions::default());
    assert_eq!(
        (t.outcome.decision(), t.columns, t.outcome.rank()),
        (Decision::Exact, 6, Some(2))
    );
    assert_eq!((t.trivial_motions, t.outcome.dof()), (3, Some(1)));
    assert_eq!(t.clusters.len(), 1);
    assert_eq!(t.clusters[0].rods, (0..m).collect::<Vec<_>>());
}

/// A permutation of `0..n` (splitmix64 Fisher–Yates).
fn permutation(n: usize, seed: u64) -> Vec<u32> {
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut p: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        p.swap(i, (next() % (i as u64 + 1)) as usize);
    }
    p
}

/// The contacts with rod `r` renamed `p[r]`, in a shuffled order, each
/// written lower rod first: an edge turned round sees the other rod from the
/// other side, so its image shift changes sign.
fn relabel(
    graph: &ContactGraph,
    shifts: &[Offset],
    p: &[u32],
    seed: u64,
) -> (ContactGraph, Vec<Offset>) {
    let order = permutation(graph.n_edges(), seed);
    let mut edges = Vec::new();
    let mut moved = Vec::new();
    for &e in &order {
        let [a, b] = graph.edges()[e as usize];
        let s = shifts[e as usize];
        let (a, b) = (p[a as usize], p[b as usize]);
        if a < b {
            edges.push([a, b]);
            moved.push(s);
        } else {
            edges.push([b, a]);
            moved.push(s.map(|k| -k));
        }
    }
    (ContactGraph::new(graph.n_nodes(), edges).unwrap(), moved)
}

/// Clusters as sorted sets of rods, in a canonical order.
fn canonical(mut clusters: Vec<Vec<u32>>) -> Vec<Vec<u32>> {
    for c in &mut clusters {
        c.sort_unstable();
    }
    clusters.sort();
    clusters
}

/// Truth does not depend on the numbering of rods or the order of
/// contacts: the same DOF, rank and clusters (mapped back) on a periodic
/// system and on a permutation of it.
#[test]
fn truth_is_the_same_under_a_relabelling_of_the_rods() {
    for seed in [1, 2, 3] {
        let (_, _, graph, shifts) = generated(4.0, 38.0, Periodic::Xyz, seed);
        let topo = Topology::periodic(&graph, &shifts).unwrap();
        let t = truth(&topo, TruthOptions::seeded(seed));
        assert_eq!(
            t.outcome.decision(),
            Decision::Exact,
            "{:?}",
            t.outcome.reason()
        );
        assert!(
            t.largest_cluster() > 10,
            "seed {seed}: a cluster worth comparing"
        );
        assert!(
            shifts.iter().filter(|s| **s != [0; 3]).count() > 10,
            "contacts across the box"
        );
        let p = permutation(graph.n_nodes(), 1000 + seed);
        let (moved, moved_shifts) = relabel(&graph, &shifts, &p, 2000 + seed);
        let turned = (0..graph.n_edges())
            .filter(|&e| {
                let [a, b] = graph.edges()[e];
                p[a as usize] > p[b as usize]
            })
            .count();
        assert!(turned > 0, "some edges are turned round");
        let mt = truth(
            &Topology::periodic(&moved, &moved_shifts).unwrap(),
            TruthOptions::seeded(seed + 7),
        );
        assert_eq!(
            mt.outcome.decision(),
            Decision::Exact,
            "{:?}",
            mt.outcome.reason()
        );
        assert_eq!(
            (mt.outcome.dof(), mt.outcome.rank()),
            (t.outcome.dof(), t.outcome.rank()),
            "seed {seed}"
        );
        assert_eq!(
            (mt.parts, mt.rows, mt.plane_classes, mt.core_rods),
            (t.parts, t.rows, t.plane_classes, t.core_rods),
            "seed {seed}"
        );
        let mut back = vec![0u32; p.len()];
        for (r, &q) in p.iter().enumerate() {
            back[q as usize] = r as u32;
        }
        let mapped: Vec<Vec<u32>> = mt
            .clusters
            .iter()
            .map(|c| c.rods.iter().map(|&q| back[q as usize]).collect())
            .collect();
        let original: Vec<Vec<u32>> = t.clusters.iter().map(|c| c.rods.clone()).collect();
        assert_eq!(canonical(mapped), canonical(original), "seed {seed}");
    }
}
