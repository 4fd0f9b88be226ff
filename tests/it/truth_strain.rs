//! The strain rank (MODEL §10): which strains of the box a system resists,
//! on hand-made periodic systems whose answers follow from the flexible
//! torus by hand. A rigid body containing the lattice vector `w` moves its
//! image by `omega x w`, which a strain must match: `E w = omega x w`, so
//! it resists `w.E w` (the stretch along `w`) and nothing else by itself; a
//! rigid body whose periods span space forces `E` antisymmetric, a rigid
//! rotation: it resists all six.

use rgc::graph::ContactGraph;
use rgc::truth::{Decision, Offset, Strain, Topology, Truth, TruthOptions, planes, prune, truth};

/// Edges of a strip of six rod triangles (rod `k` touches rods `k + 1`
/// and `k + 2`, cyclically), rods `rods`, whose contacts past the end close
/// through the box along `w`: one forced plane class wrapping along `w`
/// (a zero `w` closes it on itself, a finite band).
fn strip(rods: [u32; 6], w: Offset, edges: &mut Vec<[u32; 2]>, shifts: &mut Vec<Offset>) {
    for i in 0..6 {
        for step in [1, 2] {
            let j = (i + step) % 6;
            edges.push([rods[i], rods[j]]);
            shifts.push(if i + step >= 6 { w } else { [0; 3] });
        }
    }
}

/// A system of strips, each given by its rods and direction, and extra
/// contacts (rod pairs in one cell).
fn system(
    n: usize,
    strips: &[([u32; 6], Offset)],
    extra: &[[u32; 2]],
) -> (ContactGraph, Vec<Offset>) {
    let (mut edges, mut shifts) = (Vec::new(), Vec::new());
    for &(rods, w) in strips {
        strip(rods, w, &mut edges, &mut shifts);
    }
    for &e in extra {
        edges.push(e);
        shifts.push([0; 3]);
    }
    (ContactGraph::new(n, edges).unwrap(), shifts)
}

/// Truth of `topo`, exact with agreeing twins.
fn exact(topo: &Topology) -> Truth {
    let t = truth(topo, TruthOptions::default());
    assert_eq!(
        (t.outcome.decision(), t.outcome.reason()),
        (Decision::Exact, None)
    );
    t
}

/// The strain rank, the strains considered and those resisted alone.
fn strains(t: &Truth) -> (Option<u8>, Vec<Strain>, Vec<Strain>) {
    let s = t.strains.clone().expect("truth reports its strains");
    (s.rank, s.considered, s.resisted)
}

use Strain::{Xx, Xy, Xz, Yy, Yz, Zz};

/// Each of the six strains names its column and its axes.
#[test]
fn the_six_strains_by_name() {
    let names: Vec<String> = Strain::ALL.iter().map(Strain::to_string).collect();
    assert_eq!(names, ["xx", "yy", "zz", "yz", "xz", "xy"]);
    assert_eq!(serde_json::to_string(&Xz).unwrap(), "\"xz\"");
    assert_eq!(Strain::of_box([true; 3]), Strain::ALL);
    assert_eq!(Strain::of_box([true, true, false]), [Xx, Yy, Xy]);
    assert_eq!(Strain::of_box([false; 3]), []);
}

/// One strip wrapping along x: its plane is a rigid body containing the
/// lattice vector x, so `E x = omega x x` and `x.E x = e_xx = 0`, while
/// `e_xy = omega_z` and `e_xz = -omega_y` turn the strip: strain rank 1,
/// `xx` alone. Along y or z it is `yy` or `zz`; along the diagonal
/// `(1, 1, 0)`, `e_xx + e_yy + 2 e_xy = 0`: rank 1 again, and each of the
/// three strains in it is resisted alone; permuting the axes permutes them.
#[test]
fn a_strip_wrapping_one_direction_resists_its_stretch_alone() {
    let cases: [(Offset, &[Strain]); 6] = [
        ([1, 0, 0], &[Xx]),
        ([0, 1, 0], &[Yy]),
        ([0, 0, -1], &[Zz]),
        ([1, 1, 0], &[Xx, Yy, Xy]),
        ([0, 1, 1], &[Yy, Zz, Yz]),
        ([1, 0, 1], &[Xx, Zz, Xz]),
    ];
    for (w, resisted) in cases {
        let (graph, shifts) = system(6, &[([0, 1, 2, 3, 4, 5], w)], &[]);
        let t = exact(&Topology::periodic(&graph, &shifts).unwrap());
        assert_eq!((t.columns, t.outcome.dof()), (6, Some(1)), "{w:?}");
        assert_eq!(
            strains(&t),
            (Some(1), Strain::ALL.to_vec(), resisted.to_vec()),
            "{w:?}"
        );
    }
}

/// The same strip closed on itself (no contact crosses the box) and the
/// x strip's rods with no triangle (a ring of single contacts, each
/// crossing the box along x, fluid): nothing resists a strain.
#[test]
fn a_fluid_and_a_system_that_wraps_nothing_resist_no_strain() {
    let (graph, shifts) = system(6, &[([0, 1, 2, 3, 4, 5], [0; 3])], &[]);
    let t = exact(&Topology::periodic(&graph, &shifts).unwrap());
    assert_eq!(t.clusters.len(), 1, "one rigid band");
    assert_eq!(strains(&t), (Some(0), Strain::ALL.to_vec(), vec![]));
    // Six rods in a ring, each touching the next in the cell along x: a
    // 2-core of degree-2 rods, every one free to turn about its contacts.
    let edges: Vec<[u32; 2]> = (0..6).map(|i| [i, (i + 1) % 6]).collect();
    let shifts: Vec<Offset> = (0..6).map(|i| [i32::from(i == 5), 0, 0]).collect();
    let graph = ContactGraph::new(6, edges).unwrap();
    let t = exact(&Topology::periodic(&graph, &shifts).unwrap());
    assert!(t.clusters.is_empty());
    assert_eq!(strains(&t), (Some(0), Strain::ALL.to_vec(), vec![]));
}

/// Three strips along x, y and z, strip y sharing rod 0 with strip x and
/// strip z sharing rod 1 with it (two hinges, about lines `d1`, `d2`). In
/// the fixed box a wrapping strip turns only about its own direction, so
/// the hinges lock: one rigid cluster whose periods span space. Under
/// strain they open: `omega_y = omega_x + a d1`, `omega_z = omega_x + b
/// d2`. Each strip holds its stretch (`e_xx = e_yy = e_zz = 0`), and the
/// shears must be symmetric: `e_xy = omega_x,z = -omega_y,z`, `e_xz =
/// -omega_x,y = omega_z,y`, `e_yz = omega_y,x = -omega_z,x`, three
/// equations in the five unknowns `(omega_x, a, b)`, whose solutions give
/// the shears `(-a d1_z, b d2_y, a d1_x - b d2_x) / 2`: two free, strain
/// rank 4, yet no shear is free alone. A brace rod touching strips x and
/// y once each makes them one body (`a = 0`): rank 5. A second one
/// between strips y and z (`b = 0`): one body, all six. A cluster that
/// wraps in every direction is not yet a solid.
#[test]
fn strips_joined_by_hinges_and_braces_resist_four_five_and_six_strains() {
    let x = [0, 1, 2, 3, 4, 5];
    let y = [0, 6, 7, 8, 9, 10];
    let z = [1, 11, 12, 13, 14, 15];
    let strips = [(x, [1, 0, 0]), (y, [0, 1, 0]), (z, [0, 0, 1])];
    let cases: [(&[[u32; 2]], u8); 3] = [
        (&[], 4),
        (&[[3, 16], [8, 16]], 5),
        (&[[3, 16], [8, 16], [9, 17], [13, 17]], 6),
    ];
    for (braces, rank) in cases {
        let n = 16 + braces.len() / 2;
        let (graph, shifts) = system(n, &strips, braces);
        let topo = Topology::periodic(&graph, &shifts).unwrap();
        let core = prune::two_core(&graph);
        let planes = planes::forced(&topo, &core.active).unwrap();
        assert_eq!(planes.classes.len(), 3, "{braces:?}");
        let t = exact(&topo);
        assert_eq!(t.outcome.dof(), Some(0), "{braces:?}");
        assert_eq!(t.clusters.len(), 1, "{braces:?}: {:?}", t.clusters);
        assert_eq!(t.clusters[0].rods, (0..n as u32).collect::<Vec<_>>());
        assert_eq!(
            strains(&t),
            (Some(rank), Strain::ALL.to_vec(), Strain::ALL.to_vec()),
            "{braces:?}"
        );
    }
}

/// Six separate strips along x, y, z, x + y, x + z and y + z: no cluster
/// spans more than one direction, yet the six stretches `w.E w` they hold
/// are independent forms: the box resists every strain.
#[test]
fn six_separate_strips_resist_every_strain() {
    let dirs: [Offset; 6] = [
        [1, 0, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 1, 0],
        [1, 0, 1],
        [0, 1, 1],
    ];
    let strips: Vec<([u32; 6], Offset)> = dirs
        .iter()
        .enumerate()
        .map(|(k, &w)| (std::array::from_fn(|i| (6 * k + i) as u32), w))
        .collect();
    let (graph, shifts) = system(36, &strips, &[]);
    let t = exact(&Topology::periodic(&graph, &shifts).unwrap());
    assert_eq!(t.clusters.len(), 6);
    assert_eq!(
        strains(&t),
        (Some(6), Strain::ALL.to_vec(), Strain::ALL.to_vec())
    );
    // The first three alone hold only the three stretches.
    let (graph, shifts) = system(18, &strips[..3], &[]);
    let t = exact(&Topology::periodic(&graph, &shifts).unwrap());
    assert_eq!(
        strains(&t),
        (Some(3), Strain::ALL.to_vec(), vec![Xx, Yy, Zz])
    );
}

/// Walls: a slab is strained only along its periodic axes, so its strain
/// rank is over `xx`, `yy`, `xy`; a closed box has no strain, and truth
/// says so instead of a number.
#[test]
fn a_slab_counts_the_strains_of_its_periodic_axes_and_a_closed_box_none() {
    let (graph, shifts) = system(6, &[([0, 1, 2, 3, 4, 5], [1, 1, 0])], &[]);
    let slab = Topology {
        periodic: [true, true, false],
        ..Topology::periodic(&graph, &shifts).unwrap()
    };
    let t = exact(&slab);
    assert_eq!(strains(&t), (Some(1), vec![Xx, Yy, Xy], vec![Xx, Yy, Xy]));
    let t = exact(&Topology::finite(&graph));
    let s = t.strains.expect("truth reports its strains");
    assert_eq!((s.rank, s.considered, s.resisted), (None, vec![], vec![]));
    assert_eq!(
        s.reason.as_deref(),
        Some("no periodic axis: a finite framework has no box to strain")
    );
}

/// Not asked for, in floats, undecided: no number, each with its reason;
/// and the strain columns change neither the rank nor the clusters.
#[test]
fn the_strain_rank_is_unknown_where_it_is_not_exact() {
    let (graph, shifts) = system(6, &[([0, 1, 2, 3, 4, 5], [1, 0, 0])], &[]);
    let topo = Topology::periodic(&graph, &shifts).unwrap();
    let with = exact(&topo);
    let without = truth(
        &topo,
        TruthOptions {
            strain: false,
            ..TruthOptions::default()
        },
    );
    assert_eq!(
        (with.outcome.rank(), &with.clusters),
        (without.outcome.rank(), &without.clusters)
    );
    let reason = |t: &Truth| {
        let s = t.strains.clone().unwrap();
        assert_eq!((s.rank, s.resisted.len()), (None, 0));
        s.reason.unwrap()
    };
    assert_eq!(reason(&without), "not asked for");
    let floats = rgc::truth::truth_in_floats(&topo, TruthOptions::default());
    assert_eq!(floats.outcome.decision(), Decision::Float);
    assert_eq!(
        reason(&floats),
        "decided in floats: only the exact elimination ranks the strain columns"
    );
}

/// Generated systems (gamma 23, L = 3, rho = 34): the strain rank never
/// exceeds the six strains, is 0 where no true cluster wraps and 5 or 6
/// where one does; permuting the box axes of a system (its image offsets)
/// permutes the strains it resists, here the same rank.
#[test]
fn generated_systems_resist_none_or_most_strains_whatever_the_axes() {
    let mut found = Vec::new();
    for seed in 1..=4 {
        let network = crate::truth::system(23.0, 3.0, 34.0, seed);
        let t = rgc::truth::of_system(
            network.view(),
            rgc::spanning::Criterion::Wrap,
            TruthOptions::seeded(seed),
        );
        let (rank, considered, resisted) = strains(&t);
        assert_eq!(considered, Strain::ALL);
        let rank = rank.expect("exact");
        assert!(rank as usize <= 6 && resisted.len() >= rank as usize);
        found.push((t.spanning, rank));
        // The axes turned x -> y -> z -> x: the same system in a turned box.
        let turned: Vec<Offset> = network.shifts.iter().map(|s| [s[2], s[0], s[1]]).collect();
        let moved = truth(
            &Topology::periodic(&network.graph, &turned).unwrap(),
            TruthOptions::seeded(seed),
        );
        let turn = |c: &Strain| {
            let [i, j] = c.axes().map(|a| (a + 1) % 3);
            *Strain::ALL
                .iter()
                .find(|s| {
                    let [k, l] = s.axes();
                    (k, l) == (i.min(j), i.max(j))
                })
                .unwrap()
        };
        let mut expected: Vec<Strain> = resisted.iter().map(turn).collect();
        expected.sort_by_key(|s| s.index());
        assert_eq!(
            strains(&moved),
            (Some(rank), Strain::ALL.to_vec(), expected)
        );
    }
    assert_eq!(
        found,
        [
            (Some(false), 0),
            (Some(true), 6),
            (Some(true), 5),
            (Some(false), 0)
        ]
    );
}
