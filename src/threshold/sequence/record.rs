//! What one sequence produced, one line of a study's record file, and the
//! checks that it could have been produced: its steps replayed.

use serde::{Deserialize, Serialize};

use super::bisection::{replay, replay_until};
use super::setup::Kind;
use super::step::Step;
use crate::threshold::fss::{ContactPoint, Protocol};

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
    /// The record of sequence `index` of box `box_len` before a protocol
    /// fills it in.
    pub fn empty(box_len: f64, index: u64, seed: u64) -> Record {
        Record {
            box_len,
            index,
            seed,
            contact_critical: 0,
            rigid_critical: None,
            steps: Vec::new(),
            fresh: None,
            fixed: Vec::new(),
            contacts: Vec::new(),
            undecided: None,
            seconds: 0.0,
            peak_rss_mib: 0.0,
            cpu_seconds: None,
        }
    }

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

    /// Checks that the record is one [`super::protocol::nested`] or [`super::protocol::fixed`] could have
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
