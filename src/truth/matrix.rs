//! The rigidity matrix of a whole system in body frames (MODEL §2, §10).
//!
//! The point-based matrix of the motif checks has three columns per contact
//! point; a whole system has tens of thousands. Here every rigid *part*
//! has six columns, its angular and linear velocity `(omega, t)`: each
//! forced plane class is one part (it is a rigid body, so its rods need no
//! columns of their own), and so is every other rod. The rows:
//! * a contact between two parts: equal velocities at the contact point (3);
//! * a rod's spin about its own axis is no motion: `omega . d = 0` (1);
//! * a rod in a second class: both classes move it alike, equal velocities
//!   at two of its points (6, a hinge);
//! * a class whose plane wraps the box along `w` moves like its images:
//!   `omega x w = 0` (3 per direction).
//!
//! In a periodic box the velocities of a part's images equal its own (the
//! box is fixed), so a point is always taken in its part's frame.

use super::Topology;
use super::planes::{Offset, Planes};
use super::realize::Realization;
use crate::math::Fp;
use crate::math::sparse::SparseRow;
use crate::math::vec3::{V3, add, sub};

/// Columns per part.
pub const WIDTH: usize = 6;

/// The parts of a system and which part moves each rod.
#[derive(Clone, Debug)]
pub struct Parts {
    pub count: usize,
    /// Per rod: its part and its offset in that part's frame (active rods only).
    pub owner: Vec<Option<(u32, Offset)>>,
}

/// Classes are parts `0..classes`; each other active rod is a part of its own.
pub fn parts(planes: &Planes, active: &[bool]) -> Parts {
    let mut count = planes.classes.len();
    let owner = active
        .iter()
        .enumerate()
        .map(|(r, &on)| {
            if !on {
                return None;
            }
            Some(planes.of_rod[r].first().copied().unwrap_or_else(|| {
                count += 1;
                ((count - 1) as u32, [0; 3])
            }))
        })
        .collect();
    Parts { count, owner }
}

/// The coefficients of the three velocity components of a part at `y`:
/// `v = t + omega x y` over columns `(omega, t)`.
fn velocity(y: V3<Fp>) -> [[Fp; WIDTH]; 3] {
    let (o, z) = (Fp::ONE, Fp::ZERO);
    [
        [z, y[2], -y[1], o, z, z],
        [-y[2], z, y[0], z, o, z],
        [y[1], -y[0], z, z, z, o],
    ]
}

/// Three rows: velocity of part `a` at `ya` minus that of part `b` at `yb`.
fn equal_velocity(a: u32, ya: V3<Fp>, b: u32, yb: V3<Fp>, rows: &mut Vec<SparseRow>) {
    let (va, vb) = (velocity(ya), velocity(yb));
    for k in 0..3 {
        let mut row: SparseRow = Vec::with_capacity(2 * WIDTH);
        let mut push = |part: u32, coef: &[Fp; WIDTH], sign: Fp| {
            for (j, &c) in coef.iter().enumerate() {
                let v = c * sign;
                if !v.is_zero() {
                    row.push((part * WIDTH as u32 + j as u32, v));
                }
            }
        };
        if a < b {
            push(a, &va[k], Fp::ONE);
            push(b, &vb[k], -Fp::ONE);
        } else {
            push(b, &vb[k], -Fp::ONE);
            push(a, &va[k], Fp::ONE);
        }
        rows.push(row);
    }
}

/// The rows of the rigidity matrix.
pub fn rows(topo: &Topology, planes: &Planes, parts: &Parts, real: &Realization) -> Vec<SparseRow> {
    let graph = topo.graph;
    let mut rows = Vec::new();
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        let (Some((pa, oa)), Some((pb, ob)), Some(x)) = (
            parts.owner[a as usize],
            parts.owner[b as usize],
            real.points[e],
        ) else {
            continue;
        };
        if planes.inside[e].is_some() {
            continue;
        }
        debug_assert_ne!(pa, pb, "a contact outside every class joins two parts");
        let ya = add(x, real.lattice(oa));
        let yb = add(
            sub(x, real.lattice(topo.seen(e as u32, a))),
            real.lattice(ob),
        );
        equal_velocity(pa, ya, pb, yb, &mut rows);
    }
    for (r, owner) in parts.owner.iter().enumerate() {
        let Some((part, _)) = *owner else { continue };
        let line = real.lines[r].expect("active rods are placed");
        let classes = &planes.of_rod[r];
        if classes.is_empty() {
            let base = part * WIDTH as u32;
            rows.push(
                (0..3)
                    .filter(|&k| !line.d[k].is_zero())
                    .map(|k| (base + k as u32, line.d[k]))
                    .collect(),
            );
        }
        if let Some(&(first, o1)) = classes.first() {
            for &(other, o2) in &classes[1..] {
                for y in [line.p, add(line.p, line.d)] {
                    let (y1, y2) = (add(y, real.lattice(o1)), add(y, real.lattice(o2)));
                    equal_velocity(first, y1, other, y2, &mut rows);
                }
            }
        }
    }
    for (c, class) in planes.classes.iter().enumerate() {
        let base = (c * WIDTH) as u32;
        for w in &class.wraps {
            let w = w.map(|k| Fp::new(k as i64));
            // omega x w, one row per component.
            let comps = [
                [(1, w[2]), (2, -w[1])],
                [(2, w[0]), (0, -w[2])],
                [(0, w[1]), (1, -w[0])],
            ];
            for comp in comps {
                let mut row: SparseRow = comp
                    .iter()
                    .filter(|(_, v)| !v.is_zero())
                    .map(|&(k, v)| (base + k, v))
                    .collect();
                row.sort_unstable_by_key(|&(k, _)| k);
                if !row.is_empty() {
                    rows.push(row);
                }
            }
        }
    }
    rows
}
