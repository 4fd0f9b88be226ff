//! Sample statistics, each written once: mean and standard deviation, one
//! quantile rule, percentile intervals, and least squares.

use nalgebra::{DMatrix, DVector};

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

/// Least squares `y ~ x beta` through the normal equations; `None` when the
/// columns are linearly dependent. Returns `beta`, R² and the RMS residual.
pub fn least_squares(x: &DMatrix<f64>, y: &DVector<f64>) -> Option<(DVector<f64>, f64, f64)> {
    let xt = x.transpose();
    let beta = (&xt * x).cholesky()?.solve(&(&xt * y));
    if beta.iter().any(|b| !b.is_finite()) {
        return None;
    }
    let resid = y - x * &beta;
    let ss_res = resid.norm_squared();
    let mean = y.mean();
    let ss_tot = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
    let r2 = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    Some((beta, r2, (ss_res / y.len() as f64).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let x = DMatrix::from_fn(4, 2, |i, j| if j == 0 { 1.0 } else { i as f64 });
        let y = DVector::from_fn(4, |i, _| 3.0 - 2.0 * i as f64);
        let (beta, r2, rms) = least_squares(&x, &y).unwrap();
        assert!((beta[0] - 3.0).abs() < 1e-12 && (beta[1] + 2.0).abs() < 1e-12);
        assert!((r2 - 1.0).abs() < 1e-12 && rms < 1e-12);
    }
}
