//! The logistic spanning probability `F(rho) = 1 / (1 + exp(-(rho - mu) / s))`
//! of one box size, fitted by maximum likelihood with Newton steps: to the
//! critical densities of nested sequences, or to the spanning indicators of
//! a fixed density grid.

use nalgebra::{Matrix2, Vector2};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::{Error, Result};

/// Fewest sequences with a critical density the nested fit accepts.
pub const MIN_NESTED: usize = 5;
const MAX_NEWTON: usize = 100;

/// A fitted cumulative logistic `F(rho) = 1 / (1 + exp(-(rho - mu) / s))`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Logistic {
    pub mu: f64,
    pub s: f64,
    /// Log-likelihood at the optimum: of the critical densities (nested,
    /// densities in rods per unit volume) or of the spanning indicators (fixed).
    pub log_likelihood: f64,
}

impl Logistic {
    /// The fitted spanning probability at `rho`.
    pub fn cdf(&self, rho: f64) -> f64 {
        1.0 / (1.0 + (-(rho - self.mu) / self.s).exp())
    }

    /// The density where the fitted spanning probability is `x` (inverse prediction).
    pub fn quantile(&self, x: f64) -> f64 {
        self.mu + self.s * (x / (1.0 - x)).ln()
    }

    /// The standard deviation of the logistic distribution, the paper's `Delta rho`.
    pub fn delta_rho(&self) -> f64 {
        self.s * PI / 3f64.sqrt()
    }
}

/// Maximum-likelihood logistic distribution of a sample of critical
/// densities: its CDF is the fitted spanning probability.
pub fn fit_logistic_sample(sample: &[f64]) -> Result<Logistic> {
    if sample.iter().any(|x| !x.is_finite()) {
        return Err(Error::analysis("a critical density is not a finite number"));
    }
    if sample.len() < MIN_NESTED {
        return Err(Error::analysis(format!(
            "fewer than {MIN_NESTED} sequences with a critical density (got {})",
            sample.len()
        )));
    }
    let n = sample.len() as f64;
    let mean = sample.iter().sum::<f64>() / n;
    let sd = (sample.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    if sd <= 1e-12 * mean.abs().max(1.0) {
        return Err(Error::analysis(format!(
            "fewer than 2 distinct critical densities (all {} at {mean})",
            sample.len()
        )));
    }
    let y: Vec<f64> = sample.iter().map(|x| (x - mean) / sd).collect();
    // In (a, b) = (1/s, mu/s) of the standardized sample the log-likelihood
    // is concave, so Newton with a line search finds the unique maximum.
    let eval = |p: Vector2<f64>| {
        let (a, b) = (p[0], p[1]);
        if a <= 0.0 {
            return None;
        }
        let (mut ll, mut g, mut h) = (n * a.ln(), Vector2::new(n / a, 0.0), Matrix2::zeros());
        h[(0, 0)] = -n / (a * a);
        for &yi in &y {
            let z = a * yi - b;
            let az = z.abs();
            ll -= az + 2.0 * (-az).exp().ln_1p();
            let t = (z / 2.0).tanh();
            let w = 0.5 * (1.0 - t * t);
            g[0] -= t * yi;
            g[1] += t;
            h[(0, 0)] -= w * yi * yi;
            h[(0, 1)] += w * yi;
            h[(1, 1)] -= w;
        }
        h[(1, 0)] = h[(0, 1)];
        Some((ll, g, h))
    };
    let (p, ll) = maximize(Vector2::new(PI / 3f64.sqrt(), 0.0), eval)?;
    Ok(Logistic {
        mu: mean + sd * p[1] / p[0],
        s: sd / p[0],
        log_likelihood: ll - n * sd.ln(),
    })
}

/// Maximum-likelihood logistic regression of spanning indicators pooled
/// per density, `(density, spanning, trials)`.
pub fn fit_logistic_binomial(grid: &[(f64, usize, usize)]) -> Result<Logistic> {
    if grid.iter().any(|g| !g.0.is_finite()) {
        return Err(Error::analysis("a grid density is not a finite number"));
    }
    if grid.iter().any(|g| g.1 > g.2) {
        return Err(Error::analysis(
            "more spanning systems than trials at a density",
        ));
    }
    let grid: Vec<(f64, usize, usize)> = grid.iter().copied().filter(|g| g.2 > 0).collect();
    let (span, trials): (usize, usize) = grid.iter().fold((0, 0), |(k, n), g| (k + g.1, n + g.2));
    let (lo, hi) = match (grid.first(), grid.last()) {
        (Some(f), Some(l)) => (
            grid.iter().map(|g| g.0).fold(f.0, f64::min),
            grid.iter().map(|g| g.0).fold(l.0, f64::max),
        ),
        _ => return Err(Error::analysis("no fixed-density observations")),
    };
    if span == trials {
        return Err(Error::analysis(format!(
            "every sequence spans at every grid density ({lo} to {hi}); add lower densities"
        )));
    }
    if span == 0 {
        return Err(Error::analysis(format!(
            "no sequence spans at any grid density ({lo} to {hi}); add higher densities"
        )));
    }
    // Without a spanning system below a non-spanning one the likelihood
    // grows without bound as s -> 0 (separation): the width is unresolved.
    let first_span = grid
        .iter()
        .filter(|g| g.1 > 0)
        .map(|g| g.0)
        .fold(f64::INFINITY, f64::min);
    let last_miss = grid
        .iter()
        .filter(|g| g.1 < g.2)
        .map(|g| g.0)
        .fold(f64::NEG_INFINITY, f64::max);
    if first_span >= last_miss {
        return Err(Error::analysis(format!(
            "spanning jumps from none to all at density {first_span}..{last_miss} (perfect separation): \
             the logistic width is unresolved; add grid densities around it or more sequences"
        )));
    }
    let n: f64 = trials as f64;
    let mean = grid.iter().map(|g| g.0 * g.2 as f64).sum::<f64>() / n;
    let sd = (grid
        .iter()
        .map(|g| (g.0 - mean).powi(2) * g.2 as f64)
        .sum::<f64>()
        / n)
        .sqrt();
    let pts: Vec<(f64, f64, f64)> = grid
        .iter()
        .map(|g| ((g.0 - mean) / sd, g.1 as f64, g.2 as f64))
        .collect();
    let eval = |p: Vector2<f64>| {
        let (a, b) = (p[0], p[1]);
        let (mut ll, mut g, mut h) = (0.0, Vector2::zeros(), Matrix2::zeros());
        for &(y, k, m) in &pts {
            let z = a * y - b;
            ll += k * ln_sigmoid(z) + (m - k) * ln_sigmoid(-z);
            let prob = 1.0 / (1.0 + (-z).exp());
            let r = k - m * prob;
            let v = m * prob * (1.0 - prob);
            g[0] += r * y;
            g[1] -= r;
            h[(0, 0)] -= v * y * y;
            h[(0, 1)] += v * y;
            h[(1, 1)] -= v;
        }
        h[(1, 0)] = h[(0, 1)];
        Some((ll, g, h))
    };
    let (p, ll) = maximize(Vector2::new(PI / 3f64.sqrt(), 0.0), eval)?;
    if p[0] <= 0.0 {
        return Err(Error::analysis(
            "the fitted spanning probability decreases with density",
        ));
    }
    Ok(Logistic {
        mu: mean + sd * p[1] / p[0],
        s: sd / p[0],
        log_likelihood: ll,
    })
}

fn ln_sigmoid(z: f64) -> f64 {
    if z > 0.0 {
        -(-z).exp().ln_1p()
    } else {
        z - z.exp().ln_1p()
    }
}

type Evaluation = Option<(f64, Vector2<f64>, Matrix2<f64>)>;

/// Maximizes a concave function of two parameters by Newton's method with
/// a backtracking line search; `f` gives value, gradient and Hessian, or
/// `None` outside its domain.
fn maximize(
    start: Vector2<f64>,
    f: impl Fn(Vector2<f64>) -> Evaluation,
) -> Result<(Vector2<f64>, f64)> {
    let mut p = start;
    let (mut val, mut g, mut h) =
        f(p).ok_or_else(|| Error::analysis("the logistic fit starts outside its domain"))?;
    for _ in 0..MAX_NEWTON {
        let step = match (-h).cholesky() {
            Some(c) => c.solve(&g),
            None => g,
        };
        let decrement = g.dot(&step);
        if !decrement.is_finite() {
            break;
        }
        if decrement <= 1e-14 * (1.0 + val.abs()) {
            return Ok((p, val));
        }
        let mut t = 1.0;
        let mut moved = false;
        for _ in 0..60 {
            let q = p + step * t;
            if let Some((v, gq, hq)) = f(q)
                && v.is_finite()
                && v >= val + 1e-4 * t * decrement
            {
                (p, val, g, h) = (q, v, gq, hq);
                moved = true;
                break;
            }
            t /= 2.0;
        }
        if !moved {
            if decrement <= 1e-8 * (1.0 + val.abs()) {
                return Ok((p, val));
            }
            break;
        }
        if p.iter().any(|x| x.abs() > 1e12) {
            break;
        }
    }
    Err(Error::analysis(format!(
        "the logistic fit did not converge in {MAX_NEWTON} Newton steps"
    )))
}
