//! The foundation benchmark: rows for the systems it was allowed, rule sets
//! timed against the base engine on the same graph, and its refusals. No
//! timing is asserted beyond being positive.

use std::process::Command;

use rgc::bench::{self, RULES_SYSTEM, RuleSetBench};
use rgc::contacts;
use rgc::engine::{self, CompiledRule, RuleSet};
use rgc::graph::ContactGraph;
use rgc::rods::{RodParams, RodSystem};
use rgc::rule_file;

fn rgc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

/// `rgc ARGS --json --out PATH`'s figures, checked to succeed and to be
/// what it wrote.
fn printed_as_written(args: &[&str], path: &std::path::Path) -> serde_json::Value {
    let mut all = args.to_vec();
    all.extend(["--json", "--out", path.to_str().unwrap()]);
    let out = rgc(&all);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(printed, written);
    printed
}

fn mined() -> Vec<CompiledRule> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs/mined.json");
    rule_file::load_rules(&[path])
        .unwrap()
        .iter()
        .map(CompiledRule::new)
        .collect()
}

#[test]
fn rows_match_the_systems_they_time_and_rules_are_set_against_the_base_engine() {
    let rules = mined();
    let sets = [RuleSetBench {
        name: "mined".into(),
        rules: &rules,
    }];
    let report = bench::run(2, 5000, &sets);
    // Only gamma 23 at L = 5 has no more than 5,000 rods.
    assert_eq!(report.systems.len(), 1);
    let row = &report.systems[0];
    assert_eq!((row.gamma, row.box_len, row.n_rods), (23.0, 5.0, 5000));
    // The row describes the last repetition's system (seed 1) as the engine sees it.
    let system = RodSystem::generate(RodParams::new(23.0, 5.0, 40.0).unwrap(), 1);
    let found = contacts::detect(&system);
    let graph = ContactGraph::from_contacts(system.len(), &found);
    let run = engine::compress(&graph, RuleSet::Sound, 1);
    assert_eq!(row.n_contacts, found.len());
    assert_eq!(row.components, run.components);
    assert_eq!(row.largest_body_rods, run.largest_rods());
    assert!(row.seconds_detect > 0.0 && row.seconds_compress > 0.0);
    let per_rod = row.seconds_detect * 1e9 / 5000.0;
    assert!((row.detect_ns_per_rod - per_rod).abs() <= 1e-9 * per_rod);
    // Without gamma 98 there is no detection ratio.
    assert_eq!(report.detect_ratio_98_to_23, None);
    assert_eq!(report.rules_system, RULES_SYSTEM);
    assert_eq!(report.rules.len(), 1);
    let r = &report.rules[0];
    assert_eq!((r.name.as_str(), r.n_rules), ("mined", 20));
    assert!(r.seconds_compress > 0.0 && r.ratio_to_base > 0.0, "{r:?}");
}

#[test]
fn the_cli_writes_the_figures_it_prints_and_refuses_what_it_cannot_run() {
    let dir = crate::scratch("bench-cli");
    let path = dir.join("bench.json");
    let printed = printed_as_written(
        &["bench", "--max-rods", "5000", "--repeat", "1", "--no-rules"],
        &path,
    );
    assert_eq!(printed["systems"].as_array().unwrap().len(), 1);
    assert_eq!(printed["rules"], serde_json::json!([]));
    assert!(printed.get("networkx").is_none());

    let fails = |args: &[&str], needle: &str| {
        let out = rgc(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(needle), "{err}");
        assert!(!err.contains("panicked"), "{err}");
    };
    let missing = dir.join("nowhere");
    fails(
        &[
            "bench",
            "--max-rods",
            "5000",
            "--motifs",
            missing.to_str().unwrap(),
        ],
        &format!(
            "rule file {} not found",
            missing.join("rods-6.json").display()
        ),
    );
    fails(
        &[
            "bench",
            "--max-rods",
            "5000",
            "--no-rules",
            "--networkx",
            "--python",
            "/nonexistent/python3",
        ],
        "--networkx needs /nonexistent/python3 with networkx",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_rule_sets_load_from_the_project_motifs_and_a_missing_file_is_named() {
    let motifs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs");
    let sets = bench::load_rule_sets(&motifs).unwrap();
    let names: Vec<&str> = sets.iter().map(|(n, _)| *n).collect();
    assert_eq!(names, ["extended", "mined"]);
    assert_eq!(sets[1].1.len(), mined().len());
    let dir = crate::scratch("bench-rule-sets");
    std::fs::copy(motifs.join("rods-6.json"), dir.join("rods-6.json")).unwrap();
    let err = bench::load_rule_sets(&dir).unwrap_err().to_string();
    assert!(
        err.contains(&format!(
            "rule file {} not found",
            dir.join("rods-8.json").display()
        )),
        "{err}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--rule-load` times the extended rule sets from the project's motifs:
/// the 1,569 rules of rods-6, rods-8, mixed-4, rods-9 and rods-10, the
/// 1,738 of mixed-5 and all 3,307; a set with a file missing is named.
#[test]
fn rule_load_times_the_extended_sets_and_names_a_missing_file() {
    let out = rgc(&["bench", "--rule-load", "--repeat", "1", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sets = report["sets"].as_array().unwrap();
    let rows: Vec<(&str, u64)> = sets
        .iter()
        .map(|s| (s["name"].as_str().unwrap(), s["rules"].as_u64().unwrap()))
        .collect();
    assert_eq!(
        rows,
        [
            ("rods<=10+mixed<=4", 1569),
            ("mixed-5", 1738),
            ("all extended", 3307)
        ]
    );
    for s in sets {
        let (load, compile, total) = (
            s["seconds_load"].as_f64().unwrap(),
            s["seconds_compile"].as_f64().unwrap(),
            s["seconds"].as_f64().unwrap(),
        );
        assert!(load > 0.0 && compile > 0.0, "{s}");
        assert!((load + compile - total).abs() < 1e-9, "{s}");
    }
    let dir = crate::scratch("bench-rule-load");
    let motifs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs");
    std::fs::copy(motifs.join("rods-6.json"), dir.join("rods-6.json")).unwrap();
    let out = rgc(&["bench", "--rule-load", "--motifs", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim_end(),
        format!(
            "rgc: error: invalid parameter: rule file {} not found (--motifs names the directory of the project's rule files)",
            dir.join("rods-8.json").display()
        )
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `bench --moduli`'s row is the moduli of the very system it names, and
/// its ratio counts the truth inside them (so it is at least 1).
#[test]
fn a_moduli_row_is_its_system_s_moduli_with_truth_inside_the_time() {
    use rgc::moduli::{ModuliOptions, Solver, of_system};
    use rgc::network::Network;
    use rgc::truth::TruthOptions;
    let (density, box_len, seed) = bench::moduli::SYSTEMS[0];
    let row = bench::moduli::measure(density, box_len, seed).unwrap();
    let params = RodParams::new(23.0, box_len as f64, density).unwrap();
    let network = Network::detect(RodSystem::generate(params, seed));
    let e = of_system(
        network.view(),
        ModuliOptions {
            stiffness: 1.0,
            truth: TruthOptions::seeded(seed),
            solver: Solver::Qr,
            lsmr_iterations: rgc::moduli::LSMR_ITERATIONS,
        },
    )
    .unwrap();
    assert_eq!(
        (row.strain_rank, row.shear, row.realization.as_str()),
        (e.strain_rank, e.shear, e.realization.as_str())
    );
    assert!(row.truth_seconds > 0.0 && row.seconds >= row.truth_seconds);
    assert_eq!(row.ratio, row.seconds / row.truth_seconds);
    // The relaxation is a part of the whole, after truth; the first
    // system resists no strain, so there is none by LSMR.
    assert!(row.relaxation_ratio > 0.0 && row.relaxation_ratio < row.ratio - 1.0);
    assert_eq!((row.lsmr_relaxation_ratio, row.lsmr_shear), (None, None));
    // A solid one: LSMR's G is the QR's.
    let (density, box_len, seed) = bench::moduli::SYSTEMS[1];
    let solid = bench::moduli::measure(density, box_len, seed).unwrap();
    let lsmr = solid.lsmr_shear.unwrap();
    assert!(
        (lsmr / solid.shear - 1.0).abs() < 1e-8,
        "{lsmr} against {}",
        solid.shear
    );
    assert!(solid.lsmr_relaxation_ratio.unwrap() > 0.0);

    // The command writes the rows it prints, one per system, in order.
    let dir = crate::scratch("bench-moduli");
    let printed = printed_as_written(&["bench", "--moduli"], &dir.join("moduli.json"));
    let rows = printed.as_array().unwrap();
    assert_eq!(rows.len(), bench::moduli::SYSTEMS.len());
    for (r, &(density, box_len, seed)) in rows.iter().zip(&bench::moduli::SYSTEMS) {
        assert_eq!(
            (
                r["density"].as_f64(),
                r["box_len"].as_u64(),
                r["seed"].as_u64()
            ),
            (Some(density), Some(box_len as u64), Some(seed))
        );
        assert!(r["ratio"].as_f64().unwrap() >= 1.0, "{r}");
    }
    assert_eq!(rows[0]["shear"].as_f64(), Some(e.shear));
    std::fs::remove_dir_all(dir).unwrap();
}
