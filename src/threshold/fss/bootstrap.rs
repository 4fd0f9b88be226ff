//! One pass of the scaling analysis (each box's fit, `nu`, the
//! extrapolation) on the data or on a case resample of its sequences, and
//! the bootstrap's resamples, each drawn from its own stream of the seed.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::boxes::{BoxResult, Observation, Protocol, fit_box};
use super::scaling::{Extrapolation, NuFit, extrapolate, fit_nu};
use crate::error::four;
use crate::{Error, Result};

/// Puts the box size in front of an analysis message.
fn in_box(box_len: f64, e: Error) -> Error {
    match e {
        Error::Analysis(m) => Error::analysis(format!("box L={box_len}: {m}")),
        e => e,
    }
}

/// One pass of the analysis on one set of observations (the data or a resample).
pub(super) struct Pipeline {
    pub(super) fits: Vec<BoxResult>,
    pub(super) nu: NuFit,
    pub(super) ext: Extrapolation,
}

pub(super) fn pipeline(
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
    // A density is positive: a fit that puts one at or below 0 (a tiny
    // study, a wide logistic, nu near 0) fails, on the data as on a
    // resample, so that no interval reaches below 0.
    for (x, row) in xs.iter().zip(&rho_x) {
        if let Some((l, r)) = lens.iter().zip(row).find(|(_, r)| r.is_nan() || **r <= 0.0) {
            return Err(Error::analysis(format!(
                "box L={l}: rho_x at x = {x} is {}, not a positive density: too few sequences for the fit",
                four(*r)
            )));
        }
    }
    let ext = extrapolate(&t, &rho_x)?;
    if ext.threshold.is_nan() || ext.threshold <= 0.0 {
        return Err(Error::analysis(format!(
            "the extrapolated threshold {} is not a positive density: too few sequences (or box sizes) for the extrapolation",
            four(ext.threshold)
        )));
    }
    Ok(Pipeline { fits, nu, ext })
}

pub(super) fn first_failure(samples: &[Result<Pipeline>]) -> String {
    samples
        .iter()
        .find_map(|s| s.as_ref().err())
        .map(|e| e.to_string())
        .unwrap_or_default()
}

/// The bootstrap resamples in order; resample `b` draws from stream `b` of
/// the seed, so the result does not depend on the number of threads.
pub(super) fn bootstrap(
    lens: &[f64],
    all: &[Vec<&Observation>],
    protocol: Protocol,
    xs: &[f64],
    resamples: usize,
    seed: u64,
) -> Vec<Result<Pipeline>> {
    (0..resamples)
        .into_par_iter()
        .map(|b| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(b as u64);
            let resampled: Vec<Vec<&Observation>> = all
                .iter()
                .map(|obs| {
                    (0..obs.len())
                        .map(|_| obs[rng.random_range(0..obs.len())])
                        .collect()
                })
                .collect();
            pipeline(lens, &resampled, protocol, xs)
        })
        .collect()
}
