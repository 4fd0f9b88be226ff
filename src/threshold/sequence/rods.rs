//! One Monte Carlo sequence (MODEL §8): the seeded random rods of a box in
//! their order, whose first `n` rods are the `n`-rod system, with their
//! contacts, grown on demand; where it first spans by contacts (one
//! union-find sweep) and its contact numbers.

use crate::Result;
use crate::contacts::{self, Contact, Offset};
use crate::graph::{self, ContactGraph};
use crate::network::View;
use crate::rods::{RodParams, RodSystem};
use crate::spanning::{self, Criterion};
use crate::threshold::fss::ContactPoint;

/// A sequence's rods and contacts, grown on demand: the first `n` rods of
/// the sequence are the `n`-rod system of its seed, and their contacts are a
/// prefix of `contacts` (sorted by the later rod).
pub struct Sequence {
    pub system: RodSystem,
    pub contacts: Vec<Contact>,
    /// Each contact's image, in the order of `contacts`.
    shifts: Vec<Offset>,
    /// `ends[n]`: how many contacts the first `n` rods have among themselves.
    ends: Vec<usize>,
    pub(super) params: RodParams,
    pub(super) seed: u64,
}

impl Sequence {
    /// The first `n` rods of the sequence seeded with `seed`.
    pub fn new(gamma: f64, box_len: f64, n: usize, seed: u64) -> Result<Self> {
        let params = RodParams::new(gamma, box_len, n.max(1) as f64 / box_len.powi(3))?;
        let system = RodSystem::generate(params, seed);
        debug_assert_eq!(system.len(), n.max(1));
        let mut contacts = contacts::detect(&system);
        spanning::sort_by_sequence(&mut contacts);
        let mut ends = vec![0; system.len() + 1];
        for c in &contacts {
            ends[c.rods[1] as usize + 1] += 1;
        }
        for n in 1..ends.len() {
            ends[n] += ends[n - 1];
        }
        let shifts = contacts.iter().map(|c| c.shift).collect();
        Ok(Sequence {
            system,
            contacts,
            shifts,
            ends,
            params,
            seed,
        })
    }

    /// Rods generated so far.
    pub fn len(&self) -> usize {
        self.system.len()
    }

    pub fn is_empty(&self) -> bool {
        self.system.is_empty()
    }

    /// Makes sure at least `n` rods exist (regenerating the longer sequence
    /// from the same seed, half again as long as asked, so growth is rare).
    pub fn reach(&mut self, n: usize) -> Result<()> {
        if n > self.len() {
            let p = self.params;
            *self = Sequence::new(p.gamma, p.box_len, n + n / 2, self.seed)?;
        }
        Ok(())
    }

    /// The contacts among the first `n` rods.
    pub fn contacts_of(&self, n: usize) -> &[Contact] {
        &self.contacts[..self.ends[n]]
    }

    /// The contact graph of the first `n` rods.
    pub fn graph(&self, n: usize) -> ContactGraph {
        ContactGraph::from_contacts(n, self.contacts_of(n))
    }

    /// The first `n` rods with their contacts, `graph` being theirs
    /// ([`Sequence::graph`]).
    pub fn view<'a>(&'a self, n: usize, graph: &'a ContactGraph) -> View<'a> {
        debug_assert_eq!(graph.n_nodes(), n, "the graph of the first n rods");
        View {
            system: &self.system,
            contacts: self.contacts_of(n),
            graph,
            shifts: &self.shifts[..self.ends[n]],
        }
    }

    /// Rods at which the sequence first spans by contacts, generating more
    /// rods until it does. Under `Solid`, the first that wraps
    /// ([`Criterion::of_clusters`]): a contact network must wrap to be a
    /// solid, so a solid truth study bisects from there.
    pub fn contact_critical(&mut self, criterion: Criterion) -> Result<usize> {
        loop {
            if let Some(n) = spanning::critical_rods(&self.system, &self.contacts, criterion) {
                return Ok(n);
            }
            self.reach(2 * self.len())?;
        }
    }

    /// Contact numbers of the first `n` rods.
    pub fn contact_point(&self, n: usize) -> ContactPoint {
        let s = graph::stats(&self.graph(n));
        ContactPoint {
            density: n as f64 / self.params.box_len.powi(3),
            c0: s.c0,
            c1: s.c1,
            c2: s.c2,
        }
    }
}
