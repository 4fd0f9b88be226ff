//! Every base motif's positive example and the variants its theorem excludes,
//! with the number of nodes each must end as under both rule sets. The tests
//! and `rgc audit` check the engine against this one table.

use serde::Serialize;

use super::ruleset::RuleSet;
use super::run::compress_from;
use crate::body::{Body, BodyClass};
use crate::graph::ContactGraph;

/// A contact graph, optionally with bodies declared rigid, and its expected outcome.
#[derive(Clone, Debug)]
pub struct Example {
    pub name: &'static str,
    pub n: usize,
    pub edges: Vec<[u32; 2]>,
    pub bodies: Vec<Body>,
    /// Nodes left under `sound` and under `paper`, for every motif order.
    pub expect: [usize; 2],
}

impl Example {
    pub fn graph(&self) -> ContactGraph {
        ContactGraph::new(self.n, self.edges.clone()).expect("examples are simple graphs")
    }

    /// The example's bodies re-classed by `mask` (bit `i` set: body `i`
    /// planar), to check a motif under every planar/spatial assignment.
    pub fn bodies_classed(&self, mask: u32) -> Vec<Body> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let class = if mask >> i & 1 == 1 {
                    BodyClass::Planar
                } else {
                    BodyClass::Spatial
                };
                Body::new(b.rods.clone(), class)
            })
            .collect()
    }
}

fn spatial(rods: &[u32]) -> Body {
    Body::new(rods.to_vec(), BodyClass::Spatial)
}

fn planar(rods: &[u32]) -> Body {
    Body::new(rods.to_vec(), BodyClass::Planar)
}

fn ex(
    name: &'static str,
    n: usize,
    edges: &[(u32, u32)],
    bodies: Vec<Body>,
    expect: [usize; 2],
) -> Example {
    Example {
        name,
        n,
        edges: edges.iter().map(|&(a, b)| [a, b]).collect(),
        bodies,
        expect,
    }
}

/// Edges of K_{2,4}: rods 0 and 1 each touching rods 2..=5.
const K24: [(u32, u32); 8] = [
    (0, 2),
    (1, 2),
    (0, 3),
    (1, 3),
    (0, 4),
    (1, 4),
    (0, 5),
    (1, 5),
];

/// Edges of the rod prism: two rod triangles joined by three contacts (a hinge).
pub const PRISM: [(u32, u32); 9] = [
    (0, 1),
    (1, 2),
    (0, 2),
    (3, 4),
    (4, 5),
    (3, 5),
    (0, 3),
    (1, 4),
    (2, 5),
];

/// The table. Bodies named R1, R2, R3 in the paper are rods {0,1,2}, {3,4,5}, {6,7,8}.
pub fn all() -> Vec<Example> {
    let tri = [(0, 1), (1, 2), (0, 2)];
    let mut k24_rod = K24.to_vec();
    k24_rod.extend([(6, 2), (6, 3)]);
    let three = || {
        vec![
            spatial(&[0, 1, 2]),
            spatial(&[3, 4, 5]),
            spatial(&[6, 7, 8]),
        ]
    };
    let two = || vec![spatial(&[0, 1, 2]), spatial(&[3, 4, 5])];
    let k23: Vec<(u32, u32)> = (2..5).flat_map(|k| [(0, k), (1, k)]).collect();
    vec![
        ex("3D3C rod triangle", 3, &tri, vec![], [1, 1]),
        ex(
            "3-clique community (strip of 4 triangles)",
            6,
            &[
                (0, 1),
                (0, 2),
                (1, 2),
                (1, 3),
                (2, 3),
                (2, 4),
                (3, 4),
                (3, 5),
                (4, 5),
            ],
            vec![],
            [1, 1],
        ),
        ex(
            "two triangles sharing one rod",
            5,
            &[(0, 1), (0, 2), (1, 2), (2, 3), (2, 4), (3, 4)],
            vec![],
            [3, 3],
        ),
        ex(
            "3D2B rod touching a 3D6 body twice",
            7,
            &k24_rod,
            vec![],
            [1, 1],
        ),
        ex(
            "3D2B rod touching a planar body twice",
            4,
            &[(3, 0), (3, 1)],
            vec![planar(&[0, 1, 2])],
            [1, 1],
        ),
        ex(
            "rod touching a body once",
            4,
            &[(3, 0)],
            vec![spatial(&[0, 1, 2])],
            [2, 2],
        ),
        ex(
            "3D2A spatial + spatial",
            6,
            &[(0, 3), (1, 4), (2, 5)],
            two(),
            [1, 1],
        ),
        ex(
            "3D2A spatial + planar",
            6,
            &[(0, 3), (1, 4), (2, 5)],
            vec![spatial(&[0, 1, 2]), planar(&[3, 4, 5])],
            [1, 1],
        ),
        ex(
            "3D2A, two contacts sharing a rod",
            6,
            &[(0, 3), (0, 4), (1, 5)],
            two(),
            [1, 1],
        ),
        ex(
            "3D2A, three contacts on one rod",
            6,
            &[(0, 3), (0, 4), (0, 5)],
            two(),
            [2, 2],
        ),
        ex(
            "two bodies, two contacts",
            6,
            &[(0, 3), (1, 4)],
            two(),
            [2, 2],
        ),
        ex(
            "3D2A of two planar bodies (hinge)",
            6,
            &[(0, 3), (1, 4), (2, 5)],
            vec![planar(&[0, 1, 2]), planar(&[3, 4, 5])],
            [2, 1],
        ),
        ex(
            "rod prism (two rod triangles, 3 contacts)",
            6,
            &PRISM,
            vec![],
            [2, 1],
        ),
        ex(
            "two planar bodies, one made spatial by 3D2A first",
            9,
            &[(0, 3), (1, 4), (2, 5), (0, 6), (1, 7), (2, 8)],
            vec![planar(&[0, 1, 2]), planar(&[3, 4, 5]), spatial(&[6, 7, 8])],
            [2, 1],
        ),
        ex(
            "3D3A",
            9,
            &[(0, 3), (1, 6), (2, 7), (4, 7), (5, 8)],
            three(),
            [1, 1],
        ),
        ex(
            "3D3A, p1 p2 p3 on one rod",
            9,
            &[(0, 3), (0, 6), (0, 7), (4, 7), (5, 8)],
            three(),
            [3, 3],
        ),
        ex(
            "3D3A, p1 p4 p5 on one rod",
            9,
            &[(0, 3), (1, 6), (2, 7), (3, 7), (3, 8)],
            three(),
            [3, 3],
        ),
        ex(
            "3D3A, p2..p5 on one rod",
            9,
            &[(0, 3), (1, 6), (2, 6), (4, 6), (5, 6)],
            three(),
            [3, 3],
        ),
        ex("3D3B", 7, &[(0, 3), (1, 4), (6, 2), (6, 5)], two(), [1, 1]),
        ex(
            "3D3B, p3 on the rod of p1 and p2",
            7,
            &[(0, 3), (0, 4), (6, 0), (6, 5)],
            two(),
            [3, 3],
        ),
        ex(
            "3D4 spatial body",
            6,
            &[(3, 4), (4, 5), (3, 0), (4, 1), (5, 2)],
            vec![spatial(&[0, 1, 2])],
            [1, 1],
        ),
        ex(
            "3D4 planar body",
            6,
            &[(3, 4), (4, 5), (3, 0), (4, 1), (5, 2)],
            vec![planar(&[0, 1, 2])],
            [1, 1],
        ),
        ex(
            "3D4, body contacts on one rod",
            6,
            &[(3, 4), (4, 5), (3, 0), (4, 0), (5, 0)],
            vec![spatial(&[0, 1, 2])],
            [4, 4],
        ),
        ex(
            "triangle through a body",
            5,
            &[(3, 4), (3, 0), (4, 1)],
            vec![spatial(&[0, 1, 2])],
            [3, 3],
        ),
        ex("3D6 K_{2,4} of rods", 6, &K24, vec![], [1, 1]),
        ex(
            "4-cycle of rods",
            4,
            &[(0, 1), (1, 2), (2, 3), (3, 0)],
            vec![],
            [4, 4],
        ),
        ex("K_{2,3} of rods", 5, &k23, vec![], [5, 5]),
    ]
}

/// One row of the table: the range of nodes left over the motif orders tried.
#[derive(Clone, Debug, Serialize)]
pub struct ExampleRow {
    pub name: &'static str,
    pub sound: String,
    pub expect_sound: usize,
    pub paper: String,
    pub expect_paper: usize,
    pub pass: bool,
}

/// Compresses every example with `seeds` motif orders under both rule sets.
pub fn check_all(seeds: u64) -> Vec<ExampleRow> {
    all()
        .into_iter()
        .map(|e| {
            let g = e.graph();
            let range = |rules: RuleSet| {
                let nodes: Vec<usize> = (0..seeds)
                    .map(|s| {
                        compress_from(&g, &e.bodies, rules, s)
                            .expect("examples declare valid bodies")
                            .components
                    })
                    .collect();
                let (lo, hi) = (
                    *nodes.iter().min().unwrap_or(&0),
                    *nodes.iter().max().unwrap_or(&0),
                );
                (lo, hi)
            };
            let (s, p) = (range(RuleSet::Sound), range(RuleSet::Paper));
            let show = |(lo, hi): (usize, usize)| {
                if lo == hi {
                    lo.to_string()
                } else {
                    format!("{lo}-{hi}")
                }
            };
            ExampleRow {
                name: e.name,
                sound: show(s),
                expect_sound: e.expect[0],
                paper: show(p),
                expect_paper: e.expect[1],
                pass: s == (e.expect[0], e.expect[0]) && p == (e.expect[1], e.expect[1]),
            }
        })
        .collect()
}

/// A seeded random graph (each pair joined with probability `p`): dense
/// enough, near `p = 1/80`, to exercise every motif in engine checks.
pub fn random_graph(n: usize, p: f64, seed: u64) -> ContactGraph {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut edges = Vec::new();
    for i in 0..n as u32 {
        for j in i + 1..n as u32 {
            if rng.random::<f64>() < p {
                edges.push([i, j]);
            }
        }
    }
    ContactGraph::new(n, edges).expect("pairs are distinct")
}
