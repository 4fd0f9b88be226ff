//! Finite-size scaling against data drawn from a known scaling function,
//! and the degenerate inputs it must refuse by name.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rgc::Error;
use rgc::threshold::fss::{
    self, BoxData, ContactPoint, Estimate, FssOptions, Observation, Protocol, analyse,
};
use rgc::threshold::logistic;

const RHO_C: f64 = 40.0;
const NU: f64 = 0.9;
const LENS: [f64; 5] = [5.0, 6.0, 7.0, 8.0, 10.0];

/// `mu(L) = rho_c + a L^(-1/nu)`, `s(L) = b L^(-1/nu)`.
fn truth(l: f64) -> (f64, f64) {
    let t = l.powf(-1.0 / NU);
    (RHO_C + 10.0 * t, 3.0 * t)
}

fn logistic_draw(rng: &mut ChaCha8Rng, mu: f64, s: f64) -> f64 {
    let u: f64 = rng.random_range(1e-12..1.0 - 1e-12);
    mu + s * (u / (1.0 - u)).ln()
}

fn nested(n: usize, seed: u64) -> Vec<BoxData> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    LENS.iter()
        .map(|&l| {
            let (mu, s) = truth(l);
            BoxData {
                box_len: l,
                observations: (0..n)
                    .map(|_| Observation {
                        critical: Some(logistic_draw(&mut rng, mu, s)),
                        ..Default::default()
                    })
                    .collect(),
            }
        })
        .collect()
}

/// Independent Bernoulli draws from the logistic at a common density grid.
fn fixed(n: usize, seed: u64) -> Vec<BoxData> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let grid: Vec<f64> = (0..=24).map(|k| 39.0 + 0.25 * k as f64).collect();
    LENS.iter()
        .map(|&l| {
            let (mu, s) = truth(l);
            BoxData {
                box_len: l,
                observations: (0..n)
                    .map(|_| Observation {
                        fixed: grid
                            .iter()
                            .map(|&rho| {
                                let p = 1.0 / (1.0 + (-(rho - mu) / s).exp());
                                (rho, rng.random_range(0.0..1.0) < p)
                            })
                            .collect(),
                        ..Default::default()
                    })
                    .collect(),
            }
        })
        .collect()
}

fn covers(e: &Estimate, v: f64) -> bool {
    e.lo.unwrap() <= v && v <= e.hi.unwrap()
}

fn check_recovery(protocol: Protocol, data: &[BoxData]) {
    let opts = FssOptions {
        protocol,
        bootstrap: 200,
        seed: 7,
        ..Default::default()
    };
    let r = analyse(data, &opts).unwrap();
    let (nu, rc) = (r.nu, r.threshold);
    assert!(covers(&nu, NU), "{protocol:?}: nu {nu:?} misses {NU}");
    assert!(
        covers(&rc, RHO_C),
        "{protocol:?}: threshold {rc:?} misses {RHO_C}"
    );
    assert!((nu.value / NU - 1.0).abs() < 0.1, "{protocol:?}: nu {nu:?}");
    assert!(
        (rc.value / RHO_C - 1.0).abs() < 0.005,
        "{protocol:?}: threshold {rc:?}"
    );
    assert_eq!(r.bootstrap_failures, 0);
    assert!(r.r2_nu > 0.9 && r.r2_extrapolation > 0.99, "{r:?}");
    for b in &r.boxes {
        let (mu, s) = truth(b.box_len);
        let (lo, hi) = b.mu_interval.unwrap();
        assert!(lo <= b.mu && b.mu <= hi);
        assert!((b.mu - mu).abs() < 0.05 * s.max(1.0), "{b:?}");
        assert!((b.s / s - 1.0).abs() < 0.15, "{b:?}");
    }
    assert!(r.contact_numbers.is_none());
    assert!(r.warnings.iter().any(|w| w.contains("no contact points")));
}

#[test]
fn nested_protocol_recovers_the_scaling_function() {
    check_recovery(Protocol::Nested, &nested(1000, 1));
}

#[test]
fn fixed_protocol_recovers_the_scaling_function() {
    check_recovery(Protocol::Fixed, &fixed(400, 2));
}

#[test]
fn logistic_mle_on_a_large_sample() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let sample: Vec<f64> = (0..50_000)
        .map(|_| logistic_draw(&mut rng, 12.5, 0.8))
        .collect();
    let f = logistic::fit_logistic_sample(&sample).unwrap();
    assert!(
        (f.mu / 12.5 - 1.0).abs() < 0.02 && (f.s / 0.8 - 1.0).abs() < 0.02,
        "{f:?}"
    );
    // The optimum: nudging either parameter lowers the likelihood.
    let ll = |mu: f64, s: f64| -> f64 {
        sample
            .iter()
            .map(|x| {
                let z = (x - mu) / s;
                -z - 2.0 * (-z).exp().ln_1p() - s.ln()
            })
            .sum()
    };
    assert!((ll(f.mu, f.s) - f.log_likelihood).abs() < 1e-6 * f.log_likelihood.abs());
    for (dm, ds) in [(1e-3, 0.0), (-1e-3, 0.0), (0.0, 1e-3), (0.0, -1e-3)] {
        assert!(ll(f.mu + dm, f.s + ds) < f.log_likelihood);
    }

    let grid: Vec<(f64, usize, usize)> = (0..40)
        .map(|k| {
            let rho = 10.0 + 0.125 * k as f64;
            let p = 1.0 / (1.0 + (-(rho - 12.5) / 0.8).exp());
            let n = 2000;
            (
                rho,
                (0..n).filter(|_| rng.random_range(0.0..1.0) < p).count(),
                n,
            )
        })
        .collect();
    let g = logistic::fit_logistic_binomial(&grid).unwrap();
    assert!(
        (g.mu / 12.5 - 1.0).abs() < 0.02 && (g.s / 0.8 - 1.0).abs() < 0.02,
        "{g:?}"
    );
    assert!((g.quantile(0.5) - g.mu).abs() < 1e-12);
    assert!((g.cdf(g.quantile(0.25)) - 0.25).abs() < 1e-12);
}

#[test]
fn common_intercept_is_exact_on_noise_free_lines() {
    let t = [0.3, 0.21, 0.17, 0.1];
    let slopes = [-4.0, 0.5, 2.25];
    let rho_x: Vec<Vec<f64>> = slopes
        .iter()
        .map(|k| t.iter().map(|t| 7.5 + k * t).collect())
        .collect();
    let e = fss::extrapolate(&t, &rho_x).unwrap();
    assert!((e.threshold - 7.5).abs() < 1e-10, "{e:?}");
    for (a, b) in e.slopes.iter().zip(slopes) {
        assert!((a - b).abs() < 1e-9, "{e:?}");
    }
    assert!(e.rms < 1e-10 && (e.r2 - 1.0).abs() < 1e-12);

    let lens = [4.0, 6.0, 9.0, 13.0];
    let delta: Vec<f64> = lens
        .iter()
        .map(|l: &f64| 2.5 * l.powf(-1.0 / 1.3))
        .collect();
    let n = fss::fit_nu(&lens, &delta).unwrap();
    assert!(
        (n.nu - 1.3).abs() < 1e-10 && (n.prefactor - 2.5).abs() < 1e-10,
        "{n:?}"
    );
}

#[test]
fn bootstrap_does_not_depend_on_threads() {
    let data = nested(200, 4);
    let opts = FssOptions {
        bootstrap: 40,
        seed: 11,
        ..Default::default()
    };
    let run = |k: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(k)
            .build()
            .unwrap()
            .install(|| analyse(&data, &opts).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two);
    assert!(one.nu.lo.is_some() && one.boxes[0].rho_x_intervals.len() == 5);
    let other = analyse(
        &data,
        &FssOptions {
            seed: 12,
            ..opts.clone()
        },
    )
    .unwrap();
    assert_ne!(one.nu.lo, other.nu.lo, "another seed draws other resamples");
}

fn analysis_error(data: &[BoxData], protocol: Protocol) -> String {
    let opts = FssOptions {
        protocol,
        bootstrap: 0,
        ..Default::default()
    };
    match analyse(data, &opts) {
        Err(Error::Analysis(msg)) => msg,
        other => panic!("expected an analysis error, got {other:?}"),
    }
}

fn fixed_box(l: f64, rows: &[(f64, &[bool])]) -> BoxData {
    let n = rows[0].1.len();
    BoxData {
        box_len: l,
        observations: (0..n)
            .map(|i| Observation {
                fixed: rows.iter().map(|(rho, s)| (*rho, s[i])).collect(),
                ..Default::default()
            })
            .collect(),
    }
}

#[test]
fn degenerate_data_is_refused_by_name() {
    let good = fixed(60, 5);
    let mut all = good.clone();
    all[1] = fixed_box(6.0, &[(50.0, &[true; 8]), (51.0, &[true; 8])]);
    let msg = analysis_error(&all, Protocol::Fixed);
    assert!(
        msg.contains("L=6") && msg.contains("every sequence spans"),
        "{msg}"
    );

    let mut none = good.clone();
    none[2] = fixed_box(7.0, &[(30.0, &[false; 8]), (31.0, &[false; 8])]);
    let msg = analysis_error(&none, Protocol::Fixed);
    assert!(
        msg.contains("L=7") && msg.contains("no sequence spans"),
        "{msg}"
    );

    let mut step = good.clone();
    step[0] = fixed_box(5.0, &[(40.0, &[false; 8]), (41.0, &[true; 8])]);
    let msg = analysis_error(&step, Protocol::Fixed);
    assert!(
        msg.contains("L=5") && msg.contains("perfect separation"),
        "{msg}"
    );

    let msg = analysis_error(&nested(50, 6), Protocol::Fixed);
    assert!(
        msg.contains("no fixed-density observations") && msg.contains("nested"),
        "{msg}"
    );

    let mut same = nested(50, 6);
    for o in &mut same[3].observations {
        o.critical = Some(41.0);
    }
    let msg = analysis_error(&same, Protocol::Nested);
    assert!(
        msg.contains("L=8") && msg.contains("fewer than 2 distinct critical densities"),
        "{msg}"
    );

    let mut few = nested(50, 6);
    few[4].observations.truncate(4);
    let msg = analysis_error(&few, Protocol::Nested);
    assert!(
        msg.contains("L=10") && msg.contains("fewer than 5 sequences"),
        "{msg}"
    );

    let msg = analysis_error(&nested(50, 6)[..2], Protocol::Nested);
    assert_eq!(msg, "nu needs at least 3 box sizes, got 2");

    // Delta rho growing with L: nu would be negative.
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let growing: Vec<BoxData> = LENS
        .iter()
        .map(|&l| BoxData {
            box_len: l,
            observations: (0..300)
                .map(|_| Observation {
                    critical: Some(logistic_draw(&mut rng, 40.0, 0.1 * l)),
                    ..Default::default()
                })
                .collect(),
        })
        .collect();
    let msg = analysis_error(&growing, Protocol::Nested);
    assert!(
        msg.contains("does not shrink with L") && msg.contains("nu would be"),
        "{msg}"
    );

    let mut twice = nested(50, 6);
    twice[1].box_len = 5.0;
    let msg = analysis_error(&twice, Protocol::Nested);
    assert!(msg.contains("L=5 appears twice"), "{msg}");

    let bad = FssOptions {
        xs: vec![0.5, 1.0],
        ..Default::default()
    };
    assert!(matches!(analyse(&nested(50, 6), &bad), Err(Error::Parameter(m)) if m.contains("x=1")));
}

#[test]
fn sequences_that_never_span_are_a_warning() {
    let mut data = nested(100, 9);
    data[0].observations[0].critical = None;
    let opts = FssOptions {
        bootstrap: 0,
        ..Default::default()
    };
    let r = analyse(&data, &opts).unwrap();
    assert_eq!(r.boxes[0].sequences, 99);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("L=5: 1 of 100 sequences never spanned"))
    );
    assert!(!r.warnings.iter().any(|w| w.contains("verdict")));
    assert!(r.nu.lo.is_none() && r.boxes[0].mu_interval.is_none());

    data[0].observations[0].undecided = true;
    data[1].observations[0].critical = None;
    let r = analyse(&data, &opts).unwrap();
    let l5: Vec<&String> = r.warnings.iter().filter(|w| w.contains("L=5:")).collect();
    assert_eq!(
        l5,
        [
            "box L=5: 1 of 100 sequences lost truth's verdict (no realization of the model) before their critical number was found and are left out of the fit"
        ]
    );
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("L=6: 1 of 100 sequences never spanned"))
    );
    let curve = fss::pi_curve(&data[0], Protocol::Nested);
    assert_eq!(curve.len(), 99);
    assert!((curve.last().unwrap().1 - 0.99).abs() < 1e-12 && curve[0].2 == 100);
}

#[test]
fn contact_numbers_at_the_threshold() {
    const V: f64 = 0.0731;
    let mut data = nested(300, 10);
    for b in &mut data {
        for o in &mut b.observations {
            let rho = o.critical.unwrap();
            o.contacts = [rho - 1.0, rho, rho + 1.5]
                .iter()
                .map(|&d| ContactPoint {
                    density: d,
                    c0: V * d,
                    c1: 2.0 * V * d - 1.0,
                    c2: 0.5 + 0.01 * d,
                })
                .collect();
        }
    }
    let opts = FssOptions {
        bootstrap: 30,
        ..Default::default()
    };
    let r = analyse(&data, &opts).unwrap();
    let c = r.contact_numbers.as_ref().expect("contact numbers");
    let rc = r.threshold;
    let c0 = c.pooled.c0.at_threshold;
    assert!((c0.value - V * rc.value).abs() < 1e-10, "{c0:?}");
    assert!((c0.lo.unwrap() - V * rc.lo.unwrap()).abs() < 1e-10);
    assert!((c0.hi.unwrap() - V * rc.hi.unwrap()).abs() < 1e-10);
    assert!((c.pooled.c0.r2 - 1.0).abs() < 1e-12 && c.pooled.c0.intercept.abs() < 1e-9);
    assert!((c.pooled.c1.at_threshold.value - (2.0 * V * rc.value - 1.0)).abs() < 1e-9);
    assert_eq!(c.pooled.points, 5 * 300 * 3);
    assert_eq!(c.per_box.len(), 5);
    assert!(c.per_box.iter().all(|f| (f.c0.slope - V).abs() < 1e-10));
}

#[test]
fn csv_and_charts_are_written() {
    let data = fixed(80, 12);
    let opts = FssOptions {
        protocol: Protocol::Fixed,
        bootstrap: 20,
        ..Default::default()
    };
    let r = analyse(&data, &opts).unwrap();
    let dir = crate::scratch("fss-csv");
    rgc::threshold::report::write_scaling_tables(&r, &data, &dir).unwrap();
    let boxes = std::fs::read_to_string(dir.join("boxes.csv")).unwrap();
    assert_eq!(boxes.lines().count(), 6);
    assert!(boxes.starts_with("box_len,realizations,mu,") && boxes.contains(",rho_x_0.75"));
    let pi = std::fs::read_to_string(dir.join("pi.csv")).unwrap();
    assert_eq!(pi.lines().count(), 1 + 5 * 25);
    let rx = std::fs::read_to_string(dir.join("rho_x.csv")).unwrap();
    assert_eq!(rx.lines().count(), 1 + 5 * 5);

    let charts = rgc::plot::threshold_charts(&r, &data, "synthetic rods", &dir).unwrap();
    assert_eq!(charts.len(), 8);
    for (name, title) in [
        ("pi", "spanning probability"),
        ("collapse", "scaling collapse"),
        ("rho_x", "extrapolated to L = ∞"),
        ("delta_rho", "width"),
    ] {
        let svg = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
        assert!(
            svg.contains("synthetic rods") && svg.contains(title),
            "{name}"
        );
        let png = std::fs::read(dir.join(format!("{name}.png"))).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 10_000,
            "{name}"
        );
    }
    let points = [
        (23.0, 0.21, r.threshold),
        (
            48.0,
            0.05,
            Estimate {
                value: 11.0,
                lo: Some(10.5),
                hi: Some(11.4),
            },
        ),
        (
            98.0,
            0.013,
            Estimate {
                value: 2.9,
                lo: None,
                hi: None,
            },
        ),
    ];
    let (svg, png) = (dir.join("vex.svg"), dir.join("vex.png"));
    let title = "Rigidity threshold against the inverse excluded volume";
    let fit = rgc::threshold::aspect::fit(&points).unwrap();
    let series = rgc::plot::VexSeries {
        label: "3D-RGC",
        points: &points,
        fit: &fit,
    };
    rgc::plot::threshold_vs_vex(&[series], title, &svg, &png).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains(title), "{text}");
    assert!(std::fs::read(&png).unwrap().len() > 10_000);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failed_resamples_are_counted_and_warned() {
    // At L=6 one sequence spans early and one never does: every resample
    // that misses either is perfectly separated.
    let mut data = fixed(60, 13);
    let mut early = [false; 10];
    early[0] = true;
    let mut late = [true; 10];
    late[1] = false;
    data[1] = fixed_box(6.0, &[(40.0, &early), (41.0, &late)]);
    let opts = FssOptions {
        protocol: Protocol::Fixed,
        bootstrap: 50,
        ..Default::default()
    };
    let r = analyse(&data, &opts).unwrap();
    assert!(
        r.bootstrap_failures > 5 && r.bootstrap_failures < 50,
        "{}",
        r.bootstrap_failures
    );
    let warning = r
        .warnings
        .iter()
        .find(|w| w.contains("bootstrap resamples failed"));
    let warning = warning.expect("a warning about the failed resamples");
    assert!(
        warning.contains("L=6") && warning.contains("perfect separation"),
        "{warning}"
    );
    assert!(r.nu.lo.is_some());
}
