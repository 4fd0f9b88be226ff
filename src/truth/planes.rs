//! Forced planes (MODEL §10): the plane classes that the contacts of a
//! whole system force, and nothing more.
//!
//! Three rods that touch pairwise lie in one plane (the other realization,
//! concurrent axes, puts three contacts on one spot). Two planes that share
//! two rods are one plane, and a rod touching two rods of a plane at two
//! distinct points lies in it. The closure of these rules over a whole
//! system gives its plane classes; each is also a rigid body (a triangle is
//! rigid, and a rod held at two points is rigid with what holds it).
//!
//! In a periodic box a class has a frame: each member rod lies in the plane
//! at some image offset. A class whose contacts close a loop through the
//! box (a net offset `w`) contains the lattice direction `w`; a class may
//! wrap along at most two independent directions, since a plane cannot
//! contain three.

use rustc_hash::FxHashMap;

use crate::contacts::Offset;
use crate::graph::Topology;

/// One forced plane class.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlaneClass {
    /// Member rods, sorted, each with the image offset at which it lies in
    /// the class's plane.
    pub rods: Vec<(u32, Offset)>,
    /// Independent lattice directions the plane contains (at most two).
    pub wraps: Vec<Offset>,
}

impl PlaneClass {
    /// The offset of `rod` in this class, if it is a member.
    pub fn offset(&self, rod: u32) -> Option<Offset> {
        self.rods
            .binary_search_by_key(&rod, |&(r, _)| r)
            .ok()
            .map(|i| self.rods[i].1)
    }
}

/// The forced plane classes of a system.
#[derive(Clone, Debug, Default)]
pub struct Planes {
    pub classes: Vec<PlaneClass>,
    /// For each rod, the classes holding it with its offset in each.
    pub of_rod: Vec<Vec<(u32, Offset)>>,
    /// For each edge, the class that holds both its rods, if any (at most one:
    /// two classes sharing two rods are one).
    pub inside: Vec<Option<u32>>,
}

impl Planes {
    /// Rods in the largest class (0 when there is none).
    pub fn largest(&self) -> usize {
        self.classes.iter().map(|c| c.rods.len()).max().unwrap_or(0)
    }

    /// The class whose plane holds rod `a` and the image of rod `b` that `a`
    /// sees at offset `seen`, if any (at most one: two classes sharing two
    /// rods are one).
    pub fn shared(&self, a: u32, b: u32, seen: Offset) -> Option<u32> {
        self.of_rod[a as usize].iter().find_map(|&(id, oa)| {
            let c = &self.classes[id as usize];
            let ob = c.offset(b)?;
            same(add(oa, seen), ob, &c.wraps).then_some(id)
        })
    }
}

/// A forced plane would have to contain three independent lattice
/// directions: no realization of the line model exists in this box.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unrealizable {
    pub rods: usize,
}

fn sub(a: Offset, b: Offset) -> Offset {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: Offset, b: Offset) -> Offset {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Whether `v` lies in the real span of `basis`.
fn in_span(v: Offset, basis: &[Offset]) -> bool {
    let v = v.map(i64::from);
    let cross = |a: [i64; 3], b: [i64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    match basis {
        [] => v == [0; 3],
        [w] => cross(v, w.map(i64::from)) == [0; 3],
        [w1, w2] => {
            let n = cross(w1.map(i64::from), w2.map(i64::from));
            v[0] * n[0] + v[1] * n[1] + v[2] * n[2] == 0
        }
        _ => true,
    }
}

/// Two offsets of one plane are the same plane when they differ by a
/// direction the plane contains.
fn same(a: Offset, b: Offset, wraps: &[Offset]) -> bool {
    in_span(sub(a, b), wraps)
}

struct Work {
    members: FxHashMap<u32, Offset>,
    wraps: Vec<Offset>,
    alive: bool,
}

impl Work {
    /// Adds a direction the plane must contain; false when it would be a third.
    fn add_wrap(&mut self, w: Offset) -> bool {
        if in_span(w, &self.wraps) {
            return true;
        }
        self.wraps.push(w);
        self.wraps.len() < 3
    }
}

/// The forced plane classes of the rods marked `active` (the others are
/// ignored, as if absent).
pub fn forced(topo: &Topology, active: &[bool]) -> Result<Planes, Unrealizable> {
    let graph = topo.graph;
    let n = graph.n_nodes();
    let mut work: Vec<Work> = Vec::new();
    let mut rod_classes: Vec<Vec<u32>> = vec![Vec::new(); n];

    // Seeds: every triangle whose contacts close without a net offset (one
    // that closes through the box is a path of three lines, not a triangle).
    for a in 0..n as u32 {
        if !active[a as usize] {
            continue;
        }
        let nb = graph.neighbors(a);
        for (i, &(b, eab)) in nb.iter().enumerate() {
            if b < a || !active[b as usize] {
                continue;
            }
            for &(c, eac) in &nb[i + 1..] {
                if c < a || !active[c as usize] {
                    continue;
                }
                let Some(ebc) = graph.edge_between(b, c) else {
                    continue;
                };
                let (tab, tac) = (topo.seen(eab, a), topo.seen(eac, a));
                if add(tab, topo.seen(ebc, b)) != tac {
                    continue;
                }
                let id = work.len() as u32;
                work.push(Work {
                    members: [(a, [0; 3]), (b, tab), (c, tac)].into_iter().collect(),
                    wraps: Vec::new(),
                    alive: true,
                });
                for r in [a, b, c] {
                    rod_classes[r as usize].push(id);
                }
            }
        }
    }

    let mut queue: Vec<u32> = (0..work.len() as u32).rev().collect();
    let mut queued = vec![true; work.len()];
    let mut candidates: FxHashMap<u32, Vec<Offset>> = FxHashMap::default();
    let mut shared: FxHashMap<u32, Vec<Offset>> = FxHashMap::default();
    while let Some(p) = queue.pop() {
        queued[p as usize] = false;
        if !work[p as usize].alive {
            continue;
        }
        let mut changed = false;

        // Merge every class that shares two rods with p in one relative position.
        shared.clear();
        for (&r, &o) in &work[p as usize].members {
            for &q in &rod_classes[r as usize] {
                if q != p && work[q as usize].alive {
                    let oq = work[q as usize].members[&r];
                    shared.entry(q).or_default().push(sub(o, oq));
                }
            }
        }
        let mut merges: Vec<(u32, Offset)> = Vec::new();
        for (&q, deltas) in &shared {
            if deltas.len() < 2 {
                continue;
            }
            let mut span = work[p as usize].wraps.clone();
            span.extend(work[q as usize].wraps.iter().copied());
            'pairs: for i in 0..deltas.len() {
                for j in i + 1..deltas.len() {
                    if in_span(sub(deltas[i], deltas[j]), &span) {
                        merges.push((q, deltas[i]));
                        break 'pairs;
                    }
                }
            }
        }
        merges.sort_unstable();
        for (q, delta) in merges {
            if !work[q as usize].alive {
                continue;
            }
            let moved = std::mem::take(&mut work[q as usize].members);
            let wraps = std::mem::take(&mut work[q as usize].wraps);
            work[q as usize].alive = false;
            let target = &mut work[p as usize];
            for w in wraps {
                if !target.add_wrap(w) {
                    return Err(Unrealizable {
                        rods: target.members.len(),
                    });
                }
            }
            for (r, oq) in moved {
                let o = add(oq, delta);
                let classes = &mut rod_classes[r as usize];
                classes.retain(|&c| c != q && c != p);
                classes.push(p);
                match target.members.get(&r) {
                    Some(&old) => {
                        if !same(o, old, &target.wraps) && !target.add_wrap(sub(o, old)) {
                            return Err(Unrealizable {
                                rods: target.members.len(),
                            });
                        }
                    }
                    None => {
                        target.members.insert(r, o);
                    }
                }
            }
            changed = true;
        }

        // Grow: a rod touching two members in one image of the plane joins it;
        // a contact between members at two images means the plane contains
        // the direction between them.
        candidates.clear();
        let target = &mut work[p as usize];
        let members: Vec<(u32, Offset)> = target.members.iter().map(|(&r, &o)| (r, o)).collect();
        for &(r, o) in &members {
            for &(x, e) in graph.neighbors(r) {
                if !active[x as usize] {
                    continue;
                }
                let ox = add(o, topo.seen(e, r));
                match target.members.get(&x) {
                    Some(&old) => {
                        if !same(ox, old, &target.wraps) {
                            if !target.add_wrap(sub(ox, old)) {
                                return Err(Unrealizable {
                                    rods: target.members.len(),
                                });
                            }
                            changed = true;
                        }
                    }
                    None => candidates.entry(x).or_default().push(ox),
                }
            }
        }
        let mut joins: Vec<(u32, Offset)> = Vec::new();
        for (&x, offs) in &candidates {
            'pairs: for i in 0..offs.len() {
                for j in i + 1..offs.len() {
                    if same(offs[i], offs[j], &target.wraps) {
                        joins.push((x, offs[i]));
                        break 'pairs;
                    }
                }
            }
        }
        joins.sort_unstable();
        for (x, o) in joins {
            target.members.insert(x, o);
            rod_classes[x as usize].push(p);
            changed = true;
        }

        if changed && !queued[p as usize] {
            queued[p as usize] = true;
            queue.push(p);
        }
    }

    // Compact the live classes, largest first (ties by smallest rod).
    let mut classes: Vec<PlaneClass> = work
        .into_iter()
        .filter(|w| w.alive)
        .map(|w| {
            let mut rods: Vec<(u32, Offset)> = w.members.into_iter().collect();
            rods.sort_unstable();
            PlaneClass {
                rods,
                wraps: w.wraps,
            }
        })
        .collect();
    classes.sort_by(|a, b| b.rods.len().cmp(&a.rods.len()).then(a.rods.cmp(&b.rods)));
    let mut of_rod: Vec<Vec<(u32, Offset)>> = vec![Vec::new(); n];
    for (id, c) in classes.iter().enumerate() {
        for &(r, o) in &c.rods {
            of_rod[r as usize].push((id as u32, o));
        }
    }
    let mut planes = Planes {
        classes,
        of_rod,
        inside: Vec::new(),
    };
    planes.inside = graph
        .edges()
        .iter()
        .enumerate()
        .map(|(e, &[a, b])| planes.shared(a, b, topo.seen(e as u32, a)))
        .collect();
    Ok(planes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::ContactGraph;

    fn classes(n: usize, edges: &[[u32; 2]]) -> Vec<Vec<u32>> {
        let g = ContactGraph::new(n, edges.to_vec()).unwrap();
        let p = forced(&Topology::finite(&g), &vec![true; n]).unwrap();
        p.classes
            .iter()
            .map(|c| c.rods.iter().map(|&(r, _)| r).collect())
            .collect()
    }

    #[test]
    fn triangles_sharing_a_contact_are_one_plane() {
        // Triangles 0-1-2 and 0-1-3 share the contact 0-1.
        assert_eq!(
            classes(4, &[[0, 1], [1, 2], [0, 2], [0, 3], [1, 3]]),
            vec![vec![0, 1, 2, 3]]
        );
    }

    #[test]
    fn triangles_sharing_a_rod_are_two_planes() {
        // Triangles 0-1-2 and 0-3-4 share rod 0 only: a hinge, not one plane.
        let c = classes(5, &[[0, 1], [1, 2], [0, 2], [0, 3], [3, 4], [0, 4]]);
        assert_eq!(c, vec![vec![0, 1, 2], vec![0, 3, 4]]);
    }

    #[test]
    fn a_rod_touching_a_plane_twice_joins_it_and_so_do_its_followers() {
        // Triangle 0-1-2; rod 3 touches 0 and 1 (joins); rod 4 touches 2 and
        // 3 (joins through 3); rod 5 touches only 4 and 6; rod 6 only 5 and 0.
        let edges = [
            [0, 1],
            [1, 2],
            [0, 2],
            [3, 0],
            [3, 1],
            [4, 2],
            [4, 3],
            [5, 4],
            [5, 6],
            [6, 0],
        ];
        let c = classes(7, &edges);
        assert_eq!(c, vec![vec![0, 1, 2, 3, 4]]);
    }

    #[test]
    fn a_triangle_closing_through_the_box_is_no_plane() {
        // Rods 0, 1, 2 touch pairwise, but the loop crosses the box once.
        let g = ContactGraph::new(3, vec![[0, 1], [1, 2], [0, 2]]).unwrap();
        let shifts = [[0, 0, 0], [0, 0, 0], [1, 0, 0]];
        let topo = Topology::periodic(&g, &shifts).unwrap();
        let p = forced(&topo, &[true; 3]).unwrap();
        assert!(p.classes.is_empty());
        let flat = [[0, 0, 0]; 3];
        let topo = Topology::periodic(&g, &flat).unwrap();
        assert_eq!(forced(&topo, &[true; 3]).unwrap().classes.len(), 1);
    }

    #[test]
    fn a_ring_of_triangles_around_the_box_contains_its_direction() {
        // A strip of triangles 0-1-2, 1-2-3, 2-3-4, 3-4-5, whose last rods
        // touch the first ones' images one box further along x.
        let edges = vec![
            [0, 1],
            [0, 2],
            [1, 2],
            [1, 3],
            [2, 3],
            [2, 4],
            [3, 4],
            [3, 5],
            [4, 5],
            [4, 0],
            [5, 0],
            [5, 1],
        ];
        let mut shifts = vec![[0, 0, 0]; 9];
        shifts.extend([[-1, 0, 0]; 3]);
        let g = ContactGraph::new(6, edges).unwrap();
        let topo = Topology::periodic(&g, &shifts).unwrap();
        let p = forced(&topo, &[true; 6]).unwrap();
        assert_eq!(p.classes.len(), 1);
        assert_eq!(p.classes[0].rods.len(), 6);
        assert_eq!(p.classes[0].wraps.len(), 1);
        assert!(in_span([1, 0, 0], &p.classes[0].wraps));
    }
}
