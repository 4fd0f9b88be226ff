//! The order in which a whole system can be built exactly (MODEL §10).
//!
//! Every step of the construction must be rational, so each new line may be
//! held by only as much as a rational choice can satisfy:
//! * in no placed plane: it meets at most 3 placed lines (0: anywhere;
//!   1: through a point of it; 2: through a point of each; 3: through a
//!   point of the first, meeting the other two);
//! * in one placed plane: it meets at most 2 placed lines outside that
//!   plane, through the points where they cross it (lines inside a plane
//!   meet anyway);
//! * in two placed planes: it is their intersection, and meets no placed
//!   line outside them.
//!
//! A plane is placed with its first line, as a random plane through it
//! (unless it wraps the box twice: then its direction is fixed and it is
//! placed from the start). Placing more lines first only adds conditions,
//! so a line that can be placed last can be removed for good: peeling such
//! lines greedily finds a construction order whenever one exists.

use super::planes::Planes;
use crate::graph::Topology;

/// The rods no construction order reaches: every one of them is held by
/// more placed lines than a rational step can satisfy.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stuck {
    pub rods: Vec<u32>,
}

/// Whether a class's plane is placed before any of its lines.
pub fn preplaced(planes: &Planes, class: u32) -> bool {
    planes.classes[class as usize].wraps.len() == 2
}

/// A construction order of the `active` rods, or the rods left when peeling stops.
pub fn order(topo: &Topology, planes: &Planes, active: &[bool]) -> Result<Vec<u32>, Stuck> {
    let graph = topo.graph;
    let n = graph.n_nodes();
    let mut remaining = active.to_vec();
    // Placed lines outside a shared plane that each rod would have to meet.
    let mut held = vec![0usize; n];
    for (e, &[a, b]) in graph.edges().iter().enumerate() {
        if active[a as usize] && active[b as usize] && planes.inside[e].is_none() {
            held[a as usize] += 1;
            held[b as usize] += 1;
        }
    }
    let mut in_class: Vec<usize> = planes.classes.iter().map(|c| c.rods.len()).collect();
    // Placed planes holding each rod.
    let mut placed_planes: Vec<usize> = planes
        .of_rod
        .iter()
        .map(|classes| {
            classes
                .iter()
                .filter(|&&(c, _)| preplaced(planes, c) || in_class[c as usize] >= 2)
                .count()
        })
        .collect();
    let placeable = |r: usize, held: &[usize], placed: &[usize]| match placed[r] {
        0 => held[r] <= 3,
        1 => held[r] <= 2,
        2 => held[r] == 0,
        _ => false,
    };
    let mut stack: Vec<u32> = (0..n as u32)
        .rev()
        .filter(|&r| active[r as usize] && placeable(r as usize, &held, &placed_planes))
        .collect();
    let mut peeled = Vec::with_capacity(n);
    while let Some(r) = stack.pop() {
        let ri = r as usize;
        if !remaining[ri] || !placeable(ri, &held, &placed_planes) {
            continue;
        }
        remaining[ri] = false;
        peeled.push(r);
        for &(m, e) in graph.neighbors(r) {
            let mi = m as usize;
            if remaining[mi] && planes.inside[e as usize].is_none() {
                held[mi] -= 1;
                if placeable(mi, &held, &placed_planes) {
                    stack.push(m);
                }
            }
        }
        for &(c, _) in &planes.of_rod[ri] {
            in_class[c as usize] -= 1;
            if in_class[c as usize] == 1 && !preplaced(planes, c) {
                let last = planes.classes[c as usize]
                    .rods
                    .iter()
                    .map(|&(m, _)| m)
                    .find(|&m| remaining[m as usize])
                    .expect("one member remains");
                placed_planes[last as usize] -= 1;
                if placeable(last as usize, &held, &placed_planes) {
                    stack.push(last);
                }
            }
        }
    }
    let stuck: Vec<u32> = (0..n as u32).filter(|&r| remaining[r as usize]).collect();
    if stuck.is_empty() {
        peeled.reverse();
        Ok(peeled)
    } else {
        Err(Stuck { rods: stuck })
    }
}
