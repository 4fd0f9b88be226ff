//! Graph and typed-pattern enumeration: exact counts, filters pushed into
//! generation against filtering afterwards, agreement with nauty's geng
//! (reference files under graphs/), canonical forms.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::path::Path;

use proptest::prelude::*;
use rgc::enumerate::{
    GraphFilter, MAX_ORDER, SmallGraph, TypedFilter, canonical_graph6, canonical_pattern,
    connected_graphs, connected_small_graphs, count_connected, for_each_connected,
    maxwell_rod_edges, par_fold_connected, par_for_each_connected, typed_patterns,
    write_connected_graph6,
};
use rgc::graph::ContactGraph;
use rgc::graph::io::{parse_graph6, read_graph6_file, to_graph6};
use rgc::pattern::{NodeKind, Pattern, PatternContact};

/// Connected graphs on n = 1..=10 vertices (OEIS A001349).
const CONNECTED: [u64; 10] = [1, 1, 2, 6, 21, 112, 853, 11117, 261080, 11716571];

fn canonical_set(graphs: &[ContactGraph]) -> BTreeSet<String> {
    graphs.iter().map(canonical_graph6).collect()
}

fn reference(name: &str) -> Vec<ContactGraph> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("graphs")
        .join(name);
    read_graph6_file(&path).unwrap()
}

#[test]
fn connected_counts_up_to_nine() {
    for n in 1..=9 {
        let count = count_connected(n, &GraphFilter::all()).unwrap();
        assert_eq!(count, CONNECTED[n - 1], "n = {n}");
    }
}

#[test]
#[ignore = "11.7 million graphs: a few seconds in release"]
fn connected_count_ten() {
    assert_eq!(
        count_connected(10, &GraphFilter::all()).unwrap(),
        CONNECTED[9]
    );
}

#[test]
fn every_graph_is_connected_distinct_and_filtered() {
    for n in 1..=7 {
        let graphs = connected_graphs(n, &GraphFilter::all()).unwrap();
        assert_eq!(graphs.len() as u64, CONNECTED[n - 1]);
        for g in &graphs {
            assert_eq!(g.n_nodes(), n);
            assert!(connected(g), "{}", to_graph6(g));
        }
        assert_eq!(
            canonical_set(&graphs).len(),
            graphs.len(),
            "duplicates at n = {n}"
        );
    }
}

fn connected(g: &ContactGraph) -> bool {
    let n = g.n_nodes();
    let mut seen = vec![false; n];
    let mut stack = vec![0u32];
    seen[0] = true;
    while let Some(v) = stack.pop() {
        for &(w, _) in g.neighbors(v) {
            if !seen[w as usize] {
                seen[w as usize] = true;
                stack.push(w);
            }
        }
    }
    seen.iter().all(|&s| s)
}

#[test]
fn small_orders_by_hand() {
    let g6 = |n| -> Vec<String> {
        connected_small_graphs(n, &GraphFilter::all())
            .unwrap()
            .iter()
            .map(|g| g.canonical().graph6())
            .collect()
    };
    assert_eq!(g6(1), ["@"]);
    assert_eq!(g6(2), ["A_"]);
    // The path and the triangle.
    let three: BTreeSet<String> = g6(3).into_iter().collect();
    let expected: BTreeSet<String> = ["Bg", "Bw"]
        .iter()
        .map(|s| canonical_graph6(&parse_graph6(s).unwrap()))
        .collect();
    assert_eq!(three, expected);
}

#[test]
fn orders_outside_the_range_are_errors() {
    for n in [0, MAX_ORDER + 1] {
        assert!(count_connected(n, &GraphFilter::all()).is_err());
        assert!(connected_graphs(n, &GraphFilter::all()).is_err());
        let mut out = Vec::new();
        let e = write_connected_graph6(n, &GraphFilter::all(), &mut out).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        assert!(out.is_empty());
    }
}

fn filters(n: usize) -> Vec<GraphFilter> {
    let all = GraphFilter::all();
    let pairs = n * (n - 1) / 2;
    vec![
        all.with_min_degree(1),
        all.with_min_degree(2),
        all.with_min_degree(3),
        all.with_min_degree(n),
        GraphFilter::maxwell_rods(n),
        GraphFilter::maxwell_rods(n).with_min_degree(2),
        GraphFilter::maxwell_rods(n).with_min_degree(3),
        GraphFilter {
            min_degree: 0,
            min_edges: 0,
            max_edges: n,
        },
        GraphFilter {
            min_degree: 2,
            min_edges: n + 1,
            max_edges: (n + 1).max(pairs / 2),
        },
        GraphFilter {
            min_degree: 0,
            min_edges: pairs.saturating_sub(2),
            max_edges: usize::MAX,
        },
        GraphFilter {
            min_degree: 0,
            min_edges: 5,
            max_edges: 4,
        },
    ]
}

/// Pruning removes whole subtrees only, so the filtered run is exactly the
/// unfiltered one with the rejected graphs taken out, in the same order.
#[test]
fn filters_in_generation_equal_filtering_afterwards() {
    for n in 1..=8 {
        let everything = connected_small_graphs(n, &GraphFilter::all()).unwrap();
        for f in filters(n.max(2)) {
            let kept: Vec<SmallGraph> = everything
                .iter()
                .filter(|g| f.accepts(g))
                .copied()
                .collect();
            let generated = connected_small_graphs(n, &f).unwrap();
            assert_eq!(generated, kept, "n = {n}, {f:?}");
            assert_eq!(count_connected(n, &f).unwrap(), kept.len() as u64);
        }
    }
}

#[test]
fn filtered_counts_on_nine_vertices() {
    // Post-filtering the full n = 9 run would take the whole suite's time;
    // counts from nauty's geng instead.
    let maxwell = GraphFilter::maxwell_rods(9).with_min_degree(2);
    assert_eq!(maxwell.min_edges, 13);
    let geng_d2_e13 = count_connected(9, &maxwell).unwrap();
    let geng_d3 = count_connected(9, &GraphFilter::all().with_min_degree(3)).unwrap();
    assert_eq!((geng_d2_e13, geng_d3), (NINE_D2_E13, NINE_D3));
}

/// `nauty-geng -cu -d2 9 13:0` and `nauty-geng -cu -d3 9`.
const NINE_D2_E13: u64 = 196_904;
const NINE_D3: u64 = 84_242;

#[test]
fn maxwell_bound_for_rods() {
    assert_eq!(maxwell_rod_edges(1), 0);
    assert_eq!(maxwell_rod_edges(2), 2);
    assert_eq!(maxwell_rod_edges(3), 3);
    assert_eq!(maxwell_rod_edges(6), 8);
    assert_eq!(maxwell_rod_edges(7), 10);
    for n in 2..=12 {
        let e = maxwell_rod_edges(n);
        assert!(3 * e >= 5 * n - 6 && 3 * (e - 1) < 5 * n - 6, "n = {n}");
    }
}

#[test]
fn agrees_with_geng_reference_files() {
    let cases = [
        ("connected-n6.g6", 6, GraphFilter::all()),
        ("connected-n7.g6", 7, GraphFilter::all()),
        (
            "maxwell-mindeg2-n5.g6",
            5,
            GraphFilter::maxwell_rods(5).with_min_degree(2),
        ),
        (
            "maxwell-mindeg2-n6.g6",
            6,
            GraphFilter::maxwell_rods(6).with_min_degree(2),
        ),
        (
            "maxwell-mindeg2-n7.g6",
            7,
            GraphFilter::maxwell_rods(7).with_min_degree(2),
        ),
    ];
    for (file, n, filter) in cases {
        let geng = reference(file);
        let ours = connected_graphs(n, &filter).unwrap();
        assert_eq!(ours.len(), geng.len(), "{file}");
        assert_eq!(canonical_set(&ours), canonical_set(&geng), "{file}");
    }
}

#[test]
fn graph6_from_bitmasks_matches_graphio() {
    for n in 1..=8 {
        for g in connected_small_graphs(n, &GraphFilter::all()).unwrap() {
            let cg = g.to_contact_graph();
            let s = g.graph6();
            assert_eq!(s, to_graph6(&cg));
            assert_eq!(parse_graph6(&s).unwrap(), cg);
            assert_eq!(SmallGraph::from_contact_graph(&cg).unwrap(), g);
        }
    }
    // Orders up to the limit, with every pair present.
    for n in 1..=MAX_ORDER {
        let edges: Vec<[u32; 2]> = (1..n as u32)
            .flat_map(|j| (0..j).map(move |i| [i, j]))
            .collect();
        let cg = ContactGraph::new(n, edges).unwrap();
        let g = SmallGraph::from_contact_graph(&cg).unwrap();
        assert_eq!(g.graph6(), to_graph6(&cg));
    }
}

#[test]
fn writer_lists_and_callbacks_agree() {
    let f = GraphFilter::maxwell_rods(8).with_min_degree(2);
    let list = connected_small_graphs(8, &f).unwrap();
    let mut out = Vec::new();
    let written = write_connected_graph6(8, &f, &mut out).unwrap();
    assert_eq!(written, list.len() as u64);
    let expected: String = list.iter().map(|g| g.graph6() + "\n").collect();
    assert_eq!(String::from_utf8(out).unwrap(), expected);

    let mut seen = Vec::new();
    let called = for_each_connected(8, &f, |g| seen.push(*g)).unwrap();
    assert_eq!((called, &seen), (list.len() as u64, &list));

    let par_seen = std::sync::Mutex::new(HashSet::new());
    let par = par_for_each_connected(8, &f, |g| {
        par_seen.lock().unwrap().insert(*g);
    })
    .unwrap();
    assert_eq!(par, list.len() as u64);
    assert_eq!(
        par_seen.into_inner().unwrap(),
        list.iter().copied().collect()
    );
}

/// Folding keeps generation order: the accumulators, taken in the order
/// they are handed back, hold the graphs of the list in its order, on any
/// number of threads.
#[test]
fn folds_come_back_in_generation_order() {
    for n in [1, 4, 7, 8] {
        let f = GraphFilter::maxwell_rods(n).with_min_degree(2);
        let list = connected_small_graphs(n, &f).unwrap();
        for threads in [1, 3] {
            let mut seen: Vec<SmallGraph> = Vec::new();
            let mut parts = 0;
            let count = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    par_fold_connected(
                        n,
                        &f,
                        Vec::new,
                        |v, g| v.push(*g),
                        |v| {
                            parts += 1;
                            seen.extend(v);
                        },
                    )
                })
                .unwrap();
            assert_eq!(count, list.len() as u64);
            assert_eq!(seen, list, "n = {n}, {threads} threads");
            assert!(n < 8 || parts > 100, "{parts} accumulators");
        }
    }
}

#[test]
fn order_does_not_depend_on_threads() {
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| connected_small_graphs(8, &GraphFilter::all()).unwrap())
    };
    let one = run(1);
    assert_eq!(one.len() as u64, CONNECTED[7]);
    assert_eq!(run(2), one);
    assert_eq!(run(3), one);
}

#[test]
fn canonical_graph6_separates_every_class() {
    // Exhaustive: the classes on 7 vertices, also padded with isolated
    // vertices past the 16-vertex fast path.
    let graphs = connected_graphs(7, &GraphFilter::all()).unwrap();
    assert_eq!(canonical_set(&graphs).len(), graphs.len());
    let padded: Vec<ContactGraph> = graphs
        .iter()
        .map(|g| ContactGraph::new(20, g.edges().to_vec()).unwrap())
        .collect();
    assert_eq!(canonical_set(&padded).len(), graphs.len());
    // Past 64 vertices (multi-word rows), on the classes of order 6.
    let six = connected_graphs(6, &GraphFilter::all()).unwrap();
    let wide: Vec<ContactGraph> = six
        .iter()
        .map(|g| ContactGraph::new(70, g.edges().to_vec()).unwrap())
        .collect();
    assert_eq!(canonical_set(&wide).len(), six.len());
    for (k, g) in wide.iter().enumerate().step_by(10) {
        let moved = relabel(g, &shuffle(70, k as u64));
        assert_eq!(canonical_graph6(&moved), canonical_graph6(g));
    }
    // A canonical string is its own canonical form.
    for g in graphs.iter().chain(&padded) {
        let c = canonical_graph6(g);
        assert_eq!(canonical_graph6(&parse_graph6(&c).unwrap()), c);
    }
}

#[test]
fn canonical_graph6_of_symmetric_graphs() {
    // Petersen graph, K_{4,4}, an 18-cycle, a 3-cube: large groups, and
    // both sides of the 16-vertex boundary.
    let petersen = "IheA@GUAo";
    let k44 = ContactGraph::new(
        8,
        (0..4u32)
            .flat_map(|a| (4..8u32).map(move |b| [a, b]))
            .collect(),
    )
    .unwrap();
    let cycle = ContactGraph::new(18, (0..18u32).map(|i| [i, (i + 1) % 18]).collect()).unwrap();
    let long_cycle =
        ContactGraph::new(70, (0..70u32).map(|i| [i, (i + 1) % 70]).collect()).unwrap();
    let cube = ContactGraph::new(
        8,
        (0..8u32)
            .flat_map(|v| (0..3).map(move |b| [v, v ^ (1 << b)]))
            .filter(|[a, b]| a < b)
            .collect(),
    )
    .unwrap();
    for g in [
        parse_graph6(petersen).unwrap(),
        k44,
        cycle,
        long_cycle,
        cube,
    ] {
        let c = canonical_graph6(&g);
        for seed in 0..20u64 {
            assert_eq!(
                canonical_graph6(&relabel(&g, &shuffle(g.n_nodes(), seed))),
                c
            );
        }
    }
}

/// Two strongly regular graphs with the same parameters (16, 6, 2, 2):
/// refinement cannot tell them apart, the search must.
#[test]
fn canonical_graph6_separates_rook_and_shrikhande() {
    let on_z4 = |adjacent: &dyn Fn(i32, i32) -> bool| {
        let mut edges = Vec::new();
        for u in 0..16u32 {
            for v in u + 1..16 {
                let (du, dv) = (
                    (v / 4) as i32 - (u / 4) as i32,
                    (v % 4) as i32 - (u % 4) as i32,
                );
                if adjacent(du.rem_euclid(4), dv.rem_euclid(4)) {
                    edges.push([u, v]);
                }
            }
        }
        ContactGraph::new(16, edges).unwrap()
    };
    let rook = on_z4(&|a, b| (a == 0) != (b == 0));
    let shrikhande =
        on_z4(&|a, b| matches!((a, b), (0, 1) | (0, 3) | (1, 0) | (3, 0) | (1, 1) | (3, 3)));
    assert!((0..16).all(|v| rook.degree(v) == 6 && shrikhande.degree(v) == 6));
    let (r, s) = (canonical_graph6(&rook), canonical_graph6(&shrikhande));
    assert_ne!(r, s);
    for seed in 0..10 {
        assert_eq!(canonical_graph6(&relabel(&rook, &shuffle(16, seed))), r);
        assert_eq!(
            canonical_graph6(&relabel(&shrikhande, &shuffle(16, seed))),
            s
        );
    }
}

/// A permutation of `0..n` from a seed (splitmix64 + Fisher–Yates).
fn shuffle(n: usize, seed: u64) -> Vec<u32> {
    let mut state = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
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

fn relabel(g: &ContactGraph, p: &[u32]) -> ContactGraph {
    let edges = g
        .edges()
        .iter()
        .map(|&[a, b]| [p[a as usize], p[b as usize]])
        .collect();
    ContactGraph::new(g.n_nodes(), edges).unwrap()
}

fn graph_strategy() -> impl Strategy<Value = (ContactGraph, u64)> {
    (1usize..=24).prop_flat_map(|n| {
        let pairs = n * (n - 1) / 2;
        (
            proptest::collection::vec(any::<bool>(), pairs),
            0.05f64..0.95,
            any::<u64>(),
        )
            .prop_map(move |(bits, density, seed)| {
                let threshold = (density * 64.0) as u64;
                let mut edges = Vec::new();
                let mut k = 0;
                for j in 1..n as u32 {
                    for i in 0..j {
                        let coin = bits[k] as u64 * 40 + (seed.rotate_left(k as u32) & 63);
                        if coin % 64 < threshold {
                            edges.push([i, j]);
                        }
                        k += 1;
                    }
                }
                (ContactGraph::new(n, edges).unwrap(), seed)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn canonical_graph6_is_invariant_under_relabelling((g, seed) in graph_strategy()) {
        let c = canonical_graph6(&g);
        let h = relabel(&g, &shuffle(g.n_nodes(), seed));
        prop_assert_eq!(canonical_graph6(&h), c.clone());
        // The canonical graph is isomorphic to the input: same degree sequence.
        let back = parse_graph6(&c).unwrap();
        let degrees = |g: &ContactGraph| {
            let mut d: Vec<usize> = (0..g.n_nodes() as u32).map(|v| g.degree(v)).collect();
            d.sort_unstable();
            d
        };
        prop_assert_eq!(degrees(&back), degrees(&g));
    }

    #[test]
    fn typed_canonical_form_is_invariant(index in 0usize..10_000, seed in any::<u64>()) {
        let patterns = sharing_patterns();
        let p = &patterns[index % patterns.len()];
        let q = scramble(p, seed);
        prop_assert!(q.validate().is_ok());
        prop_assert_eq!(canonical_pattern(&q), p.clone());
    }
}

// ---------------------------------------------------------------- typed --

fn sharing_patterns() -> &'static Vec<Pattern> {
    static CACHE: std::sync::OnceLock<Vec<Pattern>> = std::sync::OnceLock::new();
    CACHE.get_or_init(|| {
        let mut f = TypedFilter::new(3);
        f.rod_sharing = true;
        f.max_mult_body_body = 2;
        let mut all = typed_patterns(&f).unwrap();
        f.nodes = 4;
        f.kinds = vec![NodeKind::Rod, NodeKind::Spatial];
        f.max_mult_rod_body = 1;
        f.max_mult_body_body = 1;
        all.extend(typed_patterns(&f).unwrap());
        all
    })
}

/// The same pattern relabelled: nodes permuted, each body's rod labels
/// permuted, contacts shuffled and turned around.
fn scramble(p: &Pattern, seed: u64) -> Pattern {
    let n = p.n_nodes();
    let perm = shuffle(n, seed);
    let mut kinds = vec![NodeKind::Rod; n];
    for (i, &k) in p.kinds.iter().enumerate() {
        kinds[perm[i] as usize] = k;
    }
    let label_perms: Vec<Vec<u32>> = (0..n)
        .map(|i| {
            if p.kinds[i].is_body() {
                shuffle(2 * p.contacts.len() + 1, seed ^ ((i as u64 + 1) * 7919))
            } else {
                vec![0]
            }
        })
        .collect();
    let order = shuffle(p.contacts.len(), seed.rotate_left(17));
    let contacts = order
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let c = p.contacts[c as usize];
            let end = |s: usize| {
                let node = c.nodes[s] as usize;
                (
                    perm[node] as u8,
                    label_perms[node][c.rods[s] as usize] as u8,
                )
            };
            let (a, b) = if (seed >> (k % 64)) & 1 == 1 {
                (end(1), end(0))
            } else {
                (end(0), end(1))
            };
            PatternContact {
                nodes: [a.0, b.0],
                rods: [a.1, b.1],
            }
        })
        .collect();
    Pattern { kinds, contacts }
}

fn count(f: &TypedFilter) -> usize {
    typed_patterns(f).unwrap().len()
}

#[test]
fn two_nodes_by_hand() {
    // Pairs of kinds with the multiplicities they allow (at least 2
    // contacts per node): rod-planar 2, rod-spatial 2, planar-planar 2 and
    // 3, planar-spatial 2 and 3, spatial-spatial 2 and 3; rod-rod has 1.
    let mut f = TypedFilter::new(2);
    assert_eq!(count(&f), 8);
    // Maxwell: 3c >= 5 + 6 - 6 and 3c >= 6: every one of them passes.
    f.maxwell = true;
    assert_eq!(count(&f), 8);
    f.maxwell = false;
    // One contact per node admits rod-rod 1 and every multiplicity 1.
    f.min_contacts_per_node = 1;
    assert_eq!(count(&f), 8 + 1 + 5);
    f.min_contacts_per_node = 2;
    // Rod sharing: a body's two ends towards one rod may not share; between
    // two bodies, m = 2 gives {none shared, one side shared} (the sides are
    // exchangeable for equal kinds: 2 classes, else 3) and m = 3 gives
    // block counts (1,3), (3,3), (3,2), (2,2) up to exchange (4 classes,
    // else 6). Total 1 + 1 + (2 + 4) + (3 + 6) + (2 + 4).
    f.rod_sharing = true;
    assert_eq!(count(&f), 23);
    // Bodies only, one kind, multiplicity at most 2: none shared or one side shared.
    f.kinds = vec![NodeKind::Spatial];
    f.max_mult_body_body = 2;
    assert_eq!(count(&f), 2);
}

#[test]
fn rods_only_match_simple_graphs_with_min_degree_two() {
    for n in 1..=6 {
        let mut f = TypedFilter::new(n);
        f.kinds = vec![NodeKind::Rod];
        let simple = GraphFilter::all().with_min_degree(2);
        assert_eq!(
            count(&f) as u64,
            count_connected(n, &simple).unwrap(),
            "n = {n}"
        );
        f.maxwell = true;
        let maxwell = GraphFilter::maxwell_rods(n).with_min_degree(2);
        assert_eq!(
            count(&f) as u64,
            count_connected(n, &maxwell).unwrap(),
            "n = {n}"
        );
        // Rods have one rod each: nothing to share.
        f.rod_sharing = true;
        assert_eq!(
            count(&f) as u64,
            count_connected(n, &maxwell).unwrap(),
            "n = {n}"
        );
    }
}

/// Typed multigraphs on three nodes by brute force: every labelled kind
/// assignment and multiplicity matrix, keyed by its smallest image under
/// all six node permutations.
#[test]
fn three_nodes_against_brute_force() {
    let all = [NodeKind::Rod, NodeKind::Planar, NodeKind::Spatial];
    for (rb, bb, min) in [(2, 3, 2), (1, 1, 1), (2, 2, 3), (3, 2, 2)] {
        let mut f = TypedFilter::new(3);
        f.max_mult_rod_body = rb;
        f.max_mult_body_body = bb;
        f.min_contacts_per_node = min;
        let bound = |a: NodeKind, b: NodeKind| match (a.is_body(), b.is_body()) {
            (false, false) => 1,
            (true, true) => bb,
            _ => rb,
        };
        let pairs = [(0, 1), (0, 2), (1, 2)];
        let perms = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let mut classes = BTreeSet::new();
        for k in 0..27 {
            let kinds = [all[k % 3], all[k / 3 % 3], all[k / 9]];
            for m in 0..(bb.max(rb) + 1).pow(3) {
                let mult = [
                    m % (bb.max(rb) + 1),
                    m / (bb.max(rb) + 1) % (bb.max(rb) + 1),
                    m / (bb.max(rb) + 1).pow(2),
                ];
                let ok = pairs
                    .iter()
                    .zip(&mult)
                    .all(|(&(a, b), &x)| x <= bound(kinds[a], kinds[b]));
                let edges = mult.iter().filter(|&&x| x > 0).count();
                let at = |v: usize| -> usize {
                    pairs
                        .iter()
                        .zip(&mult)
                        .filter(|((a, b), _)| *a == v || *b == v)
                        .map(|(_, &x)| x)
                        .sum()
                };
                if !ok || edges < 2 || (0..3).any(|v| at(v) < min) {
                    continue;
                }
                let key = perms
                    .iter()
                    .map(|p| {
                        let mut k2 = [NodeKind::Rod; 3];
                        for i in 0..3 {
                            k2[p[i]] = kinds[i];
                        }
                        let mut m2 = BTreeMap::new();
                        for (&(a, b), &x) in pairs.iter().zip(&mult) {
                            let (c, d) = (p[a].min(p[b]), p[a].max(p[b]));
                            m2.insert((c, d), x);
                        }
                        (k2, m2.into_values().collect::<Vec<_>>())
                    })
                    .min()
                    .unwrap();
                classes.insert(key);
            }
        }
        assert_eq!(
            count(&f),
            classes.len(),
            "rod-body {rb}, body-body {bb}, min {min}"
        );
    }
}

#[test]
fn typed_outputs_are_valid_canonical_distinct_and_filtered() {
    let mut f = TypedFilter::new(3);
    f.rod_sharing = true;
    f.kinds = vec![NodeKind::Rod, NodeKind::Spatial];
    f.max_mult_body_body = 2;
    f.maxwell = true;
    let mut plain = f.clone();
    plain.rod_sharing = false;
    let shared = typed_patterns(&f).unwrap();
    let unshared = typed_patterns(&plain).unwrap();
    assert!(unshared.len() < shared.len());
    let set: HashSet<&Pattern> = shared.iter().collect();
    assert_eq!(set.len(), shared.len(), "duplicates");
    // Without sharing is a subset of with sharing.
    assert!(unshared.iter().all(|p| set.contains(p)));
    for p in &shared {
        p.validate().unwrap();
        assert_eq!(&canonical_pattern(p), p);
        assert_eq!(p.n_nodes(), 3);
        assert!(p.kinds.iter().all(|k| f.kinds.contains(k)));
        assert!(p.maxwell());
        for a in 0..3u8 {
            let at = p.contacts.iter().filter(|c| c.nodes.contains(&a)).count();
            assert!(at >= 2);
            for b in a + 1..3u8 {
                let m = p.multiplicity(a, b);
                let limit = match (p.kinds[a as usize].is_body(), p.kinds[b as usize].is_body()) {
                    (false, false) => 1,
                    (true, true) => f.max_mult_body_body,
                    _ => f.max_mult_rod_body,
                };
                assert!(m <= limit);
            }
        }
        let linked = (0..3u8).all(|a| p.contacts.iter().any(|c| c.nodes.contains(&a)));
        assert!(linked);
    }
    // Deterministic order.
    assert_eq!(typed_patterns(&f).unwrap(), shared);
}

#[test]
fn typed_filter_errors() {
    assert!(typed_patterns(&TypedFilter::new(0)).is_err());
    let mut f = TypedFilter::new(2);
    f.kinds.clear();
    assert!(typed_patterns(&f).is_err());
    // Past what a pattern holds: 21 pairs of 7 nodes with up to 5 contacts.
    let mut f = TypedFilter::new(7);
    f.max_mult_body_body = 5;
    assert!(typed_patterns(&f).is_err());
    f.max_mult_body_body = 99;
    assert!(typed_patterns(&TypedFilter { nodes: 2, ..f }).is_err());
}

#[test]
fn canonical_pattern_tells_collinear_from_general() {
    // A rod touching a body twice on distinct rods, against on one rod: the
    // second is invalid (a rod touches another at most once) and comes back
    // as it is; a body-body pair sharing on one side differs from none.
    let contact = |a, ra, b, rb| PatternContact {
        nodes: [a, b],
        rods: [ra, rb],
    };
    let general = Pattern {
        kinds: vec![NodeKind::Planar, NodeKind::Planar],
        contacts: vec![contact(0, 0, 1, 0), contact(0, 1, 1, 1)],
    };
    let shared = Pattern {
        kinds: vec![NodeKind::Planar, NodeKind::Planar],
        contacts: vec![contact(0, 0, 1, 0), contact(0, 0, 1, 1)],
    };
    let other_side = Pattern {
        kinds: vec![NodeKind::Planar, NodeKind::Planar],
        contacts: vec![contact(1, 5, 0, 2), contact(1, 5, 0, 7)],
    };
    assert_ne!(canonical_pattern(&general), canonical_pattern(&shared));
    assert_eq!(canonical_pattern(&shared), canonical_pattern(&other_side));
    let invalid = Pattern {
        kinds: vec![NodeKind::Rod, NodeKind::Planar],
        contacts: vec![contact(0, 0, 1, 3), contact(0, 0, 1, 3)],
    };
    assert_eq!(canonical_pattern(&invalid), invalid);
}
