//! Truth's float fallback where no construction order exists: against the
//! motif verdict, against the exact path where both apply, and its refusals.

use rgc::graph::ContactGraph;
use rgc::graph::io::read_graph6_file;
use rgc::pattern::Pattern;
use rgc::rigidity::check_exact;
use rgc::truth::{Decision, Outcome, Topology, Truth, TruthOptions, truth, truth_in_floats};
use std::path::Path;

/// K_{m,n}: rods `0..m` each touch rods `m..m + n`.
fn complete_bipartite(m: u32, n: u32) -> ContactGraph {
    let edges = (0..m)
        .flat_map(|a| (m..m + n).map(move |b| [a, b]))
        .collect();
    ContactGraph::new((m + n) as usize, edges).unwrap()
}

/// The `d`-cube: rods `0..2^d`, touching where their indices differ in one bit.
fn cube(d: u32) -> ContactGraph {
    let n = 1u32 << d;
    let edges = (0..n)
        .flat_map(|a| (0..d).map(move |k| [a, a ^ (1 << k)]))
        .filter(|&[a, b]| a < b)
        .collect();
    ContactGraph::new(n as usize, edges).unwrap()
}

fn rods(t: &Truth) -> Vec<Vec<u32>> {
    t.clusters.iter().map(|c| c.rods.clone()).collect()
}

/// Truth of a graph no construction order reaches, decided in floats, with
/// the motif verdict's forced family (no planes in these graphs: lines in
/// general position, built exactly or by numerical projection).
fn float_and_motif(g: &ContactGraph) -> (Truth, rgc::rigidity::ComponentReport) {
    let t = truth(&Topology::finite(g), TruthOptions::default());
    let Outcome::Float { gap, reason, .. } = &t.outcome else {
        panic!("decided in floats: {:?}", t.outcome)
    };
    assert!(
        reason.contains("no rational construction order"),
        "{reason}"
    );
    assert!(*gap >= rgc::truth::fallback::MIN_GAP);
    let v = check_exact(&Pattern::from_graph(g).unwrap(), 1).unwrap();
    let forced = v
        .components
        .iter()
        .find(|c| c.built.starts_with("lines in general position"))
        .expect("the forced family");
    (t, forced.clone())
}

/// K_{4,4}, every rod touching four others with no triangle, has no
/// construction order. Its generic realization is Henrici's hyperboloid
/// grid (the two rulings of one hyperboloid), which flexes with one degree
/// of freedom, and so does truth in floats; the motif check builds that
/// family exactly (a line through three placed ones meets the fourth of a
/// regulus). The flex turns every crossing, so no two rods stay rigid.
/// K_{4,5} and K_{5,5} are the same grid.
#[test]
fn complete_bipartite_grids_flex_once_as_the_motif_check_says() {
    for (m, n) in [(4, 4), (4, 5), (5, 5)] {
        let (t, forced) = float_and_motif(&complete_bipartite(m, n));
        assert_eq!(forced.built, "lines in general position");
        assert!(!forced.projected);
        assert_eq!(t.outcome.dof(), Some(1), "K_{{{m},{n}}}");
        assert_eq!(t.outcome.dof(), Some(forced.dof), "K_{{{m},{n}}}");
        assert!(t.clusters.is_empty(), "K_{{{m},{n}}}: {:?}", rods(&t));
    }
}

/// The 4-cube graph (16 rods, 4-regular, no triangle): rigid in floats, one
/// cluster of every rod, as the motif check's own numerical projection of
/// its most generic family says.
#[test]
fn the_4_cube_is_rigid_as_the_motif_projection_says() {
    let (t, forced) = float_and_motif(&cube(4));
    assert!(forced.projected, "{forced:?}");
    assert_eq!(forced.dof, 0);
    assert_eq!(t.outcome.dof(), Some(0));
    assert_eq!(rods(&t), vec![(0..16).collect::<Vec<u32>>()]);

    // The same cube in a fixed periodic box, each rod at some image (a
    // contact sees the other rod's image shifted by the difference): still
    // one rigid cluster, which now turns in the box (3 rotations are motions).
    let g = cube(4);
    let image = |r: u32| [r as i32 % 3 - 1, (r as i32 / 3) % 2, -(r as i32 % 2)];
    let shifts: Vec<[i32; 3]> = g
        .edges()
        .iter()
        .map(|&[a, b]| [0, 1, 2].map(|k| image(b)[k] - image(a)[k]))
        .collect();
    let topo = Topology::periodic(&g, &shifts).unwrap();
    let p = truth(&topo, TruthOptions::default());
    assert_eq!(
        p.outcome.decision(),
        Decision::Float,
        "{:?}",
        p.outcome.reason()
    );
    assert_eq!(p.trivial_motions, 3);
    assert_eq!(p.outcome.dof(), Some(3));
    assert_eq!(rods(&p), rods(&t));
}

/// Two 4-cubes sharing one rod: each is rigid, and they turn against each
/// other about the shared rod's axis (one degree of freedom). The float
/// clusters keep the hinge apart: two clusters of 16 rods, both holding it.
/// Sharing a second rod (not touching the first) locks the hinge.
#[test]
fn float_clusters_keep_a_hinge_apart_and_a_second_shared_rod_locks_it() {
    let two_cubes = |second: &dyn Fn(u32) -> u32, n: usize| {
        let mut edges: Vec<[u32; 2]> = cube(4).edges().to_vec();
        edges.extend(cube(4).edges().iter().map(|e| e.map(second)));
        let g = ContactGraph::new(n, edges).unwrap();
        let t = truth(&Topology::finite(&g), TruthOptions::default());
        assert_eq!(
            t.outcome.decision(),
            Decision::Float,
            "{:?}",
            t.outcome.reason()
        );
        t
    };
    // The second cube's rod 0 is the first cube's rod 15.
    let t = two_cubes(&|v| 15 + v, 31);
    assert_eq!(t.outcome.dof(), Some(1));
    assert_eq!(
        rods(&t),
        vec![(0..16).collect::<Vec<u32>>(), (15..31).collect()]
    );
    // And its rod 3 is the first cube's rod 3 (rods 0 and 3 of a cube, as
    // 15 and 3, differ in two bits: they touch in neither).
    let t = two_cubes(
        &|v| match v {
            0 => 15,
            3 => 3,
            v => 15 + v - u32::from(v > 3),
        },
        30,
    );
    assert_eq!(t.outcome.dof(), Some(0));
    assert_eq!(rods(&t), vec![(0..30).collect::<Vec<u32>>()]);
}

/// Where a construction order exists truth stays exact, and the float path
/// forced on the same graph finds the same degrees of freedom and the same
/// clusters: every rods-only candidate with up to 7 rods, a graph with
/// hinged planes, and two generated periodic systems (realized in the
/// fixed box, with contacts across it; in the second a forced plane wraps
/// the box along two directions).
#[test]
fn the_float_path_agrees_with_the_exact_one_where_both_exist() {
    let mut graphs = Vec::new();
    for n in 5..=7 {
        let path = format!("graphs/maxwell-mindeg2-n{n}.g6");
        graphs.extend(read_graph6_file(Path::new(&path)).unwrap());
    }
    graphs.push(crate::truth::locked_hinge());
    for g in &graphs {
        let topo = Topology::finite(g);
        let exact = truth(&topo, TruthOptions::default());
        let float = truth_in_floats(&topo, TruthOptions::default());
        let g6 = rgc::graph::io::to_graph6(g);
        assert_eq!(exact.outcome.decision(), Decision::Exact, "{g6}");
        assert_eq!(
            float.outcome.decision(),
            Decision::Float,
            "{g6}: {:?}",
            float.outcome.reason()
        );
        assert_eq!(float.outcome.dof(), exact.outcome.dof(), "{g6}");
        assert_eq!(float.clusters, exact.clusters, "{g6}");
    }

    // (gamma, box, density, seed, columns, most box directions a class wraps)
    for (gamma, side, rho, seed, columns, wraps) in
        [(23.0, 3.0, 20.0, 1, 318, 0), (10.0, 2.5, 18.5, 20, 468, 2)]
    {
        let params = rgc::rods::RodParams::new(gamma, side, rho).unwrap();
        let system = rgc::rods::RodSystem::generate(params, seed);
        let contacts = rgc::contacts::detect(&system);
        let graph = ContactGraph::from_contacts(system.len(), &contacts);
        let shifts: Vec<_> = contacts.iter().map(|c| c.shift).collect();
        assert!(shifts.iter().any(|s| *s != [0; 3]));
        let topo = Topology::periodic(&graph, &shifts).unwrap();
        let core = rgc::truth::prune::two_core(&graph);
        let planes = rgc::truth::planes::forced(&topo, &core.active).unwrap();
        let most = planes.classes.iter().map(|c| c.wraps.len()).max();
        assert_eq!(most, Some(wraps));
        let exact = truth(&topo, TruthOptions::default());
        let float = truth_in_floats(&topo, TruthOptions::default());
        assert_eq!(exact.outcome.decision(), Decision::Exact);
        assert_eq!(
            float.outcome.decision(),
            Decision::Float,
            "{:?}",
            float.outcome.reason()
        );
        assert_eq!(float.columns, columns);
        assert_eq!(float.outcome.dof(), exact.outcome.dof());
        assert_eq!(float.clusters, exact.clusters);
    }
}

/// The same seed gives the same answer; another seed draws other
/// realizations and still the same one.
#[test]
fn the_float_fallback_is_deterministic_in_its_seed() {
    let g = complete_bipartite(4, 4);
    let topo = Topology::finite(&g);
    let run = |seed| {
        let mut t = truth(&topo, TruthOptions::seeded(seed));
        t.seconds = 0.0;
        t
    };
    let one = run(7);
    assert_eq!(one.outcome.decision(), Decision::Float);
    assert_eq!(one, run(7));
    let other = run(8);
    let gap = |t: &Truth| match t.outcome {
        Outcome::Float { gap, .. } => gap,
        _ => panic!("decided in floats: {:?}", t.outcome),
    };
    assert_ne!(gap(&one), gap(&other), "another seed, other realizations");
    assert_eq!(
        (other.outcome.dof(), other.outcome.rank()),
        (one.outcome.dof(), one.outcome.rank())
    );
}

/// What the fallback does not decide it says: a stuck core beyond the
/// dense SVD's columns (the 8-cube, 256 rods, 1,536 columns).
#[test]
fn the_fallback_refuses_more_columns_than_it_ranks_densely() {
    let t = truth(&Topology::finite(&cube(8)), TruthOptions::default());
    assert_eq!(t.outcome.decision(), Decision::Undecided);
    assert_eq!(t.columns, 1536);
    assert_eq!((t.outcome.dof(), t.outcome.rank()), (None, None));
    let why = t.outcome.reason().unwrap();
    assert!(why.contains("no rational construction order"), "{why}");
    assert!(why.contains("1500"), "{why}");
}

/// Certification accepts only exact answers: on `K_{4,4}` (no construction
/// order, so truth decides in floats) `sound` compresses the graph to one
/// body, and `certified` keeps none and says it could not certify.
#[test]
fn certification_does_not_trust_a_float_answer() {
    use rgc::engine::{Engine, RuleSet};
    let g = rgc::graph::io::parse_graph6("G?~vf_").unwrap();
    let t = truth(&Topology::finite(&g), TruthOptions::default());
    assert_eq!(
        (t.outcome.decision(), t.outcome.dof()),
        (Decision::Float, Some(1))
    );
    let sound = Engine::base(RuleSet::Sound);
    let certified = Engine::base(RuleSet::Certified);
    let seed = (0..64)
        .find(|&s| sound.compress(&g, &[], s).unwrap().components == 1)
        .expect("sound compresses K_{4,4} in some order");
    let run = certified.compress(&g, &[], seed).unwrap();
    assert!(run.bodies.is_empty() && run.undecided, "{run:?}");
}
