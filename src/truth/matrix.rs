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
//!
//! **Strain columns** (MODEL §10, the strain rank). Let the box deform too
//! (the flexible torus): its lattice vectors move as `L' = E L` for a
//! velocity gradient `E`, and the image of a part shifted by the lattice
//! vector `s` moves as the part plus `E s`. Only the symmetric part of `E`
//! is a strain (an antisymmetric one with every part turning alike is a
//! rigid rotation of everything), so six more columns, one per coordinate
//! strain ([`Strain::ALL`]), after every part's. Each row kind in turn:
//! * a contact or a hinge equates the velocities of one physical point
//!   `x = y_a + s_a = y_b + s_b` seen from two part frames: the two images
//!   differ by `E (s_a - s_b) = E (y_b - y_a)`, added to the row;
//! * a spin row `omega . d = 0` only fixes a part's own gauge: no image, no
//!   term;
//! * a class wrapping along `w` is one rigid body that contains its own
//!   image shifted by `W = side w`: that image moves as the body at
//!   `y + W`, and as the body's image, `v(y) + E W`. So `omega x W = E W`:
//!   the row `omega x w = 0` gains `- E w` (it is `omega x W - E W` over
//!   `side`). Its component along `w` is `-w.E w = 0` whatever `omega`: a
//!   plane wrapping along x resists `e_xx` by itself.
//!
//! Only the strains of periodic axes get columns ([`Strain::of_box`]).

use super::answer::Strain;
use super::planes::Planes;
use super::realize::Realization;
use crate::contacts::Offset;
use crate::graph::Topology;
use crate::math::Scalar;
use crate::math::sparse::SparseRow;
use crate::math::vec3::{V3, add, cross, dot, scale, sub};

/// Columns per part.
pub const WIDTH: usize = 6;

/// A rod's part and its image offset in that part's frame.
pub type Owner = (u32, Offset);

/// The parts of a system and which part moves each rod.
#[derive(Clone, Debug)]
pub struct Parts {
    pub count: usize,
    /// Parts `0..classes` are the plane classes, the others single rods.
    pub classes: usize,
    /// Per rod: its part and its offset in that part's frame (active rods only).
    pub owner: Vec<Option<Owner>>,
}

impl Parts {
    /// For an edge between two active rods: each rod's part with its offset,
    /// and the contact point (in the frame of the edge's first rod).
    pub fn contact<S: Scalar>(
        &self,
        real: &Realization<S>,
        e: usize,
        [a, b]: [u32; 2],
    ) -> Option<(Owner, Owner, V3<S>)> {
        Some((
            self.owner[a as usize]?,
            self.owner[b as usize]?,
            real.points[e]?,
        ))
    }
}

/// Classes are parts `0..classes`; each other active rod is a part of its own.
pub fn parts(planes: &Planes, active: &[bool]) -> Parts {
    let classes = planes.classes.len();
    let mut count = classes;
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
    Parts {
        count,
        classes,
        owner,
    }
}

/// The coefficients of the three velocity components of a part at `y`:
/// `v = t + omega x y` over columns `(omega, t)`.
fn velocity<S: Scalar>(y: V3<S>) -> [[S; WIDTH]; 3] {
    let (o, z) = (S::one(), S::zero());
    [
        [z, y[2], -y[1], o, z, z],
        [-y[2], z, y[0], z, o, z],
        [y[1], -y[0], z, z, z, o],
    ]
}

/// The strain columns of one matrix: the coordinate strains that have
/// columns, after the `parts` parts' columns.
#[derive(Clone, Copy, Debug)]
pub struct StrainColumns<'a> {
    pub strains: &'a [Strain],
    /// The first strain column: strain `c` is column `first + c.index()`.
    pub first: u32,
}

impl<'a> StrainColumns<'a> {
    /// `strains` after the columns of `parts`; no columns when empty.
    pub fn new(parts: &Parts, strains: &'a [Strain]) -> Self {
        StrainColumns {
            strains,
            first: (parts.count * WIDTH) as u32,
        }
    }

    /// None.
    pub fn none() -> StrainColumns<'static> {
        StrainColumns {
            strains: &[],
            first: 0,
        }
    }

    /// Appends to `row` the terms of component `k` of `E s` (`sign` times):
    /// strain `ij` contributes `s_j` to component `i` and `s_i` to `j`.
    fn push<S: Scalar>(&self, row: &mut SparseRow<S>, k: usize, s: V3<S>, sign: S) {
        for &c in self.strains {
            let [i, j] = c.axes();
            let v = match (k == i, k == j) {
                (true, true) => s[i],
                (true, false) => s[j],
                (false, true) => s[i],
                (false, false) => continue,
            } * sign;
            if !zero(v) {
                row.push((self.first + c.index() as u32, v));
            }
        }
    }
}

/// Three rows: velocity of part `a` at `ya` minus that of part `b` at `yb`,
/// the same point in two frames, with the strain terms `E (yb - ya)`.
fn equal_velocity<S: Scalar>(
    a: u32,
    ya: V3<S>,
    b: u32,
    yb: V3<S>,
    strain: &StrainColumns,
    rows: &mut Vec<SparseRow<S>>,
) {
    let (va, vb) = (velocity(ya), velocity(yb));
    let s = sub(yb, ya);
    for k in 0..3 {
        let mut row: SparseRow<S> = Vec::with_capacity(2 * WIDTH);
        let mut push = |part: u32, coef: &[S; WIDTH], sign: S| {
            for (j, &c) in coef.iter().enumerate() {
                let v = c * sign;
                if !zero(v) {
                    row.push((part * WIDTH as u32 + j as u32, v));
                }
            }
        };
        if a < b {
            push(a, &va[k], S::one());
            push(b, &vb[k], -S::one());
        } else {
            push(b, &vb[k], -S::one());
            push(a, &va[k], S::one());
        }
        strain.push(&mut row, k, s, S::one());
        rows.push(row);
    }
}

/// An exact zero: sparse rows keep every other entry, however small.
fn zero<S: Scalar>(v: S) -> bool {
    v.vanishes(0.0, 0.0)
}

/// The rows of the rigidity matrix, over F_p or in floats, with the terms
/// of the strain columns `strain`.
pub fn rows<S: Scalar>(
    topo: &Topology,
    planes: &Planes,
    parts: &Parts,
    real: &Realization<S>,
    strain: &StrainColumns,
) -> Vec<SparseRow<S>> {
    let graph = topo.graph;
    let mut rows = Vec::new();
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        let Some(((pa, oa), (pb, ob), x)) = parts.contact(real, e, [a, b]) else {
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
        equal_velocity(pa, ya, pb, yb, strain, &mut rows);
    }
    for (r, owner) in parts.owner.iter().enumerate() {
        let Some((part, _)) = *owner else { continue };
        let line = real.lines[r].expect("active rods are placed");
        let classes = &planes.of_rod[r];
        if classes.is_empty() {
            let base = part * WIDTH as u32;
            rows.push(
                (0..3)
                    .filter(|&k| !zero(line.d[k]))
                    .map(|k| (base + k as u32, line.d[k]))
                    .collect(),
            );
        }
        if let Some(&(first, o1)) = classes.first() {
            for &(other, o2) in &classes[1..] {
                for y in [line.p, add(line.p, line.d)] {
                    let (y1, y2) = (add(y, real.lattice(o1)), add(y, real.lattice(o2)));
                    equal_velocity(first, y1, other, y2, strain, &mut rows);
                }
            }
        }
    }
    for (c, class) in planes.classes.iter().enumerate() {
        let base = (c * WIDTH) as u32;
        for w in &class.wraps {
            let w = w.map(|k| S::from_i64(k as i64));
            // omega x w - E w, one row per component.
            let comps = [
                [(1, w[2]), (2, -w[1])],
                [(2, w[0]), (0, -w[2])],
                [(0, w[1]), (1, -w[0])],
            ];
            for (k, comp) in comps.into_iter().enumerate() {
                let mut row: SparseRow<S> = comp
                    .iter()
                    .filter(|&&(_, v)| !zero(v))
                    .map(|&(k, v)| (base + k, v))
                    .collect();
                row.sort_unstable_by_key(|&(k, _)| k);
                strain.push(&mut row, k, w, -S::one());
                if !row.is_empty() {
                    rows.push(row);
                }
            }
        }
    }
    rows
}

/// A rigid motion `v(y) = t + omega x y` of the whole framework in every
/// part's columns (a kernel vector of every realization: the tests check
/// it exactly, the float fallback measures its rounding by it): a class
/// moves with `(omega, t)` itself; a rod part has the spin `alpha d` about
/// its own axis taken out (`omega . d = 0`), and `t + alpha d x p` keeps its
/// axis moving with the whole.
pub fn rigid_motion<S: Scalar>(
    parts: &Parts,
    real: &Realization<S>,
    omega: V3<S>,
    t: V3<S>,
) -> Vec<S> {
    let mut x = Vec::with_capacity(parts.count * WIDTH);
    for _ in 0..parts.classes {
        x.extend(omega);
        x.extend(t);
    }
    x.resize(parts.count * WIDTH, S::zero());
    for (r, owner) in parts.owner.iter().enumerate() {
        let (Some((part, _)), Some(line)) = (*owner, real.lines[r]) else {
            continue;
        };
        if (part as usize) < parts.classes {
            continue;
        }
        let Some(inv) = dot(line.d, line.d).recip() else {
            continue;
        };
        let spin = scale(line.d, dot(omega, line.d) * inv);
        let b = part as usize * WIDTH;
        x[b..b + 3].copy_from_slice(&sub(omega, spin));
        x[b + 3..b + 6].copy_from_slice(&add(t, cross(spin, line.p)));
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::ContactGraph;
    use crate::graph::io::parse_graph6;
    use crate::math::Fp;
    use crate::truth::{order, planes, prune, realize};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// The matrix of `graph` at one exact realization, with what built it.
    fn build(topo: &Topology) -> (Parts, Realization, Vec<SparseRow>) {
        let core = prune::two_core(topo.graph);
        let planes = planes::forced(topo, &core.active).unwrap();
        let order = order::order(topo, &planes, &core.active).unwrap();
        let real = realize::build(
            topo,
            &planes,
            &core.active,
            &order,
            &mut ChaCha8Rng::seed_from_u64(3),
        )
        .unwrap();
        let parts = parts(&planes, &core.active);
        let rows = rows(topo, &planes, &parts, &real, &StrainColumns::none());
        (parts, real, rows)
    }

    fn residual(rows: &[SparseRow], x: &[Fp]) -> bool {
        rows.iter().all(|r| {
            r.iter()
                .fold(Fp::ZERO, |a, &(c, v)| a + v * x[c as usize])
                .is_zero()
        })
    }

    #[test]
    fn rigid_motions_of_a_finite_framework_are_in_the_kernel() {
        // K_{3,4} (no planes), a prism (two planes) and a 7-rod graph mixing both.
        for g6 in ["F?~v_", "E{Sw", "FEhvO"] {
            let g = parse_graph6(g6).unwrap();
            let topo = Topology::finite(&g);
            let (parts, real, rows) = build(&topo);
            let mut rng = ChaCha8Rng::seed_from_u64(9);
            let mut r3 = || [0; 3].map(|_| Fp::random(&mut rng));
            let (w, t) = (r3(), r3());
            assert!(
                residual(&rows, &rigid_motion(&parts, &real, [Fp::ZERO; 3], t)),
                "{g6}: translation"
            );
            assert!(
                residual(&rows, &rigid_motion(&parts, &real, w, [Fp::ZERO; 3])),
                "{g6}: rotation"
            );
            // A motion that is no rigid motion violates some row.
            let mut bent = rigid_motion(&parts, &real, w, t);
            bent[0] = bent[0] + Fp::ONE;
            assert!(!residual(&rows, &bent), "{g6}: a bent motion passed");
        }
    }

    #[test]
    fn translations_of_a_periodic_system_are_in_the_kernel() {
        use crate::contacts;
        use crate::rods::{RodParams, RodSystem};
        let system = RodSystem::generate(RodParams::new(23.0, 3.0, 38.0).unwrap(), 2);
        let cs = contacts::detect(&system);
        let g = ContactGraph::from_contacts(system.len(), &cs);
        let shifts: Vec<_> = cs.iter().map(|c| c.shift).collect();
        assert!(
            shifts.iter().any(|s| *s != [0; 3]),
            "contacts across the box"
        );
        let topo = Topology::periodic(&g, &shifts).unwrap();
        let (parts, real, rows) = build(&topo);
        let t = [Fp::new(3), Fp::new(-7), Fp::new(11)];
        assert!(residual(
            &rows,
            &rigid_motion(&parts, &real, [Fp::ZERO; 3], t)
        ));
    }
}
