//! Three-vectors over any [`Scalar`], with relative tests for floats that
//! are exact comparisons over F_p.

use super::field::Scalar;

/// A point or vector over a field.
pub type V3<S> = [S; 3];

/// A line `p + t d`: a rod's axis in a realization, over F_p or in floats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Line<S> {
    pub p: V3<S>,
    pub d: V3<S>,
}

/// A plane `q + a u + b v`, normal `u x v`: spanned by two directions
/// (two rods, or a rod and a box direction), so it is built without a
/// division and its points are drawn as `q + a u + b v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plane<S> {
    pub q: V3<S>,
    pub u: V3<S>,
    pub v: V3<S>,
}

impl<S: Scalar> Plane<S> {
    pub fn normal(&self) -> V3<S> {
        cross(self.u, self.v)
    }
}

pub fn sub<S: Scalar>(a: V3<S>, b: V3<S>) -> V3<S> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn add<S: Scalar>(a: V3<S>, b: V3<S>) -> V3<S> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub fn scale<S: Scalar>(a: V3<S>, k: S) -> V3<S> {
    [a[0] * k, a[1] * k, a[2] * k]
}

pub fn dot<S: Scalar>(a: V3<S>, b: V3<S>) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross<S: Scalar>(a: V3<S>, b: V3<S>) -> V3<S> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The length of a float vector.
pub fn norm(a: V3<f64>) -> f64 {
    dot(a, a).sqrt()
}

/// The point of the float line `l` nearest `x`.
pub fn foot(l: &Line<f64>, x: V3<f64>) -> V3<f64> {
    add(l.p, scale(l.d, dot(sub(x, l.p), l.d) / dot(l.d, l.d)))
}

/// How far `x` lies from the float line `l`.
pub fn distance(l: &Line<f64>, x: V3<f64>) -> f64 {
    norm(sub(x, foot(l, x)))
}

pub fn is_null<S: Scalar>(a: V3<S>) -> bool {
    a.iter().all(|x| x.negligible())
}

/// Relative tolerance below which two float points are one point, two
/// directions are parallel, or a direction is null: a few rounding errors of
/// the terms involved. Exact zero over F_p.
pub const DISTINCT_TOL: f64 = 16.0 * f64::EPSILON;

/// The size of a vector for relative tests: its largest coordinate magnitude.
pub fn size<S: Scalar>(v: V3<S>) -> f64 {
    v.iter().map(|x| x.magnitude()).fold(0.0, f64::max)
}

/// Whether every coordinate of `v` vanishes next to `scale`.
pub fn null_rel<S: Scalar>(v: V3<S>, scale: f64, tol: f64) -> bool {
    v.iter().all(|x| x.vanishes(scale, tol))
}

/// Whether two points are one (relative to their size).
pub fn same_point<S: Scalar>(x: V3<S>, y: V3<S>) -> bool {
    null_rel(sub(x, y), size(x) + size(y), DISTINCT_TOL)
}

/// Whether two directions are parallel (relative to their sizes).
pub fn parallel<S: Scalar>(a: V3<S>, b: V3<S>) -> bool {
    null_rel(cross(a, b), size(a) * size(b), DISTINCT_TOL)
}

/// Whether every coordinate is finite (always over F_p).
pub fn finite<S: Scalar>(v: V3<S>) -> bool {
    v.iter().all(|x| x.magnitude().is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_distance_from_a_line_ignores_the_length_of_its_direction() {
        // The line through (1, 0, 0) along x, its direction 2.5 long: (5, 3, 4)
        // is 5 from it, its foot (5, 0, 0).
        let l = Line {
            p: [1.0, 0.0, 0.0],
            d: [2.5, 0.0, 0.0],
        };
        assert_eq!(foot(&l, [5.0, 3.0, 4.0]), [5.0, 0.0, 0.0]);
        assert_eq!(distance(&l, [5.0, 3.0, 4.0]), 5.0);
        assert_eq!(distance(&l, [-7.0, 0.0, 0.0]), 0.0);
    }
}
