//! F_q for a prime `q` below `2^24` drawn at run time: the fields whole
//! systems are ranked over (MODEL §10).
//!
//! A fixed prime is a fixed target: a system whose generic minors all
//! vanish modulo that prime would lose rank in it on every draw, and no
//! number of draws in the same prime would show it. Each realization of
//! truth therefore draws its own prime, uniformly from the 513,708 primes
//! between `2^23` and `2^24` (below `2^24` so that the dense kernel stays
//! exact in f64, [`super::echelon`]). The prime lives in a per-thread
//! context for the extent of one closure ([`with_prime`]), as NTL's `zz_p`
//! contexts do: the elements stay four bytes, and a truth evaluation runs
//! on one thread.

use rand::{Rng, RngExt};
use std::cell::Cell;
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

use super::field::{Field, Scalar, inverse_mod};

/// The smallest prime truth draws from is above this.
pub const LOW: u32 = 1 << 23;
/// Every prime truth draws is below this (the dense kernel's bound).
pub const HIGH: u32 = 1 << 24;

/// The modulus in force on this thread, with its Barrett constant.
#[derive(Clone, Copy)]
struct Context {
    q: u32,
    /// `floor(2^64 / q)`.
    barrett: u64,
}

thread_local! {
    static CONTEXT: Cell<Option<Context>> = const { Cell::new(None) };
}

/// Runs `work` with the prime `q` in force for [`Fr`] on this thread, and
/// restores the prime before it (also when `work` panics).
pub fn with_prime<T>(q: u32, work: impl FnOnce() -> T) -> T {
    assert!(
        is_prime(q) && q < HIGH && q > 2,
        "{q} is not an odd prime below 2^24"
    );
    struct Restore(Option<Context>);
    impl Drop for Restore {
        fn drop(&mut self) {
            CONTEXT.with(|c| c.set(self.0));
        }
    }
    let context = Context {
        q,
        barrett: (u128::from(u64::MAX) + 1).div_euclid(u128::from(q)) as u64,
    };
    let _restore = Restore(CONTEXT.with(|c| c.replace(Some(context))));
    work()
}

#[inline(always)]
fn context() -> Context {
    CONTEXT
        .with(Cell::get)
        .expect("F_q arithmetic outside with_prime")
}

/// The prime in force on this thread, if any.
pub fn current() -> Option<u32> {
    CONTEXT.with(Cell::get).map(|c| c.q)
}

/// A prime drawn uniformly from those between [`LOW`] and [`HIGH`]: uniform
/// integers of the range until one is prime (one in about 16 is).
pub fn draw(rng: &mut impl Rng) -> u32 {
    loop {
        let q = rng.random_range(LOW..HIGH) | 1;
        if is_prime(q) {
            return q;
        }
    }
}

/// Two distinct primes drawn by [`draw`], one per twin.
pub fn draw_two(rng: &mut impl Rng) -> (u32, u32) {
    let first = draw(rng);
    loop {
        let second = draw(rng);
        if second != first {
            return (first, second);
        }
    }
}

/// Whether `n` is prime: Miller–Rabin with the bases 2, 7 and 61, which
/// decide every `n < 4,759,123,141` (Jaeschke 1993).
pub fn is_prime(n: u32) -> bool {
    if n < 2 {
        return false;
    }
    for p in [
        2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61,
    ] {
        if n.is_multiple_of(p) {
            return n == p;
        }
    }
    let n = u64::from(n);
    let (mut d, mut s) = (n - 1, 0);
    while d.is_multiple_of(2) {
        d /= 2;
        s += 1;
    }
    let pow = |mut b: u64, mut e: u64| {
        let mut acc = 1;
        while e > 0 {
            if e & 1 == 1 {
                acc = acc * b % n;
            }
            b = b * b % n;
            e >>= 1;
        }
        acc
    };
    [2, 7, 61].iter().all(|&a| {
        let mut x = pow(a, d);
        if x == 1 || x == n - 1 {
            return true;
        }
        for _ in 1..s {
            x = x * x % n;
            if x == n - 1 {
                return true;
            }
        }
        false
    })
}

/// An element of F_q for the prime in force ([`with_prime`]), reduced to `0..q`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct Fr(u32);

impl Fr {
    /// A uniformly random non-zero element.
    pub fn random_nonzero(rng: &mut impl Rng) -> Self {
        Fr(rng.random_range(1..context().q))
    }
}

impl fmt::Debug for Fr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl Add for Fr {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        let q = context().q;
        let s = self.0 + o.0;
        Fr(if s >= q { s - q } else { s })
    }
}

impl Sub for Fr {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Fr(if self.0 >= o.0 {
            self.0 - o.0
        } else {
            self.0 + context().q - o.0
        })
    }
}

impl Neg for Fr {
    type Output = Self;
    fn neg(self) -> Self {
        Fr(0) - self
    }
}

impl Mul for Fr {
    type Output = Self;
    /// Barrett reduction of the product: the quotient estimate is at most
    /// one short, since the product is below `q^2 < 2^48`.
    #[inline]
    fn mul(self, o: Self) -> Self {
        let c = context();
        let x = u64::from(self.0) * u64::from(o.0);
        let estimate = ((u128::from(x) * u128::from(c.barrett)) >> 64) as u64;
        let r = x - estimate * u64::from(c.q);
        Fr(if r >= u64::from(c.q) {
            r - u64::from(c.q)
        } else {
            r
        } as u32)
    }
}

impl Scalar for Fr {
    fn zero() -> Self {
        Fr(0)
    }
    fn one() -> Self {
        Fr(1)
    }
    fn from_i64(v: i64) -> Self {
        Fr(v.rem_euclid(i64::from(context().q)) as u32)
    }
    fn inverse(self) -> Option<Self> {
        (self.0 != 0).then(|| Fr(inverse_mod(u64::from(self.0), u64::from(context().q)) as u32))
    }
    fn negligible(self) -> bool {
        self.0 == 0
    }
    fn magnitude(self) -> f64 {
        if self.0 == 0 { 0.0 } else { 1.0 }
    }
    fn random<R: Rng + ?Sized>(rng: &mut R) -> Self {
        Fr(rng.random_range(0..context().q))
    }
    fn recip(self) -> Option<Self> {
        self.inverse()
    }
    fn vanishes(self, _scale: f64, _tol: f64) -> bool {
        self.0 == 0
    }
}

impl Field for Fr {
    fn modulus() -> u64 {
        u64::from(context().q)
    }
    fn residue(self) -> u64 {
        u64::from(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::field::Q1;
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn primality_agrees_with_trial_division_near_the_range() {
        // Trial division decides every number it is given; compare on a
        // window at each end of the range and on the edges of the bases.
        let slow = |n: u32| {
            n >= 2
                && (2..)
                    .take_while(|d| d * d <= n)
                    .all(|d| !n.is_multiple_of(d))
        };
        for n in (0..2000)
            .chain(LOW - 500..LOW + 500)
            .chain(HIGH - 1000..HIGH)
        {
            assert_eq!(is_prime(n), slow(n), "{n}");
        }
        assert_eq!(
            (LOW..HIGH).rev().find(|&n| is_prime(n)),
            Some(Q1::modulus() as u32),
            "the largest prime below 2^24 is Q1's"
        );
    }

    #[test]
    fn draws_are_primes_of_the_range_and_reproducible() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let drawn: Vec<u32> = (0..200).map(|_| draw(&mut rng)).collect();
        assert!(
            drawn
                .iter()
                .all(|&q| is_prime(q) && (LOW..HIGH).contains(&q))
        );
        let mut again = ChaCha8Rng::seed_from_u64(5);
        assert_eq!(
            drawn,
            (0..200).map(|_| draw(&mut again)).collect::<Vec<_>>()
        );
        let mut distinct = drawn.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert!(distinct.len() > 190, "{} distinct of 200", distinct.len());
        let (a, b) = draw_two(&mut rng);
        assert_ne!(a, b);
    }

    #[test]
    fn the_context_is_restored_after_a_scope_and_a_panic() {
        assert_eq!(current(), None);
        with_prime(16_777_199, || {
            assert_eq!(current(), Some(16_777_199));
            with_prime(8_388_617, || assert_eq!(Fr::modulus(), 8_388_617));
            assert_eq!(current(), Some(16_777_199));
            let caught = std::panic::catch_unwind(|| with_prime(8_388_617, || panic!("inside")));
            assert!(caught.is_err());
            assert_eq!(current(), Some(16_777_199));
        });
        assert_eq!(current(), None);
    }

    proptest! {
        /// Every operation agrees with plain integer arithmetic modulo the
        /// prime in force, at random primes of the range.
        #[test]
        fn arithmetic_matches_integers(seed: u64, a: u32, b: u32) {
            let q = draw(&mut ChaCha8Rng::seed_from_u64(seed));
            let (x, y) = (u64::from(a % q), u64::from(b % q));
            let qq = u64::from(q);
            with_prime(q, || {
                let (fx, fy) = (Fr::from_i64(x as i64), Fr::from_i64(y as i64));
                prop_assert_eq!((fx * fy).residue(), x * y % qq);
                prop_assert_eq!((fx + fy).residue(), (x + y) % qq);
                prop_assert_eq!((fx - fy).residue(), (x + qq - y) % qq);
                prop_assert_eq!((-fx).residue(), (qq - x) % qq);
                if x != 0 {
                    prop_assert_eq!((fx * fx.inverse().unwrap()).residue(), 1);
                }
                prop_assert_eq!(Fr::from_i64(-(x as i64)).residue(), (qq - x) % qq);
                Ok(())
            })?;
        }
    }
}
