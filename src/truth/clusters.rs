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

use petgraph::unionfind::UnionFind;
use rustc_hash::FxHashMap;

use super::Topology;
use super::matrix::{Parts, WIDTH};
use super::realize::Realization;
use crate::math::Fp;
use crate::math::vec3::{V3, add, cross, dot, scale, sub};

/// The rigid clusters of two or more rods, each sorted, largest first (ties
/// by smallest rod).
pub fn clusters(
    topo: &Topology,
    parts: &Parts,
    real: &Realization,
    kernel: &[Vec<Fp>],
) -> Vec<Vec<u32>> {
    let graph = topo.graph;
    let omega = |x: &[Fp], part: u32| -> V3<Fp> {
        let b = part as usize * WIDTH;
        [x[b], x[b + 1], x[b + 2]]
    };
    // The common omega of each contact whose rods move as one, per kernel vector.
    let mut field: Vec<Option<Vec<Fp>>> = vec![None; graph.n_edges()];
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        let Some(((pa, _), (pb, _), _)) = parts.contact(real, e, [a, b]) else {
            continue;
        };
        let da = real.lines[a as usize].expect("placed").d;
        let db = real.lines[b as usize].expect("placed").d;
        let n = cross(da, db);
        let Some(inv) = dot(n, n).inv() else { continue };
        let mut key = Vec::with_capacity(3 * kernel.len());
        let mut rigid = true;
        for x in kernel {
            let (wa, wb) = (omega(x, pa), omega(x, pb));
            // wa + alpha da = wb + beta db has a solution iff wb - wa _|_ da x db.
            let delta = sub(wb, wa);
            if !dot(delta, n).is_zero() {
                rigid = false;
                break;
            }
            let alpha = dot(cross(delta, db), n) * inv;
            key.extend(add(wa, scale(da, alpha)));
        }
        if rigid {
            field[e] = Some(key);
        }
    }
    let mut uf: UnionFind<u32> = UnionFind::new(graph.n_edges());
    let mut seen: FxHashMap<&[Fp], u32> = FxHashMap::default();
    for r in 0..graph.n_nodes() as u32 {
        seen.clear();
        for &(_, e) in graph.neighbors(r) {
            if let Some(key) = &field[e as usize] {
                match seen.get(key.as_slice()) {
                    Some(&first) => {
                        uf.union(first, e);
                    }
                    None => {
                        seen.insert(key.as_slice(), e);
                    }
                }
            }
        }
    }
    let mut groups: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        if field[e].is_some() {
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
