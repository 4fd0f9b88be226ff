//! The 3D-RGC engine on hand-made contact graphs: every base motif compresses
//! its positive example to one node, every variant its theorem excludes does
//! not, whatever the random order (checked over many seeds).

use rgc::contacts::ContactGraph;
use rgc::engine::{Body, BodyClass, Compression, Rules, compress, compress_from, compress_runs};

const SEEDS: u64 = 64;

fn graph(n: usize, edges: &[(u32, u32)]) -> ContactGraph {
    ContactGraph::new(n, edges.iter().map(|&(a, b)| [a, b]).collect()).unwrap()
}

fn body(rods: &[u32], class: BodyClass) -> Body {
    Body {
        rods: rods.to_vec(),
        class,
    }
}

/// Runs the engine with every seed and returns the outcomes.
fn outcomes(g: &ContactGraph, bodies: &[Body], rules: Rules) -> Vec<Compression> {
    (0..SEEDS)
        .map(|s| compress_from(g, bodies, rules, s).unwrap())
        .collect()
}

fn always_one_node(g: &ContactGraph, bodies: &[Body], rules: Rules) -> Vec<Compression> {
    let out = outcomes(g, bodies, rules);
    for (seed, c) in out.iter().enumerate() {
        assert_eq!(c.components, 1, "seed {seed}: {c:?}");
        assert_eq!(c.largest_rods(), g.n_nodes());
    }
    out
}

fn never_one_node(g: &ContactGraph, bodies: &[Body], rules: Rules, nodes: usize) {
    for (seed, c) in outcomes(g, bodies, rules).iter().enumerate() {
        assert_eq!(c.components, nodes, "seed {seed}: {c:?}");
    }
}

/// Edges of K_{2,4}: rods 0 and 1 each touching rods 2..=5 (offset by `o`).
fn k24(o: u32) -> Vec<(u32, u32)> {
    (2..6).flat_map(|k| [(o, o + k), (o + 1, o + k)]).collect()
}

#[test]
fn rod_triangle_is_one_planar_body() {
    for rules in [Rules::Sound, Rules::Paper] {
        let out = always_one_node(&graph(3, &[(0, 1), (1, 2), (0, 2)]), &[], rules);
        assert!(out.iter().all(|c| c.bodies[0].class == BodyClass::Planar));
        assert!(out.iter().all(|c| c.motifs.community == 1));
    }
}

#[test]
fn three_clique_community_is_one_planar_body() {
    // A strip of four triangles glued along edges: 0-1-2, 1-2-3, 2-3-4, 3-4-5.
    let g = graph(
        6,
        &[
            (0, 1),
            (0, 2),
            (1, 2),
            (1, 3),
            (2, 3),
            (2, 4),
            (3, 4),
            (3, 5),
            (4, 5),
        ],
    );
    let out = always_one_node(&g, &[], Rules::Sound);
    assert!(out.iter().all(|c| c.bodies[0].class == BodyClass::Planar));
    assert!(out.iter().all(|c| c.motifs.community == 1));
}

#[test]
fn communities_sharing_a_rod_give_it_to_one_of_them() {
    // Two triangles sharing rod 2 only: 0-1-2 and 2-3-4 (a bowtie). One
    // community takes rod 2, the other is left with rods 3 and 4 touching it
    // once each: no rod triangle remains outside a body.
    let g = graph(5, &[(0, 1), (0, 2), (1, 2), (2, 3), (2, 4), (3, 4)]);
    let out = outcomes(&g, &[], Rules::Sound);
    let mut owners = std::collections::BTreeSet::new();
    for c in &out {
        assert_eq!(c.components, 3, "{c:?}");
        assert_eq!(c.bodies.len(), 1);
        owners.insert(c.bodies[0].rods.clone());
    }
    assert_eq!(owners.len(), 2, "the shared rod goes to either community");
}

#[test]
fn d2b_rod_touching_body_twice_joins_it() {
    // 3D6 body on rods 0..=5 and rod 6 touching rods 2 and 3 (which do not touch).
    let mut e = k24(0);
    e.extend([(6, 2), (6, 3)]);
    let out = always_one_node(&graph(7, &e), &[], Rules::Sound);
    assert!(out.iter().all(|c| c.motifs.d6 == 1 && c.motifs.d2b == 1));
    // A planar body stays planar when a rod joins it by 3D2B.
    let g = graph(4, &[(3, 0), (3, 1)]);
    let out = always_one_node(&g, &[body(&[0, 1, 2], BodyClass::Planar)], Rules::Sound);
    assert!(out.iter().all(|c| c.bodies[0].class == BodyClass::Planar));
    let out = always_one_node(&g, &[body(&[0, 1, 2], BodyClass::Spatial)], Rules::Sound);
    assert!(out.iter().all(|c| c.bodies[0].class == BodyClass::Spatial));
}

#[test]
fn rod_touching_body_once_stays_free() {
    let g = graph(4, &[(3, 0)]);
    never_one_node(&g, &[body(&[0, 1, 2], BodyClass::Spatial)], Rules::Paper, 2);
}

#[test]
fn d2a_two_bodies_three_contacts() {
    let g = graph(6, &[(0, 3), (1, 4), (2, 5)]);
    let a = body(&[0, 1, 2], BodyClass::Spatial);
    let b = body(&[3, 4, 5], BodyClass::Spatial);
    let p = body(&[3, 4, 5], BodyClass::Planar);
    for rules in [Rules::Sound, Rules::Paper] {
        let out = always_one_node(&g, &[a.clone(), b.clone()], rules);
        assert!(out.iter().all(|c| c.motifs.d2a == 1));
        assert!(out.iter().all(|c| c.bodies[0].class == BodyClass::Spatial));
        always_one_node(&g, &[a.clone(), p.clone()], rules);
    }
    // Contacts sharing a rod on one side, but not all three: still rigid.
    let g = graph(6, &[(0, 3), (0, 4), (1, 5)]);
    always_one_node(&g, &[a.clone(), b.clone()], Rules::Sound);
}

#[test]
fn d2a_degenerate_variants_do_not_compress() {
    let a = body(&[0, 1, 2], BodyClass::Spatial);
    let b = body(&[3, 4, 5], BodyClass::Spatial);
    // All three contacts on rod 0.
    let g = graph(6, &[(0, 3), (0, 4), (0, 5)]);
    for rules in [Rules::Sound, Rules::Paper] {
        never_one_node(&g, &[a.clone(), b.clone()], rules, 2);
    }
    // Only two contacts.
    let g = graph(6, &[(0, 3), (1, 4)]);
    never_one_node(&g, &[a.clone(), b.clone()], Rules::Paper, 2);
    // Two planar bodies: a hinge about the line where their planes meet.
    let g = graph(6, &[(0, 3), (1, 4), (2, 5)]);
    let pa = body(&[0, 1, 2], BodyClass::Planar);
    let pb = body(&[3, 4, 5], BodyClass::Planar);
    never_one_node(&g, &[pa.clone(), pb.clone()], Rules::Sound, 2);
    always_one_node(&g, &[pa, pb], Rules::Paper);
}

#[test]
fn rod_prism_is_two_planar_bodies_under_sound_one_node_under_paper() {
    let g = graph(
        6,
        &[
            (0, 1),
            (1, 2),
            (0, 2),
            (3, 4),
            (4, 5),
            (3, 5),
            (0, 3),
            (1, 4),
            (2, 5),
        ],
    );
    for (seed, c) in outcomes(&g, &[], Rules::Sound).iter().enumerate() {
        assert_eq!(c.components, 2, "seed {seed}: {c:?}");
        assert!(c.bodies.iter().all(|b| b.class == BodyClass::Planar));
        assert_eq!(c.bodies[0].rods.len(), 3);
    }
    always_one_node(&g, &[], Rules::Paper);
}

#[test]
fn d3a_three_bodies() {
    // R1 = {0,1,2}, R2 = {3,4,5}, R3 = {6,7,8}: R1-R2 once, R1-R3 twice, R2-R3 twice.
    let bodies = [
        body(&[0, 1, 2], BodyClass::Spatial),
        body(&[3, 4, 5], BodyClass::Spatial),
        body(&[6, 7, 8], BodyClass::Spatial),
    ];
    let g = graph(9, &[(0, 3), (1, 6), (2, 7), (4, 7), (5, 8)]);
    for rules in [Rules::Sound, Rules::Paper] {
        let out = always_one_node(&g, &bodies, rules);
        assert!(out.iter().all(|c| c.motifs.d3a == 1));
    }
    // Every planar/spatial assignment is rigid (DESIGN §5).
    for mask in 0..8u32 {
        let classes: Vec<Body> = bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let class = if mask >> i & 1 == 1 {
                    BodyClass::Planar
                } else {
                    BodyClass::Spatial
                };
                body(&b.rods, class)
            })
            .collect();
        always_one_node(&g, &classes, Rules::Sound);
    }
}

#[test]
fn d3a_degenerate_variants_do_not_compress() {
    let bodies = [
        body(&[0, 1, 2], BodyClass::Spatial),
        body(&[3, 4, 5], BodyClass::Spatial),
        body(&[6, 7, 8], BodyClass::Spatial),
    ];
    // p1, p2, p3 all on rod 0 of R1.
    let g = graph(9, &[(0, 3), (0, 6), (0, 7), (4, 7), (5, 8)]);
    never_one_node(&g, &bodies, Rules::Paper, 3);
    // p1, p4, p5 all on rod 3 of R2.
    let g = graph(9, &[(0, 3), (1, 6), (2, 7), (3, 7), (3, 8)]);
    never_one_node(&g, &bodies, Rules::Paper, 3);
    // p2, p3, p4, p5 all on rod 6 of R3.
    let g = graph(9, &[(0, 3), (1, 6), (2, 6), (4, 6), (5, 6)]);
    never_one_node(&g, &bodies, Rules::Paper, 3);
}

#[test]
fn d3b_two_bodies_and_a_rod() {
    let bodies = [
        body(&[0, 1, 2], BodyClass::Spatial),
        body(&[3, 4, 5], BodyClass::Spatial),
    ];
    let g = graph(7, &[(0, 3), (1, 4), (6, 2), (6, 5)]);
    for rules in [Rules::Sound, Rules::Paper] {
        let out = always_one_node(&g, &bodies, rules);
        assert!(out.iter().all(|c| c.motifs.d3b == 1));
    }
    for mask in 0..4u32 {
        let classes: Vec<Body> = bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let class = if mask >> i & 1 == 1 {
                    BodyClass::Planar
                } else {
                    BodyClass::Spatial
                };
                body(&b.rods, class)
            })
            .collect();
        always_one_node(&g, &classes, Rules::Sound);
    }
    // The rod's contact with R1 on the rod that carries both p1 and p2: excluded.
    let g = graph(7, &[(0, 3), (0, 4), (6, 0), (6, 5)]);
    never_one_node(&g, &bodies, Rules::Paper, 3);
}

#[test]
fn d4_body_and_three_rods() {
    // Body {0,1,2}; rods 3-4-5 in a path, touching rods 0, 1, 2.
    let g = graph(6, &[(3, 4), (4, 5), (3, 0), (4, 1), (5, 2)]);
    for class in [BodyClass::Spatial, BodyClass::Planar] {
        for rules in [Rules::Sound, Rules::Paper] {
            let out = always_one_node(&g, &[body(&[0, 1, 2], class)], rules);
            assert!(out.iter().all(|c| c.motifs.d4 == 1));
        }
    }
    // Two of the three body contacts on one rod is fine.
    let g = graph(6, &[(3, 4), (4, 5), (3, 0), (4, 0), (5, 2)]);
    always_one_node(&g, &[body(&[0, 1, 2], BodyClass::Spatial)], Rules::Sound);
}

#[test]
fn d4_degenerate_variants_do_not_compress() {
    // All three body contacts on rod 0.
    let g = graph(6, &[(3, 4), (4, 5), (3, 0), (4, 0), (5, 0)]);
    never_one_node(&g, &[body(&[0, 1, 2], BodyClass::Spatial)], Rules::Paper, 4);
    // A triangle through a body: body, rods 3 and 4 touching each other and it.
    let g = graph(5, &[(3, 4), (3, 0), (4, 1)]);
    never_one_node(&g, &[body(&[0, 1, 2], BodyClass::Spatial)], Rules::Paper, 3);
}

#[test]
fn d6_k24_of_rods() {
    let out = always_one_node(&graph(6, &k24(0)), &[], Rules::Sound);
    assert!(out.iter().all(|c| c.motifs.d6 == 1));
    assert!(out.iter().all(|c| c.bodies[0].class == BodyClass::Spatial));
}

#[test]
fn flexible_rod_graphs_do_not_compress() {
    // A 4-cycle of rods.
    never_one_node(
        &graph(4, &[(0, 1), (1, 2), (2, 3), (3, 0)]),
        &[],
        Rules::Paper,
        4,
    );
    // K_{2,3} of rods.
    let k23: Vec<(u32, u32)> = (2..5).flat_map(|k| [(0, k), (1, k)]).collect();
    never_one_node(&graph(5, &k23), &[], Rules::Paper, 5);
    // Two rod triangles sharing one rod: one triangle takes it, the other
    // pair of rods touches that body once each.
    never_one_node(
        &graph(5, &[(0, 1), (0, 2), (1, 2), (2, 3), (2, 4), (3, 4)]),
        &[],
        Rules::Paper,
        3,
    );
}

#[test]
fn declared_bodies_are_validated() {
    let g = graph(4, &[(0, 1)]);
    let err = |bodies: &[Body]| {
        compress_from(&g, bodies, Rules::Sound, 0)
            .unwrap_err()
            .to_string()
    };
    assert!(err(&[body(&[0], BodyClass::Spatial)]).contains("at least two"));
    assert!(err(&[body(&[0, 9], BodyClass::Spatial)]).contains("outside 0..4"));
    assert!(
        err(&[
            body(&[0, 1], BodyClass::Spatial),
            body(&[1, 2], BodyClass::Spatial)
        ])
        .contains("rod 1 is declared in body 0 and body 1")
    );
}

/// A random graph with enough structure to exercise every motif.
fn random_graph(n: usize, p: f64, seed: u64) -> ContactGraph {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut e = Vec::new();
    for i in 0..n as u32 {
        for j in i + 1..n as u32 {
            if rng.random::<f64>() < p {
                e.push([i, j]);
            }
        }
    }
    ContactGraph::new(n, e).unwrap()
}

#[test]
fn same_seed_same_result_and_bodies_partition_rods() {
    for s in 0..8 {
        let g = random_graph(300, 0.012, s);
        let a = compress(&g, Rules::Sound, s);
        assert_eq!(a, compress(&g, Rules::Sound, s));
        let mut seen = vec![false; g.n_nodes()];
        for b in &a.bodies {
            assert!(b.rods.len() >= 3, "the smallest body is a rod triangle");
            for &r in &b.rods {
                assert!(!seen[r as usize], "rod {r} in two bodies");
                seen[r as usize] = true;
            }
        }
        let free = seen.iter().filter(|s| !**s).count();
        assert_eq!(a.components, a.bodies.len() + free);
    }
}

#[test]
fn thread_count_does_not_change_runs() {
    let g = random_graph(400, 0.01, 7);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| compress_runs(&g, Rules::Sound, 11, 6))
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one.len(), 6);
    assert!(
        one.windows(2).any(|w| w[0] != w[1]),
        "runs use different orders"
    );
}

#[test]
fn bodies_are_connected_by_their_own_contacts() {
    for s in 0..8 {
        let g = random_graph(300, 0.013, 100 + s);
        for rules in [Rules::Sound, Rules::Paper] {
            for b in compress(&g, rules, s).bodies {
                let inside: std::collections::HashSet<u32> = b.rods.iter().copied().collect();
                let mut seen = std::collections::HashSet::from([b.rods[0]]);
                let mut stack = vec![b.rods[0]];
                while let Some(r) = stack.pop() {
                    for &(v, _) in g.neighbors(r) {
                        if inside.contains(&v) && seen.insert(v) {
                            stack.push(v);
                        }
                    }
                }
                assert_eq!(
                    seen.len(),
                    b.rods.len(),
                    "body {:?} is not connected",
                    b.rods
                );
            }
        }
    }
}
