//! Families of realizations and their components (MODEL §3): the Jacobian
//! of the incidence constraints, a family's dimension against that of all
//! realizations at its sample, and the groupings explored from the forced one.

use serde::Serialize;
use std::collections::BTreeSet;

use super::construction::{Infeasible, Realization, construct};
use super::incidence::{Grouping, Incidence, body_planes};
use crate::math::vec3::{V3, cross, is_null, size, sub};
use crate::math::{Fp, Matrix, Scalar, rank_fp};

/// The Jacobian of the incidence constraints at a sample: collinearity of
/// the contacts of each line, and coplanarity of the contacts of each group
/// in `planes`. Columns: three per contact point.
pub fn jacobian<S: Scalar>(
    inc: &Incidence,
    planes: &[BTreeSet<usize>],
    points: &[V3<S>],
) -> Matrix<S> {
    let mut j = Matrix::zeros(0, 3 * points.len());
    let skew = |v: V3<S>| -> [[S; 3]; 3] {
        let z = S::zero();
        [[z, -v[2], v[1]], [v[2], z, -v[0]], [-v[1], v[0], z]]
    };
    for cs in &inc.line_contacts {
        if cs.len() < 3 {
            continue;
        }
        let (q1, q2) = (cs[0], cs[1]);
        let b = sub(points[q2], points[q1]);
        for &qj in &cs[2..] {
            // f = (qj - q1) x (q2 - q1)
            let a = sub(points[qj], points[q1]);
            let (sb, sa) = (skew(b), skew(a));
            for r in 0..3 {
                let row = j.push_row();
                for k in 0..3 {
                    j.add_to(row, 3 * qj + k, -sb[r][k]);
                    j.add_to(row, 3 * q2 + k, sa[r][k]);
                    j.add_to(row, 3 * q1 + k, sb[r][k] - sa[r][k]);
                }
            }
        }
    }
    for g in planes {
        let cs = inc.group_contacts(g);
        let Some((r1, r2, r3)) = base_triangle(&cs, points) else {
            continue;
        };
        let (a, b) = (sub(points[r2], points[r1]), sub(points[r3], points[r1]));
        let n = cross(a, b);
        for &rj in &cs {
            if rj == r1 || rj == r2 || rj == r3 {
                continue;
            }
            // g = ((r2 - r1) x (r3 - r1)) . (rj - r1)
            let w = sub(points[rj], points[r1]);
            let (d2, d3) = (cross(b, w), cross(w, a));
            let row = j.push_row();
            for k in 0..3 {
                j.add_to(row, 3 * r2 + k, d2[k]);
                j.add_to(row, 3 * r3 + k, d3[k]);
                j.add_to(row, 3 * rj + k, n[k]);
                j.add_to(row, 3 * r1 + k, -d2[k] - d3[k] - n[k]);
            }
        }
    }
    j
}

/// Three contacts of `cs` whose points are not collinear: over F_p the
/// first such, for floats the widest triangle on the first point (the
/// best-conditioned plane).
fn base_triangle<S: Scalar>(cs: &[usize], points: &[V3<S>]) -> Option<(usize, usize, usize)> {
    let r1 = *cs.first()?;
    let mut best: Option<(f64, (usize, usize, usize))> = None;
    for (i, &r2) in cs.iter().enumerate().skip(1) {
        for &r3 in &cs[i + 1..] {
            let n = cross(sub(points[r2], points[r1]), sub(points[r3], points[r1]));
            if is_null(n) {
                continue;
            }
            let area = size(n);
            if best.is_none_or(|(a, _)| area > a) {
                best = Some((area, (r1, r2, r3)));
            }
        }
    }
    best.map(|(_, t)| t)
}

/// Dimension of the realizations near a sample: `3C - rank J`.
pub fn local_dimension(inc: &Incidence, planes: &[BTreeSet<usize>], points: &[V3<Fp>]) -> usize {
    let j = jacobian(inc, planes, points);
    3 * points.len() - rank_fp(&j)
}

/// A family that was built, with its dimensions.
#[derive(Clone, Debug)]
pub struct Family {
    pub grouping: Grouping,
    /// Dimension of the family at its sample (nullity of its own constraints).
    pub dimension: usize,
    /// Dimension of all realizations at the same sample.
    pub ambient: usize,
    pub samples: Vec<Realization<Fp>>,
}

/// Summary of a family for reports.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct FamilyInfo {
    pub built: String,
    pub dimension: usize,
    /// Whether it is a component (not a special position of a larger family).
    pub component: bool,
}

/// Largest number of plane groupings explored per pattern.
pub const MAX_GROUPINGS: usize = 64;

/// Builds the realization families of a pattern: the forced grouping and
/// every grouping reachable from it by putting two touching groups or
/// constrained lines in one plane, plus the all-coplanar one, `samples`
/// independent realizations each. Returns the families and whether the
/// forced (most generic) grouping could be built.
pub fn families(inc: &Incidence, samples: usize, seed: u64) -> (Vec<Family>, bool) {
    let (built, forced_built) = realized(inc, samples, seed);
    let families = built
        .into_iter()
        .map(|(grouping, samples)| {
            let (dimension, ambient) = dimensions(inc, &grouping, &samples[0].points);
            Family {
                grouping,
                dimension,
                ambient,
                samples,
            }
        })
        .collect();
    (families, forced_built)
}

/// A family's dimension and that of all realizations at its sample.
pub(super) fn dimensions(
    inc: &Incidence,
    grouping: &Grouping,
    points: &[V3<Fp>],
) -> (usize, usize) {
    let base_planes = body_planes(inc);
    let ambient = local_dimension(inc, &base_planes, points);
    // The same constraints give the same Jacobian: a grouping of the
    // planar bodies alone is no more special than its realizations.
    let dimension = if grouping.groups == base_planes {
        ambient
    } else {
        local_dimension(inc, &grouping.groups, points)
    };
    (dimension, ambient)
}

/// A grouping that was built, with its samples.
pub(super) type Built = (Grouping, Vec<Realization<Fp>>);

/// The seed of sample `s` of the `k`-th grouping [`realized`] dequeues
/// (from 1).
fn sample_seed(seed: u64, k: usize, s: u64) -> u64 {
    seed.wrapping_add(1000 * k as u64 + s)
}

/// A grouping built by [`realized_first`]: its first sample, and where it
/// came in the queue, which seeds its later samples.
pub(super) struct FirstBuilt {
    pub grouping: Grouping,
    pub first: Realization<Fp>,
    k: usize,
}

impl FirstBuilt {
    /// Sample `s` of the grouping, the one [`realized`] would build.
    pub fn sample(
        &self,
        inc: &Incidence,
        seed: u64,
        s: u64,
    ) -> Result<Realization<Fp>, Infeasible> {
        construct(inc, &self.grouping, sample_seed(seed, self.k, s))
    }
}

/// The groupings [`families`] builds, with their samples but without their
/// dimensions (two ranks each, which a verdict needs only when more than one
/// family is built), and whether the forced grouping was built.
pub(super) fn realized(inc: &Incidence, samples: usize, seed: u64) -> (Vec<Built>, bool) {
    let (built, forced_built) = explore(inc, samples, seed);
    let built = built.into_iter().map(|(g, _, s)| (g, s)).collect();
    (built, forced_built)
}

/// [`realized`] with only the first sample of each grouping built: a grouping
/// counts as built when its first sample is. A construction order either
/// fails for every draw or for a set of draws of probability about
/// `degree / p` (Schwartz–Zippel), so when the first sample is built the
/// later ones are too, but for that chance; a verdict whose first sample is
/// rigid never needs them.
pub(super) fn realized_first(inc: &Incidence, seed: u64) -> (Vec<FirstBuilt>, bool) {
    let (built, forced_built) = explore(inc, 1, seed);
    let built = built
        .into_iter()
        .map(|(grouping, k, mut samples)| FirstBuilt {
            grouping,
            first: samples.swap_remove(0),
            k,
        })
        .collect();
    (built, forced_built)
}

/// A grouping [`explore`] built, its index in the queue and its samples.
type Explored = (Grouping, usize, Vec<Realization<Fp>>);

/// The exploration of [`realized`]: each grouping built, with its index in
/// the queue and `samples` samples.
fn explore(inc: &Incidence, samples: usize, seed: u64) -> (Vec<Explored>, bool) {
    let forced = Grouping::forced(inc);
    let mut queue = vec![forced.clone()];
    let all = Grouping::all_coplanar(inc).close(inc);
    if all != forced {
        queue.push(all);
    }
    let mut seen: BTreeSet<Grouping> = queue.iter().cloned().collect();
    let mut built: BTreeSet<Grouping> = BTreeSet::new();
    let mut out = Vec::new();
    let mut forced_built = false;
    let mut k = 0;
    while k < queue.len() && k < MAX_GROUPINGS {
        let grouping = queue[k].clone();
        k += 1;
        let attempt: Result<Vec<Realization<Fp>>, Infeasible> =
            if built.insert(grouping.effective(inc)) {
                (0..samples as u64)
                    .map(|s| construct(inc, &grouping, sample_seed(seed, k, s)))
                    .collect()
            } else {
                Err(Infeasible::NoOrder)
            };
        if let Ok(samples) = attempt {
            if grouping == forced {
                forced_built = true;
            }
            out.push((grouping.clone(), k, samples));
        }
        // Blocks that can share a plane: groups, and lines with three or more contacts.
        let mut blocks: Vec<BTreeSet<usize>> = grouping.groups.clone();
        blocks.extend(
            (0..inc.n_lines())
                .filter(|&l| !grouping.in_group(l) && inc.line_contacts[l].len() >= 3)
                .map(|l| BTreeSet::from([l])),
        );
        for i in 0..blocks.len() {
            for j in i + 1..blocks.len() {
                let touching = blocks[i].iter().any(|&a| {
                    blocks[j].contains(&a) || inc.touching(a).any(|b| blocks[j].contains(&b))
                });
                if !touching {
                    continue;
                }
                let mut groups: Vec<BTreeSet<usize>> = grouping
                    .groups
                    .iter()
                    .filter(|g| **g != blocks[i] && **g != blocks[j])
                    .cloned()
                    .collect();
                groups.push(blocks[i].union(&blocks[j]).copied().collect());
                let merged = Grouping { groups }.close(inc);
                if seen.insert(merged.clone()) {
                    queue.push(merged);
                }
            }
        }
    }
    (out, forced_built)
}

/// Whether each family is a component: its sample has no more realization
/// directions than the family itself, or no larger family was found.
pub fn components(families: &[Family]) -> Vec<bool> {
    let dims: Vec<(usize, usize)> = families.iter().map(|f| (f.dimension, f.ambient)).collect();
    components_by_dimension(&dims)
}

/// [`components`] from each family's `(dimension, ambient)`: the same rule
/// for families with a projected float sample, which have no [`Family`].
pub fn components_by_dimension(dims: &[(usize, usize)]) -> Vec<bool> {
    let largest = dims.iter().map(|d| d.0).max().unwrap_or(0);
    dims.iter()
        .map(|&(dimension, ambient)| ambient == dimension || dimension >= largest)
        .collect()
}
