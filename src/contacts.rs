//! Which rods touch: robust segment–segment distance, an O(N) cell list with
//! periodic images, the contact graph, and its statistics (DESIGN §1).

use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

use crate::rods::{Rod, RodSystem};
use crate::{Error, Result};

/// One contact between two rods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The two rods, `rods[0] < rods[1]`.
    pub rods: [u32; 2],
    /// Axis parameter of the closest point on each rod, in `[-1/2, 1/2]`.
    pub params: [f64; 2],
    /// Contact point: midpoint of the two closest points, wrapped into the primary box.
    pub point: Vector3<f64>,
    /// Periodic image of `rods[1]` that touches `rods[0]`: its center is
    /// shifted by `shift * L`.
    pub shift: [i32; 3],
}

/// Closest points of two segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// Squared distance between the closest points.
    pub dist2: f64,
    /// Parameter on the first segment.
    pub s: f64,
    /// Parameter on the second segment.
    pub t: f64,
}

/// An undirected simple graph in compressed adjacency form: node `i`'s
/// neighbours are `adjacency[offsets[i]..offsets[i+1]]`, each with the index
/// of the edge that joins them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ContactGraph {
    n: usize,
    edges: Vec<[u32; 2]>,
    offsets: Vec<u32>,
    adjacency: Vec<(u32, u32)>,
}

impl ContactGraph {
    /// Builds the graph; rejects self-loops, repeated pairs and out-of-range ends.
    pub fn new(n: usize, edges: Vec<[u32; 2]>) -> Result<Self> {
        if n > u32::MAX as usize / 2 {
            return Err(Error::Parameter(format!("{n} nodes are too many")));
        }
        let mut degree = vec![0u32; n + 1];
        for (k, &[a, b]) in edges.iter().enumerate() {
            if a as usize >= n || b as usize >= n {
                return Err(Error::Parameter(format!(
                    "edge {k} ({a}, {b}) names a node outside 0..{n}"
                )));
            }
            if a == b {
                return Err(Error::Parameter(format!(
                    "edge {k} is a self-loop on node {a}"
                )));
            }
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
        let mut offsets = Vec::with_capacity(n + 1);
        let mut acc = 0u32;
        for d in &degree[..n] {
            offsets.push(acc);
            acc += d;
        }
        offsets.push(acc);
        let mut fill = offsets.clone();
        let mut adjacency = vec![(0u32, 0u32); acc as usize];
        for (k, &[a, b]) in edges.iter().enumerate() {
            adjacency[fill[a as usize] as usize] = (b, k as u32);
            fill[a as usize] += 1;
            adjacency[fill[b as usize] as usize] = (a, k as u32);
            fill[b as usize] += 1;
        }
        for i in 0..n {
            let nb = &mut adjacency[offsets[i] as usize..offsets[i + 1] as usize];
            nb.sort_unstable();
            if let Some(w) = nb.windows(2).find(|w| w[0].0 == w[1].0) {
                return Err(Error::Parameter(format!(
                    "nodes {i} and {} are joined twice: a pair of rods touches at most once",
                    w[0].0
                )));
            }
        }
        Ok(ContactGraph {
            n,
            edges,
            offsets,
            adjacency,
        })
    }

    /// The graph of a list of detected contacts.
    pub fn from_contacts(n: usize, contacts: &[Contact]) -> Self {
        Self::new(n, contacts.iter().map(|c| c.rods).collect())
            .expect("detected contacts form a simple graph")
    }

    pub fn n_nodes(&self) -> usize {
        self.n
    }

    pub fn n_edges(&self) -> usize {
        self.edges.len()
    }

    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Neighbours of `i` with the joining edge, sorted by neighbour.
    pub fn neighbors(&self, i: u32) -> &[(u32, u32)] {
        let i = i as usize;
        &self.adjacency[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    pub fn degree(&self, i: u32) -> usize {
        self.neighbors(i).len()
    }

    /// The edge joining `a` and `b`, if any.
    pub fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        let nb = self.neighbors(a);
        nb.binary_search_by_key(&b, |&(v, _)| v)
            .ok()
            .map(|k| nb[k].1)
    }
}

/// Contact statistics of a contact graph (DESIGN §1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactStats {
    /// Mean contact number over all rods, `2 * contacts / N`.
    pub c0: f64,
    /// Mean degree within the largest connected component.
    pub c1: f64,
    /// Mean degree within the largest connected component of the 2-core.
    pub c2: f64,
    /// Average local clustering coefficient over all rods (rods of degree < 2 count 0).
    pub clustering: f64,
}

/// Half the core length: segment parameters run over `[-HALF, HALF]`.
const HALF: f64 = 0.5;

/// Below this `|u x v|^2 / (|u|^2 |v|^2)` (an angle under 1e-10 rad) the
/// interior critical point is not evaluated: the boundary then misses the true
/// minimum by at most about the angle itself, far below any length that matters.
const PARALLEL_SIN2: f64 = 1e-20;

/// Relative slack of the cheap necessary-condition filters, so that they never
/// reject a pair that the exact segment distance would accept.
const FILTER_SLACK: f64 = 1e-9;

/// Closest points of the segments `p + s u` and `q + t v`, `s, t` in
/// `[-1/2, 1/2]`, for unit vectors `u` and `v`.
///
/// Robust for (nearly) parallel segments, where the textbook 2x2 solve breaks
/// down: the four edges of the parameter square are each an exact 1-D clamp,
/// the interior critical point is tried only when the system is well
/// conditioned (and then only for `s`, with `t` re-minimized exactly), and the
/// candidate with the smallest directly computed distance wins. Exactly
/// parallel overlapping segments have many minimizers; the first candidate in
/// the fixed order (interior, `s = -1/2`, `s = 1/2`, `t = -1/2`, `t = 1/2`) wins.
pub fn closest_points(
    p: &Vector3<f64>,
    u: &Vector3<f64>,
    q: &Vector3<f64>,
    v: &Vector3<f64>,
) -> Closest {
    // f(s, t) = |s u - t v - w|^2 with w = q - p.
    let w = q - p;
    let a = u.norm_squared();
    let c = v.norm_squared();
    let b = u.dot(v);
    let d = u.dot(&w);
    let e = v.dot(&w);
    let eval = |s: f64, t: f64| Closest {
        dist2: (u * s - v * t - w).norm_squared(),
        s,
        t,
    };
    let t_for = |s: f64| ((s * b - e) / c).clamp(-HALF, HALF);
    let s_for = |t: f64| ((t * b + d) / a).clamp(-HALF, HALF);

    let mut best: Option<Closest> = None;
    let mut offer = |cand: Closest| {
        if best.is_none_or(|b| cand.dist2 < b.dist2) {
            best = Some(cand);
        }
    };
    // Lagrange's identity: |u x v|^2 = a c - b^2, without the cancellation.
    let n = u.cross(v);
    let n2 = n.norm_squared();
    if n2 > PARALLEL_SIN2 * a * c {
        // s of the lines' common perpendicular. Its error grows like
        // eps / angle but lies along the near-flat valley of f, and taking t
        // exactly from s keeps the distance error at rounding level.
        let s = (w.cross(v).dot(&n) / n2).clamp(-HALF, HALF);
        offer(eval(s, t_for(s)));
    }
    for s in [-HALF, HALF] {
        offer(eval(s, t_for(s)));
    }
    for t in [-HALF, HALF] {
        offer(eval(s_for(t), t));
    }
    best.unwrap_or(Closest {
        dist2: f64::NAN,
        s: 0.0,
        t: 0.0,
    })
}

/// A center wrapped into the primary box, and which image of the box the
/// stored center lies in (`center = wrapped + image * L`).
fn wrap_center(center: &Vector3<f64>, l: f64) -> (Vector3<f64>, [i32; 3]) {
    let mut out = *center;
    let mut image = [0i32; 3];
    for k in 0..3 {
        let x = center[k];
        if (0.0..l).contains(&x) {
            continue;
        }
        let m = (x / l).floor();
        let mut y = x - m * l;
        let mut m = m as i32;
        if y >= l {
            y -= l;
            m = m.saturating_add(1);
        } else if y < 0.0 {
            y += l;
            m = m.saturating_sub(1);
        }
        out[k] = y.clamp(0.0, l);
        image[k] = m;
    }
    (out, image)
}

/// `x mod L` in `[0, L)`.
fn wrap_coord(x: f64, l: f64) -> f64 {
    let y = x - (x / l).floor() * l;
    if y >= l || y < 0.0 { 0.0 } else { y }
}

/// The image of a (wrapped) center shifted by `shift` boxes. Both detectors
/// build it with this one expression so that they agree to the last bit.
fn image(center: &Vector3<f64>, shift: [i32; 3], l: f64) -> Vector3<f64> {
    center + Vector3::new(shift[0] as f64, shift[1] as f64, shift[2] as f64) * l
}

/// What the detectors need per rod: wrapped center, axis, and the image of
/// the stored center.
#[derive(Clone, Copy)]
struct Placed {
    center: Vector3<f64>,
    axis: Vector3<f64>,
    image: [i32; 3],
}

/// Geometry shared by the detectors.
#[derive(Clone, Copy)]
struct Geometry {
    box_len: f64,
    /// `(2r)^2`: rods touch iff the core distance squared is below this.
    touch2: f64,
    /// Squared largest center distance of touching rods, `(l + 2r)^2`, with slack.
    reach2: f64,
    two_r: f64,
}

impl Geometry {
    fn of(system: &RodSystem) -> Self {
        let r = system.radius();
        let reach = 1.0 + 2.0 * r;
        Geometry {
            box_len: system.box_len(),
            touch2: 4.0 * r * r,
            reach2: reach * reach * (1.0 + FILTER_SLACK),
            two_r: 2.0 * r,
        }
    }

    /// Tests rods `lo < hi` where `shift` (relative to the wrapped centers) is
    /// the image of `hi` that can touch `lo`. The single decision procedure of
    /// both detectors, so their outputs are identical.
    fn touch(&self, lo: u32, a: &Placed, hi: u32, b: &Placed, shift: [i32; 3]) -> Option<Contact> {
        let l = self.box_len;
        let p = a.center;
        let q = image(&b.center, shift, l);
        let w = q - p;
        if w.norm_squared() > self.reach2 {
            return None;
        }
        // The distance of the infinite lines bounds the segment distance from
        // below and rejects most candidates without the full computation.
        let n = a.axis.cross(&b.axis);
        let n2 = n.norm_squared();
        if n2 > 1e-6 {
            let wn = w.dot(&n);
            if wn * wn > self.two_r * self.two_r * n2 * (1.0 + FILTER_SLACK) {
                return None;
            }
        }
        let cp = closest_points(&p, &a.axis, &q, &b.axis);
        let touching = cp.dist2 < self.touch2;
        if !touching {
            return None;
        }
        let mid = (p + a.axis * cp.s + q + b.axis * cp.t) * 0.5;
        let point = Vector3::new(
            wrap_coord(mid.x, l),
            wrap_coord(mid.y, l),
            wrap_coord(mid.z, l),
        );
        // Translate the shift between wrapped centers into one between stored centers.
        let shift = std::array::from_fn(|k| {
            shift[k]
                .saturating_add(a.image[k])
                .saturating_sub(b.image[k])
        });
        Some(Contact {
            rods: [lo, hi],
            params: [cp.s, cp.t],
            point,
            shift,
        })
    }
}

fn place(rod: &Rod, l: f64) -> Placed {
    let (center, image) = wrap_center(&rod.center, l);
    Placed {
        center,
        axis: rod.axis,
        image,
    }
}

/// The 13 neighbour offsets that, with the cell itself, visit every
/// unordered pair of adjacent cells exactly once.
const FORWARD: [[i32; 3]; 13] = [
    [0, 0, 1],
    [0, 1, -1],
    [0, 1, 0],
    [0, 1, 1],
    [1, -1, -1],
    [1, -1, 0],
    [1, -1, 1],
    [1, 0, -1],
    [1, 0, 0],
    [1, 0, 1],
    [1, 1, -1],
    [1, 1, 0],
    [1, 1, 1],
];

/// All contacts of a rod system in O(N) with a periodic cell list, sorted by
/// rod pair (see [`Contact`] for the conventions).
///
/// Cells have side at least `l + 2r`, the largest center distance of touching
/// rods, so touching rods sit in the same or adjacent cells. The result does
/// not depend on the number of rayon threads and equals [`detect_all_pairs`].
pub fn detect(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
    let l = geo.box_len;
    let n = system.len();
    let reach = 1.0 + geo.two_r;
    // Cells no smaller than needed, and no more cells than about 2N, so a
    // sparse system in a huge box does not allocate an enormous empty grid.
    let by_size = (l / reach).floor();
    let by_count = (2.0 * n as f64).cbrt().ceil();
    let m = by_size.min(by_count);
    if m.is_nan() || m < 3.0 {
        return detect_all_pairs(system);
    }
    let m = m as usize;
    let n_cells = m * m * m;

    let placed: Vec<Placed> = system.rods.iter().map(|r| place(r, l)).collect();
    let cell_of: Vec<u32> = placed
        .iter()
        .map(|p| {
            let idx = |x: f64| ((x / l * m as f64) as usize).min(m - 1);
            ((idx(p.center.x) * m + idx(p.center.y)) * m + idx(p.center.z)) as u32
        })
        .collect();
    // Counting sort: `start[c]..start[c + 1]` are the sorted slots of cell c.
    let mut start = vec![0u32; n_cells + 1];
    for &c in &cell_of {
        start[c as usize + 1] += 1;
    }
    for c in 0..n_cells {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; n];
    for (i, &c) in cell_of.iter().enumerate() {
        order[fill[c as usize] as usize] = i as u32;
        fill[c as usize] += 1;
    }
    // Rods in cell order, coordinates also in separate arrays so that the
    // inner distance loop streams through memory.
    let sorted: Vec<Placed> = order.iter().map(|&i| placed[i as usize]).collect();
    drop(placed);
    let xs: Vec<f64> = sorted.iter().map(|p| p.center.x).collect();
    let ys: Vec<f64> = sorted.iter().map(|p| p.center.y).collect();
    let zs: Vec<f64> = sorted.iter().map(|p| p.center.z).collect();
    let line_cut2 = geo.two_r * geo.two_r * (1.0 + FILTER_SLACK);

    let visit_cell = |out: &mut Vec<Contact>, cell: usize| {
        let (ix, iy, iz) = (cell / (m * m), (cell / m) % m, cell % m);
        let own = start[cell] as usize..start[cell + 1] as usize;
        if own.is_empty() {
            return;
        }
        for off in std::iter::once([0, 0, 0]).chain(FORWARD) {
            // Neighbour cell and the image shift that makes it adjacent.
            let mut shift = [0i32; 3];
            let mut nc = [0usize; 3];
            for (k, base) in [ix, iy, iz].into_iter().enumerate() {
                let mut c = base as i64 + off[k] as i64;
                if c < 0 {
                    c += m as i64;
                    shift[k] = -1;
                } else if c >= m as i64 {
                    c -= m as i64;
                    shift[k] = 1;
                }
                nc[k] = c as usize;
            }
            let other = (nc[0] * m + nc[1]) * m + nc[2];
            let same = other == cell;
            let theirs = start[other] as usize..start[other + 1] as usize;
            let sv = Vector3::new(shift[0] as f64, shift[1] as f64, shift[2] as f64) * l;
            let back = shift.map(|s| -s);
            for a in own.clone() {
                let pa = &sorted[a];
                let (ax, ay, az) = (xs[a] - sv.x, ys[a] - sv.y, zs[a] - sv.z);
                let from = if same { a + 1 } else { theirs.start };
                // Hits as bit masks over chunks of 64: the distance loop has
                // no data-dependent branch (most rods are out of reach, and
                // such a branch mispredicts often), and only hits are visited.
                let (bx, by, bz) = (
                    &xs[from..theirs.end],
                    &ys[from..theirs.end],
                    &zs[from..theirs.end],
                );
                for (chunk, ((cx, cy), cz)) in bx
                    .chunks(64)
                    .zip(by.chunks(64))
                    .zip(bz.chunks(64))
                    .enumerate()
                {
                    let mut mask = 0u64;
                    for (k, ((x, y), z)) in cx.iter().zip(cy).zip(cz).enumerate() {
                        let (dx, dy, dz) = (x - ax, y - ay, z - az);
                        mask |= u64::from(dx * dx + dy * dy + dz * dz <= geo.reach2) << k;
                    }
                    while mask != 0 {
                        let b = from + 64 * chunk + mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let pb = &sorted[b];
                        // Distance of the infinite lines: a cheap lower bound.
                        let n = pa.axis.cross(&pb.axis);
                        let n2 = n.norm_squared();
                        if n2 > 1e-6 {
                            let wn = (pb.center + sv - pa.center).dot(&n);
                            if wn * wn > line_cut2 * n2 {
                                continue;
                            }
                        }
                        let (i, j) = (order[a], order[b]);
                        let hit = if i < j {
                            geo.touch(i, pa, j, pb, shift)
                        } else {
                            geo.touch(j, pb, i, pa, back)
                        };
                        out.extend(hit);
                    }
                }
            }
        }
    };
    let mut contacts = (0..n_cells)
        .into_par_iter()
        .with_min_len(16)
        .fold(Vec::new, |mut out, cell| {
            visit_cell(&mut out, cell);
            out
        })
        .reduce(Vec::new, |mut a, mut b| {
            a.append(&mut b);
            a
        });
    contacts.sort_unstable_by_key(|c| c.rods);
    contacts
}

/// All contacts by testing every pair: the O(N^2) reference for [`detect`],
/// with the same conventions and bit-identical output.
pub fn detect_all_pairs(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
    let l = geo.box_len;
    let placed: Vec<Placed> = system.rods.iter().map(|r| place(r, l)).collect();
    let mut contacts = Vec::new();
    for (i, a) in placed.iter().enumerate() {
        for (j, b) in placed.iter().enumerate().skip(i + 1) {
            let d = b.center - a.center;
            // Minimum image: the only image of j that can touch i (L > 2(l + 2r)).
            let shift = std::array::from_fn(|k| -(d[k] / l).round() as i32);
            contacts.extend(geo.touch(i as u32, a, j as u32, b, shift));
        }
    }
    contacts
}

/// Contact numbers and clustering of a contact graph (DESIGN §1), in
/// O(N + E sqrt(E)).
pub fn stats(graph: &ContactGraph) -> ContactStats {
    let n = graph.n_nodes();
    if n == 0 {
        return ContactStats {
            c0: 0.0,
            c1: 0.0,
            c2: 0.0,
            clustering: 0.0,
        };
    }
    let c0 = 2.0 * graph.n_edges() as f64 / n as f64;
    let everyone = vec![true; n];
    let c1 = largest_component_mean_degree(graph, &everyone);
    let core = two_core(graph);
    let c2 = largest_component_mean_degree(graph, &core);
    ContactStats {
        c0,
        c1,
        c2,
        clustering: average_clustering(graph),
    }
}

/// Membership of the 2-core: peel nodes of degree < 2 until none is left.
fn two_core(graph: &ContactGraph) -> Vec<bool> {
    let n = graph.n_nodes();
    let mut degree: Vec<usize> = (0..n as u32).map(|i| graph.degree(i)).collect();
    let mut alive = vec![true; n];
    let mut stack: Vec<u32> = (0..n as u32).filter(|&i| degree[i as usize] < 2).collect();
    while let Some(i) = stack.pop() {
        if !alive[i as usize] {
            continue;
        }
        alive[i as usize] = false;
        for &(j, _) in graph.neighbors(i) {
            let j = j as usize;
            if alive[j] {
                degree[j] -= 1;
                if degree[j] == 1 {
                    stack.push(j as u32);
                }
            }
        }
    }
    alive
}

/// Mean degree `2 E_C / N_C` of the largest connected component `C` of the
/// subgraph induced by the `alive` nodes (ties: the component of the smallest
/// node); 0 if no node is alive.
fn largest_component_mean_degree(graph: &ContactGraph, alive: &[bool]) -> f64 {
    let n = graph.n_nodes();
    let mut seen = vec![false; n];
    let mut queue = Vec::new();
    let mut best = (0usize, 0usize);
    for root in 0..n {
        if !alive[root] || seen[root] {
            continue;
        }
        seen[root] = true;
        queue.clear();
        queue.push(root as u32);
        let (mut nodes, mut degree_sum) = (0usize, 0usize);
        while let Some(i) = queue.pop() {
            nodes += 1;
            for &(j, _) in graph.neighbors(i) {
                if alive[j as usize] {
                    degree_sum += 1;
                    if !seen[j as usize] {
                        seen[j as usize] = true;
                        queue.push(j);
                    }
                }
            }
        }
        if nodes > best.0 {
            best = (nodes, degree_sum);
        }
    }
    if best.0 == 0 {
        0.0
    } else {
        best.1 as f64 / best.0 as f64
    }
}

/// networkx's `average_clustering`: the mean over all nodes of
/// `2 T / (k (k - 1))` (0 below degree 2). Triangles are counted once each by
/// orienting edges towards the higher (degree, index) rank, which bounds the
/// work by O(E sqrt(E)) even with hubs.
fn average_clustering(graph: &ContactGraph) -> f64 {
    let n = graph.n_nodes();
    if n == 0 {
        return 0.0;
    }
    let rank = |i: u32| (graph.degree(i), i);
    let mut offsets = Vec::with_capacity(n + 1);
    let mut forward = Vec::with_capacity(graph.n_edges());
    offsets.push(0usize);
    for i in 0..n as u32 {
        forward.extend(
            graph
                .neighbors(i)
                .iter()
                .map(|&(j, _)| j)
                .filter(|&j| rank(j) > rank(i)),
        );
        offsets.push(forward.len());
    }
    let out = |i: u32| &forward[offsets[i as usize]..offsets[i as usize + 1]];
    let mut triangles = vec![0u64; n];
    let mut mark = vec![u32::MAX; n];
    for u in 0..n as u32 {
        for &w in out(u) {
            mark[w as usize] = u;
        }
        for &w in out(u) {
            for &x in out(w) {
                if mark[x as usize] == u {
                    triangles[u as usize] += 1;
                    triangles[w as usize] += 1;
                    triangles[x as usize] += 1;
                }
            }
        }
    }
    let sum: f64 = (0..n as u32)
        .map(|i| {
            let k = graph.degree(i) as f64;
            if k < 2.0 {
                0.0
            } else {
                2.0 * triangles[i as usize] as f64 / (k * (k - 1.0))
            }
        })
        .sum();
    sum / n as f64
}
