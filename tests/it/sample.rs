//! One Monte Carlo sample end to end: reproducible from its seed whatever the
//! thread count, and consistent between its parts.

use rgc::engine::RuleSet;
use rgc::rods::RodParams;
use rgc::sample::{SampleOptions, SampleReport, sample};
use rgc::spanning::{Criterion, cluster_spans};

fn opts(seed: u64, rules: RuleSet, criterion: Criterion) -> SampleOptions {
    SampleOptions {
        rods: RodParams::new(23.0, 6.0, 42.0).unwrap().into(),
        seed,
        runs: 6,
        rules,
        criterion,
        truth: false,
    }
}

fn without_timings(mut r: SampleReport) -> SampleReport {
    r.seconds = 0.0;
    r.seconds_contacts = 0.0;
    r.seconds_compression = 0.0;
    r
}

#[test]
fn thread_count_does_not_change_a_sample() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| sample(&opts(5, RuleSet::Sound, Criterion::Wrap)).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.contacts, two.contacts);
    assert_eq!(one.runs, two.runs);
    assert_eq!(without_timings(one.report), without_timings(two.report));
}

#[test]
fn report_agrees_with_its_runs() {
    for seed in 0..4 {
        for (rules, criterion) in [
            (RuleSet::Sound, Criterion::Wrap),
            (RuleSet::Paper, Criterion::Faces),
        ] {
            let s = sample(&opts(seed, rules, criterion)).unwrap();
            let r = &s.report;
            assert_eq!(r.n_rods, 9072);
            assert_eq!(s.runs.len(), 6);
            // The union rule: rigid-spanning iff some run has a spanning body.
            let spans: Vec<bool> = s
                .runs
                .iter()
                .map(|c| {
                    c.bodies.iter().any(|b| {
                        cluster_spans(&s.system, &s.contacts, &s.graph, &b.rods, criterion)
                    })
                })
                .collect();
            assert_eq!(spans, s.spans);
            assert_eq!(r.rigid_spanning, spans.iter().any(|&x| x));
            assert_eq!(r.runs_spanning, spans.iter().filter(|&&x| x).count());
            assert_eq!(
                r.largest_body_rods,
                s.runs.iter().map(|c| c.largest_rods()).max().unwrap()
            );
            // A rigid body is a connected cluster: rigid spanning implies contact spanning.
            assert!(!r.rigid_spanning || r.contact_spanning);
        }
    }
}
