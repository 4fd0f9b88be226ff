//! The topology of a system: its contact graph and, in a periodic box, the
//! image at which each contact is made. Every step of truth reads it.

use super::adjacency::ContactGraph;
use crate::contacts::Offset;
use crate::rods::{Domain, Periodic};
use crate::{Error, Result};

/// The contacts of a system, and for a periodic box the image of each.
#[derive(Clone, Copy, Debug)]
pub struct Topology<'a> {
    pub graph: &'a ContactGraph,
    /// Per edge `[a, b]`: `a` touches the image of `b` shifted by this many
    /// box sides. `None`: a finite framework (a graph read from a file).
    pub shifts: Option<&'a [Offset]>,
    /// Which axes are periodic (none for a finite framework): the box can
    /// be strained only along them (MODEL §10, the strain rank).
    pub periodic: [bool; 3],
}

impl<'a> Topology<'a> {
    /// A finite framework.
    pub fn finite(graph: &'a ContactGraph) -> Self {
        Topology {
            graph,
            shifts: None,
            periodic: [false; 3],
        }
    }

    /// A system periodic along every axis, in a fixed box.
    pub fn periodic(graph: &'a ContactGraph, shifts: &'a [Offset]) -> Result<Self> {
        if shifts.len() != graph.n_edges() {
            return Err(Error::Parameter(format!(
                "{} image shifts for {} contacts",
                shifts.len(),
                graph.n_edges()
            )));
        }
        Ok(Topology {
            graph,
            shifts: Some(shifts),
            periodic: [true; 3],
        })
    }

    /// The contacts of a system in `domain`: periodic along some axis, or a
    /// finite framework when every side is a wall (the walls hold nothing).
    pub fn of_domain(graph: &'a ContactGraph, shifts: &'a [Offset], domain: &Domain) -> Self {
        debug_assert_eq!(shifts.len(), graph.n_edges(), "one shift per contact");
        let periodic = domain.periodic != Periodic::None;
        Topology {
            graph,
            shifts: periodic.then_some(shifts),
            periodic: domain.periodic.axes(),
        }
    }

    /// The image offset at which rod `r` sees the other rod of edge `e`.
    pub fn seen(&self, e: u32, r: u32) -> Offset {
        let Some(shifts) = self.shifts else {
            return [0; 3];
        };
        let s = shifts[e as usize];
        if self.graph.edges()[e as usize][0] == r {
            s
        } else {
            s.map(|k| -k)
        }
    }

    /// Rigid motions of the whole system that are no deformation: 6 for a
    /// finite framework (5 for a lone rod, which has no spin), 3
    /// translations in a fixed periodic box.
    pub fn trivial_motions(&self) -> usize {
        match (self.shifts, self.graph.n_nodes()) {
            (_, 0) => 0,
            (Some(_), _) => 3,
            (None, 1) => 5,
            (None, _) => 6,
        }
    }
}
