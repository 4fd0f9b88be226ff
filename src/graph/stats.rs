//! Contact numbers c0, c1, c2 and clustering of a contact graph (MODEL §1).

use serde::Serialize;

use super::ContactGraph;

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
