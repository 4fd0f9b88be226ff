//! A rod system with its contacts detected: the rods, the contacts, the
//! contact graph and each contact's periodic image, built once where
//! everything that analyses a whole system (sampling, truth, mining, the
//! forced planes, the benches) used to rebuild the triple itself.

use crate::contacts::{self, Contact, Offset};
use crate::graph::{ContactGraph, Topology};
use crate::rods::RodSystem;

/// A system and what touches what in it.
#[derive(Clone, Debug)]
pub struct Network {
    pub system: RodSystem,
    pub contacts: Vec<Contact>,
    pub graph: ContactGraph,
    /// Per contact (edge), the image of its second rod that the first touches.
    pub shifts: Vec<Offset>,
}

impl Network {
    /// Detects the contacts of `system` (the O(N) grid).
    pub fn detect(system: RodSystem) -> Self {
        let contacts = contacts::detect(&system);
        let graph = ContactGraph::from_contacts(system.len(), &contacts);
        let shifts = contacts.iter().map(|c| c.shift).collect();
        Network {
            system,
            contacts,
            graph,
            shifts,
        }
    }

    /// The borrowed form the analyses take.
    pub fn view(&self) -> View<'_> {
        View {
            system: &self.system,
            contacts: &self.contacts,
            graph: &self.graph,
            shifts: &self.shifts,
        }
    }

    /// The graph with each contact's image in the system's box.
    pub fn topology(&self) -> Topology<'_> {
        self.view().topology()
    }
}

/// A system with contacts, borrowed: a whole [`Network`], or the first `n`
/// rods of a sequence with their contacts (a prefix of one sorted list).
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    pub system: &'a RodSystem,
    pub contacts: &'a [Contact],
    pub graph: &'a ContactGraph,
    pub shifts: &'a [Offset],
}

impl<'a> View<'a> {
    /// Periodic along some axis, or a finite framework when every side is a wall.
    pub fn topology(&self) -> Topology<'a> {
        Topology::of_domain(self.graph, self.shifts, &self.system.domain)
    }
}
