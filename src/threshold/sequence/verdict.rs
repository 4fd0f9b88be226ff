//! Whether the first `n` rods of a sequence span: `Setup::runs`
//! compressions (certified where asked), or the exact truth.

use super::rods::Sequence;
use super::setup::{Kind, Setup};
use super::step::Step;
use crate::body::Body;
use crate::engine::{self, Engine, RuleSet, certify, run_seed};
use crate::spanning::SpanChecker;
use crate::truth::{self, TruthOptions};
use crate::{Error, Result};

/// Compresses the first `n` rods `setup.runs` times, run `k` starting from
/// `start[k]` (bodies of a smaller prefix, rigid here too) or from nothing.
/// Returns the step, each run's bodies and whether certification was
/// undecided in a run that did not span (then the step's "no" is no
/// verdict). For the truth kind, evaluates the exact truth of the prefix
/// instead (one "run", no bodies carried).
pub(super) fn compress(
    setup: &Setup,
    seq: &Sequence,
    n: usize,
    start: Option<&[Vec<Body>]>,
) -> Result<(Step, Vec<Vec<Body>>, bool)> {
    let graph = seq.graph(n);
    let contacts = seq.contacts_of(n);
    if setup.kind == Kind::Truth {
        return Ok((
            truth_step(setup, seq, n)?,
            vec![Vec::new(); setup.runs],
            false,
        ));
    }
    // The runs follow one another; each holds its state, all their bodies.
    engine::check_runs_memory(
        graph.n_nodes(),
        graph.n_edges(),
        setup.runs,
        0,
        setup.memory_limit,
    )?;
    let seed = run_seed(seq.seed, n as u64);
    // Certified compression only changes a verdict that spans (its bodies lie
    // inside the sound ones), so truth checks only the spanning runs; the
    // bodies a run carries on are certified when a later run spans.
    let certified = setup.engine.rules == RuleSet::Certified;
    let engine = if certified {
        Engine {
            rules: RuleSet::Sound,
            ..setup.engine
        }
    } else {
        setup.engine
    };
    let results: Vec<(bool, Vec<Body>, bool)> = (0..setup.runs)
        .map(|k| {
            let from = start.map_or(&[][..], |s| &s[k][..]);
            let run_seed = run_seed(seed, k as u64);
            let mut run = engine.compress(&graph, from, run_seed)?;
            let mut checker = SpanChecker::new();
            let mut spans = |run: &engine::Compression| {
                run.bodies
                    .iter()
                    .any(|b| checker.spans(&seq.system, contacts, &graph, &b.rods, setup.criterion))
            };
            let mut spanning = spans(&run);
            if certified && spanning {
                let shifts: Vec<_> = contacts.iter().map(|c| c.shift).collect();
                let topo = truth::Topology::periodic(&graph, &shifts)?;
                run = certify::certify(&topo, run, run_seed);
                spanning = spans(&run);
            }
            Ok((spanning, run.bodies, run.undecided))
        })
        .collect::<Result<_>>()?;
    let runs_spanning = results.iter().filter(|r| r.0).count();
    let step = Step::new(n, runs_spanning > 0, runs_spanning);
    let undecided = !step.spans && results.iter().any(|r| r.2);
    Ok((step, results.into_iter().map(|r| r.1).collect(), undecided))
}

/// The exact truth of the first `n` rods, its realizations seeded by the
/// sequence and `n`.
pub(super) fn truth_of(setup: &Setup, seq: &Sequence, n: usize) -> truth::Truth {
    let opts = TruthOptions {
        memory_limit: setup.memory_limit,
        ..TruthOptions::seeded(run_seed(seq.seed, n as u64))
    };
    let graph = seq.graph(n);
    truth::of_system(seq.view(n, &graph), setup.criterion, opts)
}

/// Whether a rigid cluster of the exact truth of the first `n` rods spans,
/// or `None` when truth is undecided there.
pub fn truth_spanning(setup: &Setup, seq: &Sequence, n: usize) -> Option<bool> {
    truth_of(setup, seq, n).spanning
}

/// The error of a truth refused for the memory limit.
pub(super) fn refusal(seq: &Sequence, n: usize, t: truth::Truth) -> Error {
    Error::Memory(format!(
        "truth of the first {n} rods of the sequence seeded {}: {}",
        seq.seed,
        t.outcome.reason().unwrap_or_default()
    ))
}

/// [`truth_spanning`], where an undecided truth is an error rather than a guess.
pub fn truth_spans(setup: &Setup, seq: &Sequence, n: usize) -> Result<bool> {
    truth_step(setup, seq, n).map(|s| s.spans)
}

/// The step of truth on the first `n` rods: whether it spans, its largest
/// cluster and its strain rank; an undecided truth is an error.
fn truth_step(setup: &Setup, seq: &Sequence, n: usize) -> Result<Step> {
    truth_verdict(setup, seq, n)?.map_err(|why| {
        Error::Analysis(format!(
            "truth is undecided for the first {n} rods of the sequence seeded {}: {why}",
            seq.seed
        ))
    })
}

/// [`truth_step`], where an undecided truth is an undecided step.
pub(super) fn truth_step_or_undecided(setup: &Setup, seq: &Sequence, n: usize) -> Result<Step> {
    Ok(truth_verdict(setup, seq, n)?.unwrap_or_else(|_| Step::undecided(n)))
}

/// The step of truth on the first `n` rods, or why truth is undecided
/// there; a truth refused for the memory limit is an error (a rerun with
/// more memory resumes the study).
fn truth_verdict(
    setup: &Setup,
    seq: &Sequence,
    n: usize,
) -> Result<std::result::Result<Step, String>> {
    let t = truth_of(setup, seq, n);
    if t.outcome.refused().is_some() {
        return Err(refusal(seq, n, t));
    }
    let Some(spans) = t.spanning else {
        return Ok(Err(t.outcome.reason().unwrap_or_default().to_string()));
    };
    Ok(Ok(Step {
        largest: Some(t.largest_cluster()),
        strain_rank: t.strain_rank(),
        ..Step::new(n, spans, usize::from(spans))
    }))
}
