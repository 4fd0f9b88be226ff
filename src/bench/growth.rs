//! The growth fit: how a benchmark's cost grows with the number of rods, as
//! a power law fitted in logarithms.

use serde::Serialize;

use crate::math::stats;

/// How a cost grows with the number of rods: `y = prefactor * x^exponent`,
/// fitted by least squares of `log y` against `log x`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Growth {
    pub exponent: f64,
    pub prefactor: f64,
    /// R² of the fit in logarithms.
    pub r2: f64,
    pub points: usize,
}

impl Growth {
    /// The fit through the points with both coordinates positive; `None`
    /// without two distinct `x` among them.
    pub fn fit(points: impl IntoIterator<Item = (f64, f64)>) -> Option<Growth> {
        let logs: Vec<(f64, f64)> = points
            .into_iter()
            .filter(|&(x, y)| x > 0.0 && y > 0.0)
            .map(|(x, y)| (x.ln(), y.ln()))
            .collect();
        let stats::Fit { beta, r2, .. } = stats::line(&logs)?;
        Some(Growth {
            exponent: beta[1],
            prefactor: beta[0].exp(),
            r2,
            points: logs.len(),
        })
    }

    pub fn at(&self, x: f64) -> f64 {
        self.prefactor * x.powf(self.exponent)
    }
}
