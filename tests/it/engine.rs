//! The 3D-RGC engine on hand-made contact graphs: every base motif compresses
//! its positive example to one node, every variant its theorem excludes does
//! not, whatever the random order (checked over many seeds).

use rgc::body::{Body, BodyClass};
use rgc::engine::examples::{self, Example, random_graph};
use rgc::engine::{Compression, RuleSet, compress, compress_from, compress_runs};
use rgc::graph::ContactGraph;

const SEEDS: u64 = 64;

fn example(name: &str) -> Example {
    examples::all()
        .into_iter()
        .find(|e| e.name == name)
        .unwrap_or_else(|| panic!("no example {name:?}"))
}

/// The outcomes of every seed for an example, with its bodies re-classed by `mask`
/// (bit i set: body i planar).
fn outcomes(e: &Example, rules: RuleSet, mask: u32) -> Vec<Compression> {
    let bodies: Vec<Body> = e
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let class = if mask >> i & 1 == 1 {
                BodyClass::Planar
            } else {
                b.class
            };
            Body::new(b.rods.clone(), class)
        })
        .collect();
    (0..SEEDS)
        .map(|s| compress_from(&e.graph(), &bodies, rules, s).unwrap())
        .collect()
}

#[test]
fn every_example_ends_as_expected_in_every_order() {
    for e in examples::all() {
        for (rules, expect) in [(RuleSet::Sound, e.expect[0]), (RuleSet::Paper, e.expect[1])] {
            for (seed, c) in outcomes(&e, rules, 0).iter().enumerate() {
                assert_eq!(
                    c.components, expect,
                    "{} under {rules:?}, seed {seed}: {c:?}",
                    e.name
                );
            }
        }
    }
    // The table `rgc audit` prints: one row per example, in order, each
    // showing the single node count every order ended with.
    let table = examples::check_all(8);
    let all = examples::all();
    assert_eq!(table.len(), all.len());
    for (row, e) in table.iter().zip(&all) {
        assert_eq!(row.name, e.name);
        assert_eq!(
            (row.sound.as_str(), row.paper.as_str()),
            (
                e.expect[0].to_string().as_str(),
                e.expect[1].to_string().as_str()
            ),
            "{}",
            e.name
        );
        assert!(row.pass, "{}", e.name);
    }
    // The rod prism: two planar bodies under `sound`, one body under `paper`.
    let prism = table
        .iter()
        .find(|r| r.name.starts_with("rod prism"))
        .unwrap();
    assert_eq!((prism.sound.as_str(), prism.paper.as_str()), ("2", "1"));
}

#[test]
fn each_positive_example_is_compressed_by_its_own_motif() {
    type Count = fn(&rgc::engine::MotifCounts) -> u32;
    let cases: [(&str, Count); 8] = [
        ("3D3C rod triangle", |m| m.community),
        ("3-clique community (strip of 4 triangles)", |m| m.community),
        ("3D2B rod touching a 3D6 body twice", |m| m.d2b),
        ("3D2A spatial + spatial", |m| m.d2a),
        ("3D3A", |m| m.d3a),
        ("3D3B", |m| m.d3b),
        ("3D4 planar body", |m| m.d4),
        ("3D6 K_{2,4} of rods", |m| m.d6),
    ];
    for (name, count) in cases {
        for rules in [RuleSet::Sound, RuleSet::Paper] {
            for c in outcomes(&example(name), rules, 0) {
                assert_eq!(count(&c.motifs), 1, "{name}: {:?}", c.motifs);
            }
        }
    }
}

#[test]
fn body_classes_follow_the_motif() {
    let class_of = |name: &str, rules| {
        let out = outcomes(&example(name), rules, 0);
        let classes: std::collections::BTreeSet<_> = out
            .iter()
            .flat_map(|c| c.bodies.iter().map(|b| format!("{:?}", b.class)))
            .collect();
        classes.into_iter().collect::<Vec<_>>().join(",")
    };
    assert_eq!(class_of("3D3C rod triangle", RuleSet::Sound), "Planar");
    assert_eq!(
        class_of("3-clique community (strip of 4 triangles)", RuleSet::Sound),
        "Planar"
    );
    assert_eq!(
        class_of("3D2B rod touching a planar body twice", RuleSet::Sound),
        "Planar"
    );
    assert_eq!(
        class_of("3D2B rod touching a 3D6 body twice", RuleSet::Sound),
        "Spatial"
    );
    assert_eq!(class_of("3D2A spatial + planar", RuleSet::Sound), "Spatial");
    assert_eq!(class_of("3D6 K_{2,4} of rods", RuleSet::Sound), "Spatial");
    assert_eq!(
        class_of("rod prism (two rod triangles, 3 contacts)", RuleSet::Sound),
        "Planar"
    );
    assert_eq!(
        class_of("rod prism (two rod triangles, 3 contacts)", RuleSet::Paper),
        "Spatial"
    );
}

#[test]
fn three_and_two_body_motifs_are_rigid_under_every_class_assignment() {
    for mask in 0..8 {
        for c in outcomes(&example("3D3A"), RuleSet::Sound, mask) {
            assert_eq!(c.components, 1, "3D3A with planar mask {mask:03b}");
        }
    }
    for mask in 0..4 {
        for c in outcomes(&example("3D3B"), RuleSet::Sound, mask) {
            assert_eq!(c.components, 1, "3D3B with planar mask {mask:02b}");
        }
    }
}

#[test]
fn communities_sharing_a_rod_give_it_to_one_of_them() {
    let owners: std::collections::BTreeSet<Vec<u32>> =
        outcomes(&example("two triangles sharing one rod"), RuleSet::Sound, 0)
            .into_iter()
            .map(|c| c.bodies[0].rods.clone())
            .collect();
    assert_eq!(
        owners.len(),
        2,
        "the shared rod goes to either community: {owners:?}"
    );
}

fn graph(n: usize, edges: &[(u32, u32)]) -> ContactGraph {
    ContactGraph::new(n, edges.iter().map(|&(a, b)| [a, b]).collect()).unwrap()
}

fn body(rods: &[u32], class: BodyClass) -> Body {
    Body::new(rods.to_vec(), class)
}

#[test]
fn declared_bodies_are_validated() {
    let g = graph(4, &[(0, 1)]);
    let err = |bodies: &[Body]| {
        compress_from(&g, bodies, RuleSet::Sound, 0)
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

#[test]
fn same_seed_same_result_and_bodies_partition_rods() {
    for s in 0..8 {
        let g = random_graph(300, 0.012, s);
        let a = compress(&g, RuleSet::Sound, s);
        assert_eq!(a, compress(&g, RuleSet::Sound, s));
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
            .install(|| compress_runs(&g, RuleSet::Sound, 11, 6))
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
        for rules in [RuleSet::Sound, RuleSet::Paper] {
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

/// Restarting from a run's own bodies re-examines every pair of neighbouring
/// nodes and every rod, so a motif the incremental worklist missed would be
/// compressed now.
fn assert_fixpoint(g: &ContactGraph, rules: RuleSet, seed: u64) {
    let done = compress(g, rules, seed);
    let again = compress_from(g, &done.bodies, rules, seed ^ 0xA5A5).unwrap();
    assert_eq!(
        again.components, done.components,
        "seed {seed}: a motif was left uncompressed"
    );
    assert_eq!(again.bodies, done.bodies);
}

#[test]
fn compression_ends_at_a_fixpoint_on_random_graphs() {
    for s in 0..24 {
        let g = random_graph(250, 0.008 + 0.0005 * s as f64, 500 + s);
        for rules in [RuleSet::Sound, RuleSet::Paper] {
            assert_fixpoint(&g, rules, s);
        }
    }
}

#[test]
fn compression_ends_at_a_fixpoint_on_rod_systems() {
    use rgc::contacts::detect;
    use rgc::rods::{RodParams, RodSystem};
    for (k, density) in [30.0, 40.0, 50.0].into_iter().enumerate() {
        let system = RodSystem::generate(RodParams::new(23.0, 6.0, density).unwrap(), k as u64);
        let g = ContactGraph::from_contacts(system.len(), &detect(&system));
        for rules in [RuleSet::Sound, RuleSet::Paper] {
            assert_fixpoint(&g, rules, 7 + k as u64);
        }
    }
}

/// A planar body keeps its plane inside a spatial body: a rod triangle
/// touching three rods of that plane is the prism's hinge again, so `sound`
/// refuses both 3D2A and 3D4 there; rods outside the plane make it rigid.
#[test]
fn planar_parts_of_spatial_bodies_keep_their_plane() {
    let g = graph(7, &[(3, 4), (4, 5), (3, 5), (3, 0), (4, 1), (5, 2)]);
    let mut s = body(&[0, 1, 2, 6], BodyClass::Spatial);
    s.planes = vec![vec![0, 1, 2]];
    for seed in 0..SEEDS {
        let sound = compress_from(&g, std::slice::from_ref(&s), RuleSet::Sound, seed).unwrap();
        assert_eq!(sound.components, 2, "seed {seed}: {sound:?}");
        assert_eq!(sound.bodies[0].planes, vec![vec![0, 1, 2]]);
        let paper = compress_from(&g, std::slice::from_ref(&s), RuleSet::Paper, seed).unwrap();
        assert_eq!(paper.components, 1);
    }
    // The same triangle on rods 0, 1, 6, with 6 outside the plane: rigid.
    let g = graph(7, &[(3, 4), (4, 5), (3, 5), (3, 0), (4, 1), (5, 6)]);
    for seed in 0..SEEDS {
        let sound = compress_from(&g, std::slice::from_ref(&s), RuleSet::Sound, seed).unwrap();
        assert_eq!(sound.components, 1, "seed {seed}: {sound:?}");
    }
    let mut bad = s.clone();
    bad.planes = vec![vec![0, 9]];
    let err = compress_from(&g, &[bad], RuleSet::Sound, 0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("plane rod 9"), "{err}");
}

fn verdict_of(g: &ContactGraph, bodies: &[Body]) -> rgc::rigidity::Verdict {
    let p = rgc::pattern::Pattern::from_host(g, bodies).unwrap();
    rgc::rigidity::check_exact(&p, 7).unwrap()
}

fn nodes_left(g: &ContactGraph, bodies: &[Body], rules: RuleSet) -> Vec<usize> {
    (0..SEEDS)
        .map(|s| compress_from(g, bodies, rules, s).unwrap().components)
        .collect()
}

/// K_{3,4} of rods is rigid only when all seven rods share a plane: exact
/// rank finds one DOF on the component of lines in general position. The
/// engine compresses it anyway, under `sound` too (3D6 on K_{2,4} inside,
/// then 3D2B): false rigidity that the audit counts at seven rods.
#[test]
fn k34_is_falsely_compressed_under_sound() {
    let g = rgc::graph::io::parse_graph6("F?~v_").unwrap();
    assert_eq!((g.n_nodes(), g.n_edges()), (7, 12));
    let v = verdict_of(&g, &[]);
    assert_eq!(
        (v.class.as_str(), v.dof, v.rigid),
        ("component-dependent", Some(1), Some(false))
    );
    let dof = |built: &str| v.components.iter().find(|c| c.built == built).unwrap().dof;
    assert_eq!(
        (dof("all coplanar"), dof("lines in general position")),
        (0, 1)
    );
    for rules in [RuleSet::Sound, RuleSet::Paper] {
        assert_eq!(
            nodes_left(&g, &[], rules),
            vec![1; SEEDS as usize],
            "{rules:?}"
        );
    }
}

/// K_{3,3} of rods is component-dependent too, and contains no base motif:
/// it stays six rods.
#[test]
fn k33_stays_six_rods() {
    let g = graph(
        6,
        &(0..3)
            .flat_map(|a| (3..6).map(move |b| (a, b)))
            .collect::<Vec<_>>(),
    );
    assert_eq!(rgc::graph::io::to_graph6(&g), "EFz_");
    let v = verdict_of(&g, &[]);
    assert_eq!((v.class.as_str(), v.dof), ("component-dependent", Some(1)));
    for rules in [RuleSet::Sound, RuleSet::Paper] {
        for seed in 0..SEEDS {
            let c = compress_from(&g, &[], rules, seed).unwrap();
            assert_eq!(
                (c.components, c.bodies.len()),
                (6, 0),
                "{rules:?} seed {seed}"
            );
        }
    }
}

/// The variants the theorems exclude (contacts on one rod) flex by exact
/// rank on every realization component, whatever the class of each body;
/// the engine leaves them apart.
#[test]
fn excluded_variants_are_flexible_by_exact_rank() {
    let names = [
        "3D2A, three contacts on one rod",
        "3D3A, p1 p2 p3 on one rod",
        "3D3A, p1 p4 p5 on one rod",
        "3D3A, p2..p5 on one rod",
        "3D3B, p3 on the rod of p1 and p2",
        "3D4, body contacts on one rod",
    ];
    for name in names {
        let e = example(name);
        assert!(
            e.expect[0] > 1 && e.expect[1] > 1,
            "{name} is an excluded variant"
        );
        for mask in 0..1u32 << e.bodies.len() {
            let bodies = e.bodies_classed(mask);
            let v = verdict_of(&e.graph(), &bodies);
            assert_eq!(v.class, "flexible", "{name}, planar mask {mask:b}: {v:?}");
            assert!(
                v.components.iter().all(|c| c.dof > 0),
                "{name}, planar mask {mask:b}: {v:?}"
            );
            for rules in [RuleSet::Sound, RuleSet::Paper] {
                assert!(
                    nodes_left(&e.graph(), &bodies, rules)
                        .iter()
                        .all(|&n| n > 1),
                    "{name}, planar mask {mask:b}, {rules:?}"
                );
            }
        }
    }
}

/// 3D3A and 3D3B instances with planar bodies whose contacts share rods:
/// the published conditions accept them (`paper` compresses them in every
/// order, by that motif in some), exact rank finds a flexible component,
/// and `sound` refuses them in every order.
#[test]
fn sound_refuses_3d3a_and_3d3b_instances_that_paper_compresses() {
    use rgc::pattern::{NodeKind, Pattern, PatternContact};
    let c = |a: u8, ra: u8, b: u8, rb: u8| PatternContact {
        nodes: [a, b],
        rods: [ra, rb],
    };
    // Three planar bodies pairwise joined by two contacts, sharing rods.
    let d3a = Pattern {
        kinds: vec![NodeKind::Planar; 3],
        contacts: vec![
            c(0, 0, 1, 0),
            c(0, 0, 1, 1),
            c(0, 0, 2, 0),
            c(0, 1, 2, 2),
            c(1, 0, 2, 0),
            c(1, 0, 2, 1),
        ],
    };
    // A rod touching two planar bodies joined by two contacts; it touches
    // one of them on two of its rods.
    let d3b = Pattern {
        kinds: vec![NodeKind::Rod, NodeKind::Planar, NodeKind::Planar],
        contacts: vec![
            c(0, 0, 1, 0),
            c(0, 0, 2, 0),
            c(0, 0, 2, 1),
            c(1, 0, 2, 1),
            c(1, 1, 2, 0),
        ],
    };
    type Count = fn(&rgc::engine::MotifCounts) -> u32;
    let cases: [(&str, Pattern, Count, usize); 2] =
        [("3D3A", d3a, |m| m.d3a, 3), ("3D3B", d3b, |m| m.d3b, 2)];
    for (name, p, count, sound_left) in cases {
        let v = rgc::rigidity::check_exact(&p, 7).unwrap();
        assert_eq!(
            (v.class.as_str(), v.dof),
            ("component-dependent", Some(1)),
            "{name}"
        );
        let (g, bodies, _) = p.to_host().unwrap();
        let mut by_motif = 0;
        for seed in 0..SEEDS {
            let paper = compress_from(&g, &bodies, RuleSet::Paper, seed).unwrap();
            assert_eq!(paper.components, 1, "{name} seed {seed}");
            by_motif += count(&paper.motifs);
            let sound = compress_from(&g, &bodies, RuleSet::Sound, seed).unwrap();
            assert_eq!(
                sound.components, sound_left,
                "{name} seed {seed}: {sound:?}"
            );
            assert_eq!(count(&sound.motifs), 0, "{name} seed {seed}");
        }
        assert!(by_motif > 0, "{name}: paper never used the motif");
    }
}
