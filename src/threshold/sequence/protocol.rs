//! The two protocols on one sequence: nested (the exact contact critical
//! number, the rigid one by bisection) and fixed (the paper's grid of
//! densities, each compressed from nothing).

use super::bisection::Bisection;
use super::record::Record;
use super::rods::Sequence;
use super::setup::{Kind, Setup};
use super::step::Step;
use super::verdict::{compress, refusal, truth_of, truth_step_or_undecided};
use crate::{Error, Result};

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
            if t.outcome.refused().is_some() {
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
                strain_rank: t.strain_rank(),
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
            // Where the model has no realization truth has no verdict: the
            // step says so, and the other densities of the sequence still count.
            Kind::Truth => truth_step_or_undecided(setup, seq, n)?,
            Kind::Rigid => compress(setup, seq, n, None)?.0,
        };
        record.fixed.push(step);
        record.contacts.push(seq.contact_point(n));
    }
    Ok(())
}
