//! One box size on its own: what each sequence contributes to it, its
//! empirical spanning probability and its logistic fit (MODEL §8), which a
//! study still reports when the analysis across box sizes fails.

use serde::{Deserialize, Serialize};

use crate::threshold::logistic::{Logistic, fit_logistic_binomial, fit_logistic_sample};
use crate::{Error, Result};

/// Contact numbers measured on one system of a sequence.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactPoint {
    pub density: f64,
    pub c0: f64,
    pub c1: f64,
    pub c2: f64,
}

/// What one sequence (the seeded random rods of one box) contributes;
/// the unit of the bootstrap's case resampling.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    /// The density at which the sequence first spans (nested protocol).
    pub critical: Option<f64>,
    /// Whether it spans at each density of the fixed grid (fixed protocol).
    pub fixed: Vec<(f64, bool)>,
    /// Contact numbers measured along the way.
    pub contacts: Vec<ContactPoint>,
    /// Truth lost its verdict before the sequence spanned (no realization
    /// of the model), so a missing critical density is no censoring.
    #[serde(default)]
    pub undecided: bool,
}

/// The observations of one box size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxData {
    pub box_len: f64,
    pub observations: Vec<Observation>,
}

/// Which observations of a sequence the logistic fit uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Protocol {
    /// Each sequence's exact critical density: a sample of the
    /// distribution whose CDF is `pi(rho, L)`, fitted as a logistic distribution.
    Nested,
    /// Spanning or not at a grid of densities (the paper's protocol),
    /// fitted as a logistic regression of the spanning indicators.
    Fixed,
}

/// A box size's logistic fit and the sequences that entered it.
pub(super) struct BoxResult {
    pub(super) logistic: Logistic,
    pub(super) sequences: usize,
}

pub(super) fn fit_box(obs: &[&Observation], protocol: Protocol) -> Result<BoxResult> {
    match protocol {
        Protocol::Nested => {
            let sample: Vec<f64> = obs.iter().filter_map(|o| o.critical).collect();
            if sample.is_empty() && obs.iter().any(|o| !o.fixed.is_empty()) {
                return Err(Error::analysis(
                    "no critical densities, only fixed-density observations (use the fixed protocol)",
                ));
            }
            Ok(BoxResult {
                logistic: fit_logistic_sample(&sample)?,
                sequences: sample.len(),
            })
        }
        Protocol::Fixed => {
            let used = obs.iter().filter(|o| !o.fixed.is_empty()).count();
            if used == 0 {
                let hint = if obs.iter().any(|o| o.critical.is_some()) {
                    " (the data are from the nested protocol)"
                } else {
                    ""
                };
                return Err(Error::analysis(format!(
                    "no fixed-density observations{hint}"
                )));
            }
            let grid = pooled_grid(obs.iter().copied());
            Ok(BoxResult {
                logistic: fit_logistic_binomial(&grid)?,
                sequences: used,
            })
        }
    }
}

/// One box size fitted on its own, or why its fit failed: what a study
/// still reports when the analysis across box sizes fails.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxAlone {
    pub box_len: f64,
    /// Sequences of the box, including any the fit leaves out.
    pub observations: usize,
    /// Sequences that entered the fit (0 when it failed).
    // Keeps its stored key, so `--json` output reads as before.
    #[serde(rename = "realizations")]
    pub sequences: usize,
    pub fit: Option<Logistic>,
    pub delta_rho: Option<f64>,
    /// `rho_x(L)` for each `x` asked for (empty when the fit failed).
    pub rho_x: Vec<f64>,
    pub error: Option<String>,
}

/// Each box size's logistic fit on its own, in the order given: no `nu`,
/// no extrapolation and no bootstrap, so it needs none of their conditions.
pub fn fit_each_box(data: &[BoxData], protocol: Protocol, xs: &[f64]) -> Vec<BoxAlone> {
    data.iter()
        .map(|b| {
            let obs: Vec<&Observation> = b.observations.iter().collect();
            let alone = BoxAlone {
                box_len: b.box_len,
                observations: obs.len(),
                sequences: 0,
                fit: None,
                delta_rho: None,
                rho_x: Vec::new(),
                error: None,
            };
            match fit_box(&obs, protocol) {
                Ok(r) => BoxAlone {
                    sequences: r.sequences,
                    fit: Some(r.logistic),
                    delta_rho: Some(r.logistic.delta_rho()),
                    rho_x: xs.iter().map(|&x| r.logistic.quantile(x)).collect(),
                    ..alone
                },
                Err(e) => BoxAlone {
                    error: Some(match e {
                        Error::Analysis(m) => m,
                        e => e.to_string(),
                    }),
                    ..alone
                },
            }
        })
        .collect()
}

/// The fixed-protocol indicators pooled per density: `(density, spanning, trials)`.
pub(super) fn pooled_grid<'a>(
    obs: impl Iterator<Item = &'a Observation>,
) -> Vec<(f64, usize, usize)> {
    let mut all: Vec<(f64, bool)> = obs.flat_map(|o| o.fixed.iter().copied()).collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut grid: Vec<(f64, usize, usize)> = Vec::new();
    for (rho, spans) in all {
        match grid.last_mut() {
            Some(last) if last.0 == rho => {
                last.1 += spans as usize;
                last.2 += 1;
            }
            _ => grid.push((rho, spans as usize, 1)),
        }
    }
    grid
}

/// The empirical spanning probability of one box size as `(density,
/// fraction spanning, sequences)`: the empirical CDF at each distinct
/// critical density (nested; sequences that never span count as not
/// spanning) or the fraction at each grid density (fixed).
pub fn pi_curve(data: &BoxData, protocol: Protocol) -> Vec<(f64, f64, usize)> {
    match protocol {
        Protocol::Nested => {
            let n = data.observations.len();
            let mut crit: Vec<f64> = data
                .observations
                .iter()
                .filter_map(|o| o.critical)
                .collect();
            crit.sort_by(f64::total_cmp);
            let mut out: Vec<(f64, f64, usize)> = Vec::new();
            for (i, &c) in crit.iter().enumerate() {
                let frac = (i + 1) as f64 / n as f64;
                match out.last_mut() {
                    Some(last) if last.0 == c => last.1 = frac,
                    _ => out.push((c, frac, n)),
                }
            }
            out
        }
        Protocol::Fixed => pooled_grid(data.observations.iter())
            .into_iter()
            .map(|(rho, k, n)| (rho, k as f64 / n as f64, n))
            .collect(),
    }
}
