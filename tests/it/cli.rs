//! The command-line contract: JSON fields, files written, exit codes and
//! one-line error messages.

use std::process::{Command, Output};

use serde_json::Value;

fn rgc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(args: &[&str]) -> Value {
    let out = rgc(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON object")
}

/// Runs a command that must fail with exit code 2 and a message containing `needle`.
fn fails(args: &[&str], needle: &str) {
    let out = rgc(args);
    assert_eq!(out.status.code(), Some(2), "{args:?} should exit with 2");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
}

#[test]
fn sample_json_has_the_contract_fields() {
    let v = json(&[
        "sample",
        "--gamma",
        "23",
        "--box",
        "5",
        "--density",
        "40",
        "--seed",
        "3",
        "--runs",
        "4",
        "--json",
    ]);
    for key in [
        "n_rods",
        "n_contacts",
        "c0",
        "c1",
        "c2",
        "clustering",
        "contact_spanning",
        "rigid_spanning",
        "largest_body_rods",
        "n_bodies",
        "seconds",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["n_rods"], 5000);
    let c0 = 2.0 * v["n_contacts"].as_f64().unwrap() / 5000.0;
    assert!((v["c0"].as_f64().unwrap() - c0).abs() < 1e-12);
    assert_eq!(v["runs"], 4);
    assert_eq!(v["rules"], "sound");
    assert_eq!(v["criterion"], "wrap");
    // Contact spanning is necessary for rigid spanning.
    if v["rigid_spanning"].as_bool().unwrap() {
        assert!(v["contact_spanning"].as_bool().unwrap());
    }
}

#[test]
fn sample_is_reproducible_and_saves_its_contacts() {
    let dir = std::env::temp_dir().join(format!("rgc-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("contacts.txt");
    let bodies_path = dir.join("bodies.json");
    let args = |p: &str| {
        vec![
            "sample",
            "--gamma",
            "10",
            "--box",
            "4",
            "--density",
            "12",
            "--seed",
            "9",
            "--runs",
            "3",
            "--rules",
            "paper",
            "--criterion",
            "faces",
            "--save-contacts",
            p,
            "--save-bodies",
            bodies_path.to_str().unwrap(),
            "--json",
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>()
    };
    let a = args(path.to_str().unwrap());
    let mut first = json(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let mut second = json(&a.iter().map(String::as_str).collect::<Vec<_>>());
    for v in [&mut first, &mut second] {
        for k in ["seconds", "seconds_contacts", "seconds_compression"] {
            v.as_object_mut().unwrap().remove(k);
        }
    }
    assert_eq!(first, second);
    let g = rgc::graph::io::read_edge_list(&path).unwrap();
    assert_eq!(g.n_nodes() as u64, first["n_rods"].as_u64().unwrap());
    assert_eq!(g.n_edges() as u64, first["n_contacts"].as_u64().unwrap());
    let bodies: Value =
        serde_json::from_str(&std::fs::read_to_string(&bodies_path).unwrap()).unwrap();
    let list = bodies["bodies"].as_array().unwrap();
    assert_eq!(list.len() as u64, first["n_bodies"].as_u64().unwrap());
    assert_eq!(bodies["run"], first["reported_run"]);
    let spanning = list.iter().any(|b| b["spans"].as_bool().unwrap());
    let runs_spanning = first["runs_spanning"].as_u64().unwrap();
    assert_eq!(
        spanning,
        runs_spanning > 0,
        "the reported run is a spanning one when any is"
    );
    // The saved graph compresses the same way through `rgc compress`.
    let c = json(&[
        "compress",
        "--edges",
        path.to_str().unwrap(),
        "--json",
        "--runs",
        "1",
    ]);
    assert_eq!(c["nodes"], first["n_rods"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn compress_reports_components_and_bodies() {
    // K_{2,4}: one spatial body by 3D6.
    let v = json(&["compress", "--graph6", "E]r?", "--runs", "3", "--json"]);
    assert_eq!(v["components"], 1);
    assert_eq!(
        v["bodies"][0]["rods"],
        serde_json::json!([0, 1, 2, 3, 4, 5])
    );
    assert_eq!(v["bodies"][0]["class"], "spatial");
    assert_eq!(v["components_per_run"], serde_json::json!([1, 1, 1]));
    // The rod prism: two planar bodies under sound, one body under paper.
    let prism = "E{Sw";
    let g = rgc::graph::io::parse_graph6(prism).unwrap();
    assert_eq!((g.n_nodes(), g.n_edges()), (6, 9));
    let sound = json(&["compress", "--graph6", prism, "--runs", "8", "--json"]);
    assert_eq!(sound["components"], 2);
    assert_eq!(sound["bodies"][0]["class"], "planar");
    let paper = json(&[
        "compress", "--graph6", prism, "--runs", "8", "--rules", "paper", "--json",
    ]);
    assert_eq!(paper["components"], 1);
    // A 4-cycle stays four rods.
    let v = json(&["compress", "--graph6", "Cl", "--json"]);
    assert_eq!(v["components"], 4);
    assert_eq!(v["bodies"], serde_json::json!([]));
}

#[test]
fn bad_input_is_a_one_line_error_with_exit_code_2() {
    let sample = |g: &str, l: &str, d: &str| {
        vec!["sample", "--gamma", g, "--box", l, "--density", d]
            .into_iter()
            .map(String::from)
            .collect::<Vec<_>>()
    };
    let run = |v: Vec<String>, needle: &str| {
        fails(&v.iter().map(String::as_str).collect::<Vec<_>>(), needle)
    };
    run(
        sample("-1", "5", "3"),
        "gamma must be a positive finite number",
    );
    run(
        sample("0", "5", "3"),
        "gamma must be a positive finite number",
    );
    run(
        sample("NaN", "5", "3"),
        "gamma must be a positive finite number",
    );
    run(
        sample("23", "inf", "3"),
        "box must be a positive finite number",
    );
    run(
        sample("23", "5", "-2"),
        "density must be a positive finite number",
    );
    run(sample("23", "1.5", "3"), "box 1.5 is too small");
    run(sample("23", "100", "1e9"), "more than the");
    run(sample("23", "5", "abc"), "invalid value");
    fails(&["compress", "--graph6", "A"], "malformed graph6");
    fails(&["compress", "--graph6", ""], "malformed graph6");
    fails(
        &["compress", "--edges", "/nonexistent/edges.txt"],
        "/nonexistent/edges.txt",
    );
    fails(
        &["compress", "--graph6", "A_", "--edges", "x"],
        "cannot be used with",
    );
    fails(&["compress"], "required");
    fails(&["compress", "--graph6", "A_", "--runs", "0"], "--runs");
    let dir = std::env::temp_dir().join(format!("rgc-cli-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.txt");
    std::fs::write(&bad, "0 1\n1 x\n").unwrap();
    fails(&["compress", "--edges", bad.to_str().unwrap()], "line 2");
    std::fs::write(&bad, "0 1\n2 2\n").unwrap();
    fails(&["compress", "--edges", bad.to_str().unwrap()], "line 2");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn audit_writes_its_tables_and_rule_files() {
    let dir = std::env::temp_dir().join(format!("rgc-cli-audit-{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let out = rgc(&[
        "audit",
        "--max-rods",
        "6",
        "--max-components",
        "3",
        "--results",
        d,
        "--motifs",
        d,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("base motif examples compress as expected"),
        "{text}"
    );
    assert!(
        text.contains("Rods-only motifs") && text.contains("Mixed motifs"),
        "{text}"
    );
    let rods = std::fs::read_to_string(dir.join("audit-rods.csv")).unwrap();
    let lines: Vec<&str> = rods.lines().collect();
    assert_eq!(lines.len(), 6, "header and sizes 2..=6: {rods}");
    // Connected graphs on 6 nodes: 112; with minimum degree 2: 61.
    assert!(lines[5].starts_with("rods,6,112,61,"), "{}", lines[5]);
    let mixed = std::fs::read_to_string(dir.join("audit-mixed.csv")).unwrap();
    assert_eq!(mixed.lines().count(), 3);
    // The irreducible missed motifs of six rods are written as rules that load.
    let irreducible: usize = lines[5].split(',').nth(11).unwrap().parse().unwrap();
    assert!(
        irreducible >= 1,
        "the base motifs miss rigid six-rod motifs: {}",
        lines[5]
    );
    let rules = rgc::rule_file::load_rules(&[dir.join("rods-6.json")]).unwrap();
    assert_eq!(rules.len(), irreducible);
    // A rods-only rerun rewrites the rods table (when forced: it was made
    // with other parameters) and keeps the mixed one.
    let out = rgc(&[
        "audit",
        "--max-rods",
        "4",
        "--max-components",
        "0",
        "--results",
        d,
        "--motifs",
        d,
        "--force",
    ]);
    assert!(out.status.success());
    let rods = std::fs::read_to_string(dir.join("audit-rods.csv")).unwrap();
    assert_eq!(rods.lines().count(), 4, "header and sizes 2..=4: {rods}");
    assert_eq!(
        std::fs::read_to_string(dir.join("audit-mixed.csv")).unwrap(),
        mixed
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A small threshold study's arguments, with some options replaced or added.
fn threshold_args<'a>(out: &'a str, changes: &[(&'a str, &'a str)]) -> Vec<&'a str> {
    let mut options = vec![
        ("--gamma", "10"),
        ("--boxes", "3,3.5,4"),
        ("--realizations", "40"),
        ("--runs", "2"),
        ("--bootstrap", "40"),
        ("--out", out),
    ];
    for &(flag, value) in changes {
        match options.iter_mut().find(|o| o.0 == flag) {
            Some(o) => o.1 = value,
            None => options.push((flag, value)),
        }
    }
    let mut args = vec!["threshold", "--quiet"];
    args.extend(options.into_iter().flat_map(|(f, v)| [f, v]));
    args
}

#[test]
fn threshold_killed_mid_run_resumes_to_the_uninterrupted_results() {
    let base = std::env::temp_dir().join(format!("rgc-cli-kill-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let (whole, killed) = (base.join("whole"), base.join("killed"));
    let (w, k) = (whole.to_str().unwrap(), killed.to_str().unwrap());
    let out = rgc(&threshold_args(w, &[]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("threshold rho_c = ") && text.contains("nu = "),
        "{text}"
    );

    let mut child = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(threshold_args(k, &[]))
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let records = killed.join("records.jsonl");
    let started = std::time::Instant::now();
    while std::fs::read_to_string(&records).map_or(0, |t| t.lines().count()) < 5 {
        assert!(started.elapsed().as_secs() < 120, "no records appear");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = std::fs::read_to_string(&records).unwrap().lines().count();
    let out = rgc(&threshold_args(k, &[]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(&format!("({before} found done)")) || before == 120,
        "{text}"
    );
    let read = |d: &std::path::Path| std::fs::read_to_string(d.join("summary.json")).unwrap();
    assert_eq!(read(&whole), read(&killed));
    assert_eq!(
        std::fs::read_to_string(&records).unwrap().lines().count(),
        120
    );

    // The same directory with another study is refused, naming the difference.
    fails(&threshold_args(k, &[("--runs", "3")]), "runs 2 vs 3");
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn threshold_rejects_bad_parameters() {
    let dir = std::env::temp_dir().join(format!("rgc-cli-bad-{}", std::process::id()));
    let d = dir.to_str().unwrap();
    fails(&threshold_args(d, &[("--shard", "3/2")]), "shard \"3/2\"");
    fails(
        &threshold_args(d, &[("--boxes", "1,2,3")]),
        "box 1 is too small",
    );
    fails(
        &threshold_args(d, &[("--realizations", "0")]),
        "--realizations must be at least 1",
    );
    fails(
        &threshold_args(d, &[("--gamma", "-4")]),
        "gamma must be a positive",
    );
    fails(
        &threshold_args(d, &[("--boxes", "4,4,5")]),
        "box sizes repeat",
    );
    // Two box sizes cannot give nu: a clear message, not NaN.
    fails(
        &threshold_args(d, &[("--boxes", "3,4"), ("--realizations", "8")]),
        "nu needs at least 3 box sizes, got 2",
    );
    // Refused before any realization runs: nothing was written.
    assert!(!dir.join("records.jsonl").exists());
    let missing = dir.join("no-such-study");
    fails(&["merge", missing.to_str().unwrap()], "study.json");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn aspect_ratios_chart_thresholds_of_finished_studies() {
    let base = std::env::temp_dir().join(format!("rgc-cli-aspect-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let dirs: Vec<String> = ["g10", "g20", "rigid"]
        .iter()
        .map(|d| base.join(d).to_str().unwrap().to_string())
        .collect();
    for (dir, gamma, kind) in [
        (&dirs[0], "10", "contact"),
        (&dirs[1], "20", "contact"),
        (&dirs[2], "10", "rigid"),
    ] {
        let args = threshold_args(
            dir,
            &[("--gamma", gamma), ("--kind", kind), ("--boxes", "3,4,5")],
        );
        let out = rgc(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let stem = base.join("vex");
    let out = rgc(&[
        "aspect-ratios",
        &dirs[0],
        &dirs[1],
        "--out",
        stem.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(stem.with_extension("csv")).unwrap();
    assert_eq!(csv.lines().count(), 3);
    // Contact percolation near c0 = 1.4 at both aspect ratios (Philipse's V_ex).
    for line in csv.lines().skip(1) {
        let times_vex: f64 = line.split(',').nth(5).unwrap().parse().unwrap();
        assert!((1.0..2.0).contains(&times_vex), "{line}");
    }
    assert!(stem.with_extension("png").exists());
    let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
    assert!(
        svg.contains("Contact threshold against"),
        "a contact study is titled so"
    );
    fails(
        &[
            "aspect-ratios",
            &dirs[0],
            &dirs[2],
            "--out",
            stem.to_str().unwrap(),
        ],
        "is a Rigid study",
    );
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn bench_reports_rank_throughput() {
    let out = rgc(&["bench", "--rank", "6"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("6 rods, one thread: ranks/s exact "),
        "{text}"
    );
    fails(&["bench", "--rank", "2"], "throughput needs 3 to");
}
