//! The whole finite-size-scaling analysis (MODEL §8, the paper's numerics
//! protocol): from the observations of each box size to the threshold, `nu`
//! and their intervals, with what a reader should know as warnings; and the
//! checks that a study can be analysed at all, made before its work.

use serde::{Deserialize, Serialize};

use super::bootstrap::{Pipeline, bootstrap, first_failure, pipeline};
use super::boxes::{BoxData, BoxResult, Observation, Protocol, pooled_grid};
use super::contacts::{ContactNumbers, contact_numbers};
use super::estimate::Estimate;
use crate::math::stats::percentile_interval;
use crate::threshold::logistic::{Logistic, MIN_NESTED};
use crate::{Error, Result};

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

    let samples = bootstrap(
        &lens,
        &all,
        opts.protocol,
        &opts.xs,
        opts.bootstrap,
        opts.seed,
    );
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

/// What the data lets through but a reader should know.
fn box_warnings(b: &BoxData, fit: &BoxResult, opts: &FssOptions) -> Vec<String> {
    let l = b.box_len;
    let mut out = Vec::new();
    match opts.protocol {
        Protocol::Nested => {
            let n = b.observations.len();
            let undecided = b
                .observations
                .iter()
                .filter(|o| o.critical.is_none() && o.undecided)
                .count();
            let censored = n - fit.sequences - undecided;
            if censored > 0 {
                out.push(format!(
                    "box L={l}: {censored} of {n} sequences never spanned and are left out of the fit (biases the threshold low)"
                ));
            }
            if undecided > 0 {
                out.push(format!(
                    "box L={l}: {undecided} of {n} sequences lost truth's verdict (no realization of the model) before their critical number was found and are left out of the fit"
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
