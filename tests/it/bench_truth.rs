//! The truth benchmark: consistent rows on a tiny plan, in process and
//! through `rgc bench --truth`, and the power law behind its prediction.
//! No timing is asserted beyond being positive.

use std::process::Command;

use rgc::bench::{self, Growth, REACH_DENSITY, TruthPlan, TruthRow, TruthSystem};
use rgc::progress::Silent;

fn assert_consistent(r: &TruthRow) {
    assert!(r.decided, "truth undecided: {r:?}");
    let rank = r.rank.expect("a decided truth has a rank");
    assert!(rank <= r.columns, "{r:?}");
    assert_eq!(r.columns, 6 * r.parts, "{r:?}");
    assert!(0 < r.core_rods && r.core_rods <= r.n_rods, "{r:?}");
    let (rows, cols) = r.largest_front.expect("a decided truth has a front");
    assert!(rows <= r.rows && cols <= r.columns, "{r:?}");
    assert!(r.seconds > 0.0, "{r:?}");
    // One thread cannot use more CPU than wall time (ticks are 10 ms).
    assert!(
        r.cpu_seconds
            .is_none_or(|c| (0.0..=r.seconds + 0.05).contains(&c)),
        "{r:?}"
    );
    assert!(r.truth_mib <= r.peak_mib, "{r:?}");
}

fn tiny() -> TruthPlan {
    TruthPlan {
        densities: vec![34.0],
        boxes: vec![3],
        seeds: 1,
    }
}

#[test]
fn tiny_plan_in_process_gives_consistent_rows() {
    let report = bench::run_truth(&tiny(), 600.0, Some(3), bench::measure_truth, &Silent).unwrap();
    assert_eq!(report.rows.len(), 1);
    let r = &report.rows[0];
    assert_consistent(r);
    assert_eq!((r.density, r.box_len, r.seed, r.n_rods), (34.0, 3, 1, 918));
    // Truth again without and with the strain columns, where CPU time is read.
    if rgc::usage::thread_cpu_seconds().is_some() {
        let c = r.strain_cost.expect("measured");
        assert!(c.with >= 0.0 && c.without >= 0.0, "{c:?}");
    }
    assert!(report.scaling[0].time.is_none(), "one size fits no law");
    assert!(report.scaling[0].time_tail.is_none());
    assert_eq!(report.predicted_largest_box, None);
    let reach = report.reach.expect("asked for");
    assert_eq!(reach.rows.len(), 1);
    assert_consistent(&reach.rows[0]);
    assert_eq!(reach.rows[0].density, REACH_DENSITY);
    assert_eq!(reach.largest_box, Some(3));
    assert!(!reach.stopped_by_time, "the cap stopped it");
}

#[test]
fn cli_runs_each_system_in_its_own_process() {
    let out = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args([
            "bench",
            "--truth",
            "--truth-boxes",
            "3",
            "--truth-densities",
            "34",
            "--truth-seeds",
            "1",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows: Vec<TruthRow> = serde_json::from_value(v["rows"].clone()).unwrap();
    assert_eq!(rows.len(), 1);
    assert_consistent(&rows[0]);
    assert!(rows[0].peak_mib > 0.0, "{:?}", rows[0]);
    assert!(v["reach"].is_null(), "measured only when asked");
}

#[test]
fn plans_without_systems_or_time_are_refused() {
    let no_seeds = TruthPlan { seeds: 0, ..tiny() };
    assert!(bench::run_truth(&no_seeds, 600.0, None, bench::measure_truth, &Silent).is_err());
    let too_small = TruthPlan {
        boxes: vec![2],
        ..tiny()
    };
    assert!(bench::run_truth(&too_small, 600.0, None, bench::measure_truth, &Silent).is_err());
    assert!(bench::run_truth(&tiny(), 0.0, None, bench::measure_truth, &Silent).is_err());
}

#[test]
fn power_law_fit_and_prediction() {
    let law = Growth::fit([1e3, 1e4, 1e5].map(|n: f64| (n, 1e-9 * n * n))).unwrap();
    assert!((law.exponent - 2.0).abs() < 1e-9, "{law:?}");
    assert!((law.prefactor / 1e-9 - 1.0).abs() < 1e-6, "{law:?}");
    assert!(Growth::fit([(1e3, 1.0), (1e3, 2.0)]).is_none());
    // 1e-9 N^2 <= 600 s: N <= 774 597, and 38 L^3 <= N up to L = 27.
    assert_eq!(bench::predict_largest_box(&law, 38.0, 600.0), Some(27));
    assert_eq!(bench::predict_largest_box(&law, 38.0, 1e-6), None);
}

/// A row of `n` rods that took `seconds`, for plans that need no truth.
fn fake_row(density: f64, l: usize, seed: u64, seconds: f64) -> TruthRow {
    let n_rods = (density * (l as f64).powi(3)).round() as usize;
    TruthRow {
        gamma: bench::TRUTH_GAMMA,
        density,
        box_len: l,
        seed,
        n_rods,
        core_rods: n_rods,
        parts: n_rods,
        columns: 6 * n_rods,
        rows: 6 * n_rods,
        rank: Some(6 * n_rods),
        decided: true,
        largest_front: Some((1, 6)),
        seconds,
        cpu_seconds: Some(seconds),
        peak_mib: 2.0,
        truth_mib: 1.0,
        peak_reset: true,
        strain_cost: None,
    }
}

#[test]
fn prediction_extrapolates_the_largest_boxes_only() {
    let plan = TruthPlan {
        densities: vec![REACH_DENSITY],
        boxes: (3..=7).collect(),
        seeds: 1,
    };
    // Flat on the small boxes (fixed costs), 1e-12 N^3 on the largest three.
    let measure = |density: f64, l: usize, seed| {
        let n = (density * (l as f64).powi(3)).round();
        Ok(fake_row(
            density,
            l,
            seed,
            if l < 5 { 1.0 } else { 1e-12 * n.powi(3) },
        ))
    };
    let report = bench::run_truth(&plan, 600.0, None, measure, &Silent).unwrap();
    let s = &report.scaling[0];
    assert!(s.time.unwrap().exponent < 3.0, "{s:?}");
    assert!((s.time_tail.unwrap().exponent - 3.0).abs() < 1e-9, "{s:?}");
    // 1e-12 (38 L^3)^3 <= 600 s up to L = 13.
    assert_eq!(report.predicted_largest_box, Some(13));
}

#[test]
fn the_aspect_benchmark_fits_each_gamma_and_compares_the_cost_per_rod() {
    // Rows made up to follow known laws: CPU = 1e-6 N^1.5 at gamma 98 and
    // 1e-7 N at the others, memory = N / 1000 MiB. The fits must find the
    // exponents, and the ratio the per-rod costs of gamma 98 L 7 and gamma
    // 23 L 12.
    let mut seen = Vec::new();
    let report = bench::run_truth_aspects(
        false,
        |gamma, density, l, seed| {
            seen.push((gamma, l));
            let real = bench::measure_truth_at(gamma, 10.0, 3, seed)?;
            let n = rgc::rods::RodParams::new(gamma, l as f64, density)?.n_rods();
            let cpu = if gamma == 98.0 {
                1e-6 * (n as f64).powf(1.5)
            } else {
                1e-7 * n as f64
            };
            Ok(TruthRow {
                n_rods: n,
                box_len: l,
                cpu_seconds: Some(cpu),
                truth_mib: n as f64 / 1000.0,
                ..real
            })
        },
        &Silent,
    )
    .unwrap();
    assert_eq!(seen.len(), bench::ASPECT_SYSTEMS.len());
    assert_eq!(report.scaling.len(), 3);
    for s in &report.scaling {
        let time = s.time.expect("three sizes per gamma");
        let want = if s.gamma == 98.0 { 1.5 } else { 1.0 };
        assert!((time.exponent - want).abs() < 1e-9, "{s:?}");
        assert!((s.memory.unwrap().exponent - 1.0).abs() < 1e-9, "{s:?}");
    }
    let n98 = rgc::rods::RodParams::new(98.0, 7.0, 165.0)
        .unwrap()
        .n_rods() as f64;
    let want = (1e-6 * n98.powf(1.5) / n98) / 1e-7;
    assert!((report.per_rod_ratio.unwrap() / want - 1.0).abs() < 1e-9);
}

#[test]
fn a_truth_system_reads_back_what_it_writes_and_refuses_the_rest() {
    let system = TruthSystem {
        gamma: 98.0,
        density: 165.5,
        box_len: 7,
        seed: 3,
    };
    assert_eq!(system.to_string(), "98,165.5,7,3");
    assert_eq!("98, 165.5, 7, 3".parse::<TruthSystem>().unwrap(), system);
    for bad in ["98,165.5,7", "98,165.5,7,3,1", "98,x,7,3", "98,165.5,7.5,3"] {
        let err = bad.parse::<TruthSystem>().unwrap_err().to_string();
        assert!(
            err.contains("--truth-system wants gamma,density,box,seed") && err.contains(bad),
            "{err}"
        );
    }
    // In this process it measures the system it names.
    let row = TruthSystem {
        gamma: 23.0,
        density: 34.0,
        box_len: 3,
        seed: 1,
    }
    .measure()
    .unwrap();
    assert_consistent(&row);
    assert_eq!(
        (row.gamma, row.density, row.box_len, row.seed),
        (23.0, 34.0, 3, 1)
    );
}
