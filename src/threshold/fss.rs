//! Finite-size scaling (MODEL §8, the paper's numerics protocol): from the
//! observations of each box size to the threshold, `nu` and their intervals.
//!
//! Per box size `L` a cumulative logistic `F(rho; mu, s)` is fitted by
//! maximum likelihood, `Delta rho = s pi / sqrt(3)` gives `nu` through
//! `Delta rho ~ L^(-1/nu)`, and the inverse predictions `rho_x(L)` are
//! extrapolated against `L^(-1/nu)` with one intercept shared by every `x`:
//! the threshold. Intervals come from a case bootstrap over sequences. The
//! tables a study writes from the result are `threshold::report`'s.

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::logistic::{Logistic, MIN_NESTED, fit_logistic_binomial, fit_logistic_sample};
use crate::math::stats::{least_squares, percentile_interval};
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

/// How [`analyse`] runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FssOptions {
    pub protocol: Protocol,
    /// Spanning probabilities whose densities `rho_x(L)` are extrapolated.
    pub xs: Vec<f64>,
    /// Bootstrap resamples; 0 gives point estimates without intervals.
    pub bootstrap: usize,
    /// Seed of the bootstrap (resample `b` uses stream `b` of this seed).
    pub seed: u64,
    /// Coverage of the percentile intervals.
    pub confidence: f64,
}

impl Default for FssOptions {
    fn default() -> Self {
        FssOptions {
            protocol: Protocol::Nested,
            xs: vec![0.25, 0.4, 0.5, 0.6, 0.75],
            bootstrap: 200,
            seed: 0,
            confidence: 0.95,
        }
    }
}

/// A point estimate with its bootstrap percentile interval (absent without
/// bootstrap or when no resample succeeded).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    pub value: f64,
    pub lo: Option<f64>,
    pub hi: Option<f64>,
}

impl Estimate {
    fn with(value: f64, interval: Option<(f64, f64)>) -> Self {
        Estimate {
            value,
            lo: interval.map(|i| i.0),
            hi: interval.map(|i| i.1),
        }
    }
}

/// The fit of one box size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxFit {
    pub box_len: f64,
    /// Sequences that entered the fit.
    // Keeps its stored key, so existing summaries (`summary.json`) read back.
    #[serde(rename = "realizations")]
    pub sequences: usize,
    pub mu: f64,
    pub s: f64,
    pub delta_rho: f64,
    /// `rho_x(L)` for each of [`Fss::xs`].
    pub rho_x: Vec<f64>,
    pub log_likelihood: f64,
    pub mu_interval: Option<(f64, f64)>,
    pub delta_rho_interval: Option<(f64, f64)>,
    /// Bootstrap intervals of `rho_x(L)` (empty without bootstrap).
    pub rho_x_intervals: Vec<(f64, f64)>,
}

/// `Delta rho = prefactor * L^(-1/nu)`, fitted in log-log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NuFit {
    pub nu: f64,
    pub prefactor: f64,
    pub r2: f64,
    /// Root mean square residual of `ln Delta rho`.
    pub rms: f64,
}

/// `rho_x(L) = threshold + slopes[x] * L^(-1/nu)`, one intercept for every `x`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Extrapolation {
    pub threshold: f64,
    pub slopes: Vec<f64>,
    pub r2: f64,
    /// Root mean square residual of `rho_x`, in rods per unit volume.
    pub rms: f64,
}

/// A straight line `c = intercept + slope * rho` and its prediction at the threshold.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinearFit {
    pub intercept: f64,
    pub slope: f64,
    pub r2: f64,
    /// The line at the threshold; the interval is the line at the ends of
    /// the threshold's interval (the paper's way).
    pub at_threshold: Estimate,
}

/// Contact numbers against density over the contact points of one box
/// size (`box_len`) or of all box sizes pooled (`box_len = None`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactFits {
    pub box_len: Option<f64>,
    pub points: usize,
    pub c0: LinearFit,
    pub c1: LinearFit,
    pub c2: LinearFit,
}

/// Contact numbers at the threshold: the pooled fit is the headline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactNumbers {
    pub pooled: ContactFits,
    pub per_box: Vec<ContactFits>,
}

/// The finite-size-scaling result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fss {
    pub protocol: Protocol,
    /// One fit per box size, by increasing `L`.
    pub boxes: Vec<BoxFit>,
    pub nu: Estimate,
    pub threshold: Estimate,
    /// Slope of `rho_x` against `L^(-1/nu)` for each of `xs`.
    pub slopes: Vec<f64>,
    pub xs: Vec<f64>,
    /// `f` of `Delta rho = f L^(-1/nu)`.
    pub delta_rho_prefactor: f64,
    pub r2_nu: f64,
    pub r2_extrapolation: f64,
    /// Root mean square residual of `ln Delta rho` in the `nu` fit.
    pub rms_nu: f64,
    /// Root mean square residual of `rho_x` in the extrapolation.
    pub rms_extrapolation: f64,
    pub contact_numbers: Option<ContactNumbers>,
    pub bootstrap: usize,
    pub bootstrap_failures: usize,
    pub confidence: f64,
    pub seed: u64,
    pub warnings: Vec<String>,
}

/// Fewest box sizes the analysis takes: `nu` is the slope of `ln Delta rho`
/// against `ln L`, and a line through two points fits them with no check.
pub const MIN_BOXES: usize = 3;
/// Fewest bootstrap resamples a study asks for: one gives an interval of
/// zero width, none gives no interval at all.
pub const MIN_BOOTSTRAP: usize = 2;

/// Checks, before any sequence runs, that `boxes` box sizes with
/// `sequences` each can be analysed at all, so a study too small for the
/// fit fails at once rather than after its work.
pub fn check_design(boxes: usize, sequences: u64, protocol: Protocol) -> Result<()> {
    if boxes < MIN_BOXES {
        return Err(Error::Parameter(format!(
            "nu needs at least {MIN_BOXES} box sizes, got {boxes} (--boxes)"
        )));
    }
    if protocol == Protocol::Nested && sequences < MIN_NESTED as u64 {
        return Err(Error::Parameter(format!(
            "the logistic fit of a box needs at least {MIN_NESTED} sequences, got {sequences} (--sequences)"
        )));
    }
    Ok(())
}

/// Checks a requested number of bootstrap resamples (see [`MIN_BOOTSTRAP`]).
pub fn check_bootstrap(resamples: usize) -> Result<()> {
    if resamples < MIN_BOOTSTRAP {
        return Err(Error::Parameter(format!(
            "--bootstrap must be at least {MIN_BOOTSTRAP} (resamples for the intervals), got {resamples}"
        )));
    }
    Ok(())
}
/// Above this fraction of failed resamples the intervals get a warning.
const MAX_FAILED: f64 = 0.1;

/// Puts the box size in front of an analysis message.
fn in_box(box_len: f64, e: Error) -> Error {
    match e {
        Error::Analysis(m) => Error::analysis(format!("box L={box_len}: {m}")),
        e => e,
    }
}

/// Runs the whole finite-size-scaling analysis: per-L logistic fits, `nu`,
/// the common-intercept extrapolation, bootstrap intervals and contact
/// numbers at the threshold. Degenerate data is an [`Error::Analysis`] that
/// names the box and the problem; recoverable gaps are in `warnings`.
pub fn analyse(data: &[BoxData], opts: &FssOptions) -> Result<Fss> {
    check_options(opts)?;
    let data = sorted_boxes(data)?;
    let lens: Vec<f64> = data.iter().map(|b| b.box_len).collect();
    if data.len() < MIN_BOXES {
        return Err(Error::analysis(format!(
            "nu needs at least {MIN_BOXES} box sizes, got {}",
            data.len()
        )));
    }
    let all: Vec<Vec<&Observation>> = data
        .iter()
        .map(|b| b.observations.iter().collect())
        .collect();
    let point = pipeline(&lens, &all, opts.protocol, &opts.xs)?;
    let mut warnings = Vec::new();
    for (b, fit) in data.iter().zip(&point.fits) {
        warnings.extend(box_warnings(b, fit, opts));
    }

    let samples = bootstrap(&lens, &all, opts);
    let failures = samples.iter().filter(|s| s.is_err()).count();
    let good: Vec<&Pipeline> = samples.iter().filter_map(|s| s.as_ref().ok()).collect();
    if opts.bootstrap > 0 {
        if good.is_empty() {
            warnings.push(format!(
                "all {} bootstrap resamples failed (first: {}): no intervals",
                opts.bootstrap,
                first_failure(&samples)
            ));
        } else if failures as f64 > MAX_FAILED * opts.bootstrap as f64 {
            warnings.push(format!(
                "{failures} of {} bootstrap resamples failed (first: {}): the intervals come from the rest and may be too narrow",
                opts.bootstrap,
                first_failure(&samples)
            ));
        }
    }
    let interval = |f: &dyn Fn(&Pipeline) -> f64| -> Option<(f64, f64)> {
        let mut v: Vec<f64> = good.iter().map(|p| f(p)).collect();
        percentile_interval(&mut v, opts.confidence)
    };

    let boxes: Vec<BoxFit> = point
        .fits
        .iter()
        .enumerate()
        .map(|(i, fit)| {
            let rho_x_intervals = if good.is_empty() {
                Vec::new()
            } else {
                opts.xs
                    .iter()
                    .filter_map(|&x| interval(&|p| p.fits[i].logistic.quantile(x)))
                    .collect()
            };
            BoxFit {
                box_len: lens[i],
                sequences: fit.sequences,
                mu: fit.logistic.mu,
                s: fit.logistic.s,
                delta_rho: fit.logistic.delta_rho(),
                rho_x: opts.xs.iter().map(|&x| fit.logistic.quantile(x)).collect(),
                log_likelihood: fit.logistic.log_likelihood,
                mu_interval: interval(&|p| p.fits[i].logistic.mu),
                delta_rho_interval: interval(&|p| p.fits[i].logistic.delta_rho()),
                rho_x_intervals,
            }
        })
        .collect();
    let threshold = Estimate::with(point.ext.threshold, interval(&|p| p.ext.threshold));
    let contact_numbers = contact_numbers(&data, &threshold, &mut warnings);
    Ok(Fss {
        protocol: opts.protocol,
        boxes,
        nu: Estimate::with(point.nu.nu, interval(&|p| p.nu.nu)),
        threshold,
        slopes: point.ext.slopes,
        xs: opts.xs.clone(),
        delta_rho_prefactor: point.nu.prefactor,
        r2_nu: point.nu.r2,
        r2_extrapolation: point.ext.r2,
        rms_nu: point.nu.rms,
        rms_extrapolation: point.ext.rms,
        contact_numbers,
        bootstrap: opts.bootstrap,
        bootstrap_failures: failures,
        confidence: opts.confidence,
        seed: opts.seed,
        warnings,
    })
}

fn check_options(opts: &FssOptions) -> Result<()> {
    if opts.xs.is_empty() {
        return Err(Error::Parameter(
            "no spanning probabilities x to extrapolate".into(),
        ));
    }
    if let Some(x) = opts.xs.iter().find(|x| !(**x > 0.0 && **x < 1.0)) {
        return Err(Error::Parameter(format!(
            "spanning probability x={x} is not strictly between 0 and 1"
        )));
    }
    if !(opts.confidence > 0.0 && opts.confidence < 1.0) {
        return Err(Error::Parameter(format!(
            "confidence {} is not strictly between 0 and 1",
            opts.confidence
        )));
    }
    Ok(())
}

/// The boxes by increasing `L`, refusing sizes that are not positive or repeat.
fn sorted_boxes(data: &[BoxData]) -> Result<Vec<&BoxData>> {
    if let Some(b) = data
        .iter()
        .find(|b| !(b.box_len.is_finite() && b.box_len > 0.0))
    {
        return Err(Error::analysis(format!(
            "box size L={} is not a positive number",
            b.box_len
        )));
    }
    let mut sorted: Vec<&BoxData> = data.iter().collect();
    sorted.sort_by(|a, b| a.box_len.total_cmp(&b.box_len));
    if let Some(w) = sorted.windows(2).find(|w| w[0].box_len == w[1].box_len) {
        return Err(Error::analysis(format!(
            "box size L={} appears twice; merge its observations",
            w[0].box_len
        )));
    }
    Ok(sorted)
}

struct BoxResult {
    logistic: Logistic,
    sequences: usize,
}

/// One pass of the analysis on one set of observations (the data or a resample).
struct Pipeline {
    fits: Vec<BoxResult>,
    nu: NuFit,
    ext: Extrapolation,
}

fn pipeline(
    lens: &[f64],
    boxes: &[Vec<&Observation>],
    protocol: Protocol,
    xs: &[f64],
) -> Result<Pipeline> {
    let fits = lens
        .iter()
        .zip(boxes)
        .map(|(&l, obs)| fit_box(obs, protocol).map_err(|e| in_box(l, e)))
        .collect::<Result<Vec<_>>>()?;
    let delta: Vec<f64> = fits.iter().map(|f| f.logistic.delta_rho()).collect();
    let nu = fit_nu(lens, &delta)?;
    let t: Vec<f64> = lens.iter().map(|l| l.powf(-1.0 / nu.nu)).collect();
    let rho_x: Vec<Vec<f64>> = xs
        .iter()
        .map(|&x| fits.iter().map(|f| f.logistic.quantile(x)).collect())
        .collect();
    let ext = extrapolate(&t, &rho_x)?;
    Ok(Pipeline { fits, nu, ext })
}

fn fit_box(obs: &[&Observation], protocol: Protocol) -> Result<BoxResult> {
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
fn pooled_grid<'a>(obs: impl Iterator<Item = &'a Observation>) -> Vec<(f64, usize, usize)> {
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

/// What the data lets through but a reader should know.
fn box_warnings(b: &BoxData, fit: &BoxResult, opts: &FssOptions) -> Vec<String> {
    let l = b.box_len;
    let mut out = Vec::new();
    match opts.protocol {
        Protocol::Nested => {
            let censored = b.observations.len() - fit.sequences;
            if censored > 0 {
                out.push(format!(
                    "box L={l}: {censored} of {} sequences never spanned and are left out of the fit (biases the threshold low)",
                    b.observations.len()
                ));
            }
        }
        Protocol::Fixed => {
            let grid = pooled_grid(b.observations.iter());
            let (lo, hi) = (grid[0].0, grid[grid.len() - 1].0);
            let outside: Vec<String> = opts
                .xs
                .iter()
                .filter(|&&x| {
                    let r = fit.logistic.quantile(x);
                    r < lo || r > hi
                })
                .map(|x| x.to_string())
                .collect();
            if !outside.is_empty() {
                out.push(format!(
                    "box L={l}: rho_x for x in {{{}}} lies outside the density grid [{lo}, {hi}]; the logistic is extrapolated there",
                    outside.join(", ")
                ));
            }
            let sparse = grid.iter().filter(|g| g.2 < 10).count();
            if sparse > 0 {
                out.push(format!(
                    "box L={l}: {sparse} grid densities have fewer than 10 sequences"
                ));
            }
        }
    }
    out
}

fn first_failure(samples: &[Result<Pipeline>]) -> String {
    samples
        .iter()
        .find_map(|s| s.as_ref().err())
        .map(|e| e.to_string())
        .unwrap_or_default()
}

/// The bootstrap resamples in order; resample `b` draws from stream `b` of
/// the seed, so the result does not depend on the number of threads.
fn bootstrap(lens: &[f64], all: &[Vec<&Observation>], opts: &FssOptions) -> Vec<Result<Pipeline>> {
    (0..opts.bootstrap)
        .into_par_iter()
        .map(|b| {
            let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
            rng.set_stream(b as u64);
            let resampled: Vec<Vec<&Observation>> = all
                .iter()
                .map(|obs| {
                    (0..obs.len())
                        .map(|_| obs[rng.random_range(0..obs.len())])
                        .collect()
                })
                .collect();
            pipeline(lens, &resampled, opts.protocol, &opts.xs)
        })
        .collect()
}

/// `nu` from the least-squares line of `ln Delta rho` against `ln L`
/// (slope `-1/nu`).
pub fn fit_nu(box_lens: &[f64], delta_rho: &[f64]) -> Result<NuFit> {
    if box_lens.len() != delta_rho.len() {
        return Err(Error::analysis("as many Delta rho as box sizes are needed"));
    }
    if box_lens.len() < 3 {
        return Err(Error::analysis(format!(
            "nu needs at least 3 box sizes, got {}",
            box_lens.len()
        )));
    }
    if let Some(d) = delta_rho.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
        return Err(Error::analysis(format!("Delta rho {d} is not positive")));
    }
    let x = DMatrix::from_fn(box_lens.len(), 2, |i, j| {
        if j == 0 { 1.0 } else { box_lens[i].ln() }
    });
    let y = DVector::from_iterator(delta_rho.len(), delta_rho.iter().map(|d| d.ln()));
    let (beta, r2, rms) = least_squares(&x, &y)
        .ok_or_else(|| Error::analysis("nu needs at least 2 distinct box sizes"))?;
    let nu = -1.0 / beta[1];
    if !(nu.is_finite() && nu > 0.0) {
        return Err(Error::analysis(format!(
            "Delta rho does not shrink with L (log-log slope {:.4} >= 0): nu would be <= 0 or infinite",
            beta[1]
        )));
    }
    Ok(NuFit {
        nu,
        prefactor: beta[0].exp(),
        r2,
        rms,
    })
}

/// Least squares of `rho_x[j][i]` (x number `j`, box `i`) against `t[i] =
/// L_i^(-1/nu)`: one slope per `x`, one intercept (the threshold) for all.
pub fn extrapolate(t: &[f64], rho_x: &[Vec<f64>]) -> Result<Extrapolation> {
    if rho_x.is_empty() || rho_x.iter().any(|r| r.len() != t.len()) {
        return Err(Error::analysis(
            "the extrapolation needs one rho_x per box size for each x",
        ));
    }
    if t.iter()
        .chain(rho_x.iter().flatten())
        .any(|v| !v.is_finite())
    {
        return Err(Error::analysis(
            "a rho_x or L^(-1/nu) is not a finite number",
        ));
    }
    let (m, n) = (rho_x.len(), t.len());
    let x = DMatrix::from_fn(m * n, m + 1, |row, col| {
        let (j, i) = (row / n, row % n);
        match col {
            0 => 1.0,
            c if c == j + 1 => t[i],
            _ => 0.0,
        }
    });
    let y = DVector::from_iterator(m * n, rho_x.iter().flatten().copied());
    let (beta, r2, rms) = least_squares(&x, &y).ok_or_else(|| {
        Error::analysis("the common-intercept fit needs at least 2 distinct values of L^(-1/nu)")
    })?;
    Ok(Extrapolation {
        threshold: beta[0],
        slopes: beta.iter().skip(1).copied().collect(),
        r2,
        rms,
    })
}

/// A straight line through `(rho, c)` points, `None` with fewer than two
/// distinct densities.
fn line(points: &[(f64, f64)], threshold: &Estimate) -> Option<LinearFit> {
    let x = DMatrix::from_fn(
        points.len(),
        2,
        |i, j| if j == 0 { 1.0 } else { points[i].0 },
    );
    let y = DVector::from_iterator(points.len(), points.iter().map(|p| p.1));
    let (beta, r2, _) = least_squares(&x, &y)?;
    let at = |rho: f64| beta[0] + beta[1] * rho;
    let interval = threshold
        .lo
        .zip(threshold.hi)
        .map(|(lo, hi)| (at(lo).min(at(hi)), at(lo).max(at(hi))));
    Some(LinearFit {
        intercept: beta[0],
        slope: beta[1],
        r2,
        at_threshold: Estimate::with(at(threshold.value), interval),
    })
}

fn contact_fits(
    box_len: Option<f64>,
    points: &[ContactPoint],
    threshold: &Estimate,
) -> Option<ContactFits> {
    let col = |f: fn(&ContactPoint) -> f64| -> Vec<(f64, f64)> {
        points.iter().map(|p| (p.density, f(p))).collect()
    };
    Some(ContactFits {
        box_len,
        points: points.len(),
        c0: line(&col(|p| p.c0), threshold)?,
        c1: line(&col(|p| p.c1), threshold)?,
        c2: line(&col(|p| p.c2), threshold)?,
    })
}

/// Linear fits of `c0, c1, c2` against density, pooled and per box size;
/// missing or unusable contact points are warnings, not errors.
fn contact_numbers(
    data: &[&BoxData],
    threshold: &Estimate,
    warnings: &mut Vec<String>,
) -> Option<ContactNumbers> {
    let finite = |p: &&ContactPoint| [p.density, p.c0, p.c1, p.c2].iter().all(|v| v.is_finite());
    let points = |b: &BoxData| -> Vec<ContactPoint> {
        b.observations
            .iter()
            .flat_map(|o| o.contacts.iter())
            .filter(finite)
            .copied()
            .collect()
    };
    let mut per_box = Vec::new();
    let mut pooled = Vec::new();
    for b in data {
        let pts = points(b);
        if pts.is_empty() {
            continue;
        }
        match contact_fits(Some(b.box_len), &pts, threshold) {
            Some(f) => per_box.push(f),
            None => warnings.push(format!(
                "box L={}: contact points at fewer than 2 distinct densities; no contact-number fit",
                b.box_len
            )),
        }
        pooled.extend(pts);
    }
    if pooled.is_empty() {
        warnings
            .push("no contact points: contact numbers at the threshold are not reported".into());
        return None;
    }
    match contact_fits(None, &pooled, threshold) {
        Some(pooled) => Some(ContactNumbers { pooled, per_box }),
        None => {
            warnings.push(
                "contact points at fewer than 2 distinct densities: contact numbers at the threshold are not reported"
                    .into(),
            );
            None
        }
    }
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

impl BoxFit {
    /// The fitted logistic of this box size.
    pub fn logistic(&self) -> Logistic {
        Logistic {
            mu: self.mu,
            s: self.s,
            log_likelihood: self.log_likelihood,
        }
    }
}

impl Fss {
    /// `L^(-1/nu)` of a box size, the abscissa of the extrapolation.
    pub fn scaled(&self, box_len: f64) -> f64 {
        box_len.powf(-1.0 / self.nu.value)
    }
}
