//! A float realization of a whole system where no construction order
//! exists (MODEL §10): the incidences solved by Levenberg–Marquardt from a
//! random start, then every solution that is degenerate, or more special
//! than the stated family, refused ([`degenerate`]): repaired where it
//! shows, a few times, and else given up.
//!
//! The forced planes come first: each class has a plane of its own among
//! the unknowns and its member lines are held in it by equations, so every
//! solution has them; nothing else is asked to be coplanar. Unknowns: per
//! active rod its line `p + s d`, per contact between active rods where it
//! sits on each line (`s_a`, `s_b`), per class its plane `n . x = h`.
//! Equations:
//! * a contact: `p_a + s_a d_a = p_b + side * o + s_b d_b`, where `a` sees
//!   `b` at image offset `o` (3 each; parallel lines cannot satisfy them
//!   without coinciding, unlike the bare condition that two lines meet);
//! * a line: `d . d = 1` and `p . d = 0` (a unit direction, and `p` the
//!   point nearest the origin, so nothing slides along the line);
//! * a member `r` of a class at offset `o`: `n . d_r = 0` and
//!   `n . (p_r + side * o) = h`;
//! * a class: `n . n = 1`, and `n . w = 0` for each box direction `w` it wraps.
//!
//! In a periodic box the side is fixed at a random value: the images of a
//! line are where the box puts them. The steps are
//! [`crate::math::marquardt`]'s.

use rand::{Rng, RngExt};

use super::planes::Planes;
use super::realize::{Realization, lattice};
use super::special::{Special, degenerate, spread};
use crate::graph::Topology;
use crate::math::marquardt::{self, Residual, Residuals};
use crate::math::vec3::{Line, V3, add, cross, dot, norm, scale, sub};

/// Largest residual, relative to the size of the realization, accepted as
/// a solution of the incidences.
pub const RESIDUAL_TOL: f64 = 1e-12;

/// The length of a direction, against its unit one, below which a start
/// on the sphere is in its trap at `n = 0`. The stall rule caught such
/// starts from the rods only after about 30 factorizations (gamma 23,
/// L = 5), by when their cost sat at an integer, a collapsed direction
/// each; given up here, the same starts fail sooner and every realization
/// reached is the same. At half its length a direction can still recover:
/// giving up there changed the member reached at gamma 23, L = 3, rho 38.
const COLLAPSED: f64 = 0.01;

/// The stall rule of the linear gauge: the cost must fall by 0.1% over
/// 40 steps, not 1% over 10. The linear gauge has no trap, and the
/// common rule gave up starts that were still converging: at gamma 23,
/// L = 3, 1,215 rods of the sequences of seeds 1 to 39, 7 projections from
/// the rods did not converge; with this patience 4 of them did, and 2 more
/// reached a special position. A start that converged under the common
/// rule never met it, so it converges here the same. (Measured from the
/// rods; from their planes, with the rounds of kicks, those 78 sides come
/// out the same under either rule.)
const PATIENCE: (f64, usize) = (0.001, 40);

/// Times a degenerate solution is repaired (the rods that show it, their
/// neighbours and their classes' planes drawn anew, the rest kept) before
/// the draw is given up: in a large system some local structure or other
/// often collapses, and a whole new start would likely collapse another.
/// On a periodic system of 241 core rods and 33 classes, 4 of 20 starts
/// gave a realization without repairs, 17 of 20 with up to 8.
const REPAIRS: usize = 8;

/// How far [`nearest`] first kicks the rods of a special position, in
/// mean rod lengths: far below the rods' own gaps (their diameter), far
/// above the separations that make a position special. Each further repair
/// kicks twice as far: a position one kick of this size did not cure, more
/// of the same never cured (gamma 23, L = 3, densities 41 and 45, seeds 1
/// to 39: 6 of 78 sides cured by the first kick, none by a later one), as
/// the projection fell back to the same special member; doubling cured 7
/// of the 10 left special, after 4 to 8 kicks, and changed no other side.
/// From the members' planes, kicks of 0.01 alone leave 10 of those 78
/// sides special in one round and 11 in three ([`ROUNDS`]), doubling 4
/// and 2.
const NUDGE: f64 = 0.01;

/// Rounds of growing kicks, each from the first solution again with kicks
/// drawn anew: the draws decide whether a special position is left (a
/// random start found a member without one on each of the 4 sides of
/// gamma 23, L = 3, 1,100 and 1,215 rods of seeds 1 to 39 left special
/// after one round). Two rounds left 3 of them special, three 2; a side
/// cured in the first round comes out as before.
const ROUNDS: usize = 3;

/// The unknowns of a system: where each object's start.
struct System<'a> {
    topo: &'a Topology<'a>,
    planes: &'a Planes,
    side: f64,
    /// Per rod: its `p` (then `d`), active rods only.
    line: Vec<Option<usize>>,
    /// Per edge between active rods: its `s_a` (then `s_b`).
    contact: Vec<Option<usize>>,
    /// Class `c` has `n` at `plane + 4 c`, then `h`.
    plane: usize,
    unknowns: usize,
    /// How the scale of each direction (a line's `d`, a plane's `n`) is
    /// fixed: `|d|² = 1`, or, with a reference direction `d0` from the
    /// start, `d · d0 = 1` ([`nearest`]; per direction in the order of
    /// [`System::directions`]). The sphere has a trap at `n = 0`, where a
    /// plane's every membership holds and no step can leave: a start whose
    /// rods lie far from their forced planes (the actual rods) falls into
    /// it; the linear gauge has none.
    anchors: Option<Vec<V3<f64>>>,
}

impl Residual for System<'_> {
    fn unknowns(&self) -> usize {
        self.unknowns
    }
    fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
        self.residuals(u, jacobian)
    }
    fn tolerance(&self, u: &[f64]) -> f64 {
        RESIDUAL_TOL * self.size(u)
    }
    /// The linear gauge has no trap, so a slow start there is given more
    /// patience ([`PATIENCE`]).
    fn stall(&self) -> (f64, usize) {
        match self.anchors {
            None => marquardt::STALL,
            Some(_) => PATIENCE,
        }
    }
    /// On the sphere, a direction shrunk below [`COLLAPSED`] of its unit
    /// length: the trap at `n = 0`.
    fn trapped(&self, u: &[f64]) -> bool {
        self.anchors.is_none()
            && self.directions().any(|at| {
                let d = v3(u, at);
                dot(d, d) < COLLAPSED * COLLAPSED
            })
    }
}

/// A contact's unknowns: `s_a` at `at` (then `s_b`), the lines' `p` at
/// `la` and `lb` (then `d`), and where the box puts `b`'s image from `a`.
struct Unknowns {
    at: usize,
    la: usize,
    lb: usize,
    shift: V3<f64>,
}

/// A random unit vector (uniform in a ball, then scaled).
fn unit(rng: &mut impl Rng) -> V3<f64> {
    loop {
        let v: V3<f64> = [0; 3].map(|_| rng.random_range(-1.0..=1.0));
        let len = norm(v);
        if len > 0.1 && len <= 1.0 {
            return scale(v, 1.0 / len);
        }
    }
}

fn v3(u: &[f64], at: usize) -> V3<f64> {
    [u[at], u[at + 1], u[at + 2]]
}

/// Writes the line through `p` along `d` at `at`: its point nearest the
/// origin, then `d`.
fn put_line(u: &mut [f64], at: usize, p: V3<f64>, d: V3<f64>) {
    u[at..at + 3].copy_from_slice(&sub(p, scale(d, dot(p, d))));
    u[at + 3..at + 6].copy_from_slice(&d);
}

impl<'a> System<'a> {
    fn new(topo: &'a Topology<'a>, planes: &'a Planes, active: &[bool], side: f64) -> Self {
        let mut next = 0;
        let mut take = |k: usize| {
            next += k;
            next - k
        };
        let line: Vec<Option<usize>> = active.iter().map(|&on| on.then(|| take(6))).collect();
        let contact = topo
            .graph
            .edges()
            .iter()
            .map(|&[a, b]| (active[a as usize] && active[b as usize]).then(|| take(2)))
            .collect();
        let plane = take(4 * planes.classes.len());
        System {
            topo,
            planes,
            side,
            line,
            contact,
            plane,
            unknowns: next,
            anchors: None,
        }
    }

    /// Where each direction starts: every active rod's line's `d`, then
    /// every class's plane's `n`.
    fn directions(&self) -> impl Iterator<Item = usize> + '_ {
        let lines = self.line.iter().flatten().map(|&at| at + 3);
        lines.chain((0..self.planes.classes.len()).map(|c| self.plane + 4 * c))
    }

    /// The linear gauge, each direction against its value in `u`.
    fn anchored(mut self, u: &[f64]) -> Self {
        let anchors = self
            .directions()
            .map(|at| {
                let d = v3(u, at);
                scale(d, 1.0 / dot(d, d))
            })
            .collect();
        self.anchors = Some(anchors);
        self
    }

    /// The row fixing the scale of the `k`-th direction, at `at`.
    fn gauge(&self, ev: &mut Residuals, u: &[f64], k: usize, at: usize) {
        let d = v3(u, at);
        match &self.anchors {
            None => ev.row(dot(d, d) - 1.0, (0..3).map(|i| (at + i, 2.0 * d[i]))),
            Some(a) => ev.row(dot(d, a[k]) - 1.0, (0..3).map(|i| (at + i, a[k][i]))),
        }
    }

    /// Per edge, its unknowns when it is a contact between active rods.
    fn contacts_of_edges(&self) -> impl Iterator<Item = Option<Unknowns>> + '_ {
        let edges = self.topo.graph.edges().iter().enumerate();
        edges.map(|(e, &[a, b])| {
            Some(Unknowns {
                at: self.contact[e]?,
                la: self.line[a as usize]?,
                lb: self.line[b as usize]?,
                shift: lattice(self.side, self.topo.seen(e as u32, a)),
            })
        })
    }

    /// Every contact between active rods with its unknowns.
    fn contacts(&self) -> impl Iterator<Item = Unknowns> + '_ {
        self.contacts_of_edges().flatten()
    }

    fn residuals(&self, u: &[f64], jacobian: bool) -> Residuals {
        let mut ev = Residuals::new(jacobian);
        let lines = self.line.iter().flatten().count();
        for (j, at) in self.line.iter().flatten().copied().enumerate() {
            let (p, d) = (v3(u, at), v3(u, at + 3));
            self.gauge(&mut ev, u, j, at + 3);
            ev.row(
                dot(p, d),
                (0..3).flat_map(|k| [(at + k, d[k]), (at + 3 + k, p[k])]),
            );
        }
        for Unknowns {
            at,
            la,
            lb,
            shift: t,
        } in self.contacts()
        {
            let (sa, sb) = (u[at], u[at + 1]);
            for k in 0..3 {
                let (da, db) = (u[la + 3 + k], u[lb + 3 + k]);
                ev.row(
                    u[la + k] + sa * da - u[lb + k] - t[k] - sb * db,
                    [
                        (la + k, 1.0),
                        (la + 3 + k, sa),
                        (at, da),
                        (lb + k, -1.0),
                        (lb + 3 + k, -sb),
                        (at + 1, -db),
                    ],
                );
            }
        }
        for (c, class) in self.planes.classes.iter().enumerate() {
            let at = self.plane + 4 * c;
            let (n, h) = (v3(u, at), u[at + 3]);
            self.gauge(&mut ev, u, lines + c, at);
            for w in &class.wraps {
                let w = w.map(f64::from);
                ev.row(dot(n, w), (0..3).map(|k| (at + k, w[k])));
            }
            for &(r, o) in &class.rods {
                let Some(l) = self.line[r as usize] else {
                    continue;
                };
                let (p, d) = (add(v3(u, l), lattice(self.side, o)), v3(u, l + 3));
                ev.row(
                    dot(n, d),
                    (0..3).flat_map(|k| [(at + k, d[k]), (l + 3 + k, n[k])]),
                );
                ev.row(
                    dot(n, p) - h,
                    (0..3)
                        .flat_map(|k| [(at + k, p[k]), (l + k, n[k])])
                        .chain([(at + 3, -1.0)]),
                );
            }
        }
        ev
    }

    /// The size residuals are measured against: the largest coordinate of
    /// a line's point, a contact's position on it, or the box side.
    fn size(&self, u: &[f64]) -> f64 {
        let lines = self.line.iter().flatten().map(|&at| {
            v3(u, at)
                .iter()
                .fold(0.0_f64, |m: f64, x: &f64| m.max(x.abs()))
        });
        let contacts = self
            .contact
            .iter()
            .flatten()
            .map(|&at| u[at].abs().max(u[at + 1].abs()));
        lines.chain(contacts).fold(self.side.max(1.0), f64::max)
    }

    /// A random start: a random plane per class, then every line drawn anew
    /// ([`System::redraw`]).
    fn start(&self, rng: &mut impl Rng) -> Vec<f64> {
        let mut u = vec![0.0; self.unknowns];
        let rods: Vec<u32> = (0..self.line.len() as u32).collect();
        let classes: Vec<u32> = (0..self.planes.classes.len() as u32).collect();
        self.redraw(&mut u, &rods, &classes, rng);
        u
    }

    /// Draws the planes of `classes` anew, then the lines of `rods` and of
    /// those classes' members, each moved into the plane its first class has
    /// in `u`, and puts every contact of theirs where its two lines come
    /// closest.
    fn redraw(&self, u: &mut [f64], rods: &[u32], classes: &[u32], rng: &mut impl Rng) {
        let mut rods = rods.to_vec();
        for &c in classes {
            let n = unit(rng);
            let at = self.plane + 4 * c as usize;
            u[at..at + 3].copy_from_slice(&n);
            u[at + 3] = 0.5 * dot(n, unit(rng));
            rods.extend(self.planes.classes[c as usize].rods.iter().map(|&(r, _)| r));
        }
        let mut moved = vec![false; self.line.len()];
        for &r in &rods {
            let Some(at) = self.line[r as usize] else {
                continue;
            };
            moved[r as usize] = true;
            let (mut p, mut d) = (scale(unit(rng), 0.5), unit(rng));
            if let Some((q, e, len)) = self.in_plane(u, r as usize, p, d) {
                p = q;
                d = if len > 1e-3 { scale(e, 1.0 / len) } else { e };
            }
            put_line(u, at, p, d);
        }
        self.closest_contacts(u, &moved);
    }

    /// The line `p + s d` of rod `r` moved into the plane `n . (x + side o)
    /// = h` of its first class in `u` by the least move, with the length of
    /// its direction, left unscaled (short where the line stood normal to
    /// the plane); `None` for a rod in no class.
    fn in_plane(
        &self,
        u: &[f64],
        r: usize,
        p: V3<f64>,
        d: V3<f64>,
    ) -> Option<(V3<f64>, V3<f64>, f64)> {
        let &(c, o) = self.planes.of_rod[r].first()?;
        let at = self.plane + 4 * c as usize;
        let (n, h) = (v3(u, at), u[at + 3]);
        let p = sub(p, scale(n, dot(n, add(p, lattice(self.side, o))) - h));
        let d = sub(d, scale(n, dot(n, d)));
        Some((p, d, norm(d)))
    }

    /// Moves each member of a class into its plane in `u` (the first
    /// class's, for a rod in two), by the least move of its line, and keeps
    /// every contact of a moved rod near where it was
    /// ([`System::kept_contacts`]). A
    /// class is forced by the line model's incidences, not by the actual
    /// rods, which lie far from any one plane: started from them, the
    /// planes' rows are far from solved and a normal on the sphere falls
    /// into its trap (gamma 23, L = 6, rho 36, seed 1: 216 factorizations,
    /// 54 s; from the planes 9, 4.3 s).
    fn to_planes(&self, u: &mut [f64]) {
        let before = self.points(u);
        let mut moved = vec![false; self.line.len()];
        for (r, at) in self.line.iter().enumerate() {
            let Some(at) = *at else { continue };
            // A rod normal to its plane has no nearest direction in it.
            let Some((p, d, len)) = self
                .in_plane(u, r, v3(u, at), v3(u, at + 3))
                .filter(|&(_, _, len)| len > 1e-3)
            else {
                continue;
            };
            put_line(u, at, p, scale(d, 1.0 / len));
            moved[r] = true;
        }
        self.kept_contacts(u, &before, &moved);
    }

    /// Moves every coordinate of the lines of `rods` by up to `step` at
    /// random: a kick off a special position that stays near the start.
    fn nudge(&self, u: &mut [f64], rods: &[u32], step: f64, rng: &mut impl Rng) {
        let before = self.points(u);
        let mut moved = vec![false; self.line.len()];
        for &r in rods {
            // A rod named twice (a neighbour of two) is kicked once.
            let Some(at) = self.line[r as usize].filter(|_| !moved[r as usize]) else {
                continue;
            };
            moved[r as usize] = true;
            for x in &mut u[at..at + 6] {
                *x += step * rng.random_range(-1.0..=1.0);
            }
        }
        self.kept_contacts(u, &before, &moved);
    }

    /// Per edge, its contact's point `p + s d` on its first rod's line, where
    /// it is a contact between active rods: with `d` as solved, not scaled
    /// to unit length, since the contact's equations hold for that `d` (in
    /// the linear gauge `|d|` strays from 1, and `s` along the unit
    /// direction put the point off the second rod's line).
    fn points(&self, u: &[f64]) -> Vec<Option<V3<f64>>> {
        self.contacts_of_edges()
            .map(|c| c.map(|Unknowns { at, la, .. }| add(v3(u, la), scale(v3(u, la + 3), u[at]))))
            .collect()
    }

    /// Each contact of a `moved` rod at the point of each of its lines
    /// nearest where it was (`before`, [`System::points`]): moved lines
    /// keep their contacts where the rods touched. The points where two
    /// moved lines pass closest can lie far out when they are nearly
    /// parallel, and a line's `s` counts from its point nearest the origin,
    /// so no fixed bound on `s` suits every box: bounded by 4, they sat up
    /// to several rod lengths off the rods of the larger boxes, and the
    /// member reached moved the contacts the more the larger the box.
    fn kept_contacts(&self, u: &mut [f64], before: &[Option<V3<f64>>], moved: &[bool]) {
        let edges = self.topo.graph.edges();
        for ((e, c), x) in edges.iter().zip(self.contacts_of_edges()).zip(before) {
            let (Some(Unknowns { at, la, lb, shift }), Some(x)) = (c, *x) else {
                continue;
            };
            if !moved[e[0] as usize] && !moved[e[1] as usize] {
                continue;
            }
            let along = |u: &[f64], x: V3<f64>, l: usize| {
                let d = v3(u, l + 3);
                dot(sub(x, v3(u, l)), d) / dot(d, d)
            };
            u[at] = along(u, x, la);
            u[at + 1] = along(u, sub(x, shift), lb);
        }
    }

    /// Each contact of a `moved` rod where its two lines pass closest (lines
    /// drawn through points near the origin, so `s` is bounded by 4).
    fn closest_contacts(&self, u: &mut [f64], moved: &[bool]) {
        let edges = self.topo.graph.edges();
        for (e, c) in edges.iter().zip(self.contacts_of_edges()) {
            let Some(Unknowns { at, la, lb, shift }) = c else {
                continue;
            };
            if !moved[e[0] as usize] && !moved[e[1] as usize] {
                continue;
            }
            let (pa, da) = (v3(u, la), v3(u, la + 3));
            let (pb, db) = (add(v3(u, lb), shift), v3(u, lb + 3));
            let n = cross(da, db);
            let nn = dot(n, n);
            let w = sub(pb, pa);
            let (sa, sb) = if nn > 1e-6 {
                (dot(cross(w, db), n) / nn, dot(cross(w, da), n) / nn)
            } else {
                (0.0, 0.0)
            };
            u[at] = sa.clamp(-4.0, 4.0);
            u[at + 1] = sb.clamp(-4.0, 4.0);
        }
    }

    /// The realization a solution stands for.
    fn realization(&self, u: &[f64]) -> Realization<f64> {
        let lines: Vec<Option<Line<f64>>> = self
            .line
            .iter()
            .map(|at| {
                at.map(|at| {
                    let d = v3(u, at + 3);
                    Line {
                        p: v3(u, at),
                        d: scale(d, 1.0 / norm(d)),
                    }
                })
            })
            .collect();
        Realization {
            side: self.side,
            lines,
            points: self.points(u),
        }
    }
}

/// One float realization of the active rods by numerical projection from a
/// random start, checked by [`degenerate`] and scaled so that its contact
/// points lie within distance 1 of the origin, their centroid. `Err` says
/// why this draw was refused.
pub fn project(
    topo: &Topology,
    planes: &Planes,
    active: &[bool],
    rng: &mut impl Rng,
) -> Result<Realization<f64>, String> {
    let side = if topo.shifts.is_some() {
        rng.random_range(1.0..2.0)
    } else {
        1.0
    };
    let system = System::new(topo, planes, active, side);
    let mut u = system.start(rng);
    let mut last: Option<Special> = None;
    for _ in 0..=REPAIRS {
        let Some(solution) = marquardt::solve(&system, u) else {
            return Err(match last {
                Some(s) => format!("the projection did not converge (repairing: {})", s.why),
                None => "the projection did not converge".into(),
            });
        };
        let real = system.realization(&solution);
        let Some(special) = degenerate(topo, planes, &real) else {
            return Ok(normalized(real));
        };
        if special.rods.is_empty() {
            return Err(special.why);
        }
        // Draw the rods that show it, their neighbours and their classes'
        // planes anew (a rod in two classes lies where the planes put it),
        // and keep the rest.
        let mut rods = special.rods.clone();
        for &r in &special.rods {
            rods.extend(topo.graph.neighbors(r).iter().map(|&(m, _)| m));
        }
        u = solution;
        let classes: Vec<u32> = special
            .rods
            .iter()
            .flat_map(|&r| planes.of_rod[r as usize].iter().map(|&(c, _)| c))
            .collect();
        system.redraw(&mut u, &rods, &classes, rng);
        last = Some(special);
    }
    Err(last.map_or_else(String::new, |s| s.why))
}

/// The equations of [`nearest`] and their start: the rods' own lines and
/// contact points, each class's plane fitted to its members.
fn from_rods<'a>(
    topo: &'a Topology<'a>,
    planes: &'a Planes,
    active: &[bool],
    start: &Realization<f64>,
) -> (System<'a>, Vec<f64>) {
    let system = System::new(topo, planes, active, start.side);
    let mut u = vec![0.0; system.unknowns];
    for (r, at) in system.line.iter().enumerate() {
        let (Some(at), Some(l)) = (*at, start.lines[r]) else {
            continue;
        };
        put_line(&mut u, at, l.p, scale(l.d, 1.0 / dot(l.d, l.d).sqrt()));
    }
    for (e, c) in system.contacts_of_edges().enumerate() {
        let (Some(Unknowns { at, la, lb, shift }), Some(x)) = (c, start.points[e]) else {
            continue;
        };
        u[at] = dot(sub(x, v3(&u, la)), v3(&u, la + 3));
        u[at + 1] = dot(sub(sub(x, shift), v3(&u, lb)), v3(&u, lb + 3));
    }
    for (c, class) in planes.classes.iter().enumerate() {
        // The plane nearest the members' points `p ± d / 2` (`p` as the
        // start gives it, the rod's centre): through their centroid,
        // normal to their least spread.
        let points: Vec<V3<f64>> = class
            .rods
            .iter()
            .filter_map(|&(r, o)| start.lines[r as usize].map(|l| (l, o)))
            .flat_map(|(l, o)| {
                let p = add(l.p, lattice(start.side, o));
                let d = scale(l.d, 0.5 / dot(l.d, l.d).sqrt());
                [add(p, d), sub(p, d)]
            })
            .collect();
        let k = 1.0 / points.len().max(1) as f64;
        let centroid = points.iter().fold([0.0; 3], |m, &p| add(m, scale(p, k)));
        let scatter = faer::Mat::from_fn(3, 3, |i, j| {
            points
                .iter()
                .map(|p| (p[i] - centroid[i]) * (p[j] - centroid[j]))
                .sum::<f64>()
        });
        let n = match scatter.self_adjoint_eigen(faer::Side::Lower) {
            Ok(evd) => {
                let s = evd.S();
                let k = (0..3).min_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap_or(0);
                std::array::from_fn(|i| evd.U()[(i, k)])
            }
            Err(_) => [0.0, 0.0, 1.0],
        };
        let h = dot(n, centroid);
        let at = system.plane + 4 * c;
        u[at..at + 3].copy_from_slice(&n);
        u[at + 3] = h;
    }
    system.to_planes(&mut u);
    (system, u)
}

/// Bytes [`nearest`]'s Levenberg–Marquardt holds at once for these rods
/// ([`marquardt::memory`]), or `None` when faer cannot order its pattern.
pub fn nearest_memory(
    topo: &Topology,
    planes: &Planes,
    active: &[bool],
    start: &Realization<f64>,
) -> Option<u64> {
    let (system, u) = from_rods(topo, planes, active, start);
    marquardt::memory(&system, &u)
}

/// The float realization Levenberg–Marquardt reaches from `start` (the
/// actual rods, for the elastic moduli): its lines, its box side, each
/// contact where it sits on both lines (`start.points`, in the frame of the
/// edge's first rod), each class's plane fitted to its members and the
/// members moved into it (`System::to_planes`). The steps
/// are least-norm, so the solution stays near the start; it is not moved or
/// scaled. Where that fails, again with each direction's scale fixed
/// linearly against its start (`d · d0 = 1`) and more patience for a slow
/// start, kicking the rods of a special solution by 0.01 rod lengths and
/// twice as far each further time (drawn from `rng`) and projecting again,
/// up to 8 times, in up to 3 rounds from the first solution. `Err` says
/// why it is refused: no convergence, or a solution that is no generic
/// member of the family ([`degenerate`]).
pub fn nearest(
    topo: &Topology,
    planes: &Planes,
    active: &[bool],
    start: &Realization<f64>,
    rng: &mut impl Rng,
) -> Result<Realization<f64>, String> {
    let (system, u) = from_rods(topo, planes, active, start);
    // First with every direction on the unit sphere; only where that fails,
    // with the linear scale and repairs. Where both converge they can land
    // on different members, and on one small solid the linear scale's was
    // nearly special (a singular value of R at 1e-12 of its largest).
    if let Some(solution) = marquardt::solve(&system, u.clone()) {
        let real = system.realization(&solution);
        if degenerate(topo, planes, &real).is_none() {
            return Ok(real);
        }
    }
    let system = system.anchored(&u);
    let solve =
        |u| marquardt::solve(&system, u).ok_or("the projection from the rods did not converge");
    let unkicked = solve(u)?;
    let mut special = String::new();
    for _ in 0..ROUNDS {
        let mut solution = unkicked.clone();
        for repair in 0..=REPAIRS {
            let real = system.realization(&solution);
            let Some(s) = degenerate(topo, planes, &real) else {
                return Ok(real);
            };
            if s.rods.is_empty() {
                return Err(format!(
                    "the realization nearest the rods is special: {}",
                    s.why
                ));
            }
            special = s.why;
            if repair == REPAIRS {
                break;
            }
            // Kick the rods that show it and their neighbours, further each
            // time, and project again.
            let mut rods = s.rods.clone();
            for &r in &s.rods {
                rods.extend(topo.graph.neighbors(r).iter().map(|&(m, _)| m));
            }
            system.nudge(&mut solution, &rods, NUDGE * 2f64.powi(repair as i32), rng);
            solution = solve(solution)?;
        }
    }
    Err(format!(
        "the realization nearest the rods is special after {ROUNDS} rounds of {REPAIRS} repairs: {special}"
    ))
}

/// Moved and scaled: a similarity (the box side scales too), so no rank changes.
fn normalized(mut real: Realization<f64>) -> Realization<f64> {
    let (c, r) = spread(&real);
    if r <= 0.0 {
        return real;
    }
    let k = 1.0 / r;
    let map = |x: V3<f64>| scale(sub(x, c), k);
    for l in real.lines.iter_mut().flatten() {
        l.p = map(l.p);
    }
    for x in real.points.iter_mut().flatten() {
        *x = map(*x);
    }
    real.side *= k;
    real
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::ContactGraph;
    use crate::math::vec3::distance;
    use crate::truth::{planes, prune};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// K_{4,4}: rods 0..4 each touch rods 4..8.
    fn k44() -> ContactGraph {
        let edges = (0..4).flat_map(|a| (4..8).map(move |b| [a, b])).collect();
        ContactGraph::new(8, edges).unwrap()
    }

    /// K4: the four rods touch pairwise, so one class holds them all.
    fn k4() -> ContactGraph {
        let edges = (0..4)
            .flat_map(|a| (a + 1..4).map(move |b| [a, b]))
            .collect();
        ContactGraph::new(4, edges).unwrap()
    }

    /// A projection of a small graph: one of 8 random starts reaches it.
    fn projected(
        topo: &Topology,
        planes: &Planes,
        active: &[bool],
        rng: &mut ChaCha8Rng,
    ) -> Realization<f64> {
        (0..8)
            .find_map(|_| project(topo, planes, active, rng).ok())
            .expect("a projection")
    }

    /// Runs `check` on a projection of `g` from the draws of `seed`.
    fn on_a_projection(
        g: &ContactGraph,
        seed: u64,
        check: impl FnOnce(&Topology, &Planes, &[bool], Realization<f64>, &mut ChaCha8Rng),
    ) {
        let topo = Topology::finite(g);
        let core = prune::two_core(g);
        let planes = planes::forced(&topo, &core.active).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let real = projected(&topo, &planes, &core.active, &mut rng);
        check(&topo, &planes, &core.active, real, &mut rng);
    }

    /// Each contact's point lies on both its rods' lines, to `tol`.
    fn assert_on_both_lines(g: &ContactGraph, real: &Realization<f64>, tol: f64) {
        for (e, &[a, b]) in g.edges().iter().enumerate() {
            let x = real.points[e].unwrap();
            for r in [a, b] {
                let off = distance(&real.lines[r as usize].unwrap(), x);
                assert!(off < tol, "contact {e} off rod {r}");
            }
        }
    }

    #[test]
    fn a_projection_meets_every_contact_and_is_refused_when_made_special() {
        let g = k44();
        on_a_projection(&g, 5, |topo, planes, _, real, _| {
            assert_on_both_lines(&g, &real, 1e-10);
            assert_eq!(degenerate(topo, planes, &real), None);

            // Rod 1 moved onto rod 0's line: both meet every rod 4..8 where rod
            // 0 does, and rods 0 and 1 coincide.
            let mut same = real.clone();
            same.lines[1] = same.lines[0];
            for (e, &[a, b]) in g.edges().iter().enumerate() {
                if a == 1 {
                    let twin = g.edge_between(0, b).unwrap();
                    same.points[e] = same.points[twin as usize];
                }
            }
            let s = degenerate(topo, planes, &same).unwrap();
            assert!(s.why.contains("at one point"), "{}", s.why);
            assert!(s.rods.contains(&0) && s.rods.contains(&1), "{s:?}");

            // Rods 2 and 3 (which do not touch) made to meet: rod 2 through a
            // point of rod 3.
            let mut meet = real.clone();
            let (l2, l3) = (meet.lines[2].unwrap(), meet.lines[3].unwrap());
            meet.lines[2] = Some(Line { p: l3.p, d: l2.d });
            let s = degenerate(topo, planes, &meet).unwrap();
            assert!(s.why.contains("without touching"), "{}", s.why);
            assert_eq!(s.rods, vec![2, 3]);

            // Two touching lines made parallel.
            let mut parallel = real.clone();
            let l4 = parallel.lines[4].unwrap();
            parallel.lines[0] = Some(Line {
                p: parallel.lines[0].unwrap().p,
                d: l4.d,
            });
            let s = degenerate(topo, planes, &parallel).unwrap();
            assert!(s.why.contains("parallel"), "{}", s.why);
            assert_eq!(s.rods, vec![0, 4]);
        });
    }

    #[test]
    fn members_moved_into_their_plane_lie_in_it() {
        let g = k4();
        let topo = Topology::finite(&g);
        let core = prune::two_core(&g);
        let planes = planes::forced(&topo, &core.active).unwrap();
        assert_eq!(planes.classes.len(), 1);
        let system = System::new(&topo, &planes, &core.active, 1.0);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut u = system.start(&mut rng);
        let lines: Vec<usize> = system.line.iter().flatten().copied().collect();
        for &at in &lines {
            for x in &mut u[at..at + 6] {
                *x += 0.2 * rng.random_range(-1.0..=1.0);
            }
        }
        let off = |u: &[f64]| {
            let (n, h) = (v3(u, system.plane), u[system.plane + 3]);
            lines
                .iter()
                .map(|&at| {
                    let d = v3(u, at + 3);
                    (dot(n, v3(u, at)) - h).abs() + dot(n, d).abs() / norm(d)
                })
                .fold(0.0, f64::max)
        };
        assert!(off(&u) > 0.01);
        system.to_planes(&mut u);
        assert!(off(&u) < 1e-12, "{}", off(&u));
    }

    #[test]
    fn moved_lines_keep_their_contacts_far_from_the_origin() {
        // K4's four lines meet pairwise in one plane, then moved 30 rod
        // lengths out: each contact's `s` is about 50 there.
        on_a_projection(&k4(), 3, |topo, planes, active, real, rng| {
            let far_out = [30.0, -20.0, 10.0];
            let mut far = real.clone();
            for l in far.lines.iter_mut().flatten() {
                l.p = add(l.p, far_out);
            }
            for x in far.points.iter_mut().flatten() {
                *x = add(*x, far_out);
            }
            let gap = |u: &[f64], system: &System| {
                let now = system.realization(u);
                far.points
                    .iter()
                    .zip(&now.points)
                    .map(|(a, b)| {
                        let d = sub(a.unwrap(), b.unwrap());
                        norm(d)
                    })
                    .fold(0.0, f64::max)
            };
            // Already in their plane: moved into it by nothing, and their
            // contacts stay (with `s` bounded by 4 they were put tens of rod
            // lengths off).
            let (system, mut u) = from_rods(topo, planes, active, &far);
            assert!(u[system.contact[0].unwrap()].abs() > 10.0);
            assert!(gap(&u, &system) < 1e-9, "{}", gap(&u, &system));
            // Kicked by nothing: the same.
            system.nudge(&mut u, &[0, 1, 2, 3], 0.0, rng);
            assert!(gap(&u, &system) < 1e-9, "{}", gap(&u, &system));
        });
    }

    #[test]
    fn a_direction_off_unit_length_leaves_the_contacts_on_both_lines() {
        // The linear gauge solves for `d` of any length: a solution with each
        // `d` 1.7 times longer and each `s` 1.7 times shorter is the same
        // framework, and its realization puts each contact on both lines.
        on_a_projection(&k4(), 3, |topo, planes, active, real, _| {
            let (system, mut u) = from_rods(topo, planes, active, &real);
            for at in system.line.iter().flatten() {
                for x in &mut u[at + 3..at + 6] {
                    *x *= 1.7;
                }
            }
            for at in system.contact.iter().flatten() {
                u[*at] /= 1.7;
                u[at + 1] /= 1.7;
            }
            let long = system.realization(&u);
            assert_on_both_lines(topo.graph, &long, 1e-12);
            for (x, y) in long.points.iter().zip(&real.points) {
                let d = sub(x.unwrap(), y.unwrap());
                assert!(norm(d) < 1e-12, "{x:?} moved from {y:?}");
            }
        });
    }

    #[test]
    fn a_start_is_trapped_on_the_sphere_only_where_a_direction_collapsed() {
        let g = k44();
        let topo = Topology::finite(&g);
        let core = prune::two_core(&g);
        let planes = planes::forced(&topo, &core.active).unwrap();
        let system = System::new(&topo, &planes, &core.active, 1.0);
        let mut u = system.start(&mut ChaCha8Rng::seed_from_u64(5));
        assert!(!system.trapped(&u));
        let at = system.directions().next().unwrap();
        for (shrink, trapped) in [(0.5, false), (0.02, false), (0.005, true)] {
            let mut v = u.clone();
            let d = scale(v3(&v, at), shrink / dot(v3(&v, at), v3(&v, at)).sqrt());
            v[at..at + 3].copy_from_slice(&d);
            assert_eq!(system.trapped(&v), trapped, "direction shrunk to {shrink}");
        }
        u[at..at + 3].fill(0.0);
        assert!(system.trapped(&u));
        // The linear gauge has no trap.
        let anchored = System::new(&topo, &planes, &core.active, 1.0)
            .anchored(&system.start(&mut ChaCha8Rng::seed_from_u64(5)));
        assert!(!anchored.trapped(&u));
        // Only the linear gauge is given patience.
        assert_eq!(system.stall(), marquardt::STALL);
        assert_eq!(anchored.stall(), PATIENCE);
    }
}
