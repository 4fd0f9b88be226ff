//! One Monte Carlo sequence (MODEL §8): the seeded random rods of a box in
//! their order, whose first `n` rods are the `n`-rod system; the number of
//! rods at which it first spans by contacts (one union-find sweep) and
//! rigidly (bisection over the number of rods), and the paper's
//! fixed-density protocol on the same sequence.

use serde::{Deserialize, Serialize};

use super::fss::{ContactPoint, Protocol};
use crate::body::Body;
use crate::contacts::{self, Contact};
use crate::engine::{self, Engine, RuleSet, certify, run_seed};
use crate::graph::{self, ContactGraph};
use crate::rods::{RodParams, RodSystem};
use crate::spanning::{self, Criterion, SpanChecker};
use crate::truth::{self, TruthOptions};
use crate::{Error, Result};

/// Which spanning cluster defines the threshold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// A connected cluster of touching rods spans.
    Contact,
    /// A rigid body found by the engine spans.
    #[default]
    Rigid,
    /// A rigid cluster of the exact truth (MODEL §10) spans: the reference
    /// every engine variant is measured against.
    Truth,
}

impl Kind {
    /// Whether the critical number is found by bisection over compressions
    /// (or truth evaluations) rather than by one contact sweep.
    pub fn bisects(self) -> bool {
        self != Kind::Contact
    }
}

/// What every sequence of a study shares.
#[derive(Clone, Copy, Debug)]
pub struct Setup<'r> {
    pub kind: Kind,
    pub gamma: f64,
    pub criterion: Criterion,
    pub engine: Engine<'r>,
    /// Independent compressions per system; it spans if any of them does.
    pub runs: usize,
    /// For the truth kind: refuse a system whose elimination is estimated
    /// over this many bytes.
    pub memory_limit: Option<u64>,
}

/// A sequence's rods and contacts, grown on demand: the first `n` rods of
/// the sequence are the `n`-rod system of its seed, and their contacts are a
/// prefix of `contacts` (sorted by the later rod).
pub struct Sequence {
    pub system: RodSystem,
    pub contacts: Vec<Contact>,
    /// `ends[n]`: how many contacts the first `n` rods have among themselves.
    ends: Vec<usize>,
    params: RodParams,
    seed: u64,
}

impl Sequence {
    /// The first `n` rods of the sequence seeded with `seed`.
    pub fn new(gamma: f64, box_len: f64, n: usize, seed: u64) -> Result<Self> {
        let params = RodParams::new(gamma, box_len, n.max(1) as f64 / box_len.powi(3))?;
        let system = RodSystem::generate(params, seed);
        debug_assert_eq!(system.len(), n.max(1));
        let mut contacts = contacts::detect(&system);
        spanning::sort_by_sequence(&mut contacts);
        let mut ends = vec![0; system.len() + 1];
        for c in &contacts {
            ends[c.rods[1] as usize + 1] += 1;
        }
        for n in 1..ends.len() {
            ends[n] += ends[n - 1];
        }
        Ok(Sequence {
            system,
            contacts,
            ends,
            params,
            seed,
        })
    }

    /// Rods generated so far.
    pub fn len(&self) -> usize {
        self.system.len()
    }

    pub fn is_empty(&self) -> bool {
        self.system.is_empty()
    }

    /// Makes sure at least `n` rods exist (regenerating the longer sequence
    /// from the same seed, half again as long as asked, so growth is rare).
    pub fn reach(&mut self, n: usize) -> Result<()> {
        if n > self.len() {
            let p = self.params;
            *self = Sequence::new(p.gamma, p.box_len, n + n / 2, self.seed)?;
        }
        Ok(())
    }

    /// The contacts among the first `n` rods.
    pub fn contacts_of(&self, n: usize) -> &[Contact] {
        &self.contacts[..self.ends[n]]
    }

    /// The contact graph of the first `n` rods.
    pub fn graph(&self, n: usize) -> ContactGraph {
        ContactGraph::from_contacts(n, self.contacts_of(n))
    }

    /// Rods at which the sequence first spans by contacts, generating more
    /// rods until it does.
    pub fn contact_critical(&mut self, criterion: Criterion) -> Result<usize> {
        loop {
            if let Some(n) = spanning::critical_rods(&self.system, &self.contacts, criterion) {
                return Ok(n);
            }
            self.reach(2 * self.len())?;
        }
    }

    /// Contact numbers of the first `n` rods.
    pub fn contact_point(&self, n: usize) -> ContactPoint {
        let s = graph::stats(&self.graph(n));
        ContactPoint {
            density: n as f64 / self.params.box_len.powi(3),
            c0: s.c0,
            c1: s.c1,
            c2: s.c2,
        }
    }
}

/// One compression of a prefix: whether it spans, and how many runs found
/// a spanning body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Step {
    /// Rods in the system.
    pub n: usize,
    pub spans: bool,
    /// Runs (of `Setup::runs`) with a spanning body.
    pub runs_spanning: usize,
    /// Truth (or certification) had no verdict here: a probe above the
    /// critical number that landed where the model has no realization, so
    /// the search looks below it (it does not span, by this step).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub undecided: bool,
    /// Truth kind: rods in the largest true rigid cluster, for the order of
    /// the transition (how much the cluster jumps at the critical number).
    /// `None` for compressions, and in records older than the field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub largest: Option<usize>,
}

impl Step {
    pub fn new(n: usize, spans: bool, runs_spanning: usize) -> Self {
        Step {
            n,
            spans,
            runs_spanning,
            undecided: false,
            largest: None,
        }
    }

    /// A probe without a verdict.
    fn undecided(n: usize) -> Self {
        Step {
            undecided: true,
            ..Step::new(n, false, 0)
        }
    }
}

/// What one sequence produced: one line of a study's record file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record {
    #[serde(rename = "box")]
    pub box_len: f64,
    pub index: u64,
    pub seed: u64,
    /// Rods at which the sequence first spans by contacts (exact).
    pub contact_critical: usize,
    /// Rods at which it first spans rigidly (rigid kind, nested protocol).
    pub rigid_critical: Option<usize>,
    /// The bisection's compressions, in order, each starting from the bodies
    /// of the largest non-spanning system before it.
    pub steps: Vec<Step>,
    /// A fresh compression (no carried bodies) at the rigid critical number:
    /// when it does not span, motif order broke monotonicity there.
    pub fresh: Option<Step>,
    /// The fixed protocol: one fresh compression per grid density.
    pub fixed: Vec<Step>,
    /// Contact numbers at the critical number (nested) or at each grid density (fixed).
    pub contacts: Vec<ContactPoint>,
    /// Truth kind, or certified rules: the number of rods at which truth was
    /// undecided (no realization of the model exists there), which ends the
    /// sequence without a critical number; it is then left out of the
    /// analysis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub undecided: Option<usize>,
    /// Wall time it took on its thread, in seconds (the runs of a sequence
    /// run one after another, sequences in parallel). Not part of the
    /// results: records are compared without it.
    pub seconds: f64,
    /// Peak resident memory of the process that wrote it, MiB, when it was
    /// written (0 where unknown, and in records older than the field).
    /// Not part of the results either.
    #[serde(default)]
    pub peak_rss_mib: f64,
    /// CPU time of the whole process that wrote it, all threads, since that
    /// process wrote its previous record (or started): summed over the
    /// records, the CPU the study cost, true on a shared machine where wall
    /// times are not. `None` in records older than the field, and where the
    /// system does not tell. Not part of the results.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cpu_seconds: Option<f64>,
}

impl Record {
    /// Truth kind: rods in the largest true rigid cluster one rod below the
    /// critical number and at it, where the bisection evaluated both (it
    /// does unless the critical number is the first number it tried).
    pub fn jump(&self) -> Option<(usize, usize)> {
        let n = self.rigid_critical?;
        let at = |m| self.steps.iter().find(|s| s.n == m).and_then(|s| s.largest);
        Some((at(n.checked_sub(1)?)?, at(n)?))
    }

    /// Its critical number of rods for `kind`.
    pub fn critical(&self, kind: Kind) -> Option<usize> {
        match kind {
            Kind::Contact => Some(self.contact_critical),
            Kind::Rigid | Kind::Truth => self.rigid_critical,
        }
    }

    /// Checks that the record is one [`nested`] or [`fixed`] could have
    /// written for a study of `kind`, `protocol` and `runs` runs per system,
    /// so that an edited or damaged line cannot move a threshold: the rigid
    /// critical number is where its steps' bisection ends and not below the
    /// contact critical number, the fixed protocol's steps follow `grid`
    /// (its numbers of rods for this box, when known) and contact spanning,
    /// every step's run count fits, and the contact numbers were measured
    /// at the densities the protocol measures them.
    pub fn check(
        &self,
        kind: Kind,
        protocol: Protocol,
        runs: usize,
        grid: Option<&[usize]>,
    ) -> std::result::Result<(), String> {
        let n_c = self.contact_critical;
        if n_c == 0 {
            return Err("contact_critical is 0, but no sequence spans without rods".into());
        }
        if !(self.seconds.is_finite() && self.seconds >= 0.0) {
            return Err(format!("seconds {} is not a duration", self.seconds));
        }
        if let Some(c) = self.cpu_seconds.filter(|c| !(c.is_finite() && *c >= 0.0)) {
            return Err(format!("cpu_seconds {c} is not a duration"));
        }
        for s in self.steps.iter().chain(&self.fixed).chain(&self.fresh) {
            if s.runs_spanning > runs || s.spans != (s.runs_spanning > 0) {
                return Err(format!(
                    "the compression of {} rods has {} of {runs} runs spanning but spans = {}",
                    s.n, s.runs_spanning, s.spans
                ));
            }
        }
        if let Some(u) = self.undecided {
            if kind == Kind::Contact || protocol != Protocol::Nested {
                return Err("only a nested truth or certified record can be undecided".into());
            }
            if self.rigid_critical.is_some() || self.fresh.is_some() || !self.contacts.is_empty() {
                return Err(format!(
                    "truth was undecided at {u} rods, yet the record has a critical number"
                ));
            }
            return match replay_until(n_c, &self.steps)? {
                Some(next) if next == u => Ok(()),
                other => Err(format!(
                    "truth was undecided at {u} rods, but its steps lead to {other:?} next"
                )),
            };
        }
        let nested_only =
            self.rigid_critical.is_some() || !self.steps.is_empty() || self.fresh.is_some();
        let measured: Vec<usize> = match (protocol, kind) {
            (Protocol::Nested, _) if !self.fixed.is_empty() => {
                return Err("a nested study's record has fixed-protocol steps".into());
            }
            (Protocol::Nested, Kind::Contact) if nested_only => {
                return Err("a contact study's record has rigid results".into());
            }
            (Protocol::Nested, Kind::Contact) => vec![n_c],
            (Protocol::Nested, Kind::Rigid | Kind::Truth) => {
                let n_r = self
                    .rigid_critical
                    .ok_or("a rigid study's nested record has no rigid_critical")?;
                if n_r < n_c {
                    return Err(format!(
                        "rigid_critical {n_r} is below contact_critical {n_c}, \
                         but rigid spanning needs contact spanning"
                    ));
                }
                let found = replay(n_c, &self.steps)?;
                if found != n_r {
                    return Err(format!(
                        "rigid_critical is {n_r}, but its steps find {found}"
                    ));
                }
                match self.fresh {
                    Some(f) if f.n == n_r => {}
                    Some(f) => {
                        return Err(format!(
                            "the fresh compression has {} rods, not rigid_critical {n_r}",
                            f.n
                        ));
                    }
                    None => return Err("no fresh compression at rigid_critical".into()),
                }
                vec![n_r]
            }
            (Protocol::Fixed, _) if nested_only => {
                return Err("a fixed-protocol record has nested results".into());
            }
            (Protocol::Fixed, _) => {
                let rods: Vec<usize> = self.fixed.iter().map(|s| s.n).collect();
                match grid {
                    Some(g) if rods != g => {
                        return Err(format!("its steps have {rods:?} rods, the grid {g:?}"));
                    }
                    None if rods.windows(2).any(|w| w[0] >= w[1]) => {
                        return Err(format!("its steps' rods {rods:?} do not increase"));
                    }
                    _ => {}
                }
                for s in &self.fixed {
                    let wrong = match kind {
                        Kind::Contact => s.spans != (s.n >= n_c),
                        Kind::Rigid | Kind::Truth => s.spans && s.n < n_c,
                    };
                    if wrong {
                        return Err(format!(
                            "{} rods {} but contact_critical is {n_c}",
                            s.n,
                            if s.spans { "span" } else { "do not span" }
                        ));
                    }
                }
                rods
            }
        };
        let at: Vec<usize> = self
            .contacts
            .iter()
            .map(|c| (c.density * self.box_len.powi(3)).round() as usize)
            .collect();
        let exact = self.contacts.iter().zip(&measured).all(|(c, &n)| {
            (c.density - n as f64 / self.box_len.powi(3)).abs() <= 1e-12 * c.density
        });
        if at.len() != measured.len() || !exact {
            return Err(format!(
                "contact numbers measured at {at:?} rods, not at {measured:?}"
            ));
        }
        if let Some(c) = self.contacts.iter().find(|c| {
            ![c.c0, c.c1, c.c2]
                .iter()
                .all(|x| x.is_finite() && *x >= 0.0)
        }) {
            return Err(format!(
                "contact numbers {c:?} are not all finite and non-negative"
            ));
        }
        Ok(())
    }
}

/// Where [`Bisection`] goes after replaying `steps` from contact critical
/// number `n_c`: where it waits for a verdict ([`Bisection::waiting`]), or
/// `None` when it has ended.
fn replay_until(n_c: usize, steps: &[Step]) -> std::result::Result<Option<usize>, String> {
    let mut search = Bisection::new(n_c);
    for (k, s) in steps.iter().enumerate() {
        match search.next() {
            Some(n) if n == s.n => search.replay(s)?,
            next => {
                return Err(format!(
                    "step {} has {} rods where the bisection goes to {next:?}",
                    k + 1,
                    s.n
                ));
            }
        }
    }
    Ok(search.waiting())
}

/// The rigid critical number `steps` lead to when [`Bisection`] replays
/// them from contact critical number `n_c`, or where they leave its path.
fn replay(n_c: usize, steps: &[Step]) -> std::result::Result<usize, String> {
    let mut search = Bisection::new(n_c);
    let mut steps = steps.iter().enumerate();
    while let Some(n) = search.next() {
        let Some((k, s)) = steps.next() else {
            return Err(format!(
                "the steps end where the bisection compresses {n} rods next"
            ));
        };
        if s.n != n {
            return Err(format!(
                "step {} compresses {} rods where the bisection compresses {n}",
                k + 1,
                s.n
            ));
        }
        search.replay(s)?;
    }
    match steps.next() {
        Some((k, s)) => Err(format!(
            "step {} ({} rods) comes after the bisection ended",
            k + 1,
            s.n
        )),
        None => search
            .hi
            .ok_or_else(|| "the steps end below a guess without a verdict".into()),
    }
}

/// Compresses the first `n` rods `setup.runs` times, run `k` starting from
/// `start[k]` (bodies of a smaller prefix, rigid here too) or from nothing.
/// Returns the step, each run's bodies and whether certification was
/// undecided in a run that did not span (then the step's "no" is no
/// verdict). For the truth kind, evaluates the exact truth of the prefix
/// instead (one "run", no bodies carried).
fn compress(
    setup: &Setup,
    seq: &Sequence,
    n: usize,
    start: Option<&[Vec<Body>]>,
) -> Result<(Step, Vec<Vec<Body>>, bool)> {
    let graph = seq.graph(n);
    let contacts = seq.contacts_of(n);
    if setup.kind == Kind::Truth {
        let spans = truth_spans(setup, seq, n)?;
        let step = Step::new(n, spans, usize::from(spans));
        return Ok((step, vec![Vec::new(); setup.runs], false));
    }
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
fn truth_of(setup: &Setup, seq: &Sequence, n: usize) -> truth::Truth {
    let opts = TruthOptions {
        memory_limit: setup.memory_limit,
        ..TruthOptions::seeded(run_seed(seq.seed, n as u64))
    };
    truth::of_system(
        &seq.system,
        seq.contacts_of(n),
        &seq.graph(n),
        setup.criterion,
        opts,
    )
}

/// Whether a rigid cluster of the exact truth of the first `n` rods spans,
/// or `None` when truth is undecided there.
pub fn truth_spanning(setup: &Setup, seq: &Sequence, n: usize) -> Option<bool> {
    truth_of(setup, seq, n).spanning
}

/// The error of a truth refused for the memory limit.
fn refusal(seq: &Sequence, n: usize, t: truth::Truth) -> Error {
    Error::Memory(format!(
        "truth of the first {n} rods of the sequence seeded {}: {} (raise it with --memory-limit)",
        seq.seed,
        t.reason.unwrap_or_default()
    ))
}

/// [`truth_spanning`], where an undecided truth is an error rather than a guess.
pub fn truth_spans(setup: &Setup, seq: &Sequence, n: usize) -> Result<bool> {
    let t = truth_of(setup, seq, n);
    if t.refused.is_some() {
        return Err(refusal(seq, n, t));
    }
    t.spanning.ok_or_else(|| {
        Error::Analysis(format!(
            "truth is undecided for the first {n} rods of the sequence seeded {}: {}",
            seq.seed,
            t.reason.unwrap_or_default()
        ))
    })
}

/// First guess for the rigid critical number, as a multiple of the contact
/// critical number; growth factor while the guess does not span.
const FIRST_GUESS: f64 = 2.0;
const GROWTH: f64 = 1.25;

/// The nested protocol's search for the rigid critical number: rigid
/// spanning needs contact spanning, so it starts above the contact critical
/// number `n_c`, grows its upper end from a guess until that spans, then
/// bisects. [`nested`] runs it on compressions, and [`Record::check`]
/// replays it on a record's steps.
///
/// Truth has no verdict where forced planes percolate, far above the
/// critical number; a growing guess can land there. Such a guess becomes a
/// ceiling, and the search halves the gap below it until a guess spans.
struct Bisection {
    /// Largest number of rods known not to span.
    lo: usize,
    /// Smallest number known to span, once one does.
    hi: Option<usize>,
    /// The next guess while none spans.
    probe: usize,
    /// The smallest guess without a verdict, while none spans.
    ceiling: Option<usize>,
}

impl Bisection {
    fn new(n_c: usize) -> Self {
        Bisection {
            lo: n_c - 1,
            hi: None,
            probe: (n_c as f64 * FIRST_GUESS).ceil() as usize,
            ceiling: None,
        }
    }

    /// The number of rods to compress next, or `None` once `hi` (or the
    /// ceiling, when nothing spans) is one above `lo`.
    fn next(&self) -> Option<usize> {
        match (self.hi, self.ceiling) {
            (None, None) => Some(self.probe),
            (Some(top), _) | (None, Some(top)) if top - self.lo > 1 => {
                Some(self.lo + (top - self.lo) / 2)
            }
            _ => None,
        }
    }

    /// Takes in that `n` rods (the last [`Bisection::next`]) have no
    /// verdict; whether the search goes on below it. Only a guess above
    /// everything that spans can be stepped over: inside the bisection, a
    /// missing verdict would leave the critical number unknown.
    fn undecided(&mut self, n: usize) -> bool {
        if self.hi.is_some() {
            return false;
        }
        self.ceiling = Some(n);
        self.next().is_some()
    }

    /// Where the search waits for a verdict: the next guess, or the ceiling
    /// once nothing spans below it.
    fn waiting(&self) -> Option<usize> {
        self.next().or(self.ceiling.filter(|_| self.hi.is_none()))
    }

    /// Replays one recorded step, or says why the search could not have made it.
    fn replay(&mut self, s: &Step) -> std::result::Result<(), String> {
        if !s.undecided {
            self.record(s.n, s.spans);
            return Ok(());
        }
        if s.spans || !self.undecided(s.n) {
            return Err(format!(
                "{} rods are recorded without a verdict where the search could not go on",
                s.n
            ));
        }
        Ok(())
    }

    /// Takes in whether `n` rods (the last [`Bisection::next`]) span.
    fn record(&mut self, n: usize, spans: bool) {
        if spans {
            self.hi = Some(n);
        } else {
            self.lo = n;
            if self.hi.is_none() {
                self.probe = (n as f64 * GROWTH).ceil() as usize;
            }
        }
    }
}

/// The nested protocol on one sequence: the exact contact critical
/// number, and for the rigid kind the rigid one by bisection, each
/// compression starting from the bodies of the largest non-spanning system.
pub fn nested(setup: &Setup, seq: &mut Sequence, record: &mut Record) -> Result<()> {
    let n_c = seq.contact_critical(setup.criterion)?;
    record.contact_critical = n_c;
    if setup.kind == Kind::Contact {
        record.contacts.push(seq.contact_point(n_c));
        return Ok(());
    }
    let mut search = Bisection::new(n_c);
    if setup.kind == Kind::Truth {
        while let Some(n) = search.next() {
            seq.reach(n)?;
            let t = truth_of(setup, seq, n);
            if t.refused.is_some() {
                // Over the memory limit is no verdict on the sequence: the
                // study stops, and a rerun with more memory resumes it.
                return Err(refusal(seq, n, t));
            }
            let Some(spans) = t.spanning else {
                if search.undecided(n) {
                    record.steps.push(Step::undecided(n));
                    continue;
                }
                record.undecided = Some(n);
                return Ok(());
            };
            record.steps.push(Step {
                largest: Some(t.largest_cluster()),
                ..Step::new(n, spans, usize::from(spans))
            });
            search.record(n, spans);
        }
        let Some(hi) = search.hi else {
            record.undecided = search.waiting();
            return Ok(());
        };
        record.rigid_critical = Some(hi);
        // Truth carries nothing from step to step: the last spanning step is fresh.
        record.fresh = record.steps.iter().rev().find(|s| s.n == hi).copied();
        record.contacts.push(seq.contact_point(hi));
        return Ok(());
    }
    let mut lo_bodies = vec![Vec::new(); setup.runs];
    while let Some(n) = search.next() {
        if n > crate::rods::MAX_RODS {
            return Err(Error::Parameter(format!(
                "no rigid spanning cluster below {} rods in a box of side {}",
                crate::rods::MAX_RODS,
                seq.params.box_len
            )));
        }
        seq.reach(n)?;
        let (step, bodies, undecided) = compress(setup, seq, n, Some(&lo_bodies))?;
        if undecided {
            // Certification had no truth to check against: no verdict here.
            if search.undecided(n) {
                record.steps.push(Step::undecided(n));
                continue;
            }
            record.undecided = Some(n);
            return Ok(());
        }
        record.steps.push(step);
        if !step.spans {
            lo_bodies = bodies;
        }
        search.record(n, step.spans);
    }
    let Some(hi) = search.hi else {
        record.undecided = search.waiting();
        return Ok(());
    };
    record.rigid_critical = Some(hi);
    record.fresh = Some(if setup.kind == Kind::Truth {
        // Truth carries nothing from step to step: the last spanning step is fresh.
        *record
            .steps
            .iter()
            .rev()
            .find(|s| s.n == hi)
            .expect("hi was evaluated")
    } else {
        compress(setup, seq, hi, None)?.0
    });
    record.contacts.push(seq.contact_point(hi));
    Ok(())
}

/// The fixed protocol on one sequence: whether each prefix of `grid` rods
/// spans, each compressed from nothing (the paper's protocol).
pub fn fixed(setup: &Setup, seq: &mut Sequence, grid: &[usize], record: &mut Record) -> Result<()> {
    let n_c = seq.contact_critical(setup.criterion)?;
    record.contact_critical = n_c;
    for &n in grid {
        seq.reach(n)?;
        let step = match setup.kind {
            Kind::Contact => {
                let spans = n >= n_c;
                Step::new(n, spans, usize::from(spans))
            }
            // Rigid spanning needs contact spanning: no need to compress below it.
            Kind::Rigid | Kind::Truth if n < n_c => Step::new(n, false, 0),
            Kind::Rigid | Kind::Truth => compress(setup, seq, n, None)?.0,
        };
        record.fixed.push(step);
        record.contacts.push(seq.contact_point(n));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nested loop of [`nested`] on a verdict per number of rods:
    /// its steps, and the critical number or where it stayed undecided.
    fn search(
        n_c: usize,
        verdict: impl Fn(usize) -> Option<bool>,
    ) -> (Vec<Step>, std::result::Result<usize, Option<usize>>) {
        let mut search = Bisection::new(n_c);
        let mut steps = Vec::new();
        while let Some(n) = search.next() {
            match verdict(n) {
                Some(spans) => {
                    steps.push(Step::new(n, spans, usize::from(spans)));
                    search.record(n, spans);
                }
                None if search.undecided(n) => steps.push(Step::undecided(n)),
                None => return (steps, Err(Some(n))),
            }
        }
        let end = search.hi.ok_or(search.waiting());
        (steps, end)
    }

    #[test]
    fn a_guess_without_verdict_becomes_a_ceiling() {
        // Spans from 130 rods on; no verdict from 140 on. The guesses grow
        // 100, 125, 157 (no verdict: the ceiling), then halve the gap below.
        let (steps, end) = search(50, |n| (n < 140).then_some(n >= 130));
        assert_eq!(end, Ok(130));
        let rods: Vec<(usize, bool)> = steps.iter().map(|s| (s.n, s.undecided)).collect();
        assert_eq!(
            rods[..5],
            [
                (100, false),
                (125, false),
                (157, true),
                (141, true),
                (133, false)
            ]
        );
        assert_eq!(replay(50, &steps), Ok(130));
        // Without the verdict the search would not go on, so a record that
        // claims one is refused.
        let mut forged = steps.clone();
        forged[2].undecided = false;
        assert!(replay(50, &forged).is_err());
    }

    #[test]
    fn nothing_spanning_below_the_ceiling_stays_undecided() {
        // No verdict from 140 rods on, and nothing spans below.
        let (steps, end) = search(50, |n| (n < 140).then_some(false));
        let Err(Some(at)) = end else {
            panic!("{end:?}")
        };
        assert_eq!(replay_until(50, &steps), Ok(Some(at)));
        assert!(replay(50, &steps).is_err());
        // Inside the bisection a missing verdict ends the search.
        let (_, end) = search(50, |n| if n == 112 { None } else { Some(n >= 110) });
        assert_eq!(end, Err(Some(112)));
    }
}
