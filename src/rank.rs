//! Rank of a matrix, exactly over the prime field F_p with `p = 2^61 - 1`
//! (DESIGN §4). The matrices of rgc are built from a realization whose
//! coordinates are random elements of F_p; by Schwartz–Zippel their rank is
//! the generic rank of that realization family except with probability at
//! most `degree / p`.

use rand::{Rng, RngExt};
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
        loop {
            let v = rng.random::<u64>() >> 3;
            if v < P {
                return Fp(v);
            }
        }
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

    /// The inverse of a non-zero element (Fermat).
    pub fn inv(self) -> Option<Fp> {
        (!self.is_zero()).then(|| self.pow(P - 2))
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
    let mut rank = 0;
    for c in 0..cols {
        if rank == rows {
            break;
        }
        let Some(pivot) = (rank..rows).find(|&r| !a[r * cols + c].is_zero()) else {
            continue;
        };
        if pivot != rank {
            for k in 0..cols {
                a.swap(pivot * cols + k, rank * cols + k);
            }
        }
        let inv = a[rank * cols + c].inv().expect("pivot is non-zero");
        for r in rank + 1..rows {
            let f = a[r * cols + c];
            if f.is_zero() {
                continue;
            }
            let f = f * inv;
            for k in c..cols {
                let v = a[rank * cols + k];
                if !v.is_zero() {
                    a[r * cols + k] = a[r * cols + k] - f * v;
                }
            }
        }
        rank += 1;
    }
    rank
}
