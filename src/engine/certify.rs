//! Certified compression (MODEL §10): the `sound` rules, then every body
//! checked against the exact truth of the whole graph.
//!
//! Local motifs can be forced into a flexible special position by rods far
//! outside them, so no rule set is sound on whole graphs by itself. Truth is
//! exact, and each body is kept only where it lies inside one true rigid
//! cluster; a body truth refutes is split into its parts inside the true
//! clusters (disjoint: a hinge rod goes to the larger part, and a subset of
//! a cluster is still mutually rigid). A certified body, and so a certified
//! spanning verdict, is never false.
//!
//! Truth must be taken on the system's own topology: for a generated
//! system, the fixed periodic box with each contact's image. The contact
//! graph alone, as a finite framework, closes every loop through the box
//! on itself; that is no realization of the box, and on a committed
//! sequence it makes a cluster span that does not span in the box (a test
//! keeps that case).

use rustc_hash::FxHashMap;

use super::compression::Compression;
use crate::body::Body;
use crate::truth::{self, Topology, TruthOptions};

/// Keeps the bodies of `run` (a `sound` compression of `topo`'s graph) that
/// truth confirms and splits the others along the true clusters. When truth
/// is undecided, or decided only in floats (whose gap is evidence, not
/// proof), nothing is certified: every body is dropped.
pub fn certify(topo: &Topology, mut run: Compression, seed: u64) -> Compression {
    let graph = topo.graph;
    // One realization proves what it finds rigid, and certification only
    // needs that; nor does it need the strains.
    let opts = TruthOptions {
        realizations: 1,
        strain: false,
        ..TruthOptions::seeded(seed)
    };
    let t = truth::truth(topo, opts);
    let mut bodies: Vec<Body> = Vec::with_capacity(run.bodies.len());
    let mut refuted = 0;
    if t.outcome.decision() == truth::Decision::Exact {
        let mut clusters_of: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
        for (k, c) in t.clusters.iter().enumerate() {
            for &r in &c.rods {
                clusters_of.entry(r).or_default().push(k as u32);
            }
        }
        for body in run.bodies.drain(..) {
            let mut parts: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
            for &r in &body.rods {
                for &k in clusters_of.get(&r).map_or(&[][..], Vec::as_slice) {
                    parts.entry(k).or_default().push(r);
                }
            }
            if parts.values().any(|p| p.len() == body.rods.len()) {
                bodies.push(body);
                continue;
            }
            refuted += 1;
            let mut parts: Vec<Vec<u32>> = parts.into_values().filter(|p| p.len() >= 2).collect();
            parts.sort_by(|a, b| b.len().cmp(&a.len()).then(a.cmp(b)));
            let mut taken: Vec<u32> = Vec::new();
            for mut p in parts {
                p.retain(|r| !taken.contains(r));
                if p.len() >= 2 {
                    taken.extend(&p);
                    bodies.push(Body::new(p, body.class));
                }
            }
        }
    } else {
        refuted = run.bodies.len();
        run.undecided = true;
    }
    bodies.sort_by(|a, b| {
        b.rods
            .len()
            .cmp(&a.rods.len())
            .then(a.rods[0].cmp(&b.rods[0]))
    });
    let in_bodies: usize = bodies.iter().map(|b| b.rods.len()).sum();
    run.components = bodies.len() + graph.n_nodes() - in_bodies;
    run.bodies = bodies;
    run.refuted = refuted;
    run
}
