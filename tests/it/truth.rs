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
            assert_eq!(t.dof, Some(v.components[0].dof), "{g6}: forced family {:?}", v.components[0]);
            if v.class == "component-dependent" {
                component_dependent += 1;
            }
            compared += 1;
        }
    }
    assert_eq!(compared, 7 + 55 + 467);
    assert!(component_dependent > 0);
}
