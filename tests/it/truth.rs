//! Truth on whole graphs against the exact motif verdict and the engine.

use rgc::graph::io::read_graph6_file;
use rgc::pattern::Pattern;
use rgc::rigidity::check_exact;
use rgc::truth::{Method, Topology, TruthOptions, truth};
use std::path::Path;

/// On every rods-only candidate with up to 7 rods, truth is rigid exactly
/// where the motif verdict is rigid on every component; and its DOF is
/// that of the forced family (the first component the verdict lists).
#[test]
fn truth_agrees_with_check_on_every_candidate_up_to_7_rods() {
    let mut compared = 0;
    let mut component_dependent = 0;
    for n in 5..=7 {
        let path = format!("graphs/maxwell-mindeg2-n{n}.g6");
        for g in read_graph6_file(Path::new(&path)).unwrap() {
            let t = truth(&Topology::finite(&g), TruthOptions::default());
            let v = check_exact(&Pattern::from_graph(&g).unwrap(), 1).unwrap();
            let g6 = rgc::graph::io::to_graph6(&g);
            assert_eq!(t.method, Method::Exact, "{g6}: {:?}", t.reason);
            assert_eq!(t.twins_agree, Some(true), "{g6}");
            let rigid = t.dof == Some(0);
            assert_eq!(rigid, v.class == "rigid", "{g6}: truth {t:?} check {v:?}");
            assert_eq!(
                t.dof,
                Some(v.components[0].dof),
                "{g6}: forced family {:?}",
                v.components[0]
            );
            if v.class == "component-dependent" {
                component_dependent += 1;
            }
            compared += 1;
        }
    }
    assert_eq!(compared, 7 + 55 + 467);
    assert!(component_dependent > 0);
}

/// Every rods-only candidate with up to 8 rods that `sound` compresses to
/// one node in some of 128 motif orders although it is not rigid: there
/// are 32 (2 with 7 rods, 30 with 8), truth is flexible on every one, and
/// `certified` never compresses one to a single node in 64 orders.
#[test]
fn truth_and_certified_reject_every_false_compression_up_to_8_rods() {
    use rayon::prelude::*;
    use rgc::audit::compresses;
    use rgc::engine::{Engine, RuleSet};
    use rgc::enumerate::{GraphFilter, connected_graphs};
    let sound = Engine::base(RuleSet::Sound);
    let certified = Engine::base(RuleSet::Certified);
    let mut per_size = Vec::new();
    for n in 7..=8 {
        let filter = GraphFilter::maxwell_rods(n).with_min_degree(2);
        let graphs = connected_graphs(n, &filter).unwrap();
        let found: Vec<String> = graphs
            .par_iter()
            .filter_map(|g| {
                let p = Pattern::from_graph(g).unwrap();
                let t = truth(&Topology::finite(g), TruthOptions::default());
                let v = check_exact(&p, 1).unwrap();
                let g6 = rgc::graph::io::to_graph6(g);
                assert_eq!(t.dof == Some(0), v.class == "rigid", "{g6}");
                if v.class == "rigid" || !compresses(&sound, &p, 128).unwrap() {
                    return None;
                }
                assert_ne!(t.dof, Some(0), "{g6}: truth must be flexible");
                assert!(
                    !compresses(&certified, &p, 64).unwrap(),
                    "{g6}: certified compressed a flexible graph"
                );
                Some(g6)
            })
            .collect();
        per_size.push(found.len());
    }
    assert_eq!(per_size, vec![2, 30]);
}
