//! Spanning criteria on hand-built and random rod systems.

use nalgebra::Vector3;
use rgc::contacts::{Contact, detect};
use rgc::graph::{ContactGraph, stats};
use rgc::rods::{Rod, RodParams, RodSystem};
use rgc::spanning::{Criterion, SpanChecker, cluster_spans, contact_spanning, spanning_clusters};

type V = Vector3<f64>;

struct Built {
    system: RodSystem,
    contacts: Vec<Contact>,
    graph: ContactGraph,
}

fn build(system: RodSystem) -> Built {
    let contacts = detect(&system);
    let graph = ContactGraph::from_contacts(system.len(), &contacts);
    Built {
        system,
        contacts,
        graph,
    }
}

fn from_rods(gamma: f64, l: f64, rods: Vec<Rod>) -> Built {
    let params = RodParams::new(gamma, l, rods.len().max(1) as f64 / l.powi(3)).unwrap();
    build(crate::cube(params, rods))
}

impl Built {
    fn spans(&self, rods: &[u32], criterion: Criterion) -> bool {
        cluster_spans(&self.system, &self.contacts, &self.graph, rods, criterion)
    }

    fn any_spans(&self, criterion: Criterion) -> bool {
        contact_spanning(&self.system, &self.contacts, &self.graph, criterion)
    }

    fn pairs(&self) -> Vec<([u32; 2], [i32; 3])> {
        self.contacts.iter().map(|c| (c.rods, c.shift)).collect()
    }
}

/// Moves coordinate 0 (the chain direction) to `axis`.
fn along(axis: usize, v: V) -> V {
    let mut out = V::zeros();
    for k in 0..3 {
        out[(k + axis) % 3] = v[k];
    }
    out
}

/// Four rods at spacing 0.75 along one axis of a box of side 3, tilted in
/// alternate directions so that neighbours cross: the last touches the image
/// of the first, closing a ring around the torus.
fn ring(axis: usize) -> Vec<Rod> {
    [0.25, 1.0, 1.75, 2.5]
        .iter()
        .enumerate()
        .map(|(k, &x)| {
            crate::unit(
                along(axis, V::new(x, 1.5, 1.5)),
                along(axis, V::new(1.0, if k % 2 == 0 { 0.2 } else { -0.2 }, 0.0)),
            )
        })
        .collect()
}

#[test]
fn ring_around_the_box_wraps_along_each_axis() {
    for axis in 0..3 {
        let b = from_rods(10.0, 3.0, ring(axis));
        let mut image = [0; 3];
        image[axis] = -1;
        assert_eq!(
            b.pairs(),
            vec![
                ([0, 1], [0, 0, 0]),
                ([0, 3], image),
                ([1, 2], [0, 0, 0]),
                ([2, 3], [0, 0, 0])
            ]
        );
        assert!(b.spans(&[0, 1, 2, 3], Criterion::Wrap));
        assert!(
            b.spans(&[3, 1, 0, 2], Criterion::Wrap),
            "order of rods matters"
        );
        assert!(b.any_spans(Criterion::Wrap));
        // It also pokes out of both faces along its axis.
        assert!(b.spans(&[0, 1, 2, 3], Criterion::Faces));
        assert!(b.any_spans(Criterion::Faces));
        // Any three rods of the ring form an open chain: no wrap.
        for skip in 0..4u32 {
            let rest: Vec<u32> = (0..4).filter(|&r| r != skip).collect();
            assert!(!b.spans(&rest, Criterion::Wrap), "without rod {skip}");
        }
    }
}

#[test]
fn ring_cut_once_does_not_wrap() {
    let mut rods = ring(0);
    rods.remove(1);
    let b = from_rods(10.0, 3.0, rods);
    assert_eq!(b.contacts.len(), 2);
    assert!(!b.spans(&[0, 1, 2], Criterion::Wrap));
    assert!(!b.any_spans(Criterion::Wrap));
    assert!(spanning_clusters(&b.system, &b.contacts, &b.graph, Criterion::Wrap).is_empty());
    // Its end rods still poke out of both x faces, but they are joined only
    // through the boundary: that is not spanning the primary cell.
    assert!(!b.spans(&[0, 1, 2], Criterion::Faces));
    assert!(!b.any_spans(Criterion::Faces));
}

#[test]
fn pair_straddling_a_face_does_not_span() {
    let l = 3.0;
    let b = from_rods(
        10.0,
        l,
        vec![
            crate::unit(V::new(0.1, 1.0, 1.0), V::x()),
            crate::unit(V::new(l - 0.1, 1.0, 1.05), V::x()),
        ],
    );
    assert_eq!(b.pairs(), vec![([0, 1], [-1, 0, 0])]);
    for criterion in [Criterion::Wrap, Criterion::Faces] {
        assert!(!b.spans(&[0, 1], criterion), "{criterion:?}");
        assert!(!b.any_spans(criterion), "{criterion:?}");
    }
}

#[test]
fn chain_between_faces_spans_faces_but_not_wrap() {
    // Five collinear rods along a slanted line from x = 0.3 to x = 3.36 in a
    // box of 3.8: the ends poke out of both x faces, but the line misses the
    // image of its own start by more than a rod diameter.
    let dir = V::new(1.0, 0.3, 0.0).normalize();
    let start = V::new(0.3, 1.0, 1.9);
    let rods: Vec<Rod> = (0..5)
        .map(|k| crate::unit(start + dir * (0.8 * k as f64), dir))
        .collect();
    let b = from_rods(10.0, 3.8, rods);
    let chain: Vec<([u32; 2], [i32; 3])> = (0..4).map(|k| ([k, k + 1], [0, 0, 0])).collect();
    assert_eq!(b.pairs(), chain);
    let all = [0, 1, 2, 3, 4];
    assert!(b.spans(&all, Criterion::Faces));
    assert!(!b.spans(&all, Criterion::Wrap));
    assert!(b.any_spans(Criterion::Faces));
    assert!(!b.any_spans(Criterion::Wrap));
    assert_eq!(
        spanning_clusters(&b.system, &b.contacts, &b.graph, Criterion::Faces),
        vec![all.to_vec()]
    );
    // Without an end rod it reaches only one face.
    assert!(!b.spans(&all[..4], Criterion::Faces));
    assert!(!b.spans(&all[1..], Criterion::Faces));
}

/// Rod A along x at height z = 1 ending near x = 0, rod B along x at z = 1.3
/// ending near x = L = 3, and a slanted rod M joining them inside the box.
/// `low` and `high` move A and B outwards (positive) or inwards (negative).
fn bridge(low: f64, high: f64, translate: V) -> Vec<Rod> {
    let a = crate::unit(V::new(0.55 - low, 1.0, 1.0), V::x());
    let m = crate::unit(V::new(1.5, 1.0, 1.15), V::new(1.0, 0.0, 0.3));
    let b = crate::unit(V::new(3.0 - 0.55 + high, 1.0, 1.3), V::x());
    [a, m, b]
        .into_iter()
        .map(|r| crate::unit(r.center + translate, r.axis))
        .collect()
}

#[test]
fn faces_uses_the_rod_extent_exactly() {
    // A rod along x pokes out of x = 0 iff center - 1/2 - r < 0 (r = 0.05).
    let cases = [
        (1e-9, 1e-9, true),
        (-1e-9, 1e-9, false),
        (1e-9, -1e-9, false),
    ];
    for (low, high, spans) in cases {
        let b = from_rods(10.0, 3.0, bridge(low, high, V::zeros()));
        assert_eq!(b.pairs(), vec![([0, 1], [0, 0, 0]), ([1, 2], [0, 0, 0])]);
        assert_eq!(b.spans(&[0, 1, 2], Criterion::Faces), spans, "{low} {high}");
        assert_eq!(b.any_spans(Criterion::Faces), spans);
        assert!(!b.any_spans(Criterion::Wrap));
        // Without the bridge, the two end rods are not joined.
        assert!(!b.spans(&[0, 2], Criterion::Faces));
    }
}

#[test]
fn stored_centers_outside_the_box_count_through_their_image() {
    for translate in [V::new(3.0, 0.0, 0.0), V::new(-6.0, 3.0, -3.0)] {
        let b = from_rods(10.0, 3.0, bridge(1e-6, 1e-6, translate));
        assert_eq!(b.pairs(), vec![([0, 1], [0, 0, 0]), ([1, 2], [0, 0, 0])]);
        assert!(b.spans(&[0, 1, 2], Criterion::Faces), "{translate:?}");
        let mut ring = ring(2);
        ring[1].center += translate;
        ring[3].center -= translate;
        let r = from_rods(10.0, 3.0, ring);
        assert_eq!(r.contacts.len(), 4);
        assert!(r.spans(&[0, 1, 2, 3], Criterion::Wrap), "{translate:?}");
        assert!(r.spans(&[0, 1, 2, 3], Criterion::Faces), "{translate:?}");
        assert!(!r.spans(&[0, 1, 3], Criterion::Faces), "{translate:?}");
    }
}

#[test]
fn wrap_tests_each_piece_of_a_disconnected_cluster() {
    // The ring along x and an open chain along y in a box of side 3.
    let mut rods = ring(0);
    let mut chain = ring(1);
    chain.truncate(3);
    for r in &mut chain {
        r.center.z += 1.0;
        r.center.x += 1.0;
    }
    rods.extend(chain);
    let b = from_rods(10.0, 3.0, rods);
    assert!(b.spans(&[4, 5, 6, 0, 1, 2, 3], Criterion::Wrap));
    assert!(!b.spans(&[4, 5, 6, 0, 1, 2], Criterion::Wrap));
    assert!(!b.spans(&[4, 5, 6], Criterion::Wrap));
    assert!(!b.spans(&[], Criterion::Wrap));
    assert_eq!(
        spanning_clusters(&b.system, &b.contacts, &b.graph, Criterion::Wrap),
        vec![vec![0, 1, 2, 3]]
    );
}

fn random(gamma: f64, l: f64, density: f64, seed: u64) -> Built {
    build(RodSystem::generate(
        RodParams::new(gamma, l, density).unwrap(),
        seed,
    ))
}

#[test]
fn dense_random_systems_span_and_sparse_ones_do_not() {
    // gamma = 10: V_ex = 0.224, so rho = 17.9 gives c0 ~ 4 and rho = 1.34 c0 ~ 0.3.
    for seed in 0..3 {
        let dense = random(10.0, 4.0, 17.9, seed);
        let c0 = stats(&dense.graph).c0;
        assert!((3.5..4.5).contains(&c0), "c0 {c0}");
        for criterion in [Criterion::Wrap, Criterion::Faces] {
            assert!(dense.any_spans(criterion), "{criterion:?} seed {seed}");
            let spanning =
                spanning_clusters(&dense.system, &dense.contacts, &dense.graph, criterion);
            assert_eq!(spanning.len(), 1, "one giant cluster");
            assert!(spanning[0].len() > dense.system.len() / 2);
            assert!(dense.spans(&spanning[0], criterion));
        }
        let sparse = random(10.0, 4.0, 1.34, seed);
        let c0 = stats(&sparse.graph).c0;
        assert!((0.1..0.5).contains(&c0), "c0 {c0}");
        for criterion in [Criterion::Wrap, Criterion::Faces] {
            assert!(!sparse.any_spans(criterion), "{criterion:?} seed {seed}");
        }
    }
}

/// The connected components of a graph, each sorted, by smallest rod.
fn components(graph: &ContactGraph) -> Vec<Vec<u32>> {
    let n = graph.n_nodes();
    let mut seen = vec![false; n];
    let mut out = Vec::new();
    for root in 0..n as u32 {
        if seen[root as usize] {
            continue;
        }
        seen[root as usize] = true;
        let mut comp = vec![root];
        let mut next = 0;
        while next < comp.len() {
            let i = comp[next];
            next += 1;
            for &(j, _) in graph.neighbors(i) {
                if !seen[j as usize] {
                    seen[j as usize] = true;
                    comp.push(j);
                }
            }
        }
        comp.sort_unstable();
        out.push(comp);
    }
    out
}

#[test]
fn cluster_test_agrees_with_whole_graph_scan_near_threshold() {
    // c0 ~ 1.5 in a small box: many clusters, some spanning by one criterion only.
    let mut checker = SpanChecker::new();
    let mut seen_spanning = [0; 2];
    for seed in 0..6 {
        let b = random(10.0, 3.0, 6.7, seed);
        let comps = components(&b.graph);
        for (c, criterion) in [Criterion::Wrap, Criterion::Faces].into_iter().enumerate() {
            let by_scan = spanning_clusters(&b.system, &b.contacts, &b.graph, criterion);
            let by_cluster: Vec<Vec<u32>> = comps
                .iter()
                .filter(|comp| {
                    let reused = checker.spans(&b.system, &b.contacts, &b.graph, comp, criterion);
                    assert_eq!(reused, b.spans(comp, criterion));
                    reused
                })
                .cloned()
                .collect();
            assert_eq!(by_scan, by_cluster, "{criterion:?} seed {seed}");
            assert_eq!(b.any_spans(criterion), !by_scan.is_empty());
            seen_spanning[c] += by_scan.len();
        }
    }
    assert!(seen_spanning.iter().all(|&s| s > 0), "{seen_spanning:?}");
}

#[test]
fn criterion_names() {
    use clap::ValueEnum;
    assert_eq!(Criterion::default(), Criterion::Wrap);
    assert_eq!(
        serde_json::to_string(&Criterion::Faces).unwrap(),
        "\"faces\""
    );
    assert_eq!(
        serde_json::from_str::<Criterion>("\"wrap\"").unwrap(),
        Criterion::Wrap
    );
    assert_eq!(
        Criterion::from_str("faces", false).unwrap(),
        Criterion::Faces
    );
}

/// The first `n` rods of `system` with their contacts.
fn prefix(system: &RodSystem, contacts: &[Contact], n: usize) -> (RodSystem, Vec<Contact>) {
    let rods = system.rods[..n].to_vec();
    let contacts = contacts
        .iter()
        .copied()
        .filter(|c| (c.rods[1] as usize) < n)
        .collect();
    let domain = system.domain;
    (RodSystem { domain, rods }, contacts)
}

#[test]
fn the_sweep_finds_the_first_spanning_prefix() {
    use rgc::spanning::{critical_rods, sort_by_sequence};
    // Around the contact threshold of gamma 10 in small boxes, both criteria.
    for (seed, l) in [(1, 3.0), (2, 3.0), (3, 3.5), (4, 4.0)] {
        let system = RodSystem::generate(RodParams::new(10.0, l, 12.0).unwrap(), seed);
        let mut contacts = detect(&system);
        sort_by_sequence(&mut contacts);
        for criterion in [Criterion::Wrap, Criterion::Faces] {
            let critical = critical_rods(&system, &contacts, criterion);
            let n_star = critical.expect("dense enough to span");
            assert!(n_star > 1, "seed {seed}");
            // Spanning of prefixes is monotone, and the sweep's n is the first.
            for n in [n_star - 1, n_star, (n_star + system.len()) / 2] {
                let (sub, cs) = prefix(&system, &contacts, n);
                let graph = ContactGraph::from_contacts(n, &cs);
                assert_eq!(
                    contact_spanning(&sub, &cs, &graph, criterion),
                    n >= n_star,
                    "seed {seed}, {criterion:?}, n {n}, n* {n_star}"
                );
            }
        }
    }
}

#[test]
fn the_sweep_agrees_with_the_cluster_walk_on_every_prefix() {
    use rgc::spanning::{Sweep, sort_by_sequence};
    let system = RodSystem::generate(RodParams::new(8.0, 3.0, 9.0).unwrap(), 11);
    let mut contacts = detect(&system);
    sort_by_sequence(&mut contacts);
    for criterion in [Criterion::Wrap, Criterion::Faces] {
        let mut sweep = Sweep::new(criterion);
        let mut next = 0;
        let mut changes = 0;
        for n in 1..=system.len() {
            sweep.add_rod(&system);
            while next < contacts.len() && contacts[next].rods[1] as usize == n - 1 {
                sweep.add_contact(&contacts[next]);
                next += 1;
            }
            let (sub, cs) = prefix(&system, &contacts, n);
            let graph = ContactGraph::from_contacts(n, &cs);
            let walk = contact_spanning(&sub, &cs, &graph, criterion);
            assert_eq!(sweep.spans(), walk, "{criterion:?}, n {n}");
            changes += usize::from(
                walk && n > 1
                    && !{
                        let (sub, cs) = prefix(&system, &contacts, n - 1);
                        contact_spanning(
                            &sub,
                            &cs,
                            &ContactGraph::from_contacts(n - 1, &cs),
                            criterion,
                        )
                    },
            );
        }
        assert_eq!(changes, 1, "{criterion:?}: spans from one n on");
    }
}

/// A zigzag of crossing rods from the floor to the ceiling of a slab
/// (periodic in x and y, walls at z = 0 and 2.9).
fn zigzag(periodic: rgc::rods::Periodic, skip: Option<usize>) -> Built {
    let rods = (0..4)
        .filter(|&k| Some(k) != skip)
        .map(|k| {
            let dx = if k % 2 == 0 { 0.6 } else { -0.6 };
            Rod::new(
                V::new(2.0, 2.0, 0.4 + 0.7 * k as f64),
                V::new(dx, 0.0, 0.8),
                1.0,
                0.05,
            )
        })
        .collect();
    let domain = rgc::rods::Domain::new([4.0, 4.0, 2.9], periodic).unwrap();
    build(RodSystem::new(domain, rods).unwrap())
}

/// Along an axis with walls nothing wraps: a cluster joining the two walls
/// spans under `Wrap` as under `Faces`, and one that does not, does not.
#[test]
fn a_cluster_joining_the_walls_of_a_slab_spans() {
    use rgc::rods::Periodic;
    let chain = zigzag(Periodic::Xy, None);
    assert_eq!(chain.contacts.len(), 3);
    assert!(chain.contacts.iter().all(|c| c.shift == [0; 3]));
    let all: Vec<u32> = (0..4).collect();
    for criterion in [Criterion::Wrap, Criterion::Faces] {
        assert!(chain.spans(&all, criterion), "{criterion:?}");
        assert!(contact_spanning(
            &chain.system,
            &chain.contacts,
            &chain.graph,
            criterion
        ));
        assert!(
            !chain.spans(&all[..3], criterion),
            "{criterion:?} without the top rod"
        );
    }
    let broken = zigzag(Periodic::Xy, Some(2));
    assert_eq!(broken.contacts.len(), 1);
    for criterion in [Criterion::Wrap, Criterion::Faces] {
        assert!(!contact_spanning(
            &broken.system,
            &broken.contacts,
            &broken.graph,
            criterion
        ));
    }
    // Periodic along z, the top rod's end meets the image of the bottom
    // one's: the chain closes on itself through the face and wraps.
    let ring = zigzag(Periodic::Xyz, None);
    assert_eq!(ring.contacts.len(), 4);
    assert!(ring.spans(&all, Criterion::Wrap));
}
