//! Sample statistics, each written once: mean and standard deviation, the
//! geometric mean, one quantile rule, percentile intervals, the bootstrap,
//! and least squares.

use faer::linalg::solvers::SolveLstsq;
use faer::{Mat, MatRef};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Mean and sample standard deviation (0 for a single value; NaN mean for none).
pub fn mean_sd(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = if xs.len() > 1 {
        xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

/// The geometric mean of positive values (none for an empty sample or
/// one that is not positive).
pub fn geometric_mean(xs: &[f64]) -> Option<f64> {
    if xs.is_empty() {
        return None;
    }
    let logs: Option<f64> = xs.iter().map(|&x| (x > 0.0).then(|| x.ln())).sum();
    logs.map(|s| (s / xs.len() as f64).exp())
}

/// The `q` quantile of a sorted sample by linear interpolation between
/// order statistics (Hyndman–Fan type 7, the default of R and NumPy):
/// position `(n - 1) q`. NaN for an empty sample.
pub fn quantile_sorted(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let (i, f) = (h.floor() as usize, h.fract());
    let j = (i + 1).min(sorted.len() - 1);
    sorted[i] + f * (sorted[j] - sorted[i])
}

/// The `q` quantile of a sample ([`quantile_sorted`]); sorts `v` in place.
pub fn quantile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    quantile_sorted(v, q)
}

/// The median ([`quantile`] at 1/2): the mean of the two middle values of
/// an even sample.
pub fn median(v: &mut [f64]) -> f64 {
    quantile(v, 0.5)
}

/// The central `confidence` percentile interval by [`quantile`]; `None` for
/// no values. Sorts `v` in place.
pub fn percentile_interval(v: &mut [f64], confidence: f64) -> Option<(f64, f64)> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let tail = (1.0 - confidence) / 2.0;
    Some((quantile_sorted(v, tail), quantile_sorted(v, 1.0 - tail)))
}

/// A diagonal entry of `R` at most this fraction of the largest marks a
/// column dependent on the ones before it.
const DEPENDENT: f64 = 1e-10;

/// A least-squares fit: the coefficients, R² and the RMS residual.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    pub beta: Vec<f64>,
    pub r2: f64,
    pub rms: f64,
}

/// Least squares `y ~ x beta` by faer's Householder QR, not the normal
/// equations: an intercept far from the data (a contact number's line at
/// densities near 40) keeps its digits. `None` when the columns are
/// linearly dependent or a coefficient is not finite.
pub fn least_squares(x: MatRef<'_, f64>, y: &[f64]) -> Option<Fit> {
    if x.nrows() < x.ncols() || x.nrows() != y.len() {
        return None;
    }
    let y = MatRef::from_column_major_slice(y, y.len(), 1);
    let qr = x.qr();
    let r = qr.thin_R();
    let top = (0..r.ncols()).fold(0.0_f64, |m, i| m.max(r[(i, i)].abs()));
    let pivot = |i: usize| r[(i, i)].abs();
    if (0..r.ncols()).any(|i| pivot(i).is_nan() || pivot(i) <= DEPENDENT * top) {
        return None;
    }
    let beta: Mat<f64> = qr.solve_lstsq(y);
    let beta: Vec<f64> = (0..beta.nrows()).map(|i| beta[(i, 0)]).collect();
    if beta.iter().any(|b| !b.is_finite()) {
        return None;
    }
    let fitted = x * MatRef::from_column_major_slice(&beta, beta.len(), 1);
    let n = y.nrows();
    let ss_res: f64 = (0..n).map(|i| (y[(i, 0)] - fitted[(i, 0)]).powi(2)).sum();
    let mean = (0..n).map(|i| y[(i, 0)]).sum::<f64>() / n as f64;
    let ss_tot: f64 = (0..n).map(|i| (y[(i, 0)] - mean).powi(2)).sum();
    let r2 = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    Some(Fit {
        beta,
        r2,
        rms: (ss_res / n as f64).sqrt(),
    })
}

/// The bootstrap: `f` on `resamples` resamples of `groups`, each drawn
/// with replacement within its group (the sequences of one box), in order
/// (the resamples `f` declines are left out). Resample `b` draws from
/// stream `b` of `seed`, so the intervals are the same on every machine.
pub fn bootstrap<T: Clone, R>(
    groups: &[Vec<T>],
    resamples: usize,
    seed: u64,
    mut f: impl FnMut(&[Vec<T>]) -> Option<R>,
) -> Vec<R> {
    let mut drawn: Vec<Vec<T>> = groups.iter().map(|v| Vec::with_capacity(v.len())).collect();
    (0..resamples)
        .filter_map(|b| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(b as u64);
            for (d, v) in drawn.iter_mut().zip(groups) {
                d.clear();
                d.extend((0..v.len()).map(|_| v[rng.random_range(0..v.len())].clone()));
            }
            f(&drawn)
        })
        .collect()
}

/// The straight line `y = beta[0] + beta[1] x` through `(x, y)` points by
/// [`least_squares`]; `None` with fewer than two distinct `x`.
pub fn line(points: &[(f64, f64)]) -> Option<Fit> {
    let x = Mat::from_fn(
        points.len(),
        2,
        |i, j| if j == 0 { 1.0 } else { points[i].0 },
    );
    let y: Vec<f64> = points.iter().map(|p| p.1).collect();
    least_squares(x.as_ref(), &y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_geometric_mean_is_of_positive_values_only() {
        assert!((geometric_mean(&[1.0, 100.0]).unwrap() - 10.0).abs() < 1e-12);
        assert_eq!(geometric_mean(&[1.0, 0.0]), None);
        assert_eq!(geometric_mean(&[]), None);
    }

    #[test]
    fn percentile_interval_interpolates() {
        let mut v: Vec<f64> = (0..=100).map(f64::from).rev().collect();
        let (lo, hi) = percentile_interval(&mut v, 0.9).unwrap();
        assert!(
            (lo - 5.0).abs() < 1e-9 && (hi - 95.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        let (lo, _) = percentile_interval(&mut v, 0.95).unwrap();
        assert!((lo - 2.5).abs() < 1e-9, "between 2 and 3: {lo}");
        assert_eq!(percentile_interval(&mut [], 0.9), None);
    }

    #[test]
    fn median_of_even_sample_is_the_middle_mean() {
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert!(median(&mut []).is_nan());
    }

    #[test]
    fn mean_sd_of_a_known_sample() {
        let (m, s) = mean_sd(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]);
        assert_eq!(m, 5.0);
        assert!((s - (32.0f64 / 7.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn least_squares_recovers_a_line() {
        let points: Vec<(f64, f64)> = (0..4).map(|i| (i as f64, 3.0 - 2.0 * i as f64)).collect();
        let Fit { beta, r2, rms } = line(&points).unwrap();
        assert!((beta[0] - 3.0).abs() < 1e-12 && (beta[1] + 2.0).abs() < 1e-12);
        assert!((r2 - 1.0).abs() < 1e-12 && rms < 1e-12);
        assert_eq!(line(&[(1.0, 2.0), (1.0, 3.0)]), None, "one distinct x");
    }

    #[test]
    fn least_squares_of_a_known_residual() {
        // y = 0, 1, 0, 1 on x = 0..3: slope 0.2, intercept 0.2, residuals
        // -0.2, 0.6, -0.6, 0.2, so SS_res = 0.8 of SS_tot = 1.
        let points: Vec<(f64, f64)> = [0.0, 1.0, 0.0, 1.0]
            .iter()
            .enumerate()
            .map(|(i, &y)| (i as f64, y))
            .collect();
        let fit = line(&points).unwrap();
        assert!((fit.beta[0] - 0.2).abs() < 1e-12 && (fit.beta[1] - 0.2).abs() < 1e-12);
        assert!((fit.r2 - 0.2).abs() < 1e-12, "{}", fit.r2);
        assert!((fit.rms - 0.2_f64.sqrt()).abs() < 1e-12, "{}", fit.rms);
    }
}
