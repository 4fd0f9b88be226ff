//! Whether a cluster of rods spans the periodic box (DESIGN §1).
//!
//! A periodic box has no walls, so "spanning" needs a definition; both in use
//! give the same threshold as `L -> inf` and different finite-size curves, so
//! every result must say which one it used.

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use crate::contacts::{Contact, ContactGraph};
use crate::rods::RodSystem;

/// Which definition of spanning to use.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Criterion {
    /// A cluster spans if it connects a rod to one of its own periodic images:
    /// following its contacts with unwrapped image offsets reaches some rod
    /// twice at different offsets. Natural for periodic boxes.
    #[default]
    Wrap,
    /// The paper's wording, "contacts both system boundaries along one
    /// dimension", in the primary cell: for some axis `d`, a rod poking out of
    /// the face `x_d = 0` (`center_d - |axis_d| / 2 - r < 0`) and a rod poking
    /// out of `x_d = L` are joined by contacts of the cluster that do not
    /// cross the periodic boundary along `d`. (Were they allowed to, any two
    /// touching rods straddling a face would span, and the spanning
    /// probability would tend to 1 at every density as `L` grows.)
    Faces,
}

/// Whether the cluster made of `rods` spans, using only contacts with both
/// ends in `rods`. `graph` must be `ContactGraph::from_contacts(system.len(),
/// contacts)`, so that graph edge `k` is `contacts[k]`. The internal contacts
/// may split the rods into several pieces; the cluster spans if one of them does.
///
/// Costs O(size of the cluster + the contacts of its rods); for many calls,
/// [`SpanChecker`] reuses its buffers.
pub fn cluster_spans(
    system: &RodSystem,
    contacts: &[Contact],
    graph: &ContactGraph,
    rods: &[u32],
    criterion: Criterion,
) -> bool {
    SpanChecker::new().spans(system, contacts, graph, rods, criterion)
}

/// Scratch space for [`cluster_spans`], sized by the cluster rather than by
/// the system, so that testing many small bodies costs only their own size.
#[derive(Clone, Debug, Default)]
pub struct SpanChecker {
    /// Position of each member rod in the `rods` slice being tested.
    slot: FxHashMap<u32, u32>,
    /// Unwrapped image offset of each member, once reached.
    offset: Vec<Option<[i32; 3]>>,
    /// Faces test: each member's faces and whether it is reached yet.
    members: Vec<Member>,
    stack: Vec<u32>,
}

/// What the faces test needs to know about one rod.
#[derive(Clone, Copy, Debug, Default)]
struct Member {
    /// Pokes out of the face `x_d = 0`, resp. `x_d = L`.
    low: [bool; 3],
    high: [bool; 3],
    /// Image of the box holding the stored center (`center = wrapped + image * L`).
    image: [i32; 3],
    reached: bool,
}

impl Member {
    fn of(system: &RodSystem, rod: u32) -> Self {
        let mut m = Member::default();
        let Some(rod) = system.rods.get(rod as usize) else {
            return m;
        };
        let l = system.box_len();
        let r = system.radius();
        for d in 0..3 {
            let image = (rod.center[d] / l).floor();
            let c = rod.center[d] - image * l;
            let reach = 0.5 * rod.axis[d].abs() + r;
            m.low[d] = c - reach < 0.0;
            m.high[d] = c + reach > l;
            m.image[d] = image as i32;
        }
        m
    }
}

impl SpanChecker {
    pub fn new() -> Self {
        Self::default()
    }

    /// Same as [`cluster_spans`], reusing this checker's buffers.
    pub fn spans(
        &mut self,
        system: &RodSystem,
        contacts: &[Contact],
        graph: &ContactGraph,
        rods: &[u32],
        criterion: Criterion,
    ) -> bool {
        match criterion {
            Criterion::Wrap => self.wraps(contacts, graph, rods),
            Criterion::Faces => self.faces(system, contacts, graph, rods),
        }
    }

    fn index(&mut self, rods: &[u32]) {
        self.slot.clear();
        self.slot
            .extend(rods.iter().enumerate().map(|(k, &r)| (r, k as u32)));
    }

    fn faces(
        &mut self,
        system: &RodSystem,
        contacts: &[Contact],
        graph: &ContactGraph,
        rods: &[u32],
    ) -> bool {
        debug_assert_eq!(
            graph.n_edges(),
            contacts.len(),
            "graph is not built from contacts"
        );
        self.index(rods);
        self.members.clear();
        self.members
            .extend(rods.iter().map(|&r| Member::of(system, r)));
        for d in 0..3 {
            let low = self.members.iter().any(|m| m.low[d]);
            let high = self.members.iter().any(|m| m.high[d]);
            if !(low && high) {
                continue;
            }
            for m in &mut self.members {
                m.reached = false;
            }
            for root in 0..rods.len() {
                if self.members[root].reached || (rods[root] as usize) >= graph.n_nodes() {
                    continue;
                }
                self.members[root].reached = true;
                self.stack.clear();
                self.stack.push(root as u32);
                let (mut low, mut high) = (false, false);
                while let Some(at) = self.stack.pop() {
                    let here = self.members[at as usize];
                    low |= here.low[d];
                    high |= here.high[d];
                    if low && high {
                        return true;
                    }
                    for &(nb, k) in graph.neighbors(rods[at as usize]) {
                        let Some(&nb_slot) = self.slot.get(&nb) else {
                            continue;
                        };
                        let Some(contact) = contacts.get(k as usize) else {
                            continue;
                        };
                        let there = &mut self.members[nb_slot as usize];
                        if there.reached || crosses(contact, rods[at as usize], &here, there, d) {
                            continue;
                        }
                        there.reached = true;
                        self.stack.push(nb_slot);
                    }
                }
            }
        }
        false
    }

    fn wraps(&mut self, contacts: &[Contact], graph: &ContactGraph, rods: &[u32]) -> bool {
        debug_assert_eq!(
            graph.n_edges(),
            contacts.len(),
            "graph is not built from contacts"
        );
        self.index(rods);
        self.offset.clear();
        self.offset.resize(rods.len(), None);
        for root in 0..rods.len() {
            if self.offset[root].is_some() || (rods[root] as usize) >= graph.n_nodes() {
                continue;
            }
            self.offset[root] = Some([0; 3]);
            self.stack.clear();
            self.stack.push(root as u32);
            while let Some(at) = self.stack.pop() {
                let rod = rods[at as usize];
                let Some(here) = self.offset[at as usize] else {
                    continue;
                };
                for &(nb, k) in graph.neighbors(rod) {
                    let Some(&nb_slot) = self.slot.get(&nb) else {
                        continue;
                    };
                    let Some(contact) = contacts.get(k as usize) else {
                        continue;
                    };
                    let want = step(here, rod, contact);
                    match self.offset[nb_slot as usize] {
                        Some(seen) if seen != want => return true,
                        Some(_) => {}
                        None => {
                            self.offset[nb_slot as usize] = Some(want);
                            self.stack.push(nb_slot);
                        }
                    }
                }
            }
        }
        false
    }
}

/// Image offset of the other rod of `contact`, reached from `rod` at offset `here`.
fn step(here: [i32; 3], rod: u32, contact: &Contact) -> [i32; 3] {
    // `contact.shift` is the image of rods[1] relative to rods[0].
    let sign = if contact.rods[0] == rod { 1 } else { -1 };
    std::array::from_fn(|d| here[d] + sign * contact.shift[d])
}

/// Whether `contact`, seen from `rod` (described by `here`) towards the rod
/// described by `there`, goes through the periodic boundary along axis `d`.
fn crosses(contact: &Contact, rod: u32, here: &Member, there: &Member, d: usize) -> bool {
    // `step` gives the image of the other rod's stored center; relative to
    // the wrapped centers it is offset by the two rods' own images.
    let stored = step([0; 3], rod, contact)[d];
    stored + there.image[d] - here.image[d] != 0
}

/// Whether any connected cluster of the contact graph spans; O(N + E).
pub fn contact_spanning(
    system: &RodSystem,
    contacts: &[Contact],
    graph: &ContactGraph,
    criterion: Criterion,
) -> bool {
    let mut any = false;
    for_each_cluster(system, contacts, graph, criterion, |_, spans| {
        any = spans;
        !spans
    });
    any
}

/// The connected clusters of the contact graph that span, each sorted,
/// ordered by their smallest rod; O(N + E).
pub fn spanning_clusters(
    system: &RodSystem,
    contacts: &[Contact],
    graph: &ContactGraph,
    criterion: Criterion,
) -> Vec<Vec<u32>> {
    let mut found = Vec::new();
    for_each_cluster(system, contacts, graph, criterion, |rods, spans| {
        if spans {
            let mut rods = rods.to_vec();
            rods.sort_unstable();
            found.push(rods);
        }
        true
    });
    found
}

/// Walks the connected components of `graph` in order of their smallest rod,
/// calling `visit(members, spans)` for each until it returns false.
fn for_each_cluster(
    system: &RodSystem,
    contacts: &[Contact],
    graph: &ContactGraph,
    criterion: Criterion,
    mut visit: impl FnMut(&[u32], bool) -> bool,
) {
    debug_assert_eq!(
        graph.n_edges(),
        contacts.len(),
        "graph is not built from contacts"
    );
    let n = graph.n_nodes();
    let mut checker = SpanChecker::new();
    let mut offset: Vec<Option<[i32; 3]>> = vec![None; n];
    let mut members = Vec::new();
    for root in 0..n as u32 {
        if offset[root as usize].is_some() {
            continue;
        }
        offset[root as usize] = Some([0; 3]);
        members.clear();
        members.push(root);
        let mut wraps = false;
        let mut next = 0;
        while let Some(&rod) = members.get(next) {
            next += 1;
            let Some(here) = offset[rod as usize] else {
                continue;
            };
            for &(nb, k) in graph.neighbors(rod) {
                let Some(contact) = contacts.get(k as usize) else {
                    continue;
                };
                let want = step(here, rod, contact);
                match offset[nb as usize] {
                    Some(seen) => wraps |= seen != want,
                    None => {
                        offset[nb as usize] = Some(want);
                        members.push(nb);
                    }
                }
            }
        }
        let spans = match criterion {
            Criterion::Wrap => wraps,
            Criterion::Faces => checker.faces(system, contacts, graph, &members),
        };
        if !visit(&members, spans) {
            return;
        }
    }
}
