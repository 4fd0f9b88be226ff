use rgc::contacts;
use rgc::engine::{Engine, RuleSet};
use rgc::graph::ContactGraph;
use rgc::rods::{RodParams, RodSystem};
use rgc::truth::{Topology, TruthOptions, truth};

#[test]
fn exp() {
    for rho in [30.0, 33.0, 36.0, 40.0, 45.0] {
        for seed in 1..=3 {
            let system = RodSystem::generate(RodParams::new(23.0, 3.0, rho).unwrap(), seed);
            let cs = contacts::detect(&system);
            let inner: Vec<[u32; 2]> = cs
                .iter()
                .filter(|c| c.shift == [0, 0, 0])
                .map(|c| c.rods)
                .collect();
            let g = ContactGraph::new(system.len(), inner).unwrap();
            let t = truth(&Topology::finite(&g), TruthOptions::default());
            let runs = Engine::base(RuleSet::Sound).runs(&g, 1, 10);
            let best = runs.iter().map(|r| r.largest_rods()).max().unwrap();
            let gp = ContactGraph::from_contacts(system.len(), &cs);
            let sh: Vec<[i32; 3]> = cs.iter().map(|c| c.shift).collect();
            let tp = truth(
                &Topology::periodic(&gp, &sh).unwrap(),
                TruthOptions::default(),
            );
            let runsp = Engine::base(RuleSet::Sound).runs(&gp, 1, 10);
            let bestp = runsp.iter().map(|r| r.largest_rods()).max().unwrap();
            let tq = truth(&Topology::finite(&gp), TruthOptions::default());
            println!("quotient truth {} dof {:?}", tq.largest_cluster(), tq.dof);
            println!(
                "rho {rho} seed {seed}: finite truth {} (dof {:?}) rgc {} | periodic truth {} (dof {:?}) rgc {}",
                t.largest_cluster(),
                t.dof,
                best,
                tp.largest_cluster(),
                tp.dof,
                bestp
            );
        }
    }
}

#[test]
fn exp_subgraphs() {
    use rgc::pattern::Pattern;
    use rgc::rigidity::check_exact;
    let mut compared = 0;
    let mut mismatch = 0;
    for seed in 1..=6 {
        let system = RodSystem::generate(RodParams::new(23.0, 3.0, 45.0).unwrap(), seed);
        let cs = contacts::detect(&system);
        let inner: Vec<[u32; 2]> = cs
            .iter()
            .filter(|c| c.shift == [0, 0, 0])
            .map(|c| c.rods)
            .collect();
        let g = ContactGraph::new(system.len(), inner).unwrap();
        for start in (0..g.n_nodes() as u32).step_by(37) {
            for size in [14usize, 18, 22] {
                // BFS ball of `size` rods.
                let mut take = vec![start];
                let mut i = 0;
                while take.len() < size && i < take.len() {
                    for &(m, _) in g.neighbors(take[i]) {
                        if take.len() < size && !take.contains(&m) {
                            take.push(m);
                        }
                    }
                    i += 1;
                }
                take.sort();
                let idx = |r: u32| take.binary_search(&r).ok();
                let mut edges = vec![];
                for &[a, b] in g.edges() {
                    if let (Some(x), Some(y)) = (idx(a), idx(b)) {
                        edges.push([x as u32, y as u32]);
                    }
                }
                let sub = ContactGraph::new(take.len(), edges).unwrap();
                if sub.n_edges() > 96 || sub.n_edges() < 10 {
                    continue;
                }
                let t = truth(&Topology::finite(&sub), TruthOptions::default());
                let Ok(p) = Pattern::from_graph(&sub) else {
                    continue;
                };
                let Ok(v) = check_exact(&p, 1) else { continue };
                let forced = &v.components[0];
                compared += 1;
                let runs = Engine::base(RuleSet::Sound).runs(&sub, 1, 10);
                let one = runs.iter().any(|r| r.components == 1);
                let big_truth = t.largest_cluster();
                let big_rgc = runs.iter().map(|r| r.largest_rods()).max().unwrap();
                if v.class == "rigid" && !one {
                    println!(
                        "RGC MISSES rigid {} (n={}, e={}) rgc largest {big_rgc}",
                        rgc::graph::io::to_graph6(&sub),
                        sub.n_nodes(),
                        sub.n_edges()
                    );
                }
                if big_truth > big_rgc {
                    println!(
                        "cluster gap {} truth {big_truth} rgc {big_rgc} class {}",
                        rgc::graph::io::to_graph6(&sub),
                        v.class
                    );
                }
                if t.dof != Some(forced.dof) {
                    mismatch += 1;
                    println!(
                        "MISMATCH {} truth {:?} forced {:?} ({}) class {}",
                        rgc::graph::io::to_graph6(&sub),
                        t.dof,
                        forced.dof,
                        forced.built,
                        v.class
                    );
                }
            }
        }
    }
    println!("compared {compared} mismatches {mismatch}");
}

#[test]
fn exp_contain() {
    use rgc::spanning::Criterion;
    let mut bodies = 0;
    let mut inside = 0;
    for rho in [33.0, 36.0, 40.0, 45.0] {
        for seed in 1..=4 {
            let system = RodSystem::generate(RodParams::new(23.0, 4.0, rho).unwrap(), seed);
            let cs = contacts::detect(&system);
            let g = ContactGraph::from_contacts(system.len(), &cs);
            let t =
                rgc::truth::of_system(&system, &cs, &g, Criterion::Wrap, TruthOptions::default());
            let mut cl_of: Vec<Vec<usize>> = vec![vec![]; system.len()];
            for (i, c) in t.clusters.iter().enumerate() {
                for &r in &c.rods {
                    cl_of[r as usize].push(i);
                }
            }
            for rules in [RuleSet::Sound, RuleSet::Paper] {
                for run in Engine::base(rules).runs(&g, seed, 4) {
                    for b in &run.bodies {
                        bodies += 1;
                        let ok = cl_of[b.rods[0] as usize]
                            .iter()
                            .any(|&i| b.rods.iter().all(|r| cl_of[*r as usize].contains(&i)));
                        if ok {
                            inside += 1
                        } else {
                            println!(
                                "NOT INSIDE rho {rho} seed {seed} {rules:?} body {} rods",
                                b.rods.len()
                            );
                        }
                    }
                }
            }
        }
    }
    println!("bodies {bodies} inside {inside}");
}

#[test]
fn exp_time() {
    use std::time::Instant;
    let system = RodSystem::generate(RodParams::new(23.0, 5.0, 48.0).unwrap(), 1);
    let cs = contacts::detect(&system);
    let gp = ContactGraph::from_contacts(system.len(), &cs);
    let sh: Vec<[i32; 3]> = cs.iter().map(|c| c.shift).collect();
    let t0 = Instant::now();
    let tp = truth(
        &Topology::periodic(&gp, &sh).unwrap(),
        TruthOptions::default(),
    );
    println!(
        "periodic {:.3}s rank {:?} front {:?}",
        t0.elapsed().as_secs_f64(),
        tp.rank,
        tp.largest_cluster()
    );
    let t0 = Instant::now();
    let tq = truth(&Topology::finite(&gp), TruthOptions::default());
    println!(
        "finite {:.3}s rank {:?} {:?}",
        t0.elapsed().as_secs_f64(),
        tq.rank,
        tq.largest_cluster()
    );
}

#[test]
fn exp_profile() {
    use rand::SeedableRng;
    use rgc::truth::*;
    use std::time::Instant;
    let system = RodSystem::generate(RodParams::new(23.0, 5.0, 44.0).unwrap(), 1);
    let cs = contacts::detect(&system);
    let g = ContactGraph::from_contacts(system.len(), &cs);
    let sh: Vec<[i32; 3]> = cs.iter().map(|c| c.shift).collect();
    let topo = Topology::periodic(&g, &sh).unwrap();
    let t = Instant::now();
    let core = prune::two_core(&g);
    let planes = planes::forced(&topo, &core.active).unwrap();
    println!("planes {:.3}", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let ord = order::order(&topo, &planes, &core.active).unwrap();
    println!("order {:.3}", t.elapsed().as_secs_f64());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let t = Instant::now();
    let real = realize::build(&topo, &planes, &core.active, &ord, &mut rng).unwrap();
    println!("realize {:.3}", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let parts = matrix::parts(&planes, &core.active);
    let rows = matrix::rows(&topo, &planes, &parts, &real);
    println!(
        "rows {:.3} ({} rows, {} parts)",
        t.elapsed().as_secs_f64(),
        rows.len(),
        parts.count
    );
    let t = Instant::now();
    let e = rgc::math::sparse::eliminate(&rows, parts.count, 6, 2, &mut rng);
    println!(
        "eliminate {:.3} rank {} front {:?}",
        t.elapsed().as_secs_f64(),
        e.rank,
        e.largest_front
    );
    let t = Instant::now();
    let cl = clusters::clusters(&topo, &parts, &real, &e.kernel);
    println!("clusters {:.3} {}", t.elapsed().as_secs_f64(), cl.len());
}
