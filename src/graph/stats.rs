//! Contact numbers c0, c1, c2 and clustering of a contact graph (MODEL §1).

use petgraph::unionfind::UnionFind;
use serde::Serialize;

use super::adjacency::ContactGraph;

/// Contact statistics of a contact graph (MODEL §1).
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

/// Contact numbers and clustering of a contact graph (MODEL §1), in
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
    let core = graph.two_core().0;
    let c2 = largest_component_mean_degree(graph, &core);
    ContactStats {
        c0,
        c1,
        c2,
        clustering: average_clustering(graph),
    }
}

/// Mean degree `2 E_C / N_C` of the largest connected component `C` of the
/// subgraph induced by the `alive` nodes (ties: the component of the smallest
/// node); 0 if no node is alive. Components come from petgraph's union-find.
fn largest_component_mean_degree(graph: &ContactGraph, alive: &[bool]) -> f64 {
    let n = graph.n_nodes();
    let inside = |&[a, b]: &[u32; 2]| alive[a as usize] && alive[b as usize];
    let mut components = UnionFind::<u32>::new(n);
    for &[a, b] in graph.edges().iter().filter(|e| inside(e)) {
        components.union(a, b);
    }
    let root = components.into_labeling();
    // Nodes and degree sum of each component, at its root.
    let mut size = vec![(0usize, 0usize); n];
    for &[a, _] in graph.edges().iter().filter(|e| inside(e)) {
        size[root[a as usize] as usize].1 += 2;
    }
    for i in (0..n).filter(|&i| alive[i]) {
        size[root[i] as usize].0 += 1;
    }
    // In node order, a component first comes up at its smallest node.
    let mut best = (0usize, 0usize);
    for i in (0..n).filter(|&i| alive[i]) {
        let s = size[root[i] as usize];
        if s.0 > best.0 {
            best = s;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_component_and_its_ties() {
        // A triangle {0, 1, 2} and a path 3-4-5 of as many nodes: the tie
        // goes to the component of node 0; a fourth node on the path wins.
        let g = ContactGraph::new(6, vec![[0, 1], [1, 2], [2, 0], [3, 4], [4, 5]]).unwrap();
        let all = vec![true; 6];
        assert_eq!(largest_component_mean_degree(&g, &all), 2.0);
        let g = ContactGraph::new(7, vec![[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 6]]).unwrap();
        assert_eq!(largest_component_mean_degree(&g, &[true; 7]), 1.5);
        // Dead nodes split components and their edges do not count.
        let mut alive = vec![true; 7];
        alive[4] = false;
        assert_eq!(largest_component_mean_degree(&g, &alive), 2.0);
        assert_eq!(
            g.two_core().0,
            [true, true, true, false, false, false, false]
        );
        assert_eq!(largest_component_mean_degree(&g, &[false; 7]), 0.0);
    }
}
