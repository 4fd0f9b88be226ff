//! Contact detection: segment distance, cell list against all pairs, periodic
//! shifts, Philipse's law, and contact statistics.

use nalgebra::Vector3;
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rgc::contacts::{Contact, closest_points, detect, detect_all_pairs};
use rgc::graph::{ContactGraph, stats};
use rgc::rods::{Rod, RodParams, RodSystem};

type V = Vector3<f64>;

fn random_unit(rng: &mut ChaCha8Rng) -> V {
    loop {
        let v = V::new(
            2.0 * rng.random::<f64>() - 1.0,
            2.0 * rng.random::<f64>() - 1.0,
            2.0 * rng.random::<f64>() - 1.0,
        );
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

fn random_perpendicular(rng: &mut ChaCha8Rng, u: &V) -> V {
    loop {
        let w = random_unit(rng);
        let p = w - u * u.dot(&w);
        if p.norm() > 0.1 {
            return p.normalize();
        }
    }
}

/// Distance of point `x` from the segment `q + t v`, `|t| <= 1/2`, by exact projection.
fn point_segment(x: &V, q: &V, v: &V) -> f64 {
    let t = (v.dot(&(x - q)) / v.norm_squared()).clamp(-0.5, 0.5);
    (x - q - v * t).norm()
}

/// Reference segment distance: ternary search over `s` of the exact distance
/// from `p + s u` to the other segment, which is convex in `s`.
fn reference_distance(p: &V, u: &V, q: &V, v: &V) -> f64 {
    let g = |s: f64| point_segment(&(p + u * s), q, v);
    let (mut lo, mut hi) = (-0.5f64, 0.5f64);
    let mut best = g(lo).min(g(hi));
    for _ in 0..200 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        let (g1, g2) = (g(m1), g(m2));
        best = best.min(g1).min(g2);
        if g1 < g2 {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    best.min(g(0.5 * (lo + hi)))
}

/// Checks `closest_points` against the reference and its own invariants.
fn check_pair(p: &V, u: &V, q: &V, v: &V) {
    let c = closest_points(p, u, 0.5, q, v, 0.5);
    assert!(
        (-0.5..=0.5).contains(&c.s) && (-0.5..=0.5).contains(&c.t),
        "parameters out of range: {c:?}"
    );
    let direct = (p + u * c.s - q - v * c.t).norm_squared();
    assert!(
        (direct - c.dist2).abs() <= 1e-12 * (1.0 + direct),
        "dist2 {} is not the distance of the returned points {direct}",
        c.dist2
    );
    let reference = reference_distance(p, u, q, v);
    let got = c.dist2.sqrt();
    assert!(
        (got - reference).abs() < 1e-9,
        "distance {got} vs reference {reference} (diff {:e}) for p={p:?} u={u:?} q={q:?} v={v:?}",
        got - reference
    );
}

#[test]
fn closest_points_random_pairs_match_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..5000 {
        // Box-like coordinates, with second centers near enough to be interesting.
        let p = V::new(
            rng.random::<f64>() * 15.0,
            rng.random::<f64>() * 15.0,
            rng.random::<f64>() * 15.0,
        );
        let q = p + random_unit(&mut rng) * (2.0 * rng.random::<f64>());
        let (u, v) = (random_unit(&mut rng), random_unit(&mut rng));
        check_pair(&p, &u, &q, &v);
    }
}

#[test]
fn closest_points_near_parallel_pairs_match_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let angles = [
        1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 0.0,
    ];
    let dist = |p: &V, u: &V, q: &V, v: &V| closest_points(p, u, 0.5, q, v, 0.5).dist2.sqrt();
    for &angle in &angles {
        for antiparallel in [false, true] {
            for _ in 0..150 {
                let p = V::new(
                    rng.random::<f64>() * 10.0,
                    rng.random::<f64>() * 10.0,
                    rng.random::<f64>() * 10.0,
                );
                let u = random_unit(&mut rng);
                let e = random_perpendicular(&mut rng, &u);
                let mut v = (u * f64::cos(angle) + e * f64::sin(angle)).normalize();
                if antiparallel {
                    v = -v;
                }
                // Crossing (the lines meet at given parameters), collinear-ish
                // offsets along the axis, and small sideways offsets.
                let s0 = 1.4 * rng.random::<f64>() - 0.7;
                let t0 = 1.4 * rng.random::<f64>() - 0.7;
                let crossing = p + u * s0 - v * t0;
                check_pair(&p, &u, &crossing, &v);
                if s0.abs() <= 0.5 && t0.abs() <= 0.5 {
                    // The segments share the point p + s0 u.
                    let d = dist(&p, &u, &crossing, &v);
                    assert!(d < 1e-9, "crossing segments {d} apart (angle {angle})");
                }
                let along = 3.0 * rng.random::<f64>() - 1.5;
                let side = random_perpendicular(&mut rng, &u);
                for offset in [0.0, 1e-9, 1e-6, 1e-3, 0.05, 0.3] {
                    let q = p + u * along + side * offset;
                    check_pair(&p, &u, &q, &v);
                    check_pair(&q, &v, &p, &u);
                    let (d, back) = (dist(&p, &u, &q, &v), dist(&q, &v, &p, &u));
                    assert!((d - back).abs() < 1e-12, "not symmetric: {d} vs {back}");
                    if along.abs() <= 0.5 {
                        // q lies `offset` from p + along u, a point of the first segment.
                        assert!(d <= offset + 1e-9, "{d} > {offset} (angle {angle})");
                    }
                }
            }
        }
    }
}

#[test]
fn closest_points_exact_cases() {
    let x = V::x();
    let y = V::y();
    let o = V::zeros();
    let cases: [(V, V, V, V, f64); 9] = [
        // Collinear overlapping, collinear disjoint, and antiparallel versions.
        (o, x, V::new(0.3, 0.0, 0.0), x, 0.0),
        (o, x, V::new(1.5, 0.0, 0.0), x, 0.5),
        (o, x, V::new(-1.25, 0.0, 0.0), -x, 0.25),
        // Parallel side by side, overlapping and shifted past the end.
        (o, x, V::new(0.4, 0.1, 0.0), x, 0.1),
        (o, x, V::new(1.3, 0.4, 0.0), x, 0.5),
        // Perpendicular crossing and skew.
        (o, x, V::new(0.2, 0.0, 0.0), y, 0.0),
        (o, x, V::new(0.2, 0.0, 0.7), y, 0.7),
        // Perpendicular, missing the end: closest to the endpoint (0.5, 0, 0).
        (o, x, V::new(0.8, 0.0, 0.0), y, 0.3),
        // T-junction: the second segment's end touches the first's middle.
        (o, x, V::new(0.1, 0.5, 0.0), y, 0.0),
    ];
    for (p, u, q, v, want) in cases {
        let c = closest_points(&p, &u, 0.5, &q, &v, 0.5);
        assert!(
            (c.dist2.sqrt() - want).abs() < 1e-12,
            "p={p:?} u={u:?} q={q:?} v={v:?}: got {c:?}, want distance {want}"
        );
    }
    // Exactly parallel overlapping: any minimizer, but always the same one.
    let q = V::new(0.3, 0.2, 0.0);
    let a = closest_points(&o, &x, 0.5, &q, &x, 0.5);
    let b = closest_points(&o, &x, 0.5, &q, &x, 0.5);
    assert_eq!(a, b);
    assert!((a.dist2 - 0.04).abs() < 1e-15);
}

fn system(gamma: f64, box_len: f64, density: f64, seed: u64) -> RodSystem {
    RodSystem::generate(RodParams::new(gamma, box_len, density).unwrap(), seed)
}

/// A random system plus rods crowded at the faces, edges and corners, and a
/// few centers exactly on or just outside the box, so that images matter.
fn boundary_system(
    gamma: f64,
    box_len: f64,
    n_random: usize,
    n_edge: usize,
    seed: u64,
) -> RodSystem {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let l = box_len;
    let mut rods = Vec::new();
    for _ in 0..n_random {
        let c = V::new(
            rng.random::<f64>() * l,
            rng.random::<f64>() * l,
            rng.random::<f64>() * l,
        );
        rods.push(crate::unit(c, random_unit(&mut rng)));
    }
    for k in 0..n_edge {
        // Each coordinate near 0, near L, or anywhere: faces, edges and corners.
        let coord = |rng: &mut ChaCha8Rng| match rng.random_range(0..3) {
            0 => rng.random::<f64>() * 0.15,
            1 => l - rng.random::<f64>() * 0.15,
            _ => rng.random::<f64>() * l,
        };
        let mut c = V::new(coord(&mut rng), coord(&mut rng), coord(&mut rng));
        if k % 17 == 0 {
            c.x = 0.0;
        }
        if k % 19 == 0 {
            c.y = l * (1.0 - f64::EPSILON);
        }
        rods.push(crate::unit(c, random_unit(&mut rng)));
    }
    // A few stored centers outside the primary box: their shifts must still be right.
    for c in [
        V::new(-0.02, 0.5 * l, 0.01),
        V::new(l + 0.03, l - 0.01, 0.5 * l),
        V::new(0.5 * l, -0.04, l + 0.02),
    ] {
        rods.push(crate::unit(c, random_unit(&mut rng)));
    }
    // Exactly parallel rods across a face, one of them exactly on it.
    rods.push(crate::unit(V::new(0.0, 0.3 * l, 0.3 * l), V::x()));
    rods.push(crate::unit(
        V::new(l - 0.6, 0.3 * l + 0.01, 0.3 * l),
        V::x(),
    ));
    let density = rods.len() as f64 / l.powi(3);
    crate::cube(RodParams::new(gamma, l, density).unwrap(), rods)
}

/// Checks the conventions of every contact against the rods it names.
fn check_contacts(system: &RodSystem, contacts: &[Contact]) {
    let l = system.domain.sides[0];
    let two_r = 2.0 * system.max_radius();
    for w in contacts.windows(2) {
        assert!(w[0].rods < w[1].rods, "contacts not sorted or repeated");
    }
    for c in contacts {
        let [i, j] = c.rods;
        assert!(i < j && (j as usize) < system.len());
        let (a, b) = (&system.rods[i as usize], &system.rods[j as usize]);
        let s = V::new(c.shift[0] as f64, c.shift[1] as f64, c.shift[2] as f64);
        let q = b.center + s * l;
        assert!(
            (q - a.center).norm() < 1.0 + two_r + 1e-12,
            "shift {:?} is not the touching image",
            c.shift
        );
        let cp = closest_points(&a.center, &a.axis, 0.5, &q, &b.axis, 0.5);
        assert!(
            cp.dist2.sqrt() < two_r + 1e-12,
            "rods {i}, {j} do not touch"
        );
        assert!(reference_distance(&a.center, &a.axis, &q, &b.axis) < two_r + 1e-9);
        // The parameters realize the least distance (exactly parallel
        // overlapping rods have many pairs of closest points, and which one
        // wins is a matter of rounding).
        let [s, t] = c.params;
        assert!(
            s.abs() <= 0.5 && t.abs() <= 0.5,
            "parameters {s}, {t} off the cores"
        );
        let at = (a.at(s) - (q + b.axis * t)).norm();
        assert!(
            (at - cp.dist2.sqrt()).abs() < 1e-9,
            "rods {i}, {j}: the parameters give distance {at}, the least is {}",
            cp.dist2.sqrt()
        );
        let mid = (a.at(c.params[0]) + q + b.axis * c.params[1]) * 0.5;
        for k in 0..3 {
            assert!(
                (0.0..l).contains(&c.point[k]),
                "point {:?} outside the box",
                c.point
            );
            let d = (mid[k] - c.point[k]) / l;
            assert!(
                (d - d.round()).abs() * l < 1e-9,
                "point {:?} is not the midpoint {mid:?} modulo L",
                c.point
            );
        }
    }
}

#[test]
fn detect_matches_all_pairs_on_random_systems() {
    // (gamma, L, rho): boxes from little more than two rod lengths up.
    let cases = [
        (5.0, 2.5, 20.0),
        (23.0, 3.0, 60.0),
        (23.0, 3.2, 60.0),
        (5.0, 4.5, 5.0),
        (23.0, 4.5, 30.0),
        (5.0, 6.0, 2.0),
    ];
    for (k, &(gamma, l, rho)) in cases.iter().enumerate() {
        for seed in 0..3 {
            let sys = system(gamma, l, rho, 100 * k as u64 + seed);
            let fast = detect(&sys);
            let slow = detect_all_pairs(&sys);
            assert!(
                (100..20_000).contains(&fast.len()),
                "gamma {gamma} L {l}: {} contacts is not the intended regime",
                fast.len()
            );
            assert_eq!(fast, slow, "gamma {gamma} L {l} rho {rho} seed {seed}");
            check_contacts(&sys, &fast);
        }
    }
}

#[test]
fn detect_matches_all_pairs_with_rods_at_faces_and_corners() {
    for (k, &(gamma, l)) in [
        (5.0, 3.7),
        (23.0, 3.2),
        (23.0, 4.5),
        (10.0, 5.0),
        (98.0, 2.1),
        (98.0, 3.0),
    ]
    .iter()
    .enumerate()
    {
        let sys = boundary_system(gamma, l, 300, 700, k as u64);
        let fast = detect(&sys);
        let slow = detect_all_pairs(&sys);
        assert!(fast.len() > 100, "only {} contacts", fast.len());
        assert_eq!(fast, slow, "gamma {gamma} L {l}");
        // Many contacts must go through a periodic image, or the test is moot.
        let through_images = fast.iter().filter(|c| c.shift != [0, 0, 0]).count();
        assert!(
            through_images > 20,
            "only {through_images} contacts cross the boundary"
        );
        check_contacts(&sys, &fast);
    }
}

#[test]
fn detect_matches_all_pairs_at_gamma_98_and_thick_rods() {
    // (gamma, L, rho, minimum contacts): gamma 98 at its working density in a
    // small box and in the smallest box allowed (L > 2(l + 2r) = 2.041), and
    // thick rods, whose radius exceeds the grid's cells (gamma 1: r = 1/2).
    let cases = [
        (98.0, 3.0, 190.0, 6_000),
        (98.0, 2.05, 190.0, 2_000),
        (5.0, 2.45, 10.0, 50),
        (5.0, 6.0, 3.0, 500),
        (1.0, 4.2, 2.0, 1_000),
    ];
    for &(gamma, l, rho, min_contacts) in &cases {
        for seed in 0..2 {
            let sys = system(gamma, l, rho, 50 + seed);
            let fast = detect(&sys);
            assert!(
                fast.len() >= min_contacts,
                "gamma {gamma} L {l}: only {} contacts",
                fast.len()
            );
            assert_eq!(
                fast,
                detect_all_pairs(&sys),
                "gamma {gamma} L {l} seed {seed}"
            );
            check_contacts(&sys, &fast);
        }
    }
}

#[test]
fn detect_matches_all_pairs_in_a_sparse_large_box() {
    // 2160 rods in a box of side 60: the grid coarsens to a few cells per
    // rod, each far longer than a rod.
    let sys = system(10.0, 60.0, 0.01, 4);
    let mut crowded = sys.rods.clone();
    // Clusters, so that there are contacts to find.
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for k in 0..600 {
        let base = sys.rods[k % 20].center;
        let center = base + random_unit(&mut rng) * rng.random::<f64>();
        crowded.push(Rod::new(
            center,
            random_unit(&mut rng),
            1.0,
            sys.rods[0].radius,
        ));
    }
    let sys = RodSystem {
        domain: sys.domain,
        rods: crowded,
    };
    let fast = detect(&sys);
    assert!(fast.len() > 300, "only {} contacts", fast.len());
    assert_eq!(fast, detect_all_pairs(&sys));
    check_contacts(&sys, &fast);
}

/// Rods exactly along the axes (some axis components exactly zero) with
/// centers on a lattice of step 1/12, so that many rod ends, centers and
/// sides lie exactly on cell faces (cells of side 1/3 in a box of side 4).
fn axis_aligned_system(gamma: f64, n: usize, seed: u64) -> RodSystem {
    let l: f64 = 4.0;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let dirs = [V::x(), V::y(), V::z(), -V::x(), -V::y(), -V::z()];
    let two_r = 1.0 / gamma;
    let mut rods = Vec::new();
    for k in 0..n {
        let lattice = |rng: &mut ChaCha8Rng| rng.random_range(0..48) as f64 / 12.0;
        let mut center = V::new(lattice(&mut rng), lattice(&mut rng), lattice(&mut rng));
        let axis = dirs[rng.random_range(0..6)];
        if k % 3 == 1 {
            // Beside the previous rod: exactly 2r away (not touching, as
            // contact needs a distance below 2r), or just inside or outside.
            let prev: &Rod = &rods[k - 1];
            let side = [V::x(), V::y(), V::z()]
                .into_iter()
                .find(|d| d.dot(&prev.axis) == 0.0)
                .unwrap();
            let gap = two_r * [1.0, 1.0 - 1e-12, 1.0 + 1e-12, 0.5][k % 4];
            center = prev.center + side * gap + prev.axis * (rng.random_range(-4..=4) as f64 / 8.0);
        }
        rods.push(crate::unit(center, axis));
    }
    let density = rods.len() as f64 / l.powi(3);
    crate::cube(RodParams::new(gamma, l, density).unwrap(), rods)
}

#[test]
fn detect_matches_all_pairs_for_axis_aligned_rods_on_cell_faces() {
    for (gamma, n) in [(23.0, 1500), (98.0, 3000), (5.0, 600)] {
        for seed in 0..2 {
            let sys = axis_aligned_system(gamma, n, seed);
            let fast = detect(&sys);
            assert!(
                fast.len() > n / 4,
                "gamma {gamma}: only {} contacts",
                fast.len()
            );
            assert_eq!(fast, detect_all_pairs(&sys), "gamma {gamma} seed {seed}");
            check_contacts(&sys, &fast);
        }
    }
}

#[test]
fn detect_matches_all_pairs_for_near_parallel_bundles_across_faces() {
    // Bundles of rods at angles from exactly parallel to 1e-2 rad with the
    // first, side by side at about 2r, staggered along the axis and across
    // the periodic faces: such pairs share many cells, and must be kept once.
    let l: f64 = 2.5;
    let gamma = 98.0;
    let two_r = 1.0 / gamma;
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut rods = Vec::new();
    for _ in 0..60 {
        let axis = random_unit(&mut rng);
        let side = random_perpendicular(&mut rng, &axis);
        // Near a face, so that the bundle wraps around the box.
        let base = V::new(
            rng.random::<f64>() * 0.2,
            rng.random::<f64>() * l,
            l - rng.random::<f64>() * 0.2,
        );
        rods.push(crate::unit(base, axis));
        for angle in [0.0, 1e-12, 1e-9, 1e-6, 1e-4, 1e-3, 1e-2] {
            let tilt = random_perpendicular(&mut rng, &axis);
            let v = (axis * f64::cos(angle) + tilt * f64::sin(angle)).normalize();
            let gap = two_r * (0.2 + 1.6 * rng.random::<f64>());
            let along = 1.8 * rng.random::<f64>() - 0.9;
            let v = if rng.random::<bool>() { v } else { -v };
            rods.push(crate::unit(base + side * gap + axis * along, v));
        }
    }
    let sys = crate::cube(
        RodParams::new(gamma, l, 60.0 * 8.0 / l.powi(3)).unwrap(),
        rods,
    );
    let fast = detect(&sys);
    assert!(fast.len() > 400, "only {} contacts", fast.len());
    assert_eq!(fast, detect_all_pairs(&sys));
    check_contacts(&sys, &fast);
    let across = fast.iter().filter(|c| c.shift != [0, 0, 0]).count();
    assert!(across > 50, "only {across} contacts cross a face");
}

#[test]
fn detect_finds_contacts_at_cell_corners_along_cell_diagonals() {
    // Thin rods crossing just inside a corner of the lattice of step 1/12
    // (which holds the corners of the grid's cells, of side 1/3 here), the
    // first along the diagonal through the corner: its contact lies as far
    // along it from the cell's center as a cell allows, where a bound on
    // the piece of a rod near a cell is tightest.
    let (gamma, l) = (1000.0, 4.0f64);
    let two_r = 1.0 / gamma;
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    let mut rods = Vec::new();
    for _ in 0..400 {
        let corner = V::new(
            rng.random_range(0..48) as f64 / 12.0,
            rng.random_range(0..48) as f64 / 12.0,
            rng.random_range(0..48) as f64 / 12.0,
        );
        for signs in 0..8 {
            let sign = |bit: i32| if signs >> bit & 1 == 0 { 1.0 } else { -1.0 };
            let d = V::new(sign(0), sign(1), sign(2)).normalize();
            let e = random_perpendicular(&mut rng, &d);
            let n = d.cross(&e);
            let p = corner - d * (2.0 * two_r);
            rods.push(crate::unit(p + d * (0.8 * rng.random::<f64>() - 0.4), d));
            rods.push(crate::unit(
                p + n * (0.5 * two_r) + e * (0.8 * rng.random::<f64>() - 0.4),
                e,
            ));
        }
    }
    let built = rods.len() / 2;
    let density = rods.len() as f64 / l.powi(3);
    let sys = crate::cube(RodParams::new(gamma, l, density).unwrap(), rods);
    let fast = detect(&sys);
    let pairs = fast
        .iter()
        .filter(|c| c.rods[1] == c.rods[0] + 1 && c.rods[0] % 2 == 0)
        .count();
    assert_eq!(pairs, built, "a crossing built to touch was missed");
    assert_eq!(fast, detect_all_pairs(&sys));
    check_contacts(&sys, &fast);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random small systems, with clustered centers (some outside the box),
    /// axis-aligned and near-parallel rods, at any allowed gamma and box.
    #[test]
    fn detect_equals_all_pairs_on_random_systems(
        gamma in prop_oneof![Just(1.0), 1.0f64..10.0, 10.0f64..200.0],
        extra in 1e-6f64..4.0,
        n in 0usize..250,
        seed in any::<u64>(),
    ) {
        let r = 0.5 / gamma;
        let l = 2.0 * (1.0 + 2.0 * r) + extra;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let dirs = [V::x(), V::y(), V::z(), -V::z()];
        let mut rods: Vec<Rod> = Vec::new();
        for k in 0..n {
            let center = if k > 0 && rng.random::<f64>() < 0.6 {
                rods[rng.random_range(0..k)].center + random_unit(&mut rng) * rng.random::<f64>()
            } else {
                V::new(
                    (2.0 * rng.random::<f64>() - 0.5) * l,
                    (2.0 * rng.random::<f64>() - 0.5) * l,
                    (2.0 * rng.random::<f64>() - 0.5) * l,
                )
            };
            let axis = match rng.random_range(0..4) {
                0 => dirs[rng.random_range(0..4)],
                1 if k > 0 => {
                    let prev = rods[k - 1].axis;
                    let tilt = random_perpendicular(&mut rng, &prev);
                    (prev + tilt * 10f64.powf(-12.0 * rng.random::<f64>())).normalize()
                }
                _ => random_unit(&mut rng),
            };
            rods.push(crate::unit(center, axis));
        }
        let density = (n.max(1)) as f64 / l.powi(3);
        let sys = crate::cube(RodParams::new(gamma, l, density).unwrap(), rods);
        // (`check_contacts` is not applied: for rods parallel to 1e-12 the
        // closest parameters are not unique, and a recomputation from the
        // stored centers may pick others.)
        prop_assert_eq!(detect(&sys), detect_all_pairs(&sys));
    }
}

#[test]
fn detect_finds_parallel_and_boundary_contacts() {
    let l = 4.0;
    let p = RodParams::new(10.0, l, 0.1).unwrap();
    let rods = vec![
        // Collinear across the x faces: [-0.45, 0.55] and the image [-1.35, -0.35] overlap.
        crate::unit(V::new(0.05, 1.0, 1.0), V::x()),
        crate::unit(V::new(l - 0.85, 1.0, 1.0), V::x()),
        // Corner to corner: touching through the (+1, +1, +1) image.
        crate::unit(V::new(0.01, 0.01, 0.01), V::new(1.0, 1.0, 1.0)),
        crate::unit(V::new(l - 0.01, l - 0.01, l - 0.01), V::new(1.0, -1.0, 0.0)),
        // Two parallel rods 2r - 1e-9 apart touch, 2r + 1e-9 apart do not.
        crate::unit(V::new(2.0, 3.0, 2.0), V::z()),
        crate::unit(V::new(2.0, 3.0 + 0.1 - 1e-9, 2.3), V::z()),
        crate::unit(V::new(2.0, 3.0 - 0.1 - 1e-9, 1.7), V::z()),
    ];
    let sys = crate::cube(p, rods);
    let contacts = detect(&sys);
    let pairs: Vec<([u32; 2], [i32; 3])> = contacts.iter().map(|c| (c.rods, c.shift)).collect();
    assert_eq!(
        pairs,
        vec![
            ([0, 1], [-1, 0, 0]),
            ([2, 3], [-1, -1, -1]),
            ([4, 5], [0, 0, 0])
        ]
    );
    assert_eq!(contacts, detect_all_pairs(&sys));
    check_contacts(&sys, &contacts);
}

#[test]
fn philipse_mean_contact_number() {
    // (gamma, L, rho, seeds) with rho L^3 an integer, so rho is exactly N / L^3.
    for (gamma, l, rho, seeds) in [(5.0, 5.0, 3.2, 30u64), (23.0, 6.0, 25.0, 16)] {
        let params = RodParams::new(gamma, l, rho).unwrap();
        let c0: Vec<f64> = (0..seeds)
            .map(|seed| {
                let sys = RodSystem::generate(params, 7000 + seed);
                2.0 * detect(&sys).len() as f64 / sys.len() as f64
            })
            .collect();
        let n = c0.len() as f64;
        let mean = c0.iter().sum::<f64>() / n;
        let var = c0.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let se = (var / n).sqrt();
        let expected = params.expected_c0();
        assert!(
            se < 0.02 * expected,
            "standard error {se} too large to test anything"
        );
        assert!(
            (mean - expected).abs() < 3.0 * se,
            "gamma {gamma}: mean c0 {mean} vs Philipse {expected} (se {se})"
        );
    }
}

#[test]
fn same_seed_same_contacts_for_any_thread_count() {
    let params = RodParams::new(23.0, 6.0, 30.0).unwrap();
    let a = detect(&RodSystem::generate(params, 5));
    let b = detect(&RodSystem::generate(params, 5));
    assert_eq!(a, b);
    assert_ne!(a, detect(&RodSystem::generate(params, 6)));
    let sys = RodSystem::generate(params, 5);
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        assert_eq!(pool.install(|| detect(&sys)), a, "{threads} threads");
    }
}

#[test]
fn gamma_98_contacts_for_any_thread_count() {
    let sys = system(98.0, 4.0, 190.0, 8);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| detect(&sys));
    assert!(one.len() > 15_000, "only {} contacts", one.len());
    assert_eq!(one, detect_all_pairs(&sys));
    for threads in [2, 3, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        assert_eq!(pool.install(|| detect(&sys)), one, "{threads} threads");
    }
}

#[test]
fn tiny_and_sparse_systems() {
    let p = RodParams::new(10.0, 3.0, 1.0).unwrap();
    assert!(detect(&crate::cube(p, vec![])).is_empty());
    let one = vec![crate::unit(V::new(1.0, 1.0, 1.0), V::x())];
    assert!(detect(&crate::cube(p, one)).is_empty());
    // A huge sparse box must not allocate a cell per unit volume.
    let sparse = RodSystem::generate(RodParams::new(10.0, 2000.0, 1e-7).unwrap(), 1);
    assert_eq!(detect(&sparse), detect_all_pairs(&sparse));
}

fn graph(n: usize, edges: &[[u32; 2]]) -> ContactGraph {
    ContactGraph::new(n, edges.to_vec()).unwrap()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

#[test]
fn stats_triangle_with_pendant() {
    let s = stats(&graph(4, &[[0, 1], [1, 2], [0, 2], [0, 3]]));
    assert!(
        close(s.c0, 2.0) && close(s.c1, 2.0) && close(s.c2, 2.0),
        "{s:?}"
    );
    // Node 0: 1 triangle among 3 neighbours; 1 and 2: 1; 3: 0.
    assert!(close(s.clustering, (1.0 / 3.0 + 2.0) / 4.0), "{s:?}");
}

#[test]
fn stats_two_components_and_isolated_node() {
    // Triangle {0,1,2}, path 3-4-5-6, isolated 7.
    let s = stats(&graph(8, &[[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 6]]));
    assert!(close(s.c0, 1.5), "{s:?}");
    assert!(close(s.c1, 1.5), "largest component is the path: {s:?}");
    assert!(close(s.c2, 2.0), "2-core is the triangle: {s:?}");
    assert!(close(s.clustering, 3.0 / 8.0), "{s:?}");
}

#[test]
fn stats_ties_go_to_the_first_component() {
    // A star on 0..3 (mean degree 1.5) and a 4-cycle on 4..7 (mean degree 2).
    let s = stats(&graph(
        8,
        &[[0, 1], [0, 2], [0, 3], [4, 5], [5, 6], [6, 7], [7, 4]],
    ));
    assert!(close(s.c1, 1.5), "{s:?}");
    assert!(close(s.c2, 2.0), "{s:?}");
}

#[test]
fn stats_two_core_smaller_than_largest_component() {
    // K4 on 0..3 with a tail 3-4-5-6-7, and a separate 5-cycle on 8..12. The
    // largest component is K4 + tail; the largest 2-core component is the cycle.
    let mut edges = vec![[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];
    edges.extend([[3, 4], [4, 5], [5, 6], [6, 7]]);
    edges.extend([[8, 9], [9, 10], [10, 11], [11, 12], [12, 8]]);
    let s = stats(&graph(13, &edges));
    assert!(close(s.c0, 30.0 / 13.0), "{s:?}");
    assert!(close(s.c1, 2.5), "{s:?}");
    assert!(close(s.c2, 2.0), "{s:?}");
}

#[test]
fn stats_complete_star_tree_and_empty() {
    let mut k5 = Vec::new();
    for a in 0..5 {
        for b in a + 1..5 {
            k5.push([a, b]);
        }
    }
    let s = stats(&graph(5, &k5));
    assert!(close(s.c0, 4.0) && close(s.c1, 4.0) && close(s.c2, 4.0) && close(s.clustering, 1.0));
    let s = stats(&graph(5, &[[0, 1], [0, 2], [0, 3], [0, 4]]));
    assert!(close(s.c0, 1.6) && close(s.c1, 1.6) && s.c2 == 0.0 && s.clustering == 0.0);
    let s = stats(&graph(0, &[]));
    assert_eq!((s.c0, s.c1, s.c2, s.clustering), (0.0, 0.0, 0.0, 0.0));
    let s = stats(&graph(3, &[]));
    assert_eq!((s.c0, s.c1, s.c2, s.clustering), (0.0, 0.0, 0.0, 0.0));
}

#[test]
fn clustering_matches_brute_force_on_random_graphs() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..20 {
        let n = 40;
        let mut edges = Vec::new();
        for a in 0..n as u32 {
            for b in a + 1..n as u32 {
                // Denser around node 0 to make a hub.
                let p = if a == 0 { 0.6 } else { 0.12 };
                if rng.random::<f64>() < p {
                    edges.push([a, b]);
                }
            }
        }
        let mut adj = vec![vec![false; n]; n];
        for &[a, b] in &edges {
            adj[a as usize][b as usize] = true;
            adj[b as usize][a as usize] = true;
        }
        let mut sum = 0.0;
        for v in 0..n {
            let nb: Vec<usize> = (0..n).filter(|&w| adj[v][w]).collect();
            let k = nb.len() as f64;
            if nb.len() < 2 {
                continue;
            }
            let mut t = 0.0;
            for (x, &a) in nb.iter().enumerate() {
                for &b in &nb[x + 1..] {
                    if adj[a][b] {
                        t += 1.0;
                    }
                }
            }
            sum += 2.0 * t / (k * (k - 1.0));
        }
        let s = stats(&graph(n, &edges));
        assert!((s.clustering - sum / n as f64).abs() < 1e-12);
        assert!(close(s.c0, 2.0 * edges.len() as f64 / n as f64));
    }
}

#[test]
fn stats_of_detected_contacts_are_consistent() {
    let sys = system(10.0, 5.0, 10.0, 9);
    let contacts = detect(&sys);
    let g = ContactGraph::from_contacts(sys.len(), &contacts);
    let s = stats(&g);
    assert!(close(s.c0, 2.0 * contacts.len() as f64 / sys.len() as f64));
    // Above percolation the giant component is denser than average and its
    // 2-core denser still; clustering is a probability.
    assert!(s.c1 >= s.c0 && s.c2 >= s.c1, "{s:?}");
    assert!((0.0..=1.0).contains(&s.clustering));
}
