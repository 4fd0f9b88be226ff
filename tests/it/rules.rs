//! Motif rules: the base motifs written as rules, loaded and matched by the
//! generic matcher, compress like the built-in engine.

use rgc::contacts::detect;
use rgc::engine::examples::random_graph;
use rgc::engine::shapes::base_rules;
use rgc::engine::{CompiledRule, Compression, Engine, Matching, RuleSet};
use rgc::graph::ContactGraph;
use rgc::rods::{RodParams, RodSystem};

fn generic() -> Vec<CompiledRule> {
    base_rules()
        .unwrap()
        .0
        .iter()
        .map(CompiledRule::new)
        .collect()
}

/// Each engine's result is a fixpoint of the other: neither finds a motif the other left.
fn agree(g: &ContactGraph, rules: &[CompiledRule], seed: u64) -> (Compression, Compression) {
    let builtin = Engine::base(RuleSet::Sound);
    let by_rules = Engine {
        rules: RuleSet::Sound,
        base: false,
        extra: rules,
    };
    let a = builtin.compress(g, &[], seed).unwrap();
    let b = by_rules.compress(g, &[], seed).unwrap();
    let a_then_rules = by_rules.compress(g, &a.bodies, seed).unwrap();
    let b_then_builtin = builtin.compress(g, &b.bodies, seed).unwrap();
    assert_eq!(
        a_then_rules.components, a.components,
        "the rules compress what the built-in engine left"
    );
    assert_eq!(
        b_then_builtin.components, b.components,
        "the built-in engine compresses what the rules left"
    );
    (a, b)
}

/// Bodies as (rods, class), the parts both engines must agree on.
fn shapes(c: &Compression) -> Vec<(Vec<u32>, rgc::body::BodyClass)> {
    c.bodies.iter().map(|b| (b.rods.clone(), b.class)).collect()
}

#[test]
fn base_motifs_as_rules_compress_like_the_builtin_engine() {
    let rules = generic();
    // Random graphs: the same bodies, run by run.
    let mut bodies = 0;
    for s in 0..12 {
        let g = random_graph(220, 0.010 + 0.0006 * s as f64, 900 + s);
        let (a, b) = agree(&g, &rules, s);
        assert_eq!(a.components, b.components, "graph {s}");
        assert_eq!(shapes(&a), shapes(&b), "graph {s}");
        bodies += a.bodies.len();
    }
    assert!(bodies >= 30, "graphs with bodies to compare ({bodies})");
    // Rod systems, with every motif in play: each engine's result is a
    // fixpoint of the other. Their node counts are not compared: the two
    // engines draw different motif orders, and the engine's result depends
    // on the order (on the first system, 3183 to 3253 nodes over six orders
    // for the built-in engine). Nor is it the order alone: on the 11-rod
    // graph `Jb?lIb`BCO_` (three rod communities, rigid only on some
    // realization components) the rules compress to one body in every order
    // tried, the built-in engine in 7 of 64 (false rigidity both ways);
    // reported with the suite's findings.
    for (k, density) in [35.0, 45.0].into_iter().enumerate() {
        let system = RodSystem::generate(RodParams::new(23.0, 5.0, density).unwrap(), k as u64);
        let g = ContactGraph::from_contacts(system.len(), &detect(&system));
        agree(&g, &rules, 3 + k as u64);
    }
}

/// The rules of the committed rule files `names` (in `motifs/`).
fn committed(names: &[&str]) -> Vec<CompiledRule> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs");
    let paths: Vec<_> = names
        .iter()
        .map(|n| dir.join(format!("{n}.json")))
        .collect();
    rgc::rule_file::load_rules(&paths)
        .unwrap()
        .iter()
        .map(CompiledRule::new)
        .collect()
}

/// The index may only skip attempts that cannot match, so compressions
/// with it are those of the plain matcher, body for body and motif for
/// motif: on rod systems around the rigidity threshold, with the extended
/// and the mined rules, under both rule sets, from scratch and restarted
/// from a run's bodies.
#[test]
fn indexed_matcher_compresses_like_the_unindexed_one() {
    let extended = committed(&["rods-6", "rods-8", "mixed-4"]);
    let mined = committed(&["mined"]);
    let (mut rules_applied, mut restarted) = (0, 0);
    for (k, density) in [30.0, 34.0, 38.0, 42.0, 45.0].into_iter().enumerate() {
        let seed = 40 + k as u64;
        let system = RodSystem::generate(RodParams::new(23.0, 4.0, density).unwrap(), seed);
        let g = ContactGraph::from_contacts(system.len(), &detect(&system));
        for set in [RuleSet::Sound, RuleSet::Paper] {
            for extra in [&extended, &mined] {
                let engine = Engine::with_rules(set, extra);
                let plain = engine
                    .compress_matching(&g, &[], seed, Matching::Unindexed)
                    .unwrap();
                let indexed = engine.compress(&g, &[], seed).unwrap();
                assert_eq!(indexed, plain, "density {density}, {set:?}");
                rules_applied += plain.motifs.rules;
                // A restart from half the bodies has pairs to examine at once.
                let half = &plain.bodies[..plain.bodies.len() / 2];
                let plain = engine
                    .compress_matching(&g, half, seed + 1, Matching::Unindexed)
                    .unwrap();
                let indexed = engine.compress(&g, half, seed + 1).unwrap();
                assert_eq!(indexed, plain, "density {density}, {set:?}, restarted");
                restarted += plain.motifs.rules;
            }
        }
    }
    assert!(
        rules_applied >= 200 && restarted >= 3,
        "the loaded rules compressed ({rules_applied}, restarted {restarted})"
    );
}

/// The same with the large rule sets, whose rods-only rules the sieve and
/// the trie match all at once: rods to 10 with mixed motifs to 4
/// components (1,569 rules), and with mixed ones of 5 (3,307), on small
/// rod systems at gamma 23 (the plain matcher tries every rule in turn) and,
/// with the larger set alone, at gamma 98 (where its rules fire and change
/// the run); and a restart from a run's bodies.
#[test]
fn indexed_matcher_compresses_like_the_unindexed_one_with_the_large_rule_sets() {
    let extended = committed(&["rods-6", "rods-8", "mixed-4"]);
    let rods = committed(&["rods-6", "rods-8", "rods-9", "rods-10", "mixed-4"]);
    let all = committed(&[
        "rods-6", "rods-8", "rods-9", "rods-10", "mixed-4", "mixed-5",
    ]);
    assert_eq!((rods.len(), all.len()), (1569, 3307));
    let (mut rules_applied, mut changed) = (0, 0);
    let systems = [
        (23.0, 2.5, 38.0, 60, vec![&rods, &all]),
        (23.0, 2.5, 44.0, 61, vec![&rods, &all]),
        (98.0, 2.1, 150.0, 60, vec![&all]),
    ];
    for (gamma, l, density, seed, sets) in systems {
        let system = RodSystem::generate(RodParams::new(gamma, l, density).unwrap(), seed);
        let g = ContactGraph::from_contacts(system.len(), &detect(&system));
        let smaller = Engine::with_rules(RuleSet::Sound, &extended)
            .compress(&g, &[], seed)
            .unwrap();
        for extra in sets {
            let engine = Engine::with_rules(RuleSet::Sound, extra);
            let plain = engine
                .compress_matching(&g, &[], seed, Matching::Unindexed)
                .unwrap();
            let indexed = engine.compress(&g, &[], seed).unwrap();
            assert_eq!(indexed, plain, "gamma {gamma}, density {density}");
            let half = &plain.bodies[..plain.bodies.len() / 2];
            let plain_again = engine
                .compress_matching(&g, half, seed + 1, Matching::Unindexed)
                .unwrap();
            let indexed_again = engine.compress(&g, half, seed + 1).unwrap();
            assert_eq!(indexed_again, plain_again, "gamma {gamma}, restarted");
            rules_applied += plain.motifs.rules + plain_again.motifs.rules;
            // The larger sets found what the 138 rules did not.
            changed += usize::from(plain.sequence != smaller.sequence);
        }
    }
    assert!(
        rules_applied >= 20 && changed >= 5,
        "the loaded rules compressed ({rules_applied} instances, {changed} runs unlike the 138 rules')"
    );
}

/// Every attempt the index skips is one the plain matcher would not have
/// matched (the audit matches each anyway and panics if it would have).
#[test]
fn index_skips_only_impossible_attempts() {
    let rules: Vec<CompiledRule> = committed(&["rods-6", "rods-8", "mixed-4", "mined"]);
    for (k, density) in [32.0, 40.0].into_iter().enumerate() {
        let system = RodSystem::generate(RodParams::new(23.0, 4.0, density).unwrap(), 7 + k as u64);
        let g = ContactGraph::from_contacts(system.len(), &detect(&system));
        for set in [RuleSet::Sound, RuleSet::Paper] {
            let engine = Engine::with_rules(set, &rules);
            let audited = engine
                .compress_matching(&g, &[], k as u64, Matching::Audited)
                .unwrap();
            assert_eq!(audited, engine.compress(&g, &[], k as u64).unwrap());
        }
    }
}

#[test]
#[ignore = "times both engines on a 40,000-rod system (box 10, density 40); run with --ignored"]
fn large_system_agreement() {
    let rules = generic();
    let system = RodSystem::generate(RodParams::new(23.0, 10.0, 40.0).unwrap(), 1);
    let g = ContactGraph::from_contacts(system.len(), &detect(&system));
    let t = std::time::Instant::now();
    let (a, b) = agree(&g, &rules, 1);
    println!(
        "largest: built-in {} rules {}; nodes {} {}; {:.1}s",
        a.largest_rods(),
        b.largest_rods(),
        a.components,
        b.components,
        t.elapsed().as_secs_f64()
    );
}

/// Sequences of committed studies compress as they did when committed, so
/// that the studies stay valid: rerun by the nested protocol, each gives the
/// same steps (rods, spanning, runs spanning at every compression of the
/// bisection), critical numbers, fresh compression and contact numbers. A
/// few sequences of the base engine's and the 138 extended rules' gamma 23
/// studies, and of the mined rules' gamma 98 study, at their smallest boxes.
#[test]
fn committed_studies_replay_their_sequences() {
    use rgc::threshold::sequence::{Record, Sequence, Setup, nested};
    use rgc::threshold::study::StudySpec;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let studies = [
        ("results/g23-rigid-sound", 5.0, 3),
        ("results/g23-rigid-sound-extended", 5.0, 3),
        (
            "results/studies/rigid-sound-m20-4de6c2d1-k1-nested-r40-g98-L3_4_5-wrap-s1",
            3.0,
            3,
        ),
    ];
    let mut replayed = 0;
    for (dir, box_len, sequences) in studies {
        let dir = root.join(dir);
        let spec: StudySpec =
            serde_json::from_str(&std::fs::read_to_string(dir.join("study.json")).unwrap())
                .unwrap();
        let files: Vec<_> = spec.motifs.files.iter().map(|f| root.join(f)).collect();
        let rules: Vec<CompiledRule> = rgc::rule_file::load_rules(&files)
            .unwrap()
            .iter()
            .map(CompiledRule::new)
            .collect();
        assert_eq!(rules.len(), spec.motifs.rules, "{}", dir.display());
        let setup = Setup {
            kind: spec.kind,
            gamma: spec.gamma,
            criterion: spec.criterion,
            engine: Engine::with_rules(spec.rules, &rules),
            runs: spec.runs,
            memory_limit: None,
        };
        let records = std::fs::read_to_string(dir.join("records.jsonl")).unwrap();
        let chosen = records
            .lines()
            .map(|line| serde_json::from_str::<Record>(line).unwrap())
            .filter(|r| r.box_len == box_len && r.index < sequences);
        for committed in chosen {
            // As the study generated them.
            let mut seq = Sequence::new(
                spec.gamma,
                box_len,
                spec.first_rods(box_len),
                committed.seed,
            )
            .unwrap();
            let mut again = Record::empty(box_len, committed.index, committed.seed);
            nested(&setup, &mut seq, &mut again).unwrap();
            let key = |r: &Record| {
                (
                    r.contact_critical,
                    r.rigid_critical,
                    r.steps.clone(),
                    r.fresh,
                )
            };
            let here = format!(
                "{} box {box_len} sequence {}",
                dir.display(),
                committed.index
            );
            assert_eq!(key(&again), key(&committed), "{here}");
            // Contact numbers are sums of floats the engine does not touch,
            // committed from an earlier summation: equal to rounding.
            assert_eq!(again.contacts.len(), committed.contacts.len(), "{here}");
            for (a, c) in again.contacts.iter().zip(&committed.contacts) {
                assert_eq!(a.density, c.density, "{here}");
                for (x, y) in [(a.c0, c.c0), (a.c1, c.c1), (a.c2, c.c2)] {
                    assert!((x - y).abs() <= 1e-12 * y.abs(), "{here}: {x} against {y}");
                }
            }
            replayed += 1;
        }
    }
    assert_eq!(replayed, 9);
}
