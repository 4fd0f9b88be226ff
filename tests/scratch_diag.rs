#[test]
fn diag() {
    use rgc::threshold::sequence::Sequence;
    use rgc::truth::*;
    let seq = Sequence::new(23.0, 4.0, 2134, 14287079109765344090).unwrap();
    let g = seq.graph(2134);
    let cs = seq.contacts_of(2134);
    let sh: Vec<[i32; 3]> = cs.iter().map(|c| c.shift).collect();
    let topo = Topology::periodic(&g, &sh).unwrap();
    let t = truth(&topo, Default::default());
    println!("REASON {:?}", t.reason);
    let core = prune::two_core(&g);
    let planes = planes::forced(&topo, &core.active).unwrap();
    let ord = order::order(&topo, &planes, &core.active).unwrap();
    let pos = |r: u32| ord.iter().position(|&x| x == r).unwrap();
    for r in [1770u32, 56, 396, 474, 332, 1163, 1859] {
        println!(
            "rod {r} pos {} classes {:?} nbs {:?}",
            pos(r),
            planes.of_rod[r as usize],
            g.neighbors(r)
                .iter()
                .filter(|(m, _)| core.active[*m as usize])
                .map(|&(m, e)| (m, planes.inside[e as usize], pos(m)))
                .collect::<Vec<_>>()
        );
    }
}
