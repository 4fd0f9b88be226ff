//! Numerical projection onto a family of realizations (MODEL §3), for
//! groupings that no exact construction reaches: Levenberg–Marquardt from
//! random starts on the incidence equations, then checks that the point
//! found is a realization of the family and not of a more special one.
//!
//! Unknowns: a point per contact, a direction per line, a normal and an
//! offset per group. Equations: `(x_c - x_0) x d_l = 0` for the contacts of
//! each line, `n_g . x_c = h_g` for the contacts of each group, `n_g . d_l =
//! 0` for its lines, and unit directions and normals. All are polynomial, so
//! their Jacobian is exact and small; [`crate::math::marquardt`] takes
//! the damped steps.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;

use super::construction::{Realization, check};
use super::family::jacobian;
use super::incidence::{Grouping, Incidence};
use crate::math::float::{RankRule, decide_rank_above, singular_values};
use crate::math::marquardt::{self, Residual, Residuals};
use crate::math::vec3::{Line, Plane, V3, add, cross, dot, norm, scale, size, sub};
use crate::math::{Matrix, Scalar};

/// Random starts tried before a grouping counts as not found.
pub const PROJECTION_STARTS: u64 = 16;

/// Largest residual (relative to the size of the realization) accepted as a
/// solution of the incidence equations.
pub const PROJECTION_TOL: f64 = 1e-12;

/// Smallest separation, relative to the extent of the contact points, that
/// keeps two points, two directions or a point and a plane apart: a solution
/// closer than this to a degenerate or more special position is refused
/// (its rank would be that of the special position, or unclear).
pub const SEPARATION: f64 = 1e-3;

/// The equations of a grouping, with the layout of the unknowns.
struct System<'a> {
    inc: &'a Incidence,
    groups: &'a [BTreeSet<usize>],
    /// The contacts of each group.
    group_contacts: Vec<Vec<usize>>,
}

impl System<'_> {
    fn n_contacts(&self) -> usize {
        self.inc.n_contacts()
    }
    fn dir(&self, l: usize) -> usize {
        3 * self.n_contacts() + 3 * l
    }
    fn normal(&self, g: usize) -> usize {
        3 * (self.n_contacts() + self.inc.n_lines()) + 4 * g
    }
    fn unknowns(&self) -> usize {
        self.normal(self.groups.len())
    }
    fn v(u: &[f64], at: usize) -> V3<f64> {
        [u[at], u[at + 1], u[at + 2]]
    }

    /// The residuals and, when asked, their Jacobian.
    fn residuals(&self, u: &[f64], jacobian: bool) -> Residuals {
        let mut ev = Residuals::new(jacobian);
        let x = |c: usize| Self::v(u, 3 * c);
        // [v]_x w = v x w
        let skew = |v: V3<f64>| [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
        for (l, cs) in self.inc.line_contacts.iter().enumerate() {
            let d = Self::v(u, self.dir(l));
            if let Some((&c0, rest)) = cs.split_first() {
                for &c in rest {
                    let a = sub(x(c), x(c0));
                    let f = cross(a, d);
                    let (sd, sa) = (skew(d), skew(a));
                    for k in 0..3 {
                        ev.row(
                            f[k],
                            (0..3).flat_map(|m| {
                                [
                                    (3 * c + m, -sd[k][m]),
                                    (3 * c0 + m, sd[k][m]),
                                    (self.dir(l) + m, sa[k][m]),
                                ]
                            }),
                        );
                    }
                }
            }
            ev.row(
                dot(d, d) - 1.0,
                (0..3).map(|m| (self.dir(l) + m, 2.0 * d[m])),
            );
        }
        for (g, members) in self.groups.iter().enumerate() {
            let at = self.normal(g);
            let n = Self::v(u, at);
            let h = u[at + 3];
            for &c in &self.group_contacts[g] {
                ev.row(
                    dot(n, x(c)) - h,
                    (0..3)
                        .flat_map(|m| [(at + m, x(c)[m]), (3 * c + m, n[m])])
                        .chain([(at + 3, -1.0)]),
                );
            }
            for &l in members {
                let d = Self::v(u, self.dir(l));
                ev.row(
                    dot(n, d),
                    (0..3).flat_map(|m| [(at + m, d[m]), (self.dir(l) + m, n[m])]),
                );
            }
            ev.row(dot(n, n) - 1.0, (0..3).map(|m| (at + m, 2.0 * n[m])));
        }
        ev
    }

    fn random_start(&self, rng: &mut ChaCha8Rng) -> Vec<f64> {
        (0..self.unknowns()).map(|_| f64::random(rng)).collect()
    }

    /// The sample a solution stands for.
    fn sample(&self, grouping: &Grouping, u: &[f64]) -> Realization<f64> {
        let inc = self.inc;
        let points: Vec<V3<f64>> = (0..inc.n_contacts()).map(|c| Self::v(u, 3 * c)).collect();
        let group_planes: Vec<Option<Plane<f64>>> = (0..self.groups.len())
            .map(|g| {
                let at = self.normal(g);
                let n = Self::v(u, at);
                let n = scale(n, 1.0 / norm(n));
                let other = if n[0].abs() < 0.5 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                let u1 = cross(n, other);
                let u1 = scale(u1, 1.0 / norm(u1));
                Some(Plane {
                    q: scale(n, u[at + 3]),
                    u: u1,
                    v: cross(n, u1),
                })
            })
            .collect();
        let lines = (0..inc.n_lines())
            .map(|l| {
                let p = match inc.line_contacts[l].first() {
                    Some(&c) => points[c],
                    None => self
                        .groups
                        .iter()
                        .position(|g| g.contains(&l))
                        .and_then(|g| group_planes[g])
                        .map_or([0.0; 3], |pl| pl.q),
                };
                Line {
                    p,
                    d: Self::v(u, self.dir(l)),
                }
            })
            .collect();
        let node_planes = super::construction::node_planes(inc, grouping, &group_planes);
        Realization {
            points,
            lines,
            group_planes,
            node_planes,
        }
    }

    /// Whether a sample is degenerate or more special than its grouping:
    /// two contact points (nearly) one, two touching lines parallel, or
    /// points the grouping leaves apart in a common plane (a line with two
    /// contacts in a group plane it is not in, two group planes one, or
    /// three chained lines outside any common group coplanar).
    fn special(&self, s: &Realization<f64>) -> bool {
        let inc = self.inc;
        let extent = spread(&s.points);
        let tol = SEPARATION * extent.max(f64::MIN_POSITIVE);
        let pts = &s.points;
        for i in 0..pts.len() {
            if pts[..i].iter().any(|&y| size(sub(pts[i], y)) <= tol) {
                return true;
            }
        }
        let unit = |v: V3<f64>| scale(v, 1.0 / norm(v));
        for (a, b) in inc.contact_lines.iter().map(|&[a, b]| (a, b)) {
            if size(cross(unit(s.lines[a].d), unit(s.lines[b].d))) <= SEPARATION {
                return true;
            }
        }
        let in_plane = |cs: &[usize], pl: &Plane<f64>| {
            let n = unit(pl.normal());
            cs.iter().all(|&c| dot(n, sub(pts[c], pl.q)).abs() <= tol)
        };
        let spanning = |l: usize| inc.line_contacts[l].len() >= 2;
        for (g, members) in self.groups.iter().enumerate() {
            let Some(pl) = s.group_planes[g] else {
                continue;
            };
            for l in (0..inc.n_lines()).filter(|&l| spanning(l) && !members.contains(&l)) {
                if in_plane(&inc.line_contacts[l], &pl) {
                    return true;
                }
            }
            for h in g + 1..self.groups.len() {
                if in_plane(&self.group_contacts[h], &pl) {
                    return true;
                }
            }
        }
        let together = |ls: &[usize]| self.groups.iter().any(|g| ls.iter().all(|l| g.contains(l)));
        for b in (0..inc.n_lines()).filter(|&b| spanning(b)) {
            let ends: BTreeSet<usize> = inc.touching(b).filter(|&a| spanning(a)).collect();
            for &a in &ends {
                for &c in ends.range(a + 1..) {
                    if together(&[a, b, c]) {
                        continue;
                    }
                    let mut cs: Vec<usize> = [a, b, c]
                        .iter()
                        .flat_map(|&l| inc.line_contacts[l].iter().copied())
                        .collect();
                    cs.sort_unstable();
                    cs.dedup();
                    if coplanar(pts, &cs, tol) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// The largest distance of a point from the centroid.
fn spread(points: &[V3<f64>]) -> f64 {
    let n = points.len().max(1) as f64;
    let c = points
        .iter()
        .fold([0.0; 3], |acc, &p| add(acc, scale(p, 1.0 / n)));
    points
        .iter()
        .map(|&p| dot(sub(p, c), sub(p, c)).sqrt())
        .fold(0.0, f64::max)
}

/// Whether the points `cs` lie within `tol` of one plane (smallest singular
/// value of their centred coordinates).
fn coplanar(points: &[V3<f64>], cs: &[usize], tol: f64) -> bool {
    let sel: Vec<V3<f64>> = cs.iter().map(|&c| points[c]).collect();
    let n = sel.len().max(1) as f64;
    let c = sel
        .iter()
        .fold([0.0; 3], |acc, &p| add(acc, scale(p, 1.0 / n)));
    let m = Matrix {
        rows: sel.len(),
        cols: 3,
        data: sel.iter().flat_map(|&p| sub(p, c)).collect(),
    };
    singular_values(&m).is_some_and(|sv| sv.iter().copied().fold(f64::INFINITY, f64::min) <= tol)
}

impl Residual for System<'_> {
    fn unknowns(&self) -> usize {
        self.normal(self.groups.len())
    }
    fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
        self.residuals(u, jacobian)
    }
    /// Relative to the extent of the contact points.
    fn tolerance(&self, u: &[f64]) -> f64 {
        let extent = u[..3 * self.n_contacts()]
            .iter()
            .fold(1.0_f64, |m, x| m.max(x.abs()));
        PROJECTION_TOL * extent
    }
}

/// A float realization of `grouping` found by numerical projection, or
/// `None` when no start out of [`PROJECTION_STARTS`] converges to a
/// non-degenerate realization of exactly that grouping. Deterministic in `seed`.
pub fn project(inc: &Incidence, grouping: &Grouping, seed: u64) -> Option<Realization<f64>> {
    project_twins(inc, grouping, seed, 0.0).map(|(s, _)| s)
}

/// [`project`], and a twin: the projection of the same solution with every
/// unknown nudged by up to `nudge`, a nearby member of the same family (the
/// counterpart of [`super::construction::construct_twins`]). The twin is `None` when it
/// does not converge or comes out special; no twin is sought when `nudge` is 0.
pub fn project_twins(
    inc: &Incidence,
    grouping: &Grouping,
    seed: u64,
    nudge: f64,
) -> Option<(Realization<f64>, Option<Realization<f64>>)> {
    let system = System {
        inc,
        groups: &grouping.groups,
        group_contacts: grouping
            .groups
            .iter()
            .map(|g| inc.group_contacts(g))
            .collect(),
    };
    let accept = |u: &[f64]| {
        let s = system.sample(grouping, u);
        (check(inc, grouping, &s).is_ok() && !system.special(&s)).then_some(s)
    };
    for start in 0..PROJECTION_STARTS {
        let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x2545_F491).wrapping_add(start));
        let Some(u) = marquardt::solve(&system, system.random_start(&mut rng)) else {
            continue;
        };
        let Some(base) = accept(&u) else {
            continue;
        };
        let twin = (nudge > 0.0)
            .then(|| {
                let moved = u
                    .iter()
                    .map(|x| x + nudge * f64::random(&mut rng))
                    .collect();
                marquardt::solve(&system, moved).and_then(|v| accept(&v))
            })
            .flatten();
        return Some((base, twin));
    }
    None
}

/// Dimension of the realizations with the incidences and `planes` near a
/// float sample: `3C` minus the float rank of [`jacobian`] (rows scaled to
/// unit length, SVD, [`RankRule::SVD`]); `None` when that rank is undecided.
pub fn float_local_dimension(
    inc: &Incidence,
    planes: &[BTreeSet<usize>],
    points: &[V3<f64>],
) -> Option<usize> {
    let mut j = jacobian(inc, planes, points);
    if j.rows == 0 {
        return Some(3 * points.len());
    }
    for row in j.data.chunks_mut(j.cols.max(1)) {
        let norm = row.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.0 {
            row.iter_mut().for_each(|x| *x /= norm);
        }
    }
    let values = singular_values(&j)?;
    let s0 = values.first().copied().unwrap_or(0.0);
    let noise = (j.rows.max(j.cols) as f64 * f64::EPSILON).max(PROJECTION_TOL) * s0;
    let rank = decide_rank_above(&values, noise, RankRule::SVD).rank?;
    Some(3 * points.len() - rank)
}
