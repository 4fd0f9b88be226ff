//! Rigid clusters from kernel vectors (MODEL §10): maximal sets of rods
//! with no relative motion.
//!
//! A rod can be a hinge: two clusters may each hold it and still turn about
//! its axis against each other, so clusters are not unions over rigid
//! contacts. Instead each contact whose two rods move as one rigid body
//! carries that body's angular velocity `omega`. Two such contacts on one
//! rod belong to one cluster exactly when their `omega` agree: both fields
//! already agree on the rod up to a spin about its axis, and equal `omega`
//! rules the spin out. With random kernel vectors every test holds on the
//! whole kernel except with probability about `1/p`.
//!
//! In floats ([`float_clusters`]) the kernel is an orthonormal basis from
//! the SVD, known up to its rounding, and every test compares a norm over
//! the basis with the error that rounding carries into it: within
//! [`SAFETY`] times the error it is zero, beyond [`GREY`] times that it is
//! not, and a value in between leaves the clusters undecided rather than
//! guessed.

use petgraph::unionfind::UnionFind;
use rustc_hash::FxHashMap;

use super::matrix::{Parts, WIDTH};
use super::realize::Realization;
use crate::graph::Topology;
use crate::math::vec3::{V3, add, cross, dot, scale, sub};
use crate::math::{Field, Scalar};

/// The rigid clusters of two or more rods, each sorted, largest first (ties
/// by smallest rod).
pub fn clusters<F: Field>(
    topo: &Topology,
    parts: &Parts,
    real: &Realization<F>,
    kernel: &[Vec<F>],
) -> Vec<Vec<u32>> {
    let graph = topo.graph;
    // The common omega of each contact whose rods move as one, per kernel vector.
    let mut field: Vec<Option<Vec<F>>> = vec![None; graph.n_edges()];
    for (e, slot) in field.iter_mut().enumerate() {
        let Some(c) = ContactMotion::new(parts, real, e, graph.edges()[e]) else {
            continue;
        };
        let mut key = Vec::with_capacity(3 * kernel.len());
        let mut rigid = true;
        for x in kernel {
            let (off, common) = c.relative(x);
            if off != F::zero() {
                rigid = false;
                break;
            }
            key.extend(common);
        }
        if rigid {
            *slot = Some(key);
        }
    }
    group(topo, |e| field[e].is_some(), |e, f| field[e] == field[f])
}

/// A float kernel basis and how far it may be off. The SVD's basis of a
/// matrix known up to `noise` mixes in each other right singular vector
/// `v_i` by up to `noise / s_i` (first-order perturbation of a singular
/// subspace), so a test that is linear in the kernel vectors is off by
/// about its values on those vectors so weighted.
pub struct FloatKernel<'a> {
    /// Orthonormal kernel vectors.
    pub basis: Vec<&'a [f64]>,
    /// `(noise / s_i, v_i)` for every value `s_i` counted in the rank.
    pub errors: Vec<(f64, &'a [f64])>,
}

/// A test value at most this many times its error is zero.
pub const SAFETY: f64 = 100.0;

/// A test value above [`SAFETY`] times its error but at most this many
/// times that is neither zero nor clearly not: the float clusters are then
/// undecided. On the 853 connected graphs of 7 rods forced into floats and
/// five periodic systems of up to 1,320 columns, values that are zero
/// stayed below 10 times their error and the others above `1e7` times it.
pub const GREY: f64 = 100.0;

/// The rigid clusters from a float kernel basis, as [`clusters`]; the lines
/// of `real` have unit directions. `Err` says which test fell in the grey
/// zone.
///
/// Each test (a contact's relative rotation off its lines' plane, and two
/// contacts' common angular velocities) is a linear map of the kernel
/// vectors; its value is its norm on the basis and its error its norm on
/// the weighted [`FloatKernel::errors`]. Conservative on both sides: zero
/// only within [`SAFETY`] times the error, not zero only beyond [`GREY`]
/// times that, undecided in between.
pub fn float_clusters(
    topo: &Topology,
    parts: &Parts,
    real: &Realization<f64>,
    kernel: &FloatKernel,
) -> Result<Vec<Vec<u32>>, String> {
    let graph = topo.graph;
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let unclear = |what: String| Err(format!("{what} has no clear float gap"));
    // What a value and its error say: zero, not zero, or unclear.
    let zero = |value: f64, error: f64| {
        let tol = SAFETY * error;
        if value <= tol {
            Some(true)
        } else {
            (value > tol * GREY).then_some(false)
        }
    };
    // Per rigid contact: its common omega on the basis, then on the errors.
    let mut field: Vec<Option<Vec<f64>>> = vec![None; graph.n_edges()];
    let split = 3 * kernel.basis.len();
    for (e, slot) in field.iter_mut().enumerate() {
        let [a, b] = graph.edges()[e];
        let Some(c) = ContactMotion::new(parts, real, e, [a, b]) else {
            continue;
        };
        let sin = dot(c.n, c.n).sqrt();
        let vectors = kernel.basis.iter().map(|&x| (1.0, x));
        let mut offs = [Vec::new(), Vec::new()];
        let mut key = Vec::with_capacity(split + 3 * kernel.errors.len());
        for (k, (w, x)) in vectors.chain(kernel.errors.iter().copied()).enumerate() {
            let (off, common) = c.relative(x);
            offs[usize::from(k >= kernel.basis.len())].push(w * off / sin);
            key.extend(scale(common, w));
        }
        match zero(norm(&offs[0]), norm(&offs[1])) {
            Some(true) => *slot = Some(key),
            Some(false) => {}
            None => return unclear(format!("whether rods {a} and {b} move as one")),
        }
    }
    let mut grey = None;
    let out = group(
        topo,
        |e| field[e].is_some(),
        |e, f| {
            let (ke, kf) = (
                field[e].as_ref().expect("rigid"),
                field[f].as_ref().expect("rigid"),
            );
            let diff: Vec<f64> = ke.iter().zip(kf).map(|(x, y)| x - y).collect();
            let verdict = zero(norm(&diff[..split]), norm(&diff[split..]));
            if verdict.is_none() {
                grey = Some((e, f));
            }
            verdict == Some(true)
        },
    );
    match grey {
        Some((e, f)) => unclear(format!(
            "whether contacts {e} and {f} lie in one rigid cluster"
        )),
        None => Ok(out),
    }
}

/// The two angular velocities at one contact between active rods, the
/// lines' directions `da`, `db` and `n = da x db`.
struct ContactMotion<S> {
    pa: u32,
    pb: u32,
    da: V3<S>,
    db: V3<S>,
    n: V3<S>,
    inv: S,
}

impl<S: Scalar> ContactMotion<S> {
    /// `None` for a contact not between active rods, or between parallel lines.
    fn new(parts: &Parts, real: &Realization<S>, e: usize, [a, b]: [u32; 2]) -> Option<Self> {
        let ((pa, _), (pb, _), _) = parts.contact(real, e, [a, b])?;
        let da = real.lines[a as usize]?.d;
        let db = real.lines[b as usize]?.d;
        let n = cross(da, db);
        let inv = dot(n, n).recip()?;
        Some(ContactMotion {
            pa,
            pb,
            da,
            db,
            n,
            inv,
        })
    }

    /// For the motion `x`: `(omega_b - omega_a) . n`, zero exactly when the
    /// two rods move as one (`omega_a + alpha da = omega_b + beta db` has a
    /// solution), and that common `omega_a + alpha da`.
    fn relative(&self, x: &[S]) -> (S, V3<S>) {
        let omega = |part: u32| {
            let b = part as usize * WIDTH;
            [x[b], x[b + 1], x[b + 2]]
        };
        let (wa, wb) = (omega(self.pa), omega(self.pb));
        let delta = sub(wb, wa);
        let alpha = dot(cross(delta, self.db), self.n) * self.inv;
        (dot(delta, self.n), add(wa, scale(self.da, alpha)))
    }
}

/// The clusters of the contacts `rigid` marks: two on one rod join when
/// `same` says they move alike. Sorted as [`clusters`] returns them.
fn group(
    topo: &Topology,
    rigid: impl Fn(usize) -> bool,
    mut same: impl FnMut(usize, usize) -> bool,
) -> Vec<Vec<u32>> {
    let graph = topo.graph;
    let mut uf: UnionFind<u32> = UnionFind::new(graph.n_edges());
    let mut firsts: Vec<u32> = Vec::new();
    for r in 0..graph.n_nodes() as u32 {
        // The first contact of each distinct motion met so far on this rod.
        firsts.clear();
        for &(_, e) in graph.neighbors(r) {
            if !rigid(e as usize) {
                continue;
            }
            match firsts.iter().find(|&&f| same(f as usize, e as usize)) {
                Some(&f) => {
                    uf.union(f, e);
                }
                None => firsts.push(e),
            }
        }
    }
    let mut groups: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        if rigid(e) {
            let g = groups.entry(uf.find(e as u32)).or_default();
            g.push(a);
            g.push(b);
        }
    }
    let mut out: Vec<Vec<u32>> = groups
        .into_values()
        .map(|mut rods| {
            rods.sort_unstable();
            rods.dedup();
            rods
        })
        .collect();
    out.sort_by(|a, b| b.len().cmp(&a.len()).then(a.cmp(b)));
    out
}
