//! Whether a cluster of rods spans the box (MODEL §1).
//!
//! A periodic box has no walls, so "spanning" needs a definition; both in use
//! give the same threshold as `L -> inf` and different finite-size curves, so
//! every result must say which one it used.

use petgraph::unionfind::UnionFind;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use crate::contacts::{Contact, Offset};
use crate::graph::ContactGraph;
use crate::rods::{Periodic, RodSystem};

/// Which definition of spanning to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Criterion {
    /// A cluster spans if it connects a rod to one of its own periodic images:
    /// following its contacts with unwrapped image offsets reaches some rod
    /// twice at different offsets. Natural for periodic boxes. Along an axis
    /// with walls, where nothing wraps, it spans if it joins the two walls
    /// (as under `Faces`).
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
    /// The system resists every strain its box has: truth's strain rank
    /// reaches the number of strains considered (MODEL §10). A property of
    /// the whole system, not of one cluster (six separate strips can make a
    /// solid), so truth studies only: everything that tests contacts or
    /// compressed bodies refuses it.
    Solid,
}

impl Criterion {
    /// The criterion a network of contacts or a cluster is tested under:
    /// itself, and `Wrap` for `Solid`, since a contact network must wrap
    /// to be solid. Commands that test clusters refuse `Solid` first
    /// ([`Criterion::check_clusters`]); this serves a solid truth study's
    /// contact critical number and its clusters' spans.
    pub fn of_clusters(self) -> Criterion {
        match self {
            Criterion::Solid => Criterion::Wrap,
            c => c,
        }
    }

    /// Refuses `Solid` for `what`, which tests contacts or compressed
    /// bodies rather than the exact truth.
    pub fn check_clusters(self, what: &str) -> crate::Result<()> {
        if self == Criterion::Solid {
            return Err(crate::Error::Parameter(format!(
                "--criterion solid needs the exact truth (truth studies and `rgc truth`), not {what}"
            )));
        }
        Ok(())
    }
}

impl std::fmt::Display for Criterion {
    /// The name on the command line and in files.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Criterion::Wrap => "wrap",
            Criterion::Faces => "faces",
            Criterion::Solid => "solid",
        })
    }
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
    offset: Vec<Option<Offset>>,
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
    image: Offset,
    reached: bool,
}

impl Member {
    fn of(system: &RodSystem, rod: u32) -> Self {
        let mut m = Member::default();
        let Some(rod) = system.rods.get(rod as usize) else {
            return m;
        };
        for d in 0..3 {
            let l = system.domain.sides[d];
            let image = if system.domain.wraps(d) {
                (rod.center[d] / l).floor()
            } else {
                0.0
            };
            let c = rod.center[d] - image * l;
            let reach = 0.5 * rod.length * rod.axis[d].abs() + rod.radius;
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
        match criterion.of_clusters() {
            Criterion::Faces => self.faces(system, contacts, graph, rods, [true; 3]),
            _ => {
                self.wraps(contacts, graph, rods)
                    || self.faces(system, contacts, graph, rods, walls(system))
            }
        }
    }

    fn index(&mut self, rods: &[u32]) {
        self.slot.clear();
        self.slot
            .extend(rods.iter().enumerate().map(|(k, &r)| (r, k as u32)));
    }

    /// The faces test along the axes in `axes`.
    fn faces(
        &mut self,
        system: &RodSystem,
        contacts: &[Contact],
        graph: &ContactGraph,
        rods: &[u32],
        axes: [bool; 3],
    ) -> bool {
        if !axes.contains(&true) {
            return false;
        }
        debug_assert_eq!(
            graph.n_edges(),
            contacts.len(),
            "graph is not built from contacts"
        );
        self.index(rods);
        self.members.clear();
        self.members
            .extend(rods.iter().map(|&r| Member::of(system, r)));
        for d in (0..3).filter(|&d| axes[d]) {
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

/// The axes of a system's box that are walls, not periodic.
fn walls(system: &RodSystem) -> [bool; 3] {
    system.domain.periodic.axes().map(|p| !p)
}

/// Image offset of the other rod of `contact`, reached from `rod` at offset `here`.
fn step(here: Offset, rod: u32, contact: &Contact) -> Offset {
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
    let mut offset: Vec<Option<Offset>> = vec![None; n];
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
        let spans = match criterion.of_clusters() {
            Criterion::Faces => checker.faces(system, contacts, graph, &members, [true; 3]),
            _ => wraps || checker.faces(system, contacts, graph, &members, walls(system)),
        };
        if !visit(&members, spans) {
            return;
        }
    }
}

/// Contact spanning of a growing rod sequence (MODEL §8, Newman–Ziff): rods
/// and then their contacts are added in sequence order, and a union-find
/// tells in near-constant time per contact whether some cluster spans.
///
/// `Wrap` keeps each rod's image offset relative to its root, so a contact
/// closing a loop with a non-zero net offset is a wrap. `Faces` keeps one
/// union-find per axis over the contacts that do not cross the periodic
/// boundary along it, with whether each root's cluster pokes out of the low
/// and the high face. Both agree with [`contact_spanning`] on every prefix.
#[derive(Clone, Debug)]
pub struct Sweep {
    criterion: Criterion,
    /// Wrap: union-find parents and each rod's offset from its parent (by
    /// hand: petgraph's `UnionFind` keeps no data along the path).
    parent: Vec<u32>,
    offset: Vec<Offset>,
    size: Vec<u32>,
    /// Faces: per axis, the clusters, and per root which faces its cluster reaches.
    axis_sets: [UnionFind<u32>; 3],
    faces: [Vec<(bool, bool)>; 3],
    /// Faces: each rod's description, for the boundary-crossing test.
    members: Vec<Member>,
    spans: bool,
}

impl Sweep {
    /// A sweep under `criterion` ([`Criterion::of_clusters`]).
    pub fn new(criterion: Criterion) -> Self {
        Sweep {
            criterion: criterion.of_clusters(),
            parent: Vec::new(),
            offset: Vec::new(),
            size: Vec::new(),
            axis_sets: Default::default(),
            faces: Default::default(),
            members: Vec::new(),
            spans: false,
        }
    }

    /// Whether some cluster of what was added spans.
    pub fn spans(&self) -> bool {
        self.spans
    }

    /// Rods added so far.
    pub fn len(&self) -> usize {
        match self.criterion {
            Criterion::Faces => self.members.len(),
            _ => self.parent.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Adds the next rod of `system` (rods must come in index order) and
    /// returns whether some cluster spans. Under `Wrap` the box must be
    /// periodic on every axis (the sweep serves the paper's sequences).
    pub fn add_rod(&mut self, system: &RodSystem) -> bool {
        debug_assert!(
            self.criterion == Criterion::Faces || system.domain.periodic == Periodic::Xyz,
            "the wrap sweep needs a fully periodic box"
        );
        let rod = self.len() as u32;
        match self.criterion {
            Criterion::Wrap | Criterion::Solid => {
                self.parent.push(rod);
                self.offset.push([0; 3]);
                self.size.push(1);
            }
            Criterion::Faces => {
                let m = Member::of(system, rod);
                for d in 0..3 {
                    self.axis_sets[d].new_set();
                    self.faces[d].push((m.low[d], m.high[d]));
                    self.spans |= m.low[d] && m.high[d];
                }
                self.members.push(m);
            }
        }
        self.spans
    }

    /// Adds a contact between two rods already added and returns whether
    /// some cluster spans.
    pub fn add_contact(&mut self, contact: &Contact) -> bool {
        let [a, b] = contact.rods;
        assert!(
            (b as usize) < self.len(),
            "contact {a}-{b} added before its rods"
        );
        match self.criterion {
            Criterion::Wrap | Criterion::Solid => self.join_wrap(a, b, contact.shift),
            Criterion::Faces => {
                for d in 0..3 {
                    let (here, there) = (self.members[a as usize], self.members[b as usize]);
                    if !crosses(contact, a, &here, &there, d) {
                        self.join_axis(d, a, b);
                    }
                }
            }
        }
        self.spans
    }

    /// Root of `x` and the offset of `x` from it, compressing the path.
    fn find_wrap(&mut self, x: u32) -> (u32, Offset) {
        let p = self.parent[x as usize];
        if p == x {
            return (x, [0; 3]);
        }
        let (root, to_parent) = self.find_wrap(p);
        let o = &mut self.offset[x as usize];
        *o = std::array::from_fn(|d| o[d] + to_parent[d]);
        self.parent[x as usize] = root;
        (root, *o)
    }

    fn join_wrap(&mut self, a: u32, b: u32, shift: Offset) {
        let (ra, oa) = self.find_wrap(a);
        let (rb, ob) = self.find_wrap(b);
        // Through this contact, b's image sits at a's offset plus `shift`.
        let want: Offset = std::array::from_fn(|d| oa[d] + shift[d]);
        if ra == rb {
            self.spans |= want != ob;
            return;
        }
        // Offset of rb from ra, so that b lands at `want`.
        let rb_from_ra: Offset = std::array::from_fn(|d| want[d] - ob[d]);
        let (child, root, off) = if self.size[ra as usize] >= self.size[rb as usize] {
            (rb, ra, rb_from_ra)
        } else {
            (ra, rb, rb_from_ra.map(|v| -v))
        };
        self.parent[child as usize] = root;
        self.offset[child as usize] = off;
        self.size[root as usize] += self.size[child as usize];
    }

    fn join_axis(&mut self, d: usize, a: u32, b: u32) {
        let sets = &mut self.axis_sets[d];
        let (ra, rb) = (sets.find_mut(a), sets.find_mut(b));
        if !sets.union(ra, rb) {
            return;
        }
        let root = sets.find_mut(ra);
        let child = if root == ra { rb } else { ra };
        let (cl, ch) = self.faces[d][child as usize];
        let f = &mut self.faces[d][root as usize];
        *f = (f.0 || cl, f.1 || ch);
        self.spans |= f.0 && f.1;
    }
}

/// The smallest number of leading rods of `system` whose contacts span, or
/// `None` if all of them do not. `contacts` must hold every contact of the
/// system sorted by their larger rod ([`sort_by_sequence`]).
pub fn critical_rods(
    system: &RodSystem,
    contacts: &[Contact],
    criterion: Criterion,
) -> Option<usize> {
    let mut sweep = Sweep::new(criterion);
    let mut next = contacts.iter().peekable();
    for n in 0..system.len() {
        let mut spans = sweep.add_rod(system);
        while let Some(c) = next.next_if(|c| c.rods[1] as usize == n) {
            spans = sweep.add_contact(c);
        }
        if spans {
            return Some(n + 1);
        }
    }
    None
}

/// Sorts contacts in the order their rods appear in the sequence (by larger
/// rod, then smaller), so the contacts of the first `n` rods are a prefix.
pub fn sort_by_sequence(contacts: &mut [Contact]) {
    contacts.sort_unstable_by_key(|c| (c.rods[1], c.rods[0]));
}
