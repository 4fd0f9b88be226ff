//! The point-based rigidity matrix of a contact pattern at a realization, and
//! the exact verdict over all realization components (MODEL §2–§4).
//!
//! Unknowns are the velocities of points: every contact point, plus
//! auxiliary points where a part has too few of its own. A rod keeps two
//! anchors joined by a bar and moves every other point on it affinely; a body
//! keeps four affinely independent anchors (three for a planar body) joined
//! by bars and moves every other point as their affine combination. Internal
//! degrees of freedom are `3 P - rank - 6` (5 when every point is on one line).

use super::construction::{Realization, exact, invert_all, normalized};
use super::incidence::Incidence;
use crate::math::vec3::{Line, Plane};
use crate::math::vec3::{V3, add, cross, dot, parallel, same_point, scale, size, sub};
use crate::math::{Matrix, Scalar};
use crate::pattern::NodeKind;
use rand::Rng;

/// A rigidity matrix with the points its columns belong to.
#[derive(Clone, Debug)]
pub struct Framework<S> {
    pub matrix: Matrix<S>,
    /// Contact points first (in contact order), then auxiliary points.
    pub points: Vec<V3<S>>,
}

impl<S: Scalar> Framework<S> {
    /// Dimension of the trivial motions on these points: 6, or 5 when they
    /// all lie on one line (the spin about it moves nothing).
    pub fn trivial_dimension(&self) -> usize {
        trivial_dimension(&self.points)
    }

    /// The six trivial motions (translations and rotations) as velocity vectors.
    pub fn trivial_motions(&self) -> Vec<Vec<S>> {
        let unit = |k: usize| {
            let mut e = [S::zero(); 3];
            e[k] = S::one();
            e
        };
        let mut out = Vec::new();
        for k in 0..3 {
            out.push(self.points.iter().flat_map(|_| unit(k)).collect());
            out.push(
                self.points
                    .iter()
                    .flat_map(|&p| cross(unit(k), p))
                    .collect(),
            );
        }
        out
    }
}

/// Dimension of the trivial motions on `points`: 6, or 5 when they all lie
/// on one line (the spin about it moves nothing).
pub fn trivial_dimension<S: Scalar>(points: &[V3<S>]) -> usize {
    let Some(&p0) = points.first() else {
        return 0;
    };
    let Some(d) = points
        .iter()
        .find(|&&p| !same_point(p, p0))
        .map(|&p| sub(p, p0))
    else {
        return 3;
    };
    let collinear = points.iter().all(|&p| parallel(sub(p, p0), d));
    if collinear { 5 } else { 6 }
}

/// Builds the rigidity matrix of `inc` at `sample`; `random` supplies the
/// coordinates of auxiliary points.
///
/// # Panics
///
/// When two points of one part coincide: [`super::construction::construct_in`] never
/// returns such a sample; use [`try_framework`] for samples from elsewhere.
pub fn framework<S: Scalar>(
    inc: &Incidence,
    sample: &Realization<S>,
    random: &mut impl FnMut() -> S,
) -> Framework<S> {
    try_framework(inc, sample, random).expect("the points of each part are distinct")
}

/// Relative independence an own contact point needs to serve as a body
/// anchor in floats (the sine of its angle to the span of the anchors before
/// it); a thinner simplex would amplify rounding in the affine coordinates,
/// so a random auxiliary anchor is used instead. Exact over F_p: non-zero.
pub const ANCHOR_TOL: f64 = 1e-2;

/// Tries for a random auxiliary point before the sample counts as degenerate.
const AUX_TRIES: usize = 64;

/// [`framework`], or `None` when the sample is degenerate (coincident points
/// on one part, or a planar body whose plane is too thin for anchors).
pub fn try_framework<S: Scalar>(
    inc: &Incidence,
    sample: &Realization<S>,
    random: &mut impl FnMut() -> S,
) -> Option<Framework<S>> {
    let Structure { points, rows, .. } = structure(inc, sample, random)?;
    let height = rows.iter().map(|r| r.height()).sum();
    let mut matrix = Matrix::zeros(height, 3 * points.len());
    let mut r = 0;
    for row in &rows {
        match *row {
            Row::Bar { a, b, d } => {
                for (k, &dk) in d.iter().enumerate() {
                    matrix.add_to(r, 3 * a + k, dk);
                    matrix.add_to(r, 3 * b + k, -dk);
                }
                r += 1;
            }
            Row::Affine { c, terms, len } => {
                for k in 0..3 {
                    matrix.add_to(r, 3 * c + k, S::one());
                    for &(t, coef) in &terms[..len] {
                        matrix.add_to(r, 3 * t + k, coef);
                    }
                    r += 1;
                }
            }
        }
    }
    Some(Framework { matrix, points })
}

/// A rigidity matrix as its rows are built (MODEL §2): bars, and points
/// moved affinely with the anchors of their part, the same three rows for
/// each coordinate. The exact rank uses that structure
/// ([`super::rank::structured_rank`]); [`try_framework`] spells the rows out.
#[derive(Clone, Debug)]
pub struct Structure<S> {
    /// Contact points first (in contact order), then auxiliary points.
    pub points: Vec<V3<S>>,
    /// In the order of the matrix rows.
    pub rows: Vec<Row<S>>,
    /// The parts (pattern nodes) the rows belong to, in node order.
    pub parts: Vec<Part>,
}

/// The rows of one rod or body in a [`Structure`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    pub rod: bool,
    /// Two anchors for a rod, three or four for a body.
    pub anchors: [usize; 4],
    pub n_anchors: usize,
    pub rows: std::ops::Range<usize>,
}

/// One bar row, or the three rows (one per coordinate) of an affine point.
#[derive(Clone, Copy, Debug)]
pub enum Row<S> {
    /// `d . (u_a - u_b) = 0`, with `d = p_a - p_b`.
    Bar { a: usize, b: usize, d: V3<S> },
    /// `u_c + sum_j coef_j u_(t_j) = 0` in each coordinate, for the first
    /// `len` terms `(t_j, coef_j)`: two anchors of a rod, three or four of a body.
    Affine {
        c: usize,
        terms: [(usize, S); 4],
        len: usize,
    },
}

impl<S> Row<S> {
    /// Rows of the matrix this stands for.
    fn height(&self) -> usize {
        match self {
            Row::Bar { .. } => 1,
            Row::Affine { .. } => 3,
        }
    }
}

/// The rows of the rigidity matrix of `inc` at `sample`, with the points
/// they act on; `random` supplies auxiliary points. `None` when the sample
/// is degenerate (see [`try_framework`]).
pub fn structure<S: Scalar>(
    inc: &Incidence,
    sample: &Realization<S>,
    random: &mut impl FnMut() -> S,
) -> Option<Structure<S>> {
    let mut points: Vec<V3<S>> = Vec::with_capacity(sample.points.len() + 4);
    points.extend_from_slice(&sample.points);
    // A part's rows: a bar per anchor pair and an affine row per other point.
    let mut rows: Vec<Row<S>> = Vec::with_capacity(2 * inc.n_contacts() + 6 * inc.kinds.len());
    let mut own: Vec<usize> = Vec::new();
    let mut parts: Vec<Part> = Vec::with_capacity(inc.kinds.len());
    // In exact arithmetic the rods' inverses are taken together at the end.
    let mut deferred = exact::<S>().then(Vec::new);
    for (node, kind) in inc.kinds.iter().enumerate() {
        let lines = &inc.node_lines[node];
        own.clear();
        own.extend(
            lines
                .iter()
                .flat_map(|&l| inc.line_contacts[l].iter().copied()),
        );
        own.sort_unstable();
        own.dedup();
        match kind {
            NodeKind::Rod => {
                let line: &Line<S> = &sample.lines[lines[0]];
                let mut tries = 0;
                while own.len() < 2 {
                    tries += 1;
                    if tries > AUX_TRIES {
                        return None;
                    }
                    let p = add(line.p, scale(line.d, random()));
                    if own.iter().all(|&c| !same_point(points[c], p)) {
                        points.push(p);
                        own.push(points.len() - 1);
                    }
                }
                let start = rows.len();
                rod_rows(&points, &own, &mut rows, deferred.as_mut())?;
                let Row::Bar { a, b, .. } = rows[start] else {
                    unreachable!("a rod's rows start with its bar")
                };
                parts.push(Part {
                    rod: true,
                    anchors: [a, b, 0, 0],
                    n_anchors: 2,
                    rows: start..rows.len(),
                });
            }
            NodeKind::Planar | NodeKind::Spatial => {
                let planar = *kind == NodeKind::Planar;
                let plane: Option<Plane<S>> = sample.node_planes[node];
                let want = if planar { 3 } else { 4 };
                let mut anchors: Vec<usize> = Vec::with_capacity(want);
                for &c in &own {
                    if anchors.len() < want && independent(&points, &anchors, points[c]) {
                        anchors.push(c);
                    }
                }
                let mut tries = 0;
                while anchors.len() < want {
                    tries += 1;
                    if tries > AUX_TRIES {
                        return None;
                    }
                    let p = match (planar, plane) {
                        (true, Some(pl)) => {
                            add(pl.q, add(scale(pl.u, random()), scale(pl.v, random())))
                        }
                        _ => [random(), random(), random()],
                    };
                    if independent(&points, &anchors, p) {
                        points.push(p);
                        anchors.push(points.len() - 1);
                    }
                }
                let start = rows.len();
                body_rows(&points, &anchors, &own, &mut rows)?;
                let mut fixed = [0; 4];
                fixed[..anchors.len()].copy_from_slice(&anchors);
                parts.push(Part {
                    rod: false,
                    anchors: fixed,
                    n_anchors: anchors.len(),
                    rows: start..rows.len(),
                });
            }
        }
    }
    if let Some(rods) = deferred {
        finish_rods(&mut rows, &rods)?;
    }
    Some(Structure {
        points,
        rows,
        parts,
    })
}

/// Whether `p` is affinely independent of the points `anchors`, with a
/// margin of [`ANCHOR_TOL`] for floats (exactly over F_p).
fn independent<S: Scalar>(points: &[V3<S>], anchors: &[usize], p: V3<S>) -> bool {
    let Some(&a) = anchors.first() else {
        return true;
    };
    let w = sub(p, points[a]);
    match anchors[1..] {
        [] => !w
            .iter()
            .all(|x| x.vanishes(size(p) + size(points[a]), ANCHOR_TOL)),
        [b] => {
            let e = sub(points[b], points[a]);
            !cross(e, w)
                .iter()
                .all(|x| x.vanishes(size(e) * size(w), ANCHOR_TOL))
        }
        [b, c, ..] => {
            let n = cross(sub(points[b], points[a]), sub(points[c], points[a]));
            !dot(n, w).vanishes(size(n) * size(w), ANCHOR_TOL)
        }
    }
}

/// Bar between two points of a rod; the others move affinely along it. The
/// anchors are the first point and the one farthest from it, and `s` is read
/// on the coordinate along which they differ most: the best-conditioned
/// choice for floats, any distinct pair over F_p.
///
/// With `deferred`, the affine rows wait for the inverse of `d_i`: they
/// hold `p_c[i] - p_b[i]` in place of `s`, and the rod (its first affine
/// row, their number and `d_i`) goes on `deferred`, for [`finish_rods`] to
/// invert every rod's `d_i` at once (exact arithmetic).
fn rod_rows<S: Scalar>(
    points: &[V3<S>],
    own: &[usize],
    rows: &mut Vec<Row<S>>,
    deferred: Option<&mut Vec<(usize, usize, S)>>,
) -> Option<()> {
    let a = own[0];
    let far = |c: usize| size(sub(points[c], points[a]));
    let b = own[1..]
        .iter()
        .copied()
        .fold(own[1], |best, c| if far(c) > far(best) { c } else { best });
    let d = sub(points[a], points[b]);
    rows.push(Row::Bar { a, b, d });
    let i = (0..3).fold(0, |best, x| {
        if d[x].magnitude() > d[best].magnitude() {
            x
        } else {
            best
        }
    });
    let inv = match deferred {
        Some(rods) => {
            rods.push((rows.len(), own.len() - 2, d[i]));
            None
        }
        None => Some(d[i].recip()?),
    };
    for &c in own.iter().filter(|&&c| c != a && c != b) {
        let along = points[c][i] - points[b][i];
        let s = inv.map_or(along, |inv| along * inv);
        let mut terms = [(0, S::zero()); 4];
        terms[0] = (a, -s);
        terms[1] = (b, s - S::one());
        rows.push(Row::Affine { c, terms, len: 2 });
    }
    Some(())
}

/// Completes the deferred affine rows of rods (see [`rod_rows`]), every
/// rod's `d_i` inverted at once: `s` is the held value times the inverse.
fn finish_rods<S: Scalar>(rows: &mut [Row<S>], rods: &[(usize, usize, S)]) -> Option<()> {
    let mut inverses: Vec<S> = rods.iter().map(|&(_, _, v)| v).collect();
    let mut prefix = Vec::with_capacity(inverses.len());
    if !invert_all(&mut inverses, &mut prefix) {
        return None;
    }
    for (&(first, count, _), &inv) in rods.iter().zip(&inverses) {
        for row in &mut rows[first..first + count] {
            if let Row::Affine { terms, .. } = row {
                let s = -terms[0].1 * inv;
                terms[0].1 = -s;
                terms[1].1 = s - S::one();
            }
        }
    }
    Some(())
}

/// Bars among a body's anchors; every other point is their affine combination.
fn body_rows<S: Scalar>(
    points: &[V3<S>],
    anchors: &[usize],
    own: &[usize],
    rows: &mut Vec<Row<S>>,
) -> Option<()> {
    for (i, &a) in anchors.iter().enumerate() {
        for &b in &anchors[i + 1..] {
            rows.push(Row::Bar {
                a,
                b,
                d: sub(points[a], points[b]),
            });
        }
    }
    for &c in own.iter().filter(|c| !anchors.contains(c)) {
        let lambda = affine_coordinates(points, anchors, points[c])?;
        let mut terms = [(0, S::zero()); 4];
        for (term, (&a, &l)) in terms.iter_mut().zip(anchors.iter().zip(&lambda)) {
            *term = (a, -l);
        }
        rows.push(Row::Affine {
            c,
            terms,
            len: anchors.len(),
        });
    }
    Some(())
}

/// Affine coordinates of `x` with respect to three or four anchors.
fn affine_coordinates<S: Scalar>(points: &[V3<S>], anchors: &[usize], x: V3<S>) -> Option<Vec<S>> {
    let last = points[*anchors.last()?];
    let cols: Vec<V3<S>> = anchors[..anchors.len() - 1]
        .iter()
        .map(|&a| sub(points[a], last))
        .collect();
    let rhs = sub(x, last);
    let lam: Vec<S> = if cols.len() == 3 {
        // Cramer's rule on the 3x3 system [c0 c1 c2] l = rhs.
        let det = dot(cols[0], cross(cols[1], cols[2]));
        let inv = det.recip()?;
        vec![
            dot(rhs, cross(cols[1], cols[2])) * inv,
            dot(cols[0], cross(rhs, cols[2])) * inv,
            dot(cols[0], cross(cols[1], rhs)) * inv,
        ]
    } else {
        // Two columns in 3-space: the pair of rows with the largest 2x2 minor.
        let (i, j) = [(0, 1), (0, 2), (1, 2)]
            .into_iter()
            .max_by(|&(a, b), &(c, d)| {
                let m = |i: usize, j: usize| {
                    (cols[0][i] * cols[1][j] - cols[1][i] * cols[0][j]).magnitude()
                };
                m(a, b).total_cmp(&m(c, d))
            })
            .unwrap_or((0, 1));
        let det = cols[0][i] * cols[1][j] - cols[1][i] * cols[0][j];
        let inv = det.recip()?;
        vec![
            (rhs[i] * cols[1][j] - cols[1][i] * rhs[j]) * inv,
            (cols[0][i] * rhs[j] - rhs[i] * cols[0][j]) * inv,
        ]
    };
    let rest = lam.iter().fold(S::one(), |acc, &l| acc - l);
    let mut out = lam;
    out.push(rest);
    Some(out)
}

/// Internal degrees of freedom of a framework with a given rank.
pub fn dof<S: Scalar>(f: &Framework<S>, rank: usize) -> usize {
    (3 * f.points.len()).saturating_sub(rank + f.trivial_dimension())
}

/// The largest `|R t| / |t|` over the trivial motions `t`: zero for an exact
/// realization, the size of its incidence rounding for a float one.
pub fn trivial_residual(f: &Framework<f64>) -> f64 {
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    f.trivial_motions()
        .iter()
        .map(|t| norm(&f.matrix.apply(t)) / norm(t).max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max)
}

/// The float rigidity matrix the float check ranks: the sample normalized
/// ([`normalized`]), auxiliary points uniform in `[-1, 1]`, and
/// rows scaled to unit length ([`equilibrate`]). `None` for a degenerate sample.
pub fn float_framework(
    inc: &Incidence,
    sample: Realization<f64>,
    rng: &mut impl Rng,
) -> Option<Framework<f64>> {
    let sample = normalized(sample);
    let mut f = try_framework(inc, &sample, &mut || f64::random(rng))?;
    equilibrate(&mut f.matrix);
    Some(f)
}

/// Scales every row of `m` to unit Euclidean length (zero rows stay zero):
/// that changes no exact rank, and keeps bar rows (whose entries scale with
/// distances) comparable with affine rows (entries of order one), so the
/// spectrum reflects the geometry rather than its units.
pub fn equilibrate(m: &mut Matrix<f64>) {
    for row in m.data.chunks_mut(m.cols.max(1)) {
        let norm = row.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.0 {
            row.iter_mut().for_each(|x| *x /= norm);
        }
    }
}
