//! Mining the rigidity 3D-RGC misses: minimal sets found by truth, their
//! patterns, the rule file they make, and `rgc mine` on the command line.

use std::collections::HashSet;
use std::path::Path;

use crate::cli::{fails, rgc};
use std::sync::OnceLock;

use rgc::contacts::{self, Contact};
use rgc::engine::{CompiledRule, Engine, RuleSet};
use rgc::graph::ContactGraph;
use rgc::mine::{self, MinimalSet, Parameters, Report, Search};
use rgc::progress::Silent;
use rgc::rigidity::check_exact;
use rgc::rods::{RodParams, RodSystem};
use rgc::rule_file::{self, RULE_SEED, load_rules, write_rules};
use rgc::truth::{Topology, TruthOptions, truth};

/// A search small enough for tests.
const SMALL: Search = Search {
    pairs: 1,
    max_radius: 2,
    max_ball_rods: 400,
};

/// The quotient of one `sound` run, as `mine` numbers it: the bodies in
/// the run's order, then the free rods in rod order.
fn quotient(graph: &ContactGraph, seed: u64) -> Vec<Vec<u32>> {
    let run = Engine::base(RuleSet::Sound).runs(graph, seed, 1).remove(0);
    let mut nodes: Vec<Vec<u32>> = run.bodies.iter().map(|b| b.rods.clone()).collect();
    let in_body: HashSet<u32> = nodes.iter().flatten().copied().collect();
    nodes.extend(
        (0..graph.n_nodes() as u32)
            .filter(|r| !in_body.contains(r))
            .map(|r| vec![r]),
    );
    nodes
}

/// Truth (with twins) on the rods of `nodes` and the contacts among them,
/// in the box when `contacts` are given: the clusters, in global rods.
fn clusters_of(
    graph: &ContactGraph,
    contacts: Option<&[Contact]>,
    quotient: &[Vec<u32>],
    nodes: &[u32],
) -> Vec<Vec<u32>> {
    let mut rods: Vec<u32> = nodes
        .iter()
        .flat_map(|&x| quotient[x as usize].iter().copied())
        .collect();
    rods.sort_unstable();
    let mut edges = Vec::new();
    let mut shifts = Vec::new();
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        if let (Ok(i), Ok(j)) = (rods.binary_search(&a), rods.binary_search(&b)) {
            edges.push([i as u32, j as u32]);
            if let Some(c) = contacts {
                shifts.push(c[e].shift);
            }
        }
    }
    let sub = ContactGraph::new(rods.len(), edges).unwrap();
    let topo = match contacts {
        Some(_) => Topology::periodic(&sub, &shifts).unwrap(),
        None => Topology::finite(&sub),
    };
    let t = truth(&topo, TruthOptions::default());
    assert!(t.decided(), "{:?}", t.outcome.reason());
    t.clusters
        .iter()
        .map(|c| c.rods.iter().map(|&k| rods[k as usize]).collect())
        .collect()
}

/// Whether some cluster holds every rod of the nodes `held`.
fn holds(clusters: &[Vec<u32>], quotient: &[Vec<u32>], held: &[u32]) -> bool {
    clusters.iter().any(|c| {
        held.iter()
            .flat_map(|&x| &quotient[x as usize])
            .all(|r| c.binary_search(r).is_ok())
    })
}

/// What a set keeps: the whole set in one cluster with its pair, or (a
/// set that only holds the pair together) the pair in one cluster.
fn keeps(
    graph: &ContactGraph,
    contacts: Option<&[Contact]>,
    quotient: &[Vec<u32>],
    set: &MinimalSet,
    nodes: &[u32],
) -> bool {
    let clusters = clusters_of(graph, contacts, quotient, nodes);
    holds(
        &clusters,
        quotient,
        if set.whole { nodes } else { &set.pair[..] },
    )
}

/// Every node but the pair is needed: without it, truth no longer keeps
/// what the set kept.
fn assert_minimal(
    graph: &ContactGraph,
    contacts: Option<&[Contact]>,
    quotient: &[Vec<u32>],
    set: &MinimalSet,
) {
    assert!(keeps(graph, contacts, quotient, set, &set.nodes), "{set:?}");
    for &x in set.nodes.iter().filter(|x| !set.pair.contains(x)) {
        let rest: Vec<u32> = set.nodes.iter().copied().filter(|&y| y != x).collect();
        assert!(
            !keeps(graph, contacts, quotient, set, &rest),
            "node {x} of {:?} can go",
            set.nodes
        );
    }
}

/// The locked hinge of `tests/it/truth.rs`: two rod triangles on a shared
/// rod, locked by a third triangle touching one rod of each. Truth holds
/// the five hinge rods in one cluster that `sound` leaves as a body and two
/// rods. The minimal set that holds the body and a rod together needs the
/// locking triangle, which touches the rest at two points and turns about
/// the line through them: the set is not whole, its pattern has one degree
/// of freedom, and no rule (which merges all of its nodes) can express the
/// lock. The two free rods alone are held by the body's shared rod (their
/// triangle is a plane turning about it): not whole either.
#[test]
fn a_locked_hinge_is_mined_with_its_turning_lock() {
    let g = crate::truth::locked_hinge();
    assert_eq!(rgc::graph::io::to_graph6(&g), "G{d?gK");
    let mined = mine::mine_graph(&g, 1, &Search::default());
    assert_eq!(mined.counts.missed_clusters, 1);
    assert_eq!(mined.sets.len(), 2, "{:?}", mined.sets);
    let q = quotient(&g, 1);
    let sound = Engine::base(RuleSet::Sound);
    for set in &mined.sets {
        assert!(!set.whole);
        assert_minimal(&g, None, &q, set);
        let pattern = set.pattern.as_ref().unwrap();
        let v = check_exact(pattern, RULE_SEED).unwrap();
        assert_eq!(v.dof, Some(1), "{:?}", set.canonical);
        assert!(!sound.compresses(pattern, 32).unwrap());
    }
    let lock = mined.sets.iter().find(|s| s.nodes.len() == 4).unwrap();
    assert_eq!(lock.rods, (0..8).collect::<Vec<u32>>());
    assert_eq!(lock.held_rods, vec![0, 1, 2, 3, 4]);
    let hinge = mined.sets.iter().find(|s| s.nodes.len() == 3).unwrap();
    assert_eq!(hinge.rods, vec![0, 1, 2, 3, 4]);
    assert_eq!(hinge.held_rods, vec![3, 4]);
}

/// A rods-only motif the audit found missed (`motifs/rods-6.json`), given
/// as a whole graph: the engine compresses nothing, truth holds all six
/// rods, and mining gives back exactly that motif, rigid on every component,
/// which the engine compresses once it is a rule.
#[test]
fn a_missed_rigid_motif_is_mined_whole_and_the_engine_uses_its_rule() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs/rods-6.json");
    let audit = load_rules(&[path]).unwrap().remove(0);
    let (g, bodies, _) = audit.pattern.to_host().unwrap();
    assert!(bodies.is_empty());
    let mined = mine::mine_graph(&g, 1, &Search::default());
    assert_eq!(mined.sets.len(), 1, "{:?}", mined.sets);
    let set = &mined.sets[0];
    assert!(set.whole);
    assert_eq!(set.rods, (0..6).collect::<Vec<u32>>());
    assert_eq!(set.canonical.as_deref(), Some(audit.canonical.as_str()));
    assert_minimal(&g, None, &quotient(&g, 1), set);
    let pattern = set.pattern.clone().unwrap();
    assert_eq!(check_exact(&pattern, RULE_SEED).unwrap().class, "rigid");
    assert!(
        !Engine::base(RuleSet::Sound)
            .compresses(&pattern, 32)
            .unwrap()
    );
    let rule = rule_file::Rule::new("mined-0".into(), pattern.clone(), Default::default()).unwrap();
    let compiled = [CompiledRule::new(&rule)];
    assert!(
        Engine::with_rules(RuleSet::Sound, &compiled)
            .compresses(&pattern, 32)
            .unwrap()
    );
}

fn system(box_len: f64, rho: f64, seed: u64) -> (Vec<Contact>, ContactGraph) {
    let sys = RodSystem::generate(RodParams::new(23.0, box_len, rho).unwrap(), seed);
    let found = contacts::detect(&sys);
    let graph = ContactGraph::from_contacts(sys.len(), &found);
    (found, graph)
}

/// In a generated system every mined set is minimal by truth in the box,
/// whole or not, and its rods are those of its nodes.
#[test]
fn mined_sets_of_a_generated_system_are_minimal_by_truth() {
    let (found, graph) = system(3.0, 36.0, 2);
    let (report, sets) = mine::mine_system(23.0, 3.0, 36.0, 2, &SMALL).unwrap();
    let q = quotient(&graph, 2);
    assert_eq!(report.counts.nodes, q.len());
    assert_eq!(report.counts.sets, sets.len());
    assert!(sets.iter().any(|s| s.whole) && sets.iter().any(|s| !s.whole));
    for set in &sets {
        let mut rods: Vec<u32> = set
            .nodes
            .iter()
            .flat_map(|&x| q[x as usize].clone())
            .collect();
        rods.sort_unstable();
        assert_eq!(rods, set.rods);
        assert!(set.pair.iter().all(|x| set.held.contains(x)));
        assert_eq!(set.whole, set.held == set.nodes);
        assert_minimal(&graph, Some(&found), &q, set);
    }
}

fn small_parameters() -> Parameters {
    Parameters {
        gamma: 23.0,
        box_len: 3.0,
        densities: vec![34.0, 36.0],
        systems: 2,
        seed: 1,
        search: SMALL,
        runs: 16,
        top: 10,
        extended: Vec::new(),
    }
}

/// A mining run with `threads` rayon threads, its timings zeroed.
fn mined_with(threads: usize) -> Report {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut r = pool
        .install(|| mine::run(&small_parameters(), &[], "test", &Silent))
        .unwrap();
    r.seconds = 0.0;
    for s in &mut r.systems {
        s.seconds = 0.0;
    }
    r
}

fn one_thread() -> &'static Report {
    static REPORT: OnceLock<Report> = OnceLock::new();
    REPORT.get_or_init(|| mined_with(1))
}

#[test]
fn mining_is_the_same_for_one_and_two_threads() {
    let one = one_thread();
    assert_eq!(one.systems.len(), 4);
    assert!(one.motifs.iter().any(|m| m.candidate));
    assert_eq!(*one, mined_with(2));
}

/// The counts add up: per density, the systems' sets over the patterns,
/// and the most frequent pattern first.
#[test]
fn a_report_counts_every_set_once() {
    let r = one_thread();
    for (d, summary) in r.densities.iter().enumerate() {
        let sets: usize = r
            .systems
            .iter()
            .filter(|s| s.density == summary.density)
            .map(|s| s.counts.sets - s.counts.too_large)
            .sum();
        let counted: u64 = r.motifs.iter().map(|m| m.per_density[d].occurrences).sum();
        assert_eq!(sets as u64, counted);
        assert_eq!(summary.pairs, summary.found + summary.not_local);
    }
    assert!(
        r.motifs
            .windows(2)
            .all(|w| w[0].occurrences >= w[1].occurrences)
    );
    for m in &r.motifs {
        assert_eq!(m.candidate, m.class == "rigid" && !m.sound_compresses);
        assert_eq!(
            m.occurrences,
            m.per_density.iter().map(|f| f.occurrences).sum::<u64>()
        );
    }
}

/// The rules written are the top candidates, load back (re-verified by
/// exact rank) unchanged with their frequencies, and let the engine
/// compress each mined pattern that `sound` alone leaves apart.
#[test]
fn the_rule_file_round_trips_and_the_engine_compresses_with_it() {
    let r = one_thread();
    let rules = mine::rules(r).unwrap();
    let candidates: Vec<_> = r.motifs.iter().filter(|m| m.candidate).collect();
    assert_eq!(rules.len(), candidates.len().min(10));
    assert!(!rules.is_empty());
    let dir = crate::scratch("mine-rules");
    let path = dir.join("mined.json");
    write_rules(&path, &rules).unwrap();
    let loaded = load_rules(&[path]).unwrap();
    assert_eq!(loaded, rules);
    let compiled: Vec<CompiledRule> = loaded.iter().map(CompiledRule::new).collect();
    let with = Engine::with_rules(RuleSet::Sound, &compiled);
    for (rule, m) in loaded.iter().zip(&candidates) {
        assert_eq!(rule.provenance.source, "mined");
        assert_eq!(rule.provenance.frequency, m.per_density);
        assert_eq!(rule.canonical, m.canonical);
        assert!(with.compresses(&rule.pattern, 32).unwrap(), "{}", rule.id);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn mine_refuses_bad_input_before_any_work() {
    let dir = crate::scratch("mine-cli-bad");
    let out = dir.join("mined.json");
    let results = dir.join("results");
    let with = |extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = ["mine", "--quiet", "--extended", ""]
            .iter()
            .map(|s| s.to_string())
            .collect();
        a.extend(["--out".into(), out.display().to_string()]);
        a.extend(["--results".into(), results.display().to_string()]);
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let check = |extra: &[&str], needle: &str| {
        let a = with(extra);
        fails(&a.iter().map(String::as_str).collect::<Vec<_>>(), needle);
    };
    check(&["--densities", "30,0"], "density must be a positive");
    check(&["--densities", "30,-4"], "density must be a positive");
    check(&["--box", "0"], "box must be a positive");
    check(&["--box", "1.5"], "too small");
    check(&["--densities", ""], "invalid value");
    check(&["--densities", "30,30"], "given twice");
    check(&["--systems", "0"], "at least one system");
    check(&["--pairs", "0"], "at least one seed pair");
    check(&["--runs", "0"], "at least one motif order");
    let a = [
        "mine",
        "--quiet",
        "--extended",
        "",
        "--out",
        dir.to_str().unwrap(),
    ];
    fails(&a, "is a directory");
    std::fs::write(dir.join("plain"), "").unwrap();
    let inside = dir.join("plain").join("results");
    let a = [
        "mine",
        "--quiet",
        "--extended",
        "",
        "--out",
        out.to_str().unwrap(),
        "--results",
        inside.to_str().unwrap(),
    ];
    fails(&a, "plain");
    // A rule file that mining did not make is not replaced.
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs/base.json"),
        &out,
    )
    .unwrap();
    check(&[], "not mined with these parameters");
    assert!(!results.join("mined-motifs.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A small run writes its rule file and tables, records its command, and
/// refuses to be replaced by a run with other parameters unless forced.
#[test]
fn mine_writes_its_files_and_guards_them() {
    let dir = crate::scratch("mine-cli-run");
    let out = dir.join("mined.json");
    let results = dir.join("results");
    let repo = |p: &str| Path::new(env!("CARGO_MANIFEST_DIR")).join(p);
    let extended = format!(
        "{},{}",
        repo("motifs/rods-6.json").display(),
        repo("motifs/mixed-4.json").display()
    );
    let args = |seed: &str, force: bool| -> Vec<String> {
        let mut a: Vec<String> = [
            "mine",
            "--box",
            "3",
            "--densities",
            "36",
            "--systems",
            "1",
            "--seed",
            seed,
            "--pairs",
            "1",
            "--max-radius",
            "2",
            "--max-ball-rods",
            "400",
            "--runs",
            "8",
            "--json",
            "--extended",
            &extended,
            "--out",
            out.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        if force {
            a.push("--force".into());
        }
        a
    };
    let run = |a: Vec<String>| rgc(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let first = run(args("2", false));
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&first.stdout).unwrap();
    assert!(
        v["command"]
            .as_str()
            .unwrap()
            .starts_with("rgc mine --box 3")
    );
    assert_eq!(v["parameters"]["densities"], serde_json::json!([36.0]));
    assert!(v["motifs"].as_array().is_some_and(|m| !m.is_empty()));
    assert!(v["motifs"][0]["extended_compresses"].is_boolean());
    for name in ["mined-motifs.json", "mined-motifs.csv", "mined-motifs.md"] {
        assert!(results.join(name).is_file(), "{name}");
    }
    let written: Report =
        serde_json::from_str(&std::fs::read_to_string(results.join("mined-motifs.json")).unwrap())
            .unwrap();
    assert_eq!(serde_json::to_value(&written).unwrap(), v);
    let rules = load_rules(std::slice::from_ref(&out)).unwrap();
    assert_eq!(
        rules.len(),
        written.motifs.iter().filter(|m| m.rule.is_some()).count()
    );
    // The same parameters may replace it; others may not, unless forced.
    assert!(run(args("2", false)).status.success());
    let refused = run(args("3", false));
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--force"));
    assert!(run(args("3", true)).status.success());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Mined rules are rigid on every component as patterns, yet no more sound
/// on whole systems than the base motifs: on one committed sequence (gamma
/// 23, L = 3, found where `sound + mined` first spans below truth in the
/// `rgc bias` study), the mined rules make a spanning body (100 of the
/// system's 829 rods) in every motif order, which lies in no true rigid
/// cluster (at most 65 of its rods share one); `sound` alone
/// does not span there, truth does not, and certifying against the box
/// removes the span.
#[test]
fn mined_rules_can_span_falsely_where_certification_does_not() {
    use rgc::engine::run_seed;
    let rules: Vec<CompiledRule> =
        load_rules(&[Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs/mined.json")])
            .unwrap()
            .iter()
            .map(CompiledRule::new)
            .collect();
    let (seed, n) = (3454578912086077735, 829);
    let p = crate::truth::Prefix::new(seed, n);
    assert_eq!(p.truth.spanning, Some(false));
    let seed_n = run_seed(seed, n as u64);
    let sound = Engine::base(RuleSet::Sound).runs(&p.graph, seed_n, 8);
    assert!(
        sound
            .iter()
            .all(|r| r.bodies.iter().all(|b| !p.spans(&b.rods)))
    );
    let mined = Engine::with_rules(RuleSet::Sound, &rules).runs(&p.graph, seed_n, 8);
    for (k, run) in mined.into_iter().enumerate() {
        assert!(run.motifs.rules > 0, "run {k} applied no mined rule");
        let false_body = run
            .bodies
            .iter()
            .find(|b| p.spans(&b.rods))
            .expect("a spanning body");
        assert!(
            !p.in_true_cluster(&false_body.rods),
            "run {k}: the spanning body lies in a true cluster"
        );
        let run = rgc::engine::certify::certify(&p.topology(), run, run_seed(seed_n, k as u64));
        assert!(
            run.bodies.iter().all(|b| !p.spans(&b.rods)),
            "certified run {k} spans"
        );
    }
}

/// The rods-6 motif of `motifs/rods-6.json` (0-1, 0-2, 1-3, 1-4, 2-4, 0-5,
/// 3-5, 4-5): rigid as a whole, while no five of its rods hold any two
/// together (`rgc truth --edges` on each: no cluster). The engine leaves
/// its six rods apart.
fn rods_6() -> ContactGraph {
    let edges = [
        [0, 1],
        [0, 2],
        [1, 3],
        [1, 4],
        [2, 4],
        [0, 5],
        [3, 5],
        [4, 5],
    ];
    ContactGraph::new(6, edges.to_vec()).unwrap()
}

/// `g` mined as a finite framework (seed 1) within these caps.
fn mined_within(
    g: &ContactGraph,
    pairs: usize,
    max_radius: usize,
    max_ball_rods: usize,
) -> mine::Mined {
    let search = Search {
        pairs,
        max_radius,
        max_ball_rods,
    };
    mine::mine_graph(g, 1, &search)
}

/// Not-local accounting on the rods-6 motif, every one of its eight
/// contacts a seed pair: four pairs ({0,1}, {1,4}, {0,5}, {4,5}) see all six
/// rods one layer out, the other four need two layers. With one layer the
/// first four find the motif and the others count beyond the radius; with
/// five rods per ball every pair counts beyond the rods (one layer out is
/// six rods for the first four; five that hold nothing, then six, for the
/// others); with six rods and two layers all eight find it. Nothing is
/// exhausted: every rod is in the missed cluster.
#[test]
fn pairs_not_local_within_the_caps_are_counted_as_such() {
    let g = rods_6();
    let counted = |max_radius, max_ball_rods| {
        let c = mined_within(&g, 8, max_radius, max_ball_rods).counts;
        assert_eq!((c.bodies, c.nodes), (0, 6));
        assert_eq!(
            (c.missed_clusters, c.missed_rods, c.unseeded_clusters),
            (1, 6, 0)
        );
        assert_eq!((c.pairs, c.exhausted, c.too_large), (8, 0, 0));
        (c.found, c.beyond_radius, c.beyond_rods, c.sets)
    };
    assert_eq!(counted(1, 800), (4, 4, 0, 1));
    assert_eq!(counted(3, 5), (0, 0, 8, 0));
    assert_eq!(counted(2, 6), (8, 0, 0, 1));
    assert_eq!(counted(1, 6), (4, 4, 0, 1));
}

/// 27 rods and 43 contacts, triangle free, rigid as a whole (`rgc truth
/// --edges`: DOF 0, one cluster of 27 rods) while no 26 of them hold any two
/// together (each rod left out in turn: no cluster): Maxwell's count
/// `3 m = 5 n - 6` with no rigid part.
fn rigid_27() -> ContactGraph {
    let edges = [
        [0, 9],
        [0, 19],
        [0, 22],
        [1, 6],
        [1, 13],
        [2, 4],
        [2, 8],
        [2, 19],
        [3, 9],
        [3, 23],
        [4, 15],
        [5, 7],
        [5, 10],
        [5, 20],
        [6, 16],
        [6, 20],
        [7, 9],
        [7, 15],
        [7, 21],
        [8, 10],
        [8, 24],
        [8, 25],
        [9, 13],
        [9, 20],
        [9, 24],
        [10, 21],
        [11, 21],
        [11, 23],
        [11, 26],
        [12, 15],
        [12, 16],
        [12, 23],
        [13, 18],
        [13, 19],
        [14, 16],
        [14, 17],
        [16, 25],
        [17, 24],
        [17, 26],
        [18, 22],
        [18, 26],
        [20, 26],
        [22, 25],
    ];
    ContactGraph::new(27, edges.to_vec()).unwrap()
}

/// Every seed pair of the 27 rods needs all of them: the one minimal set
/// has 27 nodes, more than a pattern holds (24), so it counts as too large,
/// with no pattern and no canonical form. Capped at one layer, or at 26
/// rods per ball, each of the three seed pairs (3 per started ten nodes)
/// counts as not local instead, and no set is found.
#[test]
fn a_minimal_set_beyond_the_pattern_sizes_is_counted_too_large() {
    let g = rigid_27();
    let mine_with = |max_radius, max_ball_rods| mined_within(&g, 1, max_radius, max_ball_rods);
    let mined = mine_with(27, 800);
    let c = &mined.counts;
    assert_eq!(
        (c.bodies, c.nodes, c.missed_clusters, c.missed_rods),
        (0, 27, 1, 27)
    );
    assert_eq!((c.pairs, c.found, c.sets, c.too_large), (3, 3, 1, 1));
    assert_eq!((c.beyond_radius, c.beyond_rods, c.exhausted), (0, 0, 0));
    let set = &mined.sets[0];
    assert_eq!(set.nodes, (0..27).collect::<Vec<u32>>());
    assert!(set.whole);
    assert_eq!((set.pattern.as_ref(), set.canonical.as_ref()), (None, None));
    assert_eq!(rgc::pattern::MAX_PATTERN_NODES, 24);

    // (pairs, found, beyond the radius, beyond the rods, sets, too large)
    let capped = |max_radius, max_ball_rods| {
        let c = mine_with(max_radius, max_ball_rods).counts;
        let all = (c.pairs, c.found, c.beyond_radius, c.beyond_rods, c.sets);
        (all, c.too_large)
    };
    assert_eq!(capped(1, 800), ((3, 0, 3, 0, 0), 0));
    assert_eq!(capped(27, 26), ((3, 0, 0, 3, 0), 0));
}
