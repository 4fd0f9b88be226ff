//! An exact realization of a whole system over F_p (MODEL §10): one line
//! per rod and one point per contact, placed in a construction order
//! ([`super::order`]) with every free choice random, so that it is a
//! generic member of the family where planes are only the forced ones.
//!
//! Each incidence is checked exactly once the lines are placed, and every
//! rod's contacts must be distinct points; a draw that lands on a
//! degenerate position (probability about `1/p` per step) is redrawn.

use rand::Rng;

use super::order::preplaced;
use super::planes::Planes;
use crate::contacts::Offset;
use crate::graph::Topology;
use crate::math::vec3::{Line, Plane, V3, add, cross, dot, is_null, scale, sub};
use crate::math::{Field, Fp, Scalar};

/// One realization of the active rods: exact over F_p, or in floats where
/// no construction order exists ([`super::projection`]). A whole system's,
/// so unlike a motif's ([`crate::rigidity::construction::Realization`]) it
/// has a box side for the periodic images, and lines and points only where
/// the rods are active.
#[derive(Clone, Debug)]
pub struct Realization<S = Fp> {
    /// The box side: the image at offset `o` is shifted by `side * o`.
    pub side: S,
    /// Per rod, its line (active rods only).
    pub lines: Vec<Option<Line<S>>>,
    /// Per edge, the contact point in the frame of the edge's first rod
    /// (edges between active rods only).
    pub points: Vec<Option<V3<S>>>,
}

impl<S: Scalar> Realization<S> {
    /// The lattice translation of an image offset.
    pub fn lattice(&self, o: Offset) -> V3<S> {
        lattice(self.side, o)
    }
}

/// The translation by `side` times the image offset `o`.
pub fn lattice<S: Scalar>(side: S, o: Offset) -> V3<S> {
    o.map(|k| side * S::from_i64(k as i64))
}

fn random_v3<F: Field>(rng: &mut impl Rng) -> V3<F> {
    [F::random(rng), F::random(rng), F::random(rng)]
}

fn random_nonzero<F: Field>(rng: &mut impl Rng) -> F {
    loop {
        let v = F::random(rng);
        if v != F::zero() {
            return v;
        }
    }
}

/// Why a draw failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Failure {
    /// A random choice hit a special position: draw again. Says which.
    Degenerate(String),
    /// A constructed incidence does not hold: a bug, never a special draw.
    Broken(String),
}

fn point_on<F: Field>(l: &Line<F>, rng: &mut impl Rng) -> V3<F> {
    add(l.p, scale(l.d, F::random(rng)))
}

/// Where line `l` crosses plane `pl`.
fn crossing<F: Field>(l: &Line<F>, pl: &Plane<F>) -> Result<V3<F>, Failure> {
    let n = pl.normal();
    let den = dot(n, l.d);
    let inv = den
        .inverse()
        .ok_or_else(|| Failure::Degenerate("a line parallel to a plane it must cross".into()))?;
    Ok(add(l.p, scale(l.d, dot(n, sub(pl.q, l.p)) * inv)))
}

fn through<F: Field>(a: V3<F>, b: V3<F>) -> Line<F> {
    Line { p: a, d: sub(b, a) }
}

/// Builds one realization of the rods of `order` (a construction order of
/// the active rods).
pub fn build<F: Field>(
    topo: &Topology,
    planes: &Planes,
    active: &[bool],
    order: &[u32],
    rng: &mut impl Rng,
) -> Result<Realization<F>, Failure> {
    let graph = topo.graph;
    let side: F = random_nonzero(rng);
    let mut lines: Vec<Option<Line<F>>> = vec![None; graph.n_nodes()];
    let mut plane: Vec<Option<Plane<F>>> = vec![None; planes.classes.len()];
    for (c, class) in planes.classes.iter().enumerate() {
        if preplaced(planes, c as u32) {
            let [w1, w2] = [class.wraps[0], class.wraps[1]].map(|w| lattice(F::one(), w));
            plane[c] = Some(Plane {
                q: random_v3(rng),
                u: w1,
                v: w2,
            });
        }
    }
    for &x in order {
        let xi = x as usize;
        let held: Vec<Plane<F>> = planes.of_rod[xi]
            .iter()
            .filter_map(|&(c, o)| {
                plane[c as usize].map(|pl| Plane {
                    q: sub(pl.q, lattice(side, o)),
                    ..pl
                })
            })
            .collect();
        let targets: Vec<Line<F>> = graph
            .neighbors(x)
            .iter()
            .filter(|&&(m, e)| active[m as usize] && planes.inside[e as usize].is_none())
            .filter_map(|&(m, e)| {
                lines[m as usize].map(|l| Line {
                    p: add(l.p, lattice(side, topo.seen(e, x))),
                    d: l.d,
                })
            })
            .collect();
        let line = match (held.as_slice(), targets.as_slice()) {
            ([], []) => Line {
                p: random_v3(rng),
                d: random_v3(rng),
            },
            ([], [t]) => Line {
                p: point_on(t, rng),
                d: random_v3(rng),
            },
            ([], [t1, t2]) => through(point_on(t1, rng), point_on(t2, rng)),
            ([], [t1, t2, t3]) => {
                // Through a point of the first, in the planes it spans with the others.
                let x1 = point_on(t1, rng);
                let n2 = cross(sub(x1, t2.p), t2.d);
                let n3 = cross(sub(x1, t3.p), t3.d);
                Line {
                    p: x1,
                    d: cross(n2, n3),
                }
            }
            ([pl], ts) if ts.len() <= 2 => {
                let mut pts = Vec::with_capacity(2);
                for t in ts {
                    pts.push(crossing(t, pl)?);
                }
                let in_plane = |rng: &mut _| cross(random_v3(rng), pl.normal());
                match pts.as_slice() {
                    [] => Line {
                        p: add(pl.q, in_plane(rng)),
                        d: in_plane(rng),
                    },
                    [a] => Line {
                        p: *a,
                        d: in_plane(rng),
                    },
                    [a, b] => through(*a, *b),
                    _ => unreachable!("at most two crossings"),
                }
            }
            ([p1, p2], []) => {
                let d = cross(p1.normal(), p2.normal());
                let inv = dot(d, d).inverse().ok_or_else(|| {
                    Failure::Degenerate(format!("rod {x}: two planes without a common line"))
                })?;
                let (h1, h2) = (dot(p1.normal(), p1.q), dot(p2.normal(), p2.q));
                let p = add(
                    scale(cross(p2.normal(), d), h1),
                    scale(cross(d, p1.normal()), h2),
                );
                Line {
                    p: scale(p, inv),
                    d,
                }
            }
            _ => {
                return Err(Failure::Broken(format!(
                    "rod {x} is held by {} placed planes and {} placed lines: not a construction order",
                    held.len(),
                    targets.len()
                )));
            }
        };
        if is_null(line.d) {
            return Err(Failure::Degenerate(format!(
                "rod {x}: its line has no direction ({} planes, {} lines to meet)",
                held.len(),
                targets.len()
            )));
        }
        lines[xi] = Some(line);
        for &(c, o) in &planes.of_rod[xi] {
            let c = c as usize;
            if plane[c].is_some() {
                continue;
            }
            let other = match planes.classes[c].wraps.as_slice() {
                [] => random_v3(rng),
                [w] => lattice(F::one(), *w),
                _ => unreachable!("a class wrapping twice is placed first"),
            };
            let held = Plane {
                q: add(line.p, lattice(side, o)),
                u: line.d,
                v: other,
            };
            if is_null(held.normal()) {
                return Err(Failure::Degenerate(format!(
                    "the plane of class {c} through rod {x} is undetermined"
                )));
            }
            plane[c] = Some(held);
        }
    }

    // The contact points, each checked on both lines.
    let mut points: Vec<Option<V3<F>>> = vec![None; graph.n_edges()];
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        let (Some(la), Some(lb)) = (lines[a as usize], lines[b as usize]) else {
            continue;
        };
        let pb = add(lb.p, lattice(side, topo.seen(e as u32, a)));
        let n = cross(la.d, lb.d);
        let inv = dot(n, n)
            .inverse()
            .ok_or_else(|| Failure::Degenerate(format!("rods {a} and {b} are parallel")))?;
        let s = dot(cross(sub(pb, la.p), lb.d), n) * inv;
        let x = add(la.p, scale(la.d, s));
        if !is_null(cross(sub(x, pb), lb.d)) {
            return Err(Failure::Broken(format!(
                "the lines of rods {a} and {b} do not meet although they touch"
            )));
        }
        points[e] = Some(x);
    }

    // Contacts on one rod are distinct points (no concurrent triangles).
    let mut along: Vec<Vec<(u64, u32)>> = vec![Vec::new(); graph.n_nodes()];
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        let Some(x) = points[e] else { continue };
        for (r, other, y) in [
            (a, b, x),
            (b, a, sub(x, lattice(side, topo.seen(e as u32, a)))),
        ] {
            let l = lines[r as usize].expect("placed");
            let k = (0..3)
                .find(|&k| l.d[k] != F::zero())
                .expect("non-null direction");
            let s = (y[k] - l.p[k]) * l.d[k].inverse().expect("non-zero");
            along[r as usize].push((s.residue(), other));
        }
    }
    for (r, list) in along.iter_mut().enumerate() {
        list.sort_unstable();
        if let Some(w) = list.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(Failure::Degenerate(format!(
                "rod {r} meets rods {} and {} at one point",
                w[0].1, w[1].1
            )));
        }
    }
    Ok(Realization {
        side,
        lines,
        points,
    })
}
