//! Realizations of a contact pattern (MODEL §3), built exactly.
//!
//! A realization places one point per contact so that the contacts of one
//! rod are collinear (they lie on its axis), the contacts of a planar body
//! are coplanar, and all contact points are distinct. The set of
//! realizations can have several components on which the rigidity rank
//! differs, so every component must be sampled.
//!
//! Families of realizations are built from *plane groupings*: sets of rods
//! placed in one common plane, where any two lines meet. The forced grouping
//! (planar bodies, rod triangles and rods touching a plane twice) is the
//! most generic family; merging groups or rods into planes gives the others,
//! up to the all-coplanar realization. Each family is constructed exactly
//! over F_p by placing planes and lines one after another, every step
//! rational: a line meeting 0, 1, 2 or 3 placed lines, a plane through a
//! placed line, a group line through at most two required points.
//! Where no such order exists, [`super::projection`] finds a float
//! realization by Levenberg–Marquardt instead.
//!
//! A family is its own component when the realization set has no more
//! directions at its sample than the family itself (the nullity of the
//! Jacobian of all incidence constraints equals that of the family's
//! constraints); otherwise the sample is a special position of a larger
//! family and its rank says nothing about rigidity.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::incidence::{Grouping, Incidence};
use crate::math::vec3::{
    DISTINCT_TOL, Line, Plane, V3, add, cross, dot, finite, null_rel, parallel, same_point, scale,
    size, sub,
};
use crate::math::{Fp, Scalar};
use crate::pattern::NodeKind;

/// Relative tolerance within which a float construction must satisfy its
/// incidences (points on their lines and planes). Looser than
/// [`DISTINCT_TOL`] because a point where two nearly parallel lines meet
/// carries their conditioning; tight enough that a violated incidence
/// (residual of order 1) is never accepted.
pub const INCIDENCE_TOL: f64 = 1e-9;

/// One realization: a point per contact, a line per rod, a plane per group.
#[derive(Clone, Debug)]
pub struct Realization<S> {
    pub points: Vec<V3<S>>,
    pub lines: Vec<Line<S>>,
    /// The plane of each group of the grouping, by index.
    pub group_planes: Vec<Option<Plane<S>>>,
    /// The plane of each planar body: its group's (the one holding all its
    /// rods; a rod it shares with a rod triangle is in two planes).
    pub node_planes: Vec<Option<Plane<S>>>,
}

/// The plane of each planar body: that of the group holding all its rods.
pub(crate) fn node_planes<S: Copy>(
    inc: &Incidence,
    grouping: &Grouping,
    group_planes: &[Option<Plane<S>>],
) -> Vec<Option<Plane<S>>> {
    inc.kinds
        .iter()
        .enumerate()
        .map(|(i, k)| {
            if *k != NodeKind::Planar {
                return None;
            }
            grouping
                .groups
                .iter()
                .position(|g| inc.node_lines[i].iter().all(|l| g.contains(l)))
                .and_then(|gi| group_planes[gi])
        })
        .collect()
}
/// Which degenerate realization a construction approaches (MODEL §4: where
/// floats fail). Each puts the free choices of the construction `eps` away
/// from a degenerate position; the incidences hold exactly (up to rounding)
/// at every `eps`, so for `eps != 0` the realization is a generic member of
/// its family and the exact verdict is the reference. Over F_p, `eps = 0`
/// builds the degenerate limit itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Degeneracy {
    /// Every free choice uniform.
    #[default]
    Generic,
    /// Free line directions within about `eps` of one common direction (of
    /// the plane's first direction, inside a plane): nearly parallel rods.
    Parallel,
    /// Free points on a line within about `eps` of each other, free points
    /// within `eps` of one common point: nearly coincident contacts.
    Coincident,
    /// Free points within `eps` of one common line: nearly collinear contacts.
    Collinear,
}

/// How a construction draws its free choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometry<S> {
    pub degeneracy: Degeneracy,
    /// Distance from the degenerate position (unused when generic).
    pub eps: S,
}

impl<S: Scalar> Geometry<S> {
    /// Uniform random choices.
    pub fn generic() -> Self {
        Geometry {
            degeneracy: Degeneracy::Generic,
            eps: S::zero(),
        }
    }
}

/// The common direction of [`Degeneracy::Parallel`].
fn common_direction<S: Scalar>() -> V3<S> {
    [S::one(), S::one(), S::one()]
}

/// Random elements for constructions, shaped by a [`Geometry`].
struct Draw<'r, S, R: Rng> {
    rng: &'r mut R,
    geometry: Geometry<S>,
    /// For a twin realization: a second source, and the size of the nudge
    /// it adds to every free choice (after the geometry shaped it, so the
    /// nudge is not scaled down with `eps`).
    nudge: Option<(ChaCha8Rng, S)>,
}

impl<S: Scalar, R: Rng> Draw<'_, S, R> {
    fn s(&mut self) -> S {
        S::random(self.rng)
    }
    fn vector(&mut self) -> V3<S> {
        [self.s(), self.s(), self.s()]
    }
    /// A small random vector: `eps` times uniform.
    fn small(&mut self) -> V3<S> {
        let v = self.vector();
        scale(v, self.geometry.eps)
    }
    fn nudged(&mut self, x: S) -> S {
        match &mut self.nudge {
            Some((rng, eta)) => x + S::random(rng) * *eta,
            None => x,
        }
    }
    fn nudged_vector(&mut self, v: V3<S>) -> V3<S> {
        [self.nudged(v[0]), self.nudged(v[1]), self.nudged(v[2])]
    }
    /// A free vector (no geometry applies).
    fn free(&mut self) -> V3<S> {
        let v = self.vector();
        self.nudged_vector(v)
    }
    /// A free point.
    fn point(&mut self) -> V3<S> {
        let p = match self.geometry.degeneracy {
            Degeneracy::Coincident => self.small(),
            Degeneracy::Collinear => {
                let [_, y, z] = self.small();
                [self.s(), y, z]
            }
            Degeneracy::Generic | Degeneracy::Parallel => self.vector(),
        };
        self.nudged_vector(p)
    }
    /// A free direction.
    fn direction(&mut self) -> V3<S> {
        let d = match self.geometry.degeneracy {
            Degeneracy::Parallel => add(common_direction(), self.small()),
            _ => self.vector(),
        };
        self.nudged_vector(d)
    }
    /// A free parameter along a line or in a plane.
    fn param(&mut self) -> S {
        let t = match self.geometry.degeneracy {
            Degeneracy::Coincident => self.s() * self.geometry.eps,
            _ => self.s(),
        };
        self.nudged(t)
    }
    fn on_line(&mut self, l: &Line<S>) -> V3<S> {
        let t = self.param();
        add(l.p, scale(l.d, t))
    }
    fn in_plane(&mut self, pl: &Plane<S>) -> V3<S> {
        let (a, b) = (self.param(), self.param());
        add(pl.q, add(scale(pl.u, a), scale(pl.v, b)))
    }
    /// A free direction inside a plane: `a u + b v`.
    fn plane_direction(&mut self, pl: &Plane<S>) -> V3<S> {
        let (a, b) = (self.s(), self.s());
        let (a, b) = match self.geometry.degeneracy {
            Degeneracy::Parallel => (S::one() + a * self.geometry.eps, b * self.geometry.eps),
            _ => (a, b),
        };
        let (a, b) = (self.nudged(a), self.nudged(b));
        add(scale(pl.u, a), scale(pl.v, b))
    }
}

/// The point where two coplanar, non-parallel lines meet.
fn meet<S: Scalar>(a: &Line<S>, b: &Line<S>) -> Option<V3<S>> {
    let (det, num) = meet_fraction(a, b)?;
    meet_at(a, b, num * det.recip()?)
}

/// The parameter of the point where `b` meets `a` (`a.p + s a.d`) as a
/// fraction `num / det`; `None` for parallel lines.
fn meet_fraction<S: Scalar>(a: &Line<S>, b: &Line<S>) -> Option<(S, S)> {
    // a.p + s a.d = b.p + t b.d: solve the two rows with the largest minor, check the third.
    if parallel(a.d, b.d) {
        return None;
    }
    let r = sub(b.p, a.p);
    let det = |i: usize, j: usize| a.d[i] * (-b.d[j]) - (-b.d[i]) * a.d[j];
    // Each minor once; the first of the largest (in order) is taken.
    let minors = [
        ((0, 1), det(0, 1)),
        ((0, 2), det(0, 2)),
        ((1, 2), det(1, 2)),
    ];
    let ((i, j), minor) = minors.into_iter().fold(
        None,
        |best: Option<((usize, usize), S)>, (ij, m)| match best {
            Some((_, b)) if b.magnitude() >= m.magnitude() => best,
            _ => Some((ij, m)),
        },
    )?;
    Some((minor, r[i] * (-b.d[j]) - (-b.d[i]) * r[j]))
}

/// The point of `a` at parameter `s`, if it lies on `b`.
fn meet_at<S: Scalar>(a: &Line<S>, b: &Line<S>, s: S) -> Option<V3<S>> {
    let x = add(a.p, scale(a.d, s));
    on_line(x, b).then_some(x)
}

/// Whether `S` is exact arithmetic (F_p): there [`Scalar::vanishes`] is
/// exact zero, so one is never negligible.
pub(super) fn exact<S: Scalar>() -> bool {
    !S::one().vanishes(1.0, 1.0)
}

/// Replaces each of `xs` by its inverse with one inversion and three
/// products per element (Montgomery's trick); `false` if one is zero. Exact
/// arithmetic only: the inverses are the same as one by one, whereas floats
/// would round differently.
pub(super) fn invert_all<S: Scalar>(xs: &mut [S], prefix: &mut Vec<S>) -> bool {
    prefix.clear();
    let mut acc = S::one();
    for &x in xs.iter() {
        prefix.push(acc);
        acc = acc * x;
    }
    let Some(mut inv) = acc.recip() else {
        return false;
    };
    for (x, &before) in xs.iter_mut().zip(prefix.iter()).rev() {
        let x_inv = inv * before;
        inv = inv * *x;
        *x = x_inv;
    }
    true
}

/// Where a line crosses a plane (none when it is parallel to it).
fn pierce<S: Scalar>(l: &Line<S>, pl: &Plane<S>) -> Option<V3<S>> {
    let n = pl.normal();
    let across = dot(n, l.d);
    if across.vanishes(size(pl.u) * size(pl.v) * size(l.d), DISTINCT_TOL) {
        return None;
    }
    let t = dot(n, sub(pl.q, l.p)) * across.recip()?;
    Some(add(l.p, scale(l.d, t)))
}

fn on_line<S: Scalar>(x: V3<S>, l: &Line<S>) -> bool {
    let scale = (size(x) + size(l.p)) * size(l.d);
    null_rel(cross(sub(x, l.p), l.d), scale, INCIDENCE_TOL)
}

fn on_plane<S: Scalar>(x: V3<S>, pl: &Plane<S>) -> bool {
    on_plane_with(x, pl, pl.normal())
}

/// [`on_plane`] with the plane's normal given.
fn on_plane_with<S: Scalar>(x: V3<S>, pl: &Plane<S>, normal: V3<S>) -> bool {
    let scale = size(pl.u) * size(pl.v) * (size(x) + size(pl.q));
    dot(normal, sub(x, pl.q)).vanishes(scale, INCIDENCE_TOL)
}

fn line_in_plane<S: Scalar>(l: &Line<S>, pl: &Plane<S>) -> bool {
    let scale = size(pl.u) * size(pl.v) * size(l.d);
    on_plane(l.p, pl) && dot(pl.normal(), l.d).vanishes(scale, INCIDENCE_TOL)
}

fn lines_meet<S: Scalar>(a: &Line<S>, b: &Line<S>) -> bool {
    let n = cross(a.d, b.d);
    let scale = (size(a.p) + size(b.p)) * size(a.d) * size(b.d);
    !parallel(a.d, b.d) && dot(sub(b.p, a.p), n).vanishes(scale, INCIDENCE_TOL)
}

fn through<S: Scalar>(x: V3<S>, y: V3<S>) -> Option<Line<S>> {
    (!same_point(x, y)).then(|| Line { p: x, d: sub(y, x) })
}

/// What is placed as one step of a construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Object {
    Group(usize),
    Line(usize),
}

/// Why a construction did not produce a realization.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Infeasible {
    /// No order places every object with rational steps.
    NoOrder,
    /// Random choices kept producing coincident points (or, for floats,
    /// points too close to tell apart or incidences lost to rounding).
    Degenerate,
}

/// Builds one exact realization of `grouping`, or says why it cannot.
pub fn construct(
    inc: &Incidence,
    grouping: &Grouping,
    seed: u64,
) -> Result<Realization<Fp>, Infeasible> {
    construct_in(inc, grouping, &Geometry::generic(), seed)
}

/// Builds one realization of `grouping` over any [`Scalar`], with free
/// choices drawn by `geometry`: the same construction serves the exact
/// verdict (F_p) and the float one (f64, relative tolerances).
pub fn construct_in<S: Scalar>(
    inc: &Incidence,
    grouping: &Grouping,
    geometry: &Geometry<S>,
    seed: u64,
) -> Result<Realization<S>, Infeasible> {
    construct_attempts(inc, grouping, geometry, seed).map(|(s, _)| s)
}

/// [`construct_in`], and a twin: the same construction with every free
/// choice nudged by up to `nudge` (after `geometry` shaped it). A rank that
/// differs between the two is not locally constant: the realization is at
/// or near a special position, whatever `geometry` did. The twin is `None`
/// when the nudged construction fails.
pub fn construct_twins<S: Scalar>(
    inc: &Incidence,
    grouping: &Grouping,
    geometry: &Geometry<S>,
    seed: u64,
    nudge: S,
) -> Result<(Realization<S>, Option<Realization<S>>), Infeasible> {
    let (base, attempt) = construct_attempts(inc, grouping, geometry, seed)?;
    let mut rng = attempt_rng(seed, attempt);
    let mut draw = Draw {
        rng: &mut rng,
        geometry: *geometry,
        nudge: Some((ChaCha8Rng::seed_from_u64(!seed ^ attempt), nudge)),
    };
    let twin = try_construct(inc, grouping, &mut draw, attempt).ok();
    Ok((base, twin))
}

fn attempt_rng(seed: u64, attempt: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9).wrapping_add(attempt))
}

/// The first of a few attempts that builds, and its index.
fn construct_attempts<S: Scalar>(
    inc: &Incidence,
    grouping: &Grouping,
    geometry: &Geometry<S>,
    seed: u64,
) -> Result<(Realization<S>, u64), Infeasible> {
    let mut last = Infeasible::NoOrder;
    for attempt in 0..8u64 {
        let mut rng = attempt_rng(seed, attempt);
        let mut draw = Draw {
            rng: &mut rng,
            geometry: *geometry,
            nudge: None,
        };
        match try_construct(inc, grouping, &mut draw, attempt) {
            Ok(s) => return Ok((s, attempt)),
            Err(e) => last = e,
        }
    }
    Err(last)
}

fn try_construct<S: Scalar, R: Rng>(
    inc: &Incidence,
    grouping: &Grouping,
    draw: &mut Draw<'_, S, R>,
    attempt: u64,
) -> Result<Realization<S>, Infeasible> {
    let n_lines = inc.n_lines();
    let heavy: Vec<usize> = (0..n_lines)
        .filter(|&l| !grouping.in_group(l) && inc.line_contacts[l].len() >= 3)
        .collect();
    let mut objects: Vec<Object> = (0..grouping.groups.len()).map(Object::Group).collect();
    objects.extend(heavy.iter().map(|&l| Object::Line(l)));
    // Lines placed so far, and the plane of each group.
    let mut line: Vec<Option<Line<S>>> = vec![None; n_lines];
    let mut group_planes: Vec<Option<Plane<S>>> = vec![None; grouping.groups.len()];
    let mut placed = vec![false; objects.len()];
    // Ties between equally constrained objects, broken differently per attempt.
    let tie: Vec<u64> = (0..objects.len() as u64)
        .map(|k| k.wrapping_mul(attempt + 1) % (objects.len() as u64 + 1))
        .collect();
    for _ in 0..objects.len() {
        // Most constrained object first; later attempts break ties differently.
        let constraints = |o: &Object, line: &Vec<Option<Line<S>>>| -> usize {
            match *o {
                Object::Line(l) => inc.placed_touching(l, |m| line[m].is_some()),
                Object::Group(g) => grouping.groups[g]
                    .iter()
                    .map(|&l| inc.touching(l).filter(|&m| line[m].is_some()).count())
                    .sum(),
            }
        };
        let next = (0..objects.len())
            .filter(|&k| !placed[k])
            .max_by_key(|&k| {
                let c = constraints(&objects[k], &line);
                let simple = match objects[k] {
                    Object::Line(_) => c <= 3,
                    Object::Group(_) => true,
                };
                (simple, c, tie[k])
            })
            .ok_or(Infeasible::NoOrder)?;
        placed[next] = true;
        match objects[next] {
            Object::Line(l) => {
                let mut meets: Vec<Line<S>> = Vec::new();
                let mut seen: Vec<usize> = Vec::new();
                for m in inc.touching(l) {
                    if let Some(lm) = line[m]
                        && !seen.contains(&m)
                    {
                        seen.push(m);
                        meets.push(lm);
                    }
                }
                let new = line_meeting(&meets, draw).ok_or(Infeasible::NoOrder)?;
                line[l] = Some(new);
            }
            Object::Group(g) => {
                let members = &grouping.groups[g];
                let shared: Vec<Line<S>> = members.iter().filter_map(|&l| line[l]).collect();
                let pl = plane_through(&shared, draw).ok_or(Infeasible::NoOrder)?;
                if shared.iter().any(|l| !line_in_plane(l, &pl)) {
                    return Err(Infeasible::NoOrder);
                }
                group_planes[g] = Some(pl);
                for &l in members {
                    if line[l].is_some() {
                        continue;
                    }
                    let mut required: Vec<V3<S>> = Vec::new();
                    for m in inc.touching(l) {
                        if members.contains(&m) {
                            continue;
                        }
                        if let Some(lm) = line[m] {
                            let x = pierce(&lm, &pl).ok_or(Infeasible::NoOrder)?;
                            if !required.iter().any(|&y| same_point(x, y)) {
                                required.push(x);
                            }
                        }
                    }
                    let new = match required.as_slice() {
                        [] => Line {
                            p: draw.in_plane(&pl),
                            d: draw.plane_direction(&pl),
                        },
                        [x] => Line {
                            p: *x,
                            d: draw.plane_direction(&pl),
                        },
                        [x, y, rest @ ..] => {
                            let l2 = through(*x, *y).ok_or(Infeasible::Degenerate)?;
                            if rest.iter().any(|&z| !on_line(z, &l2)) {
                                return Err(Infeasible::NoOrder);
                            }
                            l2
                        }
                    };
                    if null_rel(new.d, size(pl.u) + size(pl.v), DISTINCT_TOL) {
                        return Err(Infeasible::Degenerate);
                    }
                    line[l] = Some(new);
                }
            }
        }
    }
    // Contact points: where two placed lines meet, else a random point on the placed one.
    let mut points = Vec::with_capacity(inc.n_contacts());
    // In exact arithmetic the meeting points come after the draws (which
    // they do not use), their inverses in one batch: an inverse costs
    // dozens of products, and a realization has a meeting point per contact.
    let exact = exact::<S>();
    let mut meets: Vec<usize> = Vec::new();
    for (k, &[a, b]) in inc.contact_lines.iter().enumerate() {
        let x = match (line[a], line[b]) {
            (Some(_), Some(_)) if exact => {
                meets.push(k);
                [S::zero(); 3]
            }
            (Some(la), Some(lb)) => meet(&la, &lb).ok_or(Infeasible::NoOrder)?,
            (Some(l), None) | (None, Some(l)) => draw.on_line(&l),
            (None, None) => draw.point(),
        };
        points.push(x);
    }
    if !meets.is_empty() {
        let placed = |k: usize| {
            let [a, b] = inc.contact_lines[k];
            (line[a].expect("placed"), line[b].expect("placed"))
        };
        let mut dets = Vec::with_capacity(meets.len());
        let mut nums = Vec::with_capacity(meets.len());
        for &k in &meets {
            let (la, lb) = placed(k);
            let (det, num) = meet_fraction(&la, &lb).ok_or(Infeasible::NoOrder)?;
            dets.push(det);
            nums.push(num);
        }
        let mut prefix = Vec::with_capacity(meets.len());
        if !invert_all(&mut dets, &mut prefix) {
            return Err(Infeasible::NoOrder);
        }
        for ((&k, &inv), &num) in meets.iter().zip(&dets).zip(&nums) {
            let (la, lb) = placed(k);
            points[k] = meet_at(&la, &lb, num * inv).ok_or(Infeasible::NoOrder)?;
        }
    }
    for i in 0..points.len() {
        if points[..i].iter().any(|&y| same_point(points[i], y)) {
            return Err(Infeasible::Degenerate);
        }
    }
    // Light lines: through their contact points (or one point and a random direction).
    let lines: Vec<Line<S>> = (0..n_lines)
        .map(|l| {
            line[l].unwrap_or_else(|| {
                let cs = &inc.line_contacts[l];
                let p = cs.first().map_or_else(|| draw.point(), |&c| points[c]);
                let d = match cs.get(1) {
                    Some(&c) => sub(points[c], p),
                    None => draw.direction(),
                };
                Line { p, d }
            })
        })
        .collect();
    let node_planes = node_planes(inc, grouping, &group_planes);
    let sample = Realization {
        points,
        lines,
        group_planes,
        node_planes,
    };
    check(inc, grouping, &sample).map_err(|_| Infeasible::Degenerate)?;
    Ok(sample)
}

/// A line meeting each of `lines` (at most three generic ones; more only when
/// the line through the first three happens to meet them all).
fn line_meeting<S: Scalar, R: Rng>(
    lines: &[Line<S>],
    draw: &mut Draw<'_, S, R>,
) -> Option<Line<S>> {
    let new = match lines {
        [] => Line {
            p: draw.point(),
            d: draw.direction(),
        },
        [a] => Line {
            p: draw.on_line(a),
            d: draw.direction(),
        },
        [a, b] => through(draw.on_line(a), draw.on_line(b))?,
        [a, b, c, ..] => {
            // Through a random point x of a: the planes (x, b) and (x, c) meet in it.
            let x = draw.on_line(a);
            let n1 = cross(b.d, sub(b.p, x));
            let n2 = cross(c.d, sub(c.p, x));
            if parallel(n1, n2) {
                return None;
            }
            Line {
                p: x,
                d: cross(n1, n2),
            }
        }
    };
    let null = !finite(new.d) || new.d.iter().all(|x| x.vanishes(0.0, 0.0));
    (!null && lines.iter().all(|l| lines_meet(&new, l))).then_some(new)
}

/// A plane containing `lines` (random when there are none).
fn plane_through<S: Scalar, R: Rng>(
    lines: &[Line<S>],
    draw: &mut Draw<'_, S, R>,
) -> Option<Plane<S>> {
    let pl = match lines {
        [] => Plane {
            q: draw.point(),
            u: draw.direction(),
            v: draw.free(),
        },
        [a] => Plane {
            q: a.p,
            u: a.d,
            v: draw.free(),
        },
        [a, b, ..] => {
            let v = if parallel(a.d, b.d) {
                sub(b.p, a.p)
            } else {
                b.d
            };
            Plane { q: a.p, u: a.d, v }
        }
    };
    (!parallel(pl.u, pl.v)).then_some(pl)
}

/// Verifies a sample: finite, contact points on both their lines, group
/// points in their planes.
pub(crate) fn check<S: Scalar>(
    inc: &Incidence,
    grouping: &Grouping,
    s: &Realization<S>,
) -> Result<(), String> {
    if !s.points.iter().all(|&p| finite(p)) || !s.lines.iter().all(|l| finite(l.p) && finite(l.d)) {
        return Err("a coordinate is not finite".into());
    }
    for (c, &[a, b]) in inc.contact_lines.iter().enumerate() {
        for l in [a, b] {
            if !on_line(s.points[c], &s.lines[l]) {
                return Err(format!("contact {c} is off line {l}"));
            }
        }
    }
    for (g, plane) in grouping.groups.iter().zip(&s.group_planes) {
        let Some(pl) = plane else {
            continue;
        };
        // The contacts of the group's lines (a contact between two of them
        // is tested twice, to the same effect), with the normal computed once.
        let normal = pl.normal();
        let mut contacts = g.iter().flat_map(|&l| inc.line_contacts[l].iter());
        if contacts.any(|&c| !on_plane_with(s.points[c], pl, normal)) {
            return Err("a group point is off its plane".into());
        }
    }
    Ok(())
}

/// A float sample moved and scaled so that its contact points are centred
/// on the origin within the unit cube, with unit line and plane directions:
/// a similarity, so no rank changes, and random auxiliary points in
/// `[-1, 1]^3` come out at the scale of the contacts.
pub fn normalized(mut s: Realization<f64>) -> Realization<f64> {
    let n = s.points.len().max(1) as f64;
    let c = s
        .points
        .iter()
        .fold([0.0; 3], |acc, &p| add(acc, scale(p, 1.0 / n)));
    let extent = s
        .points
        .iter()
        .map(|&p| size(sub(p, c)))
        .fold(0.0, f64::max);
    let k = if extent > 0.0 { 1.0 / extent } else { 1.0 };
    let unit = |v: V3<f64>| {
        let m = size(v);
        if m > 0.0 { scale(v, 1.0 / m) } else { v }
    };
    let place = |p: V3<f64>| scale(sub(p, c), k);
    for p in &mut s.points {
        *p = place(*p);
    }
    for l in &mut s.lines {
        *l = Line {
            p: place(l.p),
            d: unit(l.d),
        };
    }
    for pl in s
        .group_planes
        .iter_mut()
        .chain(s.node_planes.iter_mut())
        .flatten()
    {
        *pl = Plane {
            q: place(pl.q),
            u: unit(pl.u),
            v: unit(pl.v),
        };
    }
    s
}
