//! The fits across box sizes (MODEL §8), by least squares: `nu` from the
//! widths `Delta rho ~ L^(-1/nu)`, and the threshold as the one intercept
//! of every `rho_x(L)` against `L^(-1/nu)`.

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::math::stats::{Fit, least_squares, line};
use crate::{Error, Result};

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
    let points: Vec<(f64, f64)> = box_lens
        .iter()
        .zip(delta_rho)
        .map(|(l, d)| (l.ln(), d.ln()))
        .collect();
    let Fit { beta, r2, rms } =
        line(&points).ok_or_else(|| Error::analysis("nu needs at least 2 distinct box sizes"))?;
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
    let x = Mat::from_fn(m * n, m + 1, |row, col| {
        let (j, i) = (row / n, row % n);
        match col {
            0 => 1.0,
            c if c == j + 1 => t[i],
            _ => 0.0,
        }
    });
    let y: Vec<f64> = rho_x.iter().flatten().copied().collect();
    let Fit { beta, r2, rms } = least_squares(x.as_ref(), &y).ok_or_else(|| {
        Error::analysis("the common-intercept fit needs at least 2 distinct values of L^(-1/nu)")
    })?;
    Ok(Extrapolation {
        threshold: beta[0],
        slopes: beta.iter().skip(1).copied().collect(),
        r2,
        rms,
    })
}
