//! Rank of a matrix, exactly over the prime field F_p with `p = 2^61 - 1`
//! (DESIGN §4). The matrices of rgc are built from a realization whose
//! coordinates are random elements of F_p; by Schwartz–Zippel their rank is
//! the generic rank of that realization family except with probability at
//! most `degree / p`.

use rand::{Rng, RngExt};
use serde::Serialize;
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// The Mersenne prime `2^61 - 1`.
pub const P: u64 = (1 << 61) - 1;

/// An element of F_p, always reduced to `0..P`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct Fp(u64);

impl Fp {
    pub const ZERO: Fp = Fp(0);
    pub const ONE: Fp = Fp(1);

    /// The residue of a signed integer.
    pub fn new(v: i64) -> Fp {
        let r = v.rem_euclid(P as i64);
        Fp(r as u64)
    }

    pub fn value(self) -> u64 {
        self.0
    }

    /// A uniformly random element.
    pub fn random(rng: &mut impl Rng) -> Fp {
        <Fp as Scalar>::random(rng)
    }

    /// A uniformly random non-zero element.
    pub fn random_nonzero(rng: &mut impl Rng) -> Fp {
        loop {
            let v = Fp::random(rng);
            if v != Fp::ZERO {
                return v;
            }
        }
    }

    pub fn is_zero(self) -> bool {
        self.0 == 0
    }

    pub fn pow(self, mut e: u64) -> Fp {
        let (mut base, mut acc) = (self, Fp::ONE);
        while e > 0 {
            if e & 1 == 1 {
                acc = acc * base;
            }
            base = base * base;
            e >>= 1;
        }
        acc
    }

    /// The inverse of a non-zero element, by the extended Euclidean
    /// algorithm (several times faster than Fermat's `a^(p-2)`, and the
    /// elimination takes one inverse per pivot).
    pub fn inv(self) -> Option<Fp> {
        if self.is_zero() {
            return None;
        }
        let (mut r0, mut r1) = (P as i64, self.0 as i64);
        let (mut t0, mut t1) = (0i64, 1i64); // |t| <= P: no overflow
        while r1 != 0 {
            let q = r0 / r1;
            (r0, r1) = (r1, r0 - q * r1);
            (t0, t1) = (t1, t0 - q * t1);
        }
        debug_assert_eq!(r0, 1, "P is prime");
        Some(Fp(t0.rem_euclid(P as i64) as u64))
    }
}

impl fmt::Debug for Fp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl Add for Fp {
    type Output = Fp;
    fn add(self, o: Fp) -> Fp {
        let s = self.0 + o.0;
        Fp(if s >= P { s - P } else { s })
    }
}

impl Sub for Fp {
    type Output = Fp;
    fn sub(self, o: Fp) -> Fp {
        Fp(if self.0 >= o.0 {
            self.0 - o.0
        } else {
            self.0 + P - o.0
        })
    }
}

impl Neg for Fp {
    type Output = Fp;
    fn neg(self) -> Fp {
        Fp::ZERO - self
    }
}

impl Mul for Fp {
    type Output = Fp;
    fn mul(self, o: Fp) -> Fp {
        let t = self.0 as u128 * o.0 as u128;
        // Mersenne reduction: t = hi * 2^61 + lo = hi + lo (mod P).
        let s = (t as u64 & P) + (t >> 61) as u64;
        Fp(if s >= P { s - P } else { s })
    }
}

/// The arithmetic a rigidity or Jacobian matrix is built with: exact F_p or floats.
pub trait Scalar:
    Copy
    + fmt::Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
{
    fn zero() -> Self;
    fn one() -> Self;
    fn from_i64(v: i64) -> Self;
    /// `1 / self`, or `None` when `self` is (numerically) zero.
    fn inverse(self) -> Option<Self>;
    /// Whether `self` counts as zero (exactly for F_p).
    fn negligible(self) -> bool;
    /// A size for choosing pivots: `|x|` for floats; F_p has no order, so 1 for any non-zero.
    fn magnitude(self) -> f64;
    /// A random element for constructions: uniform in F_p, uniform in `[-1, 1]` for floats.
    fn random<R: Rng + ?Sized>(rng: &mut R) -> Self;
    /// `1 / self` unless `self` is exactly zero (or, for floats, the result is not finite).
    /// Unlike [`Scalar::inverse`] it has no absolute threshold: floats decide
    /// smallness relative to a scale, with [`Scalar::vanishes`].
    fn recip(self) -> Option<Self>;
    /// Whether `self` is zero next to `scale`, the size of the terms it was
    /// computed from: exactly zero over F_p, `|x| <= tol * scale` for floats.
    /// A non-finite float never vanishes, so NaN cannot pass an incidence test.
    fn vanishes(self, scale: f64, tol: f64) -> bool;
}

impl Scalar for Fp {
    fn zero() -> Self {
        Fp::ZERO
    }
    fn one() -> Self {
        Fp::ONE
    }
    fn from_i64(v: i64) -> Self {
        Fp::new(v)
    }
    fn inverse(self) -> Option<Self> {
        self.inv()
    }
    fn negligible(self) -> bool {
        self.is_zero()
    }
    fn magnitude(self) -> f64 {
        if self.is_zero() { 0.0 } else { 1.0 }
    }
    fn random<R: Rng + ?Sized>(rng: &mut R) -> Self {
        loop {
            let v = rng.random::<u64>() >> 3;
            if v < P {
                return Fp(v);
            }
        }
    }
    fn recip(self) -> Option<Self> {
        self.inv()
    }
    fn vanishes(self, _scale: f64, _tol: f64) -> bool {
        self.is_zero()
    }
}

impl Scalar for f64 {
    fn zero() -> Self {
        0.0
    }
    fn one() -> Self {
        1.0
    }
    fn from_i64(v: i64) -> Self {
        v as f64
    }
    fn inverse(self) -> Option<Self> {
        (!self.negligible()).then(|| 1.0 / self)
    }
    fn negligible(self) -> bool {
        self.abs() < 1e-12
    }
    fn magnitude(self) -> f64 {
        self.abs()
    }
    fn random<R: Rng + ?Sized>(rng: &mut R) -> Self {
        rng.random_range(-1.0..=1.0)
    }
    fn recip(self) -> Option<Self> {
        let r = 1.0 / self;
        r.is_finite().then_some(r)
    }
    fn vanishes(self, scale: f64, tol: f64) -> bool {
        self.abs() <= tol * scale
    }
}

/// A dense row-major matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix<S> {
    pub rows: usize,
    pub cols: usize,
    pub data: Vec<S>,
}

impl<S: Scalar> Matrix<S> {
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Matrix {
            rows,
            cols,
            data: vec![S::zero(); rows * cols],
        }
    }

    /// Appends a zero row and returns its index.
    pub fn push_row(&mut self) -> usize {
        self.data.extend(std::iter::repeat_n(S::zero(), self.cols));
        self.rows += 1;
        self.rows - 1
    }

    pub fn get(&self, r: usize, c: usize) -> S {
        self.data[r * self.cols + c]
    }

    pub fn set(&mut self, r: usize, c: usize, v: S) {
        self.data[r * self.cols + c] = v;
    }

    /// Adds `v` to entry `(r, c)`.
    pub fn add_to(&mut self, r: usize, c: usize, v: S) {
        let x = &mut self.data[r * self.cols + c];
        *x = *x + v;
    }

    /// `self * x` for a column vector `x`.
    pub fn apply(&self, x: &[S]) -> Vec<S> {
        (0..self.rows)
            .map(|r| {
                self.data[r * self.cols..(r + 1) * self.cols]
                    .iter()
                    .zip(x)
                    .fold(S::zero(), |acc, (&a, &b)| acc + a * b)
            })
            .collect()
    }
}

/// Exact rank over F_p by Gaussian elimination (consumes a copy).
pub fn rank_fp(m: &Matrix<Fp>) -> usize {
    let mut a = m.data.clone();
    let (rows, cols) = (m.rows, m.cols);
    // Rigidity and Jacobian rows have a handful of non-zeros: eliminating
    // with the pivot row's non-zeros only is several times faster than dense.
    let mut pivot_row: Vec<(usize, Fp)> = Vec::with_capacity(cols);
    let mut rank = 0;
    for c in 0..cols {
        if rank == rows {
            break;
        }
        let Some(pivot) = (rank..rows).find(|&r| !a[r * cols + c].is_zero()) else {
            continue;
        };
        if pivot != rank {
            let (top, bottom) = a.split_at_mut(pivot * cols);
            top[rank * cols..(rank + 1) * cols].swap_with_slice(&mut bottom[..cols]);
        }
        let inv = a[rank * cols + c].inv().expect("pivot is non-zero");
        pivot_row.clear();
        pivot_row.extend(
            (c + 1..cols)
                .map(|k| (k, a[rank * cols + k]))
                .filter(|(_, v)| !v.is_zero()),
        );
        for r in rank + 1..rows {
            let f = a[r * cols + c];
            if f.is_zero() {
                continue;
            }
            let f = f * inv;
            let row = &mut a[r * cols..(r + 1) * cols];
            row[c] = Fp::ZERO;
            for &(k, v) in &pivot_row {
                row[k] = row[k] - f * v;
            }
        }
        rank += 1;
    }
    rank
}

/// The singular values of a float matrix, descending (faer SVD, one thread:
/// rgc's matrices are small and many, so they are parallel across patterns).
/// `None` when the matrix has a non-finite entry or the SVD does not converge.
pub fn singular_values(m: &Matrix<f64>) -> Option<Vec<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::svd::{self, ComputeSvdVectors};
    let a = to_faer(m)?;
    let mut s = faer::diag::Diag::<f64>::zeros(m.rows.min(m.cols));
    let no = ComputeSvdVectors::No;
    let scratch = svd::svd_scratch::<f64>(m.rows, m.cols, no, no, faer::Par::Seq, default());
    let mut mem = MemBuffer::new(scratch);
    let stack = MemStack::new(&mut mem);
    svd::svd(
        a.as_ref(),
        s.as_mut(),
        None,
        None,
        faer::Par::Seq,
        stack,
        default(),
    )
    .ok()?;
    Some(descending(s.column_vector().iter().copied()))
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
