//! Generated ensembles beyond the paper: exact contacts for unequal rods in
//! any box, and contact numbers against their expectations (the pair average
//! of the excluded volume for polydisperse isotropic rods, a direct Monte
//! Carlo estimate of the pair overlap probability for aligned ones).

use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rgc::contacts::{closest_points, detect, detect_all_pairs};
use rgc::rods::ensemble::{Dist, Ensemble, Orientation};
use rgc::rods::{
    Domain, Periodic, Rod, RodParams, RodSystem, excluded_volume, pair_excluded_volume,
};

type V = Vector3<f64>;

fn ensemble(sides: [f64; 3], periodic: Periodic, density: f64) -> Ensemble {
    Ensemble {
        domain: Domain { sides, periodic },
        density,
        length: Dist::Lognormal { mean: 1.0, sd: 0.3 },
        radius: Dist::Uniform { lo: 0.01, hi: 0.04 },
        orientation: Orientation::Isotropic,
    }
}

/// Every touching pair by brute force: every pair, every image along the
/// periodic axes, the segment distance against `r_i + r_j`.
fn brute_force(system: &RodSystem) -> Vec<[u32; 2]> {
    let d = &system.domain;
    let images: Vec<i32> = vec![-1, 0, 1];
    let mut pairs = Vec::new();
    for (i, a) in system.rods.iter().enumerate() {
        for (j, b) in system.rods.iter().enumerate().skip(i + 1) {
            let mut touch = false;
            for &kx in &images {
                for &ky in &images {
                    for &kz in &images {
                        let k = [kx, ky, kz];
                        if (0..3).any(|a| k[a] != 0 && !d.wraps(a)) {
                            continue;
                        }
                        let shift = V::from_fn(|a, _| k[a] as f64 * d.sides[a]);
                        let c = closest_points(
                            &a.center,
                            &a.axis,
                            0.5 * a.length,
                            &(b.center + shift),
                            &b.axis,
                            0.5 * b.length,
                        );
                        touch |= c.dist2 < (a.radius + b.radius).powi(2);
                    }
                }
            }
            if touch {
                pairs.push([i as u32, j as u32]);
            }
        }
    }
    pairs
}

/// The grid detector equals the all-pairs one and a brute force over all
/// images, for unequal, partly aligned rods in boxes of three sides, with
/// walls or without; every contact point lies within each rod's radius of
/// its core (the property the grid's one-cell rule rests on).
#[test]
fn unequal_rods_touch_exactly_in_every_kind_of_box() {
    for (k, (sides, periodic)) in [
        ([4.0, 5.0, 6.0], Periodic::Xyz),
        ([5.0, 5.0, 3.0], Periodic::Xy),
        ([4.0, 3.0, 5.0], Periodic::None),
    ]
    .into_iter()
    .enumerate()
    {
        let mut e = ensemble(sides, periodic, 12.0);
        e.length = Dist::Uniform { lo: 0.3, hi: 1.5 };
        e.orientation = Orientation::Aligned {
            order: 0.4,
            director: [1.0, 1.0, 0.0],
        };
        e.check().unwrap();
        let system = e.generate(k as u64).unwrap();
        let fast = detect(&system);
        assert!(fast.len() > 150, "only {} contacts", fast.len());
        assert_eq!(fast, detect_all_pairs(&system), "{periodic:?}");
        let pairs: Vec<[u32; 2]> = fast.iter().map(|c| c.rods).collect();
        assert_eq!(pairs, brute_force(&system), "{periodic:?}");
        for c in &fast {
            let [a, b] = c.rods.map(|i| &system.rods[i as usize]);
            let [s, t] = c.params;
            assert!(s.abs() <= 0.5 * a.length && t.abs() <= 0.5 * b.length);
            let shift = V::from_fn(|i, _| c.shift[i] as f64 * sides[i]);
            let (pa, pb) = (a.at(s), b.at(t) + shift);
            // The point, unwrapped next to rod a.
            let mut p = c.point;
            for i in 0..3 {
                if system.domain.wraps(i) {
                    p[i] -= ((p[i] - pa[i]) / sides[i]).round() * sides[i];
                } else {
                    assert!((0.0..=sides[i]).contains(&p[i]), "point outside a wall");
                }
            }
            assert!((p - pa).norm() <= a.radius * (1.0 + 1e-9));
            assert!((p - pb).norm() <= b.radius * (1.0 + 1e-9));
        }
        if periodic != Periodic::Xyz {
            assert!(fast.iter().all(|c| c.shift[2] == 0));
        }
        if periodic == Periodic::None {
            assert!(fast.iter().all(|c| c.shift == [0; 3]));
        }
    }
}

/// The O(N) pair average of the excluded volume equals the O(N^2) one, and
/// equal unit rods give Philipse's `rho V_ex (N - 1) / N`.
#[test]
fn the_pair_averaged_excluded_volume_sums_every_pair() {
    let system = ensemble([6.0; 3], Periodic::Xyz, 2.0).generate(4).unwrap();
    let n = system.len();
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            if i != j {
                sum += pair_excluded_volume(&system.rods[i], &system.rods[j]);
            }
        }
    }
    let direct = sum / (n as f64 * system.domain.volume());
    let fast = system.expected_isotropic_c0();
    assert!(
        (fast - direct).abs() < 1e-12 * direct,
        "{fast} against {direct}"
    );

    let p = RodParams::new(23.0, 5.0, 40.0).unwrap();
    let paper = RodSystem::generate(p, 1);
    let philipse = p.expected_c0();
    assert!((paper.expected_isotropic_c0() - philipse).abs() < 1e-12 * philipse);
    let rod = paper.rods[0];
    assert!((pair_excluded_volume(&rod, &rod) - excluded_volume(23.0)).abs() < 1e-15);
}

/// Mean and standard error of the mean.
fn mean_se(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// Polydisperse isotropic rods: over seeds, the mean contact number `c0`
/// minus each system's pair-averaged expectation is zero within 3 standard
/// errors. The monodisperse law at each system's mean length and radius is 2% off,
/// which these seeds resolve (for thin rods with independent sizes the
/// leading term `pi/2 <l_i l_j (r_i + r_j)>` is the same; caps and `r^2`
/// terms make the difference).
#[test]
fn polydisperse_contact_numbers_follow_the_pair_averaged_excluded_volume() {
    let e = ensemble([9.0; 3], Periodic::Xyz, 24.0);
    e.check().unwrap();
    let (mut gaps, mut naive_gaps) = (Vec::new(), Vec::new());
    for seed in 0..40 {
        let system = e.generate(seed).unwrap();
        let n = system.len() as f64;
        let c0 = 2.0 * detect(&system).len() as f64 / n;
        gaps.push(c0 - system.expected_isotropic_c0());
        // Equal rods of this system's mean length and radius: another law.
        let mean = |f: fn(&Rod) -> f64| system.rods.iter().map(f).sum::<f64>() / n;
        let rod = Rod::new(V::zeros(), V::z(), mean(|r| r.length), mean(|r| r.radius));
        let naive = pair_excluded_volume(&rod, &rod) * (n - 1.0) / system.domain.volume();
        naive_gaps.push(c0 - naive);
    }
    let (gap, se) = mean_se(&gaps);
    assert!(
        gap.abs() < 3.0 * se,
        "c0 off its expectation by {gap} (SE {se})"
    );
    let (naive_gap, naive_se) = mean_se(&naive_gaps);
    assert!(
        naive_gap.abs() > 5.0 * naive_se,
        "the mean-rod law cannot be told from c0: off by {naive_gap} (SE {naive_se})"
    );
}

/// The Watson sampler gives the asked nematic order parameter.
#[test]
fn aligned_rods_have_the_asked_order_parameter() {
    for (order, director) in [
        (0.7, [0.0, 0.0, 1.0]),
        (-0.3, [1.0, 2.0, 2.0]),
        (0.0, [1.0, 0.0, 0.0]),
    ] {
        let e = Ensemble {
            domain: Domain::cube(30.0),
            density: 2.0,
            length: Dist::Fixed { value: 1.0 },
            radius: Dist::Fixed { value: 0.02 },
            orientation: Orientation::Aligned { order, director },
        };
        e.check().unwrap();
        let system = e.generate(9).unwrap();
        let d = V::from(director).normalize();
        let p2: Vec<f64> = system
            .rods
            .iter()
            .map(|r| 1.5 * r.axis.dot(&d).powi(2) - 0.5)
            .collect();
        let (s, se) = mean_se(&p2);
        assert!(
            (s - order).abs() < 3.0 * se,
            "S = {s} +- {se}, asked {order}"
        );
        assert!(
            system
                .rods
                .iter()
                .all(|r| (r.axis.norm() - 1.0).abs() < 1e-12)
        );
    }
}

/// Aligned rods: the mean contact number over seeds matches `rho V_ex (N-1)/N`
/// with `V_ex` the pair overlap probability times the volume it is sampled
/// in, estimated directly from independent pairs of the same ensemble (within
/// 3 combined standard errors); the isotropic law is far off.
#[test]
fn aligned_contact_numbers_follow_the_sampled_pair_overlap() {
    let gamma = 23.0;
    let e = Ensemble {
        domain: Domain::cube(6.0),
        density: 40.0,
        length: Dist::Fixed { value: 1.0 },
        radius: Dist::Fixed { value: 0.5 / gamma },
        orientation: Orientation::Aligned {
            order: 0.7,
            director: [0.0, 0.0, 1.0],
        },
    };
    e.check().unwrap();
    let n = e.n_rods() as f64;
    let c0s: Vec<f64> = (0..20)
        .map(|seed| 2.0 * detect(&e.generate(seed).unwrap()).len() as f64 / n)
        .collect();
    let (c0, se_c0) = mean_se(&c0s);

    // Pairs: orientations drawn from the ensemble's (a million rods' axes), the
    // second centre uniform in the ball of radius l + 2r about the first,
    // outside which no two rods touch (Onsager's exact excluded volume of
    // spherocylinders at angle theta, `2 l^2 D |sin theta| + 2 pi D^2 l +
    // 4 pi D^3 / 3`, with this ensemble's <|sin theta|> = 0.5305 gives
    // c0 = 2.334).
    let mut pool = e;
    pool.domain = Domain::cube(80.0);
    pool.density = 2.0;
    let axes: Vec<V> = pool
        .generate(99)
        .unwrap()
        .rods
        .iter()
        .map(|r| r.axis)
        .collect();
    let r = 0.5 / gamma;
    let reach = (1.0 + 2.0 * r) * (1.0 + 1e-9);
    let ball = 4.0 / 3.0 * std::f64::consts::PI * reach.powi(3);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let trials = 20_000_000usize;
    let mut hits = 0usize;
    for _ in 0..trials {
        let pick = |rng: &mut ChaCha8Rng| axes[rng.random_range(0..axes.len())];
        let (u, v) = (pick(&mut rng), pick(&mut rng));
        let w = loop {
            let w = V::from_fn(|_, _| 2.0 * rng.random::<f64>() - 1.0);
            if w.norm_squared() <= 1.0 {
                break w * reach;
            }
        };
        let c = closest_points(&V::zeros(), &u, 0.5, &w, &v, 0.5);
        hits += usize::from(c.dist2 < 4.0 * r * r);
    }
    let p = hits as f64 / trials as f64;
    let v_ex = p * ball;
    let se_v = (p * (1.0 - p) / trials as f64).sqrt() * ball;
    let expected = 40.0 * v_ex * (n - 1.0) / n;
    let se = (se_c0.powi(2) + (40.0 * se_v).powi(2)).sqrt();
    assert!(
        (c0 - expected).abs() < 3.0 * se,
        "c0 = {c0} against the sampled {expected} (combined SE {se})"
    );
    let isotropic = RodParams::new(gamma, 6.0, 40.0).unwrap().expected_c0();
    assert!(
        (isotropic - c0).abs() > 10.0 * se,
        "the isotropic law {isotropic} cannot be told from c0 = {c0}"
    );
}

/// `Z(kappa) = int_0^1 exp(kappa t^2) dt` in closed form, by series with
/// positive terms only: `sqrt(pi) erfi(x) / (2 x)` with `x = sqrt(kappa)`
/// for `kappa > 0`, `sqrt(pi) erf(x) / (2 x)` with `x = sqrt(-kappa)` for
/// `kappa < 0` (erf by its series `2/sqrt(pi) exp(-x^2) sum 2^n x^(2n+1) /
/// (2n+1)!!`).
fn watson_z(kappa: f64) -> f64 {
    let (mut sum, mut term, mut n) = (0.0, 1.0, 0.0);
    if kappa >= 0.0 {
        // erfi: sum kappa^n / (n! (2n + 1)).
        while term > 1e-18 * sum || n < 2.0 {
            sum += term / (2.0 * n + 1.0);
            n += 1.0;
            term *= kappa / n;
        }
        sum
    } else {
        // exp(-x^2) sum (2 x^2)^n / (2n + 1)!!.
        let x2 = -kappa;
        while term > 1e-18 * sum || n < 2.0 {
            sum += term;
            n += 1.0;
            term *= 2.0 * x2 / (2.0 * n + 1.0);
        }
        (-x2).exp() * sum
    }
}

/// `<t^2>` and `<t>` under the density `exp(kappa t^2)` on `[0, 1]`, by parts:
/// `<t^2> = e^kappa / (2 kappa Z) - 1 / (2 kappa)`, `<t> = (e^kappa - 1) / (2 kappa Z)`.
fn watson_moments(kappa: f64) -> (f64, f64) {
    let z = watson_z(kappa);
    (
        kappa.exp() / (2.0 * kappa * z) - 0.5 / kappa,
        (kappa.exp() - 1.0) / (2.0 * kappa * z),
    )
}

/// The order parameter of the Watson distribution of concentration `kappa`.
fn watson_s(kappa: f64) -> f64 {
    1.5 * watson_moments(kappa).0 - 0.5
}

/// The closed form itself: its known limits, S ~ 2 kappa / 15 near 0,
/// 1 - 3 / (2 kappa) for large kappa and -1/2 + 3 / (4 |kappa|) for large
/// negative kappa; and at kappa = 1, `<t^2> = e / (2 Z) - 1/2` with
/// `Z = 1.4626517459071816` (erfi(1) sqrt(pi) / 2).
#[test]
fn the_watson_closed_form_has_its_known_limits() {
    assert!((watson_z(1.0) - 1.462_651_745_907_181_6).abs() < 1e-15);
    assert!((watson_z(-1.0) - 0.746_824_132_812_427).abs() < 1e-14);
    let s = watson_s(1e-4);
    assert!((s / (2e-4 / 15.0) - 1.0).abs() < 1e-3, "{s}");
    let s = watson_s(400.0);
    assert!((s - (1.0 - 3.0 / 800.0)).abs() < 1e-4, "{s}");
    let s = watson_s(-400.0);
    assert!((s - (-0.5 + 3.0 / 1600.0)).abs() < 1e-4, "{s}");
}

/// The Watson sampler against the distribution's closed form: asked the
/// order parameter S(kappa) of a known kappa, the rods' mean `P2` is S and
/// their mean `|cos|` to the director is `<t>(kappa)` (a second moment the
/// order parameter does not fix), each within 4 standard errors; and the
/// azimuth about the director is uniform: the means of cos, sin, cos 2 and
/// sin 2 of it are 0 within 4 standard errors.
#[test]
fn aligned_rods_follow_the_watson_closed_form_with_a_uniform_azimuth() {
    let d = V::new(1.0, 2.0, 2.0) / 3.0;
    // A frame across the director of the test's own choosing.
    let e1 = (V::x() - d * d.x).normalize();
    let e2 = d.cross(&e1);
    for kappa in [-2.5, 1.5, 6.0] {
        let order = watson_s(kappa);
        let e = Ensemble {
            domain: Domain::cube(30.0),
            density: 2.0,
            length: Dist::Fixed { value: 1.0 },
            radius: Dist::Fixed { value: 0.02 },
            orientation: Orientation::Aligned {
                order,
                director: [1.0, 2.0, 2.0],
            },
        };
        let system = e.generate(13).unwrap();
        assert_eq!(system.len(), 54_000);
        let t: Vec<f64> = system.rods.iter().map(|r| r.axis.dot(&d).abs()).collect();
        let p2: Vec<f64> = t.iter().map(|t| 1.5 * t * t - 0.5).collect();
        let (s, se) = mean_se(&p2);
        assert!(
            (s - order).abs() < 4.0 * se,
            "kappa {kappa}: S = {s} +- {se}, closed form {order}"
        );
        let (mean_t, se_t) = mean_se(&t);
        let want = watson_moments(kappa).1;
        assert!(
            (mean_t - want).abs() < 4.0 * se_t,
            "kappa {kappa}: <t> = {mean_t} +- {se_t}, closed form {want}"
        );
        let phi: Vec<f64> = system
            .rods
            .iter()
            .map(|r| r.axis.dot(&e2).atan2(r.axis.dot(&e1)))
            .collect();
        for (name, f) in [
            ("cos", f64::cos as fn(f64) -> f64),
            ("sin", f64::sin),
            ("cos 2", |p: f64| (2.0 * p).cos()),
            ("sin 2", |p: f64| (2.0 * p).sin()),
        ] {
            let (m, se) = mean_se(&phi.iter().map(|&p| f(p)).collect::<Vec<_>>());
            assert!(
                m.abs() < 4.0 * se,
                "kappa {kappa}: mean {name}(phi) = {m} +- {se}"
            );
        }
    }
}

/// A seed's rods come in a fixed order, so the first `n` rods of a
/// polydisperse or aligned system are the `n`-rod system of the same seed
/// (a sequence's prefixes, MODEL §8), bit for bit, in a periodic box and
/// between walls, whatever rejection sampling the sizes and orientations
/// take.
#[test]
fn the_first_n_rods_of_a_seed_are_its_n_rod_system() {
    let bits = |r: &Rod| {
        [
            r.center.x, r.center.y, r.center.z, r.axis.x, r.axis.y, r.axis.z, r.length, r.radius,
        ]
        .map(f64::to_bits)
    };
    for periodic in [Periodic::Xyz, Periodic::None] {
        for orientation in [
            Orientation::Isotropic,
            Orientation::Aligned {
                order: 0.6,
                director: [1.0, 1.0, 0.0],
            },
            Orientation::Aligned {
                order: -0.3,
                director: [0.0, 0.0, 1.0],
            },
        ] {
            let at = |density: f64| Ensemble {
                density,
                orientation,
                ..ensemble([8.0, 8.0, 8.0], periodic, 0.0)
            };
            let (long, short) = (at(4.0), at(1.5));
            assert_eq!((long.n_rods(), short.n_rods()), (2048, 768));
            for seed in [1, 17] {
                let all = long.generate(seed).unwrap();
                let first = short.generate(seed).unwrap();
                assert_eq!(first.len(), 768);
                let prefix: Vec<_> = all.rods[..768].iter().map(bits).collect();
                let alone: Vec<_> = first.rods.iter().map(bits).collect();
                assert!(prefix == alone, "{periodic:?} {orientation:?} seed {seed}");
                // Another seed is another system.
                let other = short.generate(seed + 1).unwrap();
                assert!(other.rods.iter().map(bits).ne(alone.iter().copied()));
            }
        }
    }
}
