//! Float rank: faer's SVD and pivoted QR, and the rule that reads a rank
//! (or "undecided") off a descending spectrum (MODEL §4).

use serde::Serialize;

use super::matrix::Matrix;

/// The singular values of a float matrix, descending (faer SVD, one thread:
/// rgc's matrices are small and many, so they are parallel across patterns).
/// `None` when the matrix has a non-finite entry or the SVD does not converge.
pub fn singular_values(m: &Matrix<f64>) -> Option<Vec<f64>> {
    svd(m, None).map(|s| descending(s.into_iter()))
}

/// The singular values of a float matrix, descending, and its right
/// singular vectors: column `k` of the `cols x cols` matrix belongs to value
/// `k`, and the columns past the numerical rank span the kernel (those past
/// `min(rows, cols)` have no value and lie in it). `None` as for
/// [`singular_values`].
pub fn singular_vectors(m: &Matrix<f64>) -> Option<(Vec<f64>, faer::Mat<f64>)> {
    let mut v = faer::Mat::<f64>::zeros(m.cols, m.cols);
    let s = svd(m, Some(v.as_mut()))?;
    Some((s, v))
}

/// faer's SVD on one thread, with the full right singular vectors in `v`
/// when asked; the values come nonincreasing.
fn svd(m: &Matrix<f64>, v: Option<faer::MatMut<'_, f64>>) -> Option<Vec<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::svd::{self, ComputeSvdVectors};
    let a = to_faer(m)?;
    let mut s = faer::diag::Diag::<f64>::zeros(m.rows.min(m.cols));
    let no = ComputeSvdVectors::No;
    let want_v = if v.is_some() {
        ComputeSvdVectors::Full
    } else {
        no
    };
    let scratch = svd::svd_scratch::<f64>(m.rows, m.cols, no, want_v, faer::Par::Seq, default());
    let mut mem = MemBuffer::new(scratch);
    let stack = MemStack::new(&mut mem);
    svd::svd(
        a.as_ref(),
        s.as_mut(),
        None,
        v,
        faer::Par::Seq,
        stack,
        default(),
    )
    .ok()?;
    Some(s.column_vector().iter().map(|x| x.abs()).collect())
}

/// The diagonal of `R` of a column-pivoted QR factorization (faer), in
/// absolute value and descending: a cheaper rank-revealing spectrum than the
/// SVD. `None` when the matrix has a non-finite entry.
pub fn qr_diagonal(m: &Matrix<f64>) -> Option<Vec<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::qr::col_pivoting::factor;
    let mut a = to_faer(m)?;
    let size = m.rows.min(m.cols);
    let block = factor::recommended_block_size::<f64>(m.rows, m.cols);
    let mut coeff = faer::Mat::<f64>::zeros(block, size);
    let (mut fwd, mut bwd) = (vec![0usize; m.cols], vec![0usize; m.cols]);
    let scratch =
        factor::qr_in_place_scratch::<usize, f64>(m.rows, m.cols, block, faer::Par::Seq, default());
    let mut mem = MemBuffer::new(scratch);
    let stack = MemStack::new(&mut mem);
    factor::qr_in_place(
        a.as_mut(),
        coeff.as_mut(),
        &mut fwd,
        &mut bwd,
        faer::Par::Seq,
        stack,
        default(),
    );
    Some(descending((0..size).map(|i| a[(i, i)])))
}

fn default<T: Default>() -> T {
    T::default()
}

fn to_faer(m: &Matrix<f64>) -> Option<faer::Mat<f64>> {
    m.data
        .iter()
        .all(|x| x.is_finite())
        .then(|| faer::Mat::from_fn(m.rows, m.cols, |i, j| m.get(i, j)))
}

fn descending(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.map(f64::abs).collect();
    v.sort_by(|a, b| b.total_cmp(a));
    v
}

/// How a float rank is read off a descending spectrum (singular values or
/// `|R_ii|`). With `floor = max(m, n) * f64::EPSILON * s_0`, the roundoff
/// level of a backward-stable factorization:
/// - values `<= floor * safety` (the `tolerance`) count as zero;
/// - the rank is decided only when the smallest value counted clears
///   `tolerance * grey`: a value in the grey zone between could be a true
///   zero spoiled by an ill-conditioned realization or a true non-zero
///   crushed by a nearly degenerate one, so the rank is undecided.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RankRule {
    pub safety: f64,
    pub grey: f64,
}

impl RankRule {
    /// For singular values. Measured by [`crate::stability::calibrate`] on
    /// 162,000 float matrices (every family of the panel, 3000 seeds), in
    /// units of the noise: values that are zero in exact arithmetic have
    /// median 0.025, 99.9% below 4 and the largest at 825; non-zero values
    /// have 0.1% below 3e9 and the smallest at 1.6e6. `safety = 100` puts the
    /// tolerance 25x above the 99.9% quantile of zeros; the grey zone up to
    /// `1e6` swallows the rare larger zeros (undecided, never a false rank)
    /// and sits below every non-zero value measured. The stability study
    /// shows no wrong decided verdict with these values.
    pub const SVD: RankRule = RankRule {
        safety: 100.0,
        grey: 1e4,
    };
    /// For the diagonal of a pivoted QR. Measured the same way, its trailing
    /// values overestimate the singular values they stand for by less than
    /// 2x here (largest zero 1244, smallest non-zero 1.9e6): the same rule.
    pub const QR: RankRule = RankRule {
        safety: 100.0,
        grey: 1e4,
    };
}

/// A numerical rank with the evidence for it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FloatRank {
    /// The rank, or `None` when a value sits in the grey zone (undecided).
    pub rank: Option<usize>,
    /// `s_{r-1} / s_r` around the rank `r` counted by the tolerance: the
    /// smallest value counted over the largest one not (`s_r` taken as
    /// `f64::EPSILON * s_0` when every value counts). Infinite for a zero
    /// matrix, 0 when the spectrum is not finite.
    pub gap: f64,
    /// The threshold below which values counted as zero.
    pub tolerance: f64,
    /// The number of values above the tolerance: what a plain numerical-rank
    /// routine reports, decided or not.
    pub counted: usize,
}

/// Decides the numerical rank of an `rows x cols` matrix from its descending
/// spectrum `values` under `rule`, the noise being the roundoff floor
/// `max(rows, cols) * f64::EPSILON * s_0`.
pub fn decide_rank(values: &[f64], rows: usize, cols: usize, rule: RankRule) -> FloatRank {
    let s0 = values.first().copied().unwrap_or(0.0);
    decide_rank_above(values, rows.max(cols) as f64 * f64::EPSILON * s0, rule)
}

/// [`decide_rank`] with a given noise level: the size of the perturbation
/// the spectrum may carry (the roundoff floor, or more when the matrix was
/// built from a realization with rounding in its incidences). The tolerance
/// is `noise * rule.safety`.
pub fn decide_rank_above(values: &[f64], noise: f64, rule: RankRule) -> FloatRank {
    if values.iter().any(|v| !v.is_finite()) || !noise.is_finite() {
        return FloatRank {
            rank: None,
            gap: 0.0,
            tolerance: f64::NAN,
            counted: 0,
        };
    }
    let s0 = values.first().copied().unwrap_or(0.0);
    let tolerance = noise * rule.safety;
    let r = values.iter().take_while(|&&v| v > tolerance).count();
    if r == 0 {
        // A zero matrix has rank 0; a non-zero one drowned in its noise has none.
        return FloatRank {
            rank: (s0 == 0.0).then_some(0),
            gap: f64::INFINITY,
            tolerance,
            counted: 0,
        };
    }
    let below = values.get(r).copied().unwrap_or(0.0).max(f64::EPSILON * s0);
    let smallest = values[r - 1];
    FloatRank {
        rank: (smallest > tolerance * rule.grey).then_some(r),
        gap: smallest / below,
        tolerance,
        counted: r,
    }
}

/// The numerical rank by SVD.
pub fn rank_svd(m: &Matrix<f64>) -> FloatRank {
    spectrum_rank(singular_values(m), m, RankRule::SVD)
}

/// The numerical rank by column-pivoted QR.
pub fn rank_qr(m: &Matrix<f64>) -> FloatRank {
    spectrum_rank(qr_diagonal(m), m, RankRule::QR)
}

fn spectrum_rank(values: Option<Vec<f64>>, m: &Matrix<f64>, rule: RankRule) -> FloatRank {
    match values {
        Some(v) => decide_rank(&v, m.rows, m.cols, rule),
        None => decide_rank(&[f64::NAN], m.rows, m.cols, rule),
    }
}
