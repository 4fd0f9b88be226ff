//! The prime field F_p with `p = 2^61 - 1` (MODEL §4), and the [`Scalar`]
//! arithmetic that rigidity and Jacobian matrices are built with: exact F_p
//! or floats. By Schwartz–Zippel, a matrix built from random F_p coordinates
//! has the generic rank of its family except with probability at most
//! `degree / p`.

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
        (!self.is_zero()).then(|| Fp(inverse_mod(self.0, P)))
    }
}

/// The inverse of `a` modulo a prime `m > a > 0`, by the extended Euclidean
/// algorithm (several times faster than Fermat's `a^(m-2)`; eliminations
/// take one inverse per pivot).
pub fn inverse_mod(a: u64, m: u64) -> u64 {
    debug_assert!(a != 0 && a < m);
    let (mut r0, mut r1) = (m as i64, a as i64);
    let (mut t0, mut t1) = (0i64, 1i64); // |t| <= m: no overflow
    while r1 != 0 {
        let q = r0 / r1;
        (r0, r1) = (r1, r0 - q * r1);
        (t0, t1) = (t1, t0 - q * t1);
    }
    debug_assert_eq!(r0, 1, "the modulus is prime");
    t0.rem_euclid(m as i64) as u64
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

/// An exact prime field: what realizations are built and matrices
/// eliminated over.
pub trait Field: Scalar + Eq + std::hash::Hash {
    /// The prime (for [`super::prime::Fr`], the one in force on this thread).
    fn modulus() -> u64;
    /// The residue, in `0..modulus()`.
    fn residue(self) -> u64;
}

impl Field for Fp {
    fn modulus() -> u64 {
        P
    }
    fn residue(self) -> u64 {
        self.0
    }
}

/// F_q for a prime `q` below `2^24`: the fields whole systems are ranked
/// over. Their residues and products are exact in f64, so the dense work
/// of a whole-system elimination runs in floating-point matrix products
/// ([`super::echelon`]), many times faster than 61-bit residues. The price
/// is a larger chance of an unlucky draw than in F_p. Truth draws its
/// primes at run time ([`super::prime::Fr`]); these two fixed ones serve
/// the kernel's own tests and benchmarks.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct Fq<const Q: u32>(u32);

/// The largest prime below `2^24`.
pub type Q1 = Fq<16_777_213>;
/// The second largest prime below `2^24`.
pub type Q2 = Fq<16_777_199>;

impl<const Q: u32> Fq<Q> {
    pub const ZERO: Self = Fq(0);
    pub const ONE: Self = Fq(1);

    /// The residue of a signed integer.
    pub fn new(v: i64) -> Self {
        <Self as Scalar>::from_i64(v)
    }

    pub fn is_zero(self) -> bool {
        self.0 == 0
    }

    /// A uniformly random non-zero element.
    pub fn random_nonzero(rng: &mut impl Rng) -> Self {
        Fq(rng.random_range(1..Q))
    }
}

impl<const Q: u32> fmt::Debug for Fq<Q> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl<const Q: u32> Add for Fq<Q> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        let s = self.0 + o.0;
        Fq(if s >= Q { s - Q } else { s })
    }
}

impl<const Q: u32> Sub for Fq<Q> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Fq(if self.0 >= o.0 {
            self.0 - o.0
        } else {
            self.0 + Q - o.0
        })
    }
}

impl<const Q: u32> Neg for Fq<Q> {
    type Output = Self;
    fn neg(self) -> Self {
        Fq(0) - self
    }
}

impl<const Q: u32> Mul for Fq<Q> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Fq((self.0 as u64 * o.0 as u64 % Q as u64) as u32)
    }
}

impl<const Q: u32> Scalar for Fq<Q> {
    fn zero() -> Self {
        Fq(0)
    }
    fn one() -> Self {
        Fq(1)
    }
    fn from_i64(v: i64) -> Self {
        Fq(v.rem_euclid(Q as i64) as u32)
    }
    fn inverse(self) -> Option<Self> {
        (self.0 != 0).then(|| Fq(inverse_mod(self.0 as u64, Q as u64) as u32))
    }
    fn negligible(self) -> bool {
        self.0 == 0
    }
    fn magnitude(self) -> f64 {
        if self.0 == 0 { 0.0 } else { 1.0 }
    }
    fn random<R: Rng + ?Sized>(rng: &mut R) -> Self {
        Fq(rng.random_range(0..Q))
    }
    fn recip(self) -> Option<Self> {
        self.inverse()
    }
    fn vanishes(self, _scale: f64, _tol: f64) -> bool {
        self.0 == 0
    }
}

impl<const Q: u32> Field for Fq<Q> {
    fn modulus() -> u64 {
        Q as u64
    }
    fn residue(self) -> u64 {
        self.0 as u64
    }
}
