//! The nested protocol's search for the rigid critical number, and its
//! replay on a record's steps.

use super::step::Step;

/// First guess for the rigid critical number, as a multiple of the contact
/// critical number; growth factor while the guess does not span.
const FIRST_GUESS: f64 = 2.0;
const GROWTH: f64 = 1.25;

/// The nested protocol's search for the rigid critical number: rigid
/// spanning needs contact spanning, so it starts above the contact critical
/// number `n_c`, grows its upper end from a guess until that spans, then
/// bisects. [`nested`](super::protocol::nested) runs it on compressions, and [`Record::check`]
/// replays it on a record's steps.
///
/// Truth has no verdict where forced planes percolate, far above the
/// critical number; a growing guess can land there. Such a guess becomes a
/// ceiling, and the search halves the gap below it until a guess spans.
pub(super) struct Bisection {
    /// Largest number of rods known not to span.
    lo: usize,
    /// Smallest number known to span, once one does.
    pub(super) hi: Option<usize>,
    /// The next guess while none spans.
    probe: usize,
    /// The smallest guess without a verdict, while none spans.
    ceiling: Option<usize>,
}

impl Bisection {
    pub(super) fn new(n_c: usize) -> Self {
        Bisection {
            lo: n_c - 1,
            hi: None,
            probe: (n_c as f64 * FIRST_GUESS).ceil() as usize,
            ceiling: None,
        }
    }

    /// The number of rods to compress next, or `None` once `hi` (or the
    /// ceiling, when nothing spans) is one above `lo`.
    pub(super) fn next(&self) -> Option<usize> {
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
    pub(super) fn undecided(&mut self, n: usize) -> bool {
        if self.hi.is_some() {
            return false;
        }
        self.ceiling = Some(n);
        self.next().is_some()
    }

    /// Where the search waits for a verdict: the next guess, or the ceiling
    /// once nothing spans below it.
    pub(super) fn waiting(&self) -> Option<usize> {
        self.next().or(self.ceiling.filter(|_| self.hi.is_none()))
    }

    /// Replays one recorded step, or says why the search could not have made it.
    pub(super) fn replay(&mut self, s: &Step) -> std::result::Result<(), String> {
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
    pub(super) fn record(&mut self, n: usize, spans: bool) {
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

/// Where [`Bisection`] goes after replaying `steps` from contact critical
/// number `n_c`: where it waits for a verdict ([`Bisection::waiting`]), or
/// `None` when it has ended.
pub(super) fn replay_until(
    n_c: usize,
    steps: &[Step],
) -> std::result::Result<Option<usize>, String> {
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
pub(super) fn replay(n_c: usize, steps: &[Step]) -> std::result::Result<usize, String> {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The nested loop of [`nested`](super::super::protocol::nested) on a verdict per number of rods:
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
