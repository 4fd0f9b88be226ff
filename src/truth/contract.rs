//! The second twin's check on a smaller matrix (MODEL §10): the first
//! twin's rigid clusters, each contracted to one part.
//!
//! The rods of a rigid cluster move as one body up to their spins, so in
//! every kernel vector a rod part's columns are the body's motion, seen from
//! the rod's frame, plus a multiple of its spin. Replacing them by the
//! body's six columns and dropping the rods' spin rows (which only fix
//! those multiples) leaves the kernel's dimension as it was. Above the
//! threshold a cluster holds a large share of the rods, and the contracted
//! matrix is a small part of the whole.
//!
//! Only rods that are parts of their own are contracted: a plane class can
//! turn about a rod it shares with a cluster, so it stays a part. A cluster
//! whose rods touch one another only through classes becomes one body per
//! piece that touches directly, and a rod already in a body (a hinge between
//! two clusters) stays in the first: any subset of a cluster moves as one.

use std::collections::VecDeque;

use super::matrix::{Parts, WIDTH};
use super::realize::Realization;
use crate::contacts::Offset;
use crate::graph::Topology;
use crate::math::Field;
use crate::math::sparse::SparseRow;
use crate::math::vec3::cross;

/// Old parts mapped to new ones: each body of contracted rod parts is one.
#[derive(Clone, Debug)]
pub struct Contraction {
    /// Per old part: its new part, and for a rod in a body its frame's
    /// offset in the body's frame.
    map: Vec<(u32, Option<Offset>)>,
    /// Parts after contraction.
    pub count: usize,
    /// Bodies of two or more rods.
    pub bodies: usize,
    /// Rods whose frame lies at another image than their body's.
    pub crossing: usize,
}

/// The bodies `clusters` (rods, largest first) give, over the parts `parts`.
pub fn of_clusters(topo: &Topology, parts: &Parts, clusters: &[Vec<u32>]) -> Contraction {
    const NONE: u32 = u32::MAX;
    let graph = topo.graph;
    // The rod of each rod part, and each part's body once it has one.
    let mut rod_of = vec![NONE; parts.count];
    for (r, owner) in parts.owner.iter().enumerate() {
        if let Some((p, _)) = *owner
            && p as usize >= parts.classes
        {
            rod_of[p as usize] = r as u32;
        }
    }
    let part = |r: u32| {
        parts.owner[r as usize]
            .map(|(p, _)| p)
            .filter(|&p| p as usize >= parts.classes)
    };
    let mut body = vec![NONE; parts.count];
    let mut shift: Vec<Offset> = vec![[0; 3]; parts.count];
    // Which cluster last claimed a part, to walk one cluster at a time.
    let mut claimed = vec![NONE; parts.count];
    let mut bodies = 0u32;
    let mut queue = VecDeque::new();
    for (k, cluster) in clusters.iter().enumerate() {
        let k = k as u32;
        for &r in cluster {
            if let Some(p) = part(r)
                && body[p as usize] == NONE
            {
                claimed[p as usize] = k;
            }
        }
        for &r in cluster {
            let Some(start) = part(r) else { continue };
            if claimed[start as usize] != k || body[start as usize] != NONE {
                continue;
            }
            let mut piece = vec![start];
            body[start as usize] = bodies;
            shift[start as usize] = [0; 3];
            queue.push_back(start);
            while let Some(p) = queue.pop_front() {
                let rod = rod_of[p as usize];
                for &(other, e) in graph.neighbors(rod) {
                    let Some(q) = part(other) else { continue };
                    if claimed[q as usize] != k || body[q as usize] != NONE {
                        continue;
                    }
                    // The contact point in the rod's frame, less the seen
                    // offset, is the point in the other's frame.
                    let seen = topo.seen(e, rod);
                    let s = shift[p as usize];
                    shift[q as usize] = [s[0] - seen[0], s[1] - seen[1], s[2] - seen[2]];
                    body[q as usize] = bodies;
                    piece.push(q);
                    queue.push_back(q);
                }
            }
            if piece.len() < 2 {
                body[start as usize] = NONE;
            } else {
                bodies += 1;
            }
        }
    }
    // New parts in the order of their first old part.
    let mut first = vec![NONE; bodies as usize];
    let mut count = 0u32;
    let map = (0..parts.count)
        .map(|p| match body[p] {
            NONE => {
                count += 1;
                (count - 1, None)
            }
            b => {
                if first[b as usize] == NONE {
                    first[b as usize] = count;
                    count += 1;
                }
                (first[b as usize], Some(shift[p]))
            }
        })
        .collect();
    let crossing = (0..parts.count)
        .filter(|&p| body[p] != NONE && shift[p] != [0; 3])
        .count();
    Contraction {
        map,
        count: count as usize,
        bodies: bodies as usize,
        crossing,
    }
}

impl Contraction {
    /// The rows of the contracted matrix at `real` from those of the whole:
    /// a body's member `p` moves as `(omega, t - omega x S_p)` for the
    /// body's `(omega, t)` and the lattice vector `S_p` of its frame, so
    /// its coefficients `(c_omega, c_t)` become `(c_omega - S_p x c_t,
    /// c_t)`. The spin rows of contracted rods go, and rows left empty.
    pub fn rows<F: Field>(
        &self,
        real: &Realization<F>,
        rows: &[SparseRow<F>],
    ) -> Vec<SparseRow<F>> {
        let width = WIDTH as u32;
        let mut out = Vec::with_capacity(rows.len());
        let mut acc: Vec<(u32, [F; WIDTH])> = Vec::new();
        for row in rows {
            let Some(&(c0, _)) = row.first() else {
                continue;
            };
            let p0 = c0 / width;
            let single = row.iter().all(|&(c, _)| c / width == p0);
            if single && self.map.get(p0 as usize).is_some_and(|m| m.1.is_some()) {
                continue;
            }
            acc.clear();
            for &(c, v) in row {
                let (p, j) = ((c / width) as usize, (c % width) as usize);
                // Strain columns, if any, are left out: the check is of the
                // fixed box's kernel.
                let Some(&(new, offset)) = self.map.get(p) else {
                    continue;
                };
                let slot = match acc.iter().position(|a| a.0 == new) {
                    Some(i) => i,
                    None => {
                        acc.push((new, [F::zero(); WIDTH]));
                        acc.len() - 1
                    }
                };
                let coef = &mut acc[slot].1;
                coef[j] = coef[j] + v;
                if let (Some(o), true) = (offset, j >= 3) {
                    let mut unit = [F::zero(); 3];
                    unit[j - 3] = v;
                    let turn = cross(real.lattice(o), unit);
                    for k in 0..3 {
                        coef[k] = coef[k] - turn[k];
                    }
                }
            }
            acc.sort_unstable_by_key(|a| a.0);
            let contracted: SparseRow<F> = acc
                .iter()
                .flat_map(|&(p, coef)| {
                    coef.into_iter()
                        .enumerate()
                        .filter(|(_, v)| *v != F::zero())
                        .map(move |(j, v)| (p * width + j as u32, v))
                })
                .collect();
            if !contracted.is_empty() {
                out.push(contracted);
            }
        }
        out
    }
}
