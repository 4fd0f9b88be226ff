//! Truth's realizations: each in a prime of its own, and an unlucky draw
//! caught by the others (MODEL §10).

use rgc::graph::io::parse_graph6;
use rgc::truth::{Outcome, Topology, Truth, TruthOptions, realization_ranks, truth};

/// Large primes of the range truth draws from.
const LARGE: [u32; 2] = [16_777_213, 16_777_199];

/// The rank, DOF and agreement of an exact answer.
fn exact(t: &Truth) -> Option<(usize, usize, Option<bool>)> {
    match t.outcome {
        Outcome::Exact {
            rank,
            dof,
            twins_agree,
        } => Some((rank, dof, twins_agree)),
        _ => None,
    }
}

/// Bad draws forced on K_{2,4} (3D6, rigid): realizations in F_13, where
/// random points land in special positions often, lose rank on some seeds.
/// A realization in a large prime catches every one: the answer is its
/// rank and DOF, and the realizations agree exactly where the first one
/// lost no rank. With the first two in F_13, the third catches what both
/// lost.
#[test]
fn draws_in_a_tiny_prime_lose_rank_and_a_large_prime_catches_them() {
    let g = parse_graph6("E]r?").unwrap();
    let topo = Topology::finite(&g);
    let (true_rank, dof, _) = exact(&truth(&topo, TruthOptions::default())).expect("exact");
    for primes in [[13, LARGE[0], LARGE[1]], [13, 13, LARGE[0]]] {
        let realizations = if primes[1] == 13 { 3 } else { 2 };
        let (mut both, mut decided) = (0, 0);
        for seed in 0..300 {
            let opts = TruthOptions {
                primes: Some(primes),
                realizations,
                ..TruthOptions::seeded(seed)
            };
            let (Some(ranks), Some((rank, d, agree))) =
                (realization_ranks(&topo, opts), exact(&truth(&topo, opts)))
            else {
                continue;
            };
            decided += 1;
            let large = ranks[realizations - 1].1;
            assert_eq!(large, true_rank, "seed {seed}: the large prime's rank");
            assert!(
                ranks.iter().all(|r| r.1 <= true_rank),
                "only lost rank: {ranks:?}"
            );
            assert_eq!((rank, d), (true_rank, dof), "seed {seed}: {ranks:?}");
            // A later realization that lost rank still confirms a first
            // one that did not (its contracted kernel is the first's); a
            // first one that lost rank is always caught.
            let lost = ranks[0].1 < true_rank;
            both += usize::from(ranks[..realizations - 1].iter().all(|r| r.1 < true_rank));
            assert_eq!(agree, Some(!lost), "seed {seed}: ranks {ranks:?}");
        }
        assert!(decided > 100, "{primes:?}: {decided} of 300 seeds decided");
        assert!(
            both > 0,
            "{primes:?}: no draw in F_13 lost rank in {decided}"
        );
    }
}

/// The primes are drawn per evaluation from the seed: distinct, of the
/// range, the same for the same seed, and one per realization asked for.
#[test]
fn each_realization_has_a_prime_of_its_own() {
    let g = parse_graph6("E]r?").unwrap();
    let topo = Topology::finite(&g);
    let three = TruthOptions {
        realizations: 3,
        ..TruthOptions::seeded(7)
    };
    let t = truth(&topo, three);
    assert_eq!(t.primes.len(), 3);
    assert!(
        t.primes
            .iter()
            .all(|&q| rgc::math::prime::is_prime(q) && q > 1 << 23 && q < 1 << 24)
    );
    assert!(t.primes[0] != t.primes[1] && t.primes[1] != t.primes[2] && t.primes[0] != t.primes[2]);
    assert_eq!(truth(&topo, three).primes, t.primes);
    assert_ne!(truth(&topo, TruthOptions::seeded(8)).primes[0], t.primes[0]);
    let one = truth(
        &topo,
        TruthOptions {
            realizations: 1,
            ..TruthOptions::seeded(7)
        },
    );
    assert_eq!(one.primes, t.primes[..1]);
    assert_eq!(
        exact(&one).map(|e| e.2),
        Some(None),
        "one realization checks nothing"
    );
}

/// Why truth's rigid clusters need the twins as much as its flexibilities:
/// a realization can only lose rank, but one with the generic rank can
/// still lock a mechanism. A planar four-bar (ground A–D pinned, crank A–J,
/// coupler J–B, rocker B–D) has one motion; at its dead centre (A, J and B
/// on one line) the rank is the generic one, yet the only motion moves J
/// alone: the rocker is rigid with the ground there and nowhere near it.
#[test]
fn a_realization_with_the_generic_rank_can_lock_a_mechanism() {
    use rgc::math::{Fp, Matrix, rank_exact};
    // Columns: the velocities of J and B; rows: the three bars, then (to
    // test the lock) the two rows that hold B still.
    let four_bar = |j: [i64; 2], b: [i64; 2], d: [i64; 2], hold_b: bool| {
        let f = Fp::new;
        let mut m = Matrix::zeros(if hold_b { 5 } else { 3 }, 4);
        let (bj, bd) = ([b[0] - j[0], b[1] - j[1]], [b[0] - d[0], b[1] - d[1]]);
        for k in 0..2 {
            m.set(0, k, f(j[k]));
            m.set(1, k, f(-bj[k]));
            m.set(1, 2 + k, f(bj[k]));
            m.set(2, 2 + k, f(bd[k]));
        }
        if hold_b {
            m.set(3, 2, Fp::ONE);
            m.set(4, 3, Fp::ONE);
        }
        rank_exact(&m)
    };
    let (generic, dead) = (([1, 2], [5, 3], [4, 0]), ([1, 1], [2, 2], [3, 0]));
    for (j, b, d) in [generic, dead] {
        assert_eq!(four_bar(j, b, d, false), 3, "one motion at {j:?} {b:?}");
    }
    assert_eq!(
        four_bar(generic.0, generic.1, generic.2, true),
        4,
        "the rocker moves"
    );
    assert_eq!(
        four_bar(dead.0, dead.1, dead.2, true),
        3,
        "the rocker is locked"
    );
}

/// The one unlucky draw `rgc twins` met in 7,793 evaluations at gamma 23
/// (L = 5, 6, 7; `results/truth-twins/`): the first 11,783 rods of the
/// 66th sequence of L = 7. Its second realization loses one rank in its
/// prime; the first and a third, each in a prime of its own, do not, and
/// truth answers with the larger rank.
#[test]
fn the_unlucky_draw_found_in_the_committed_studies_is_outranked() {
    use rgc::engine::run_seed;
    use rgc::threshold::sequence::Sequence;
    let (seed, n) = (2_528_998_726_754_218_708, 11_783);
    let seq = Sequence::new(23.0, 7.0, n, seed).unwrap();
    let graph = seq.graph(n);
    let view = seq.view(n, &graph);
    let opts = TruthOptions {
        realizations: 3,
        ..TruthOptions::seeded(run_seed(seed, n as u64))
    };
    let ranks = realization_ranks(&view.topology(), opts).expect("exact");
    assert_eq!(
        ranks,
        [
            (10_455_209, 30_409),
            (12_408_127, 30_408),
            (15_300_433, 30_409)
        ]
    );
    let t = truth(&view.topology(), opts);
    assert_eq!(exact(&t).map(|e| e.0), Some(30_409));
}

/// The committed measurement of how often realizations disagree
/// (`results/truth-twins/`), tallied again from its evaluations: the
/// counts MODEL §10 and `rgc truth --help` state, and its own tally files.
#[test]
fn the_committed_twins_measurement_counts_as_stated() {
    use rgc::threshold::twins::{read, tally};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("results/truth-twins");
    let mut totals = [0; 4];
    for (gamma, boxes, expected) in [
        ("g23", 3, [600, 7_793, 1, 0]),
        ("g48", 2, [200, 2_739, 0, 1]),
        ("g98", 1, [100, 1_420, 0, 1]),
    ] {
        let dir = root.join(gamma);
        let tallies = tally(&read(&dir.join("evaluations.jsonl")).unwrap());
        assert_eq!(tallies.len(), boxes, "{gamma}");
        let sum = |f: fn(&rgc::threshold::twins::Tally) -> usize| tallies.iter().map(f).sum();
        let counts: [usize; 4] = [
            sum(|t| t.sequences),
            sum(|t| t.evaluations),
            sum(|t| t.twins_differ),
            sum(|t| t.lone_differs),
        ];
        assert_eq!(counts, expected, "{gamma}");
        for (total, c) in totals.iter_mut().zip(counts) {
            *total += c;
        }
        // Every evaluation where some rank is low is one of those two kinds.
        assert_eq!(sum(|t| t.any_below), expected[2] + expected[3]);
        let file: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("tally.json")).unwrap())
                .unwrap();
        assert_eq!(file["tallies"], serde_json::to_value(&tallies).unwrap());
    }
    // Three realizations per evaluation: 3 of 35,856 lost rank.
    assert_eq!(totals, [900, 11_952, 1, 2]);
}
