//! The command-line contract: JSON fields, files written, exit codes and
//! one-line error messages.

use std::process::{Command, Output};

use serde_json::Value;

pub fn rgc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&stdout_of(args)).expect("stdout is one JSON object")
}

/// Runs a command that must fail with exit code 2 and a message containing `needle`.
pub fn fails(args: &[&str], needle: &str) {
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
    let dir = crate::scratch("cli-sample-saves");
    let path = dir.join("contacts.txt");
    let bodies_path = dir.join("bodies.json");
    let graphml_path = dir.join("contacts.graphml");
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
            "--save-graphml",
            graphml_path.to_str().unwrap(),
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
    // The GraphML holds the same graph, with each contact's geometry.
    let ml = rgc::graph::graphml::read_graphml(&graphml_path).unwrap();
    assert_eq!(ml.system.len(), g.n_nodes());
    let ml_edges: Vec<[u32; 2]> = ml.contacts.iter().map(|c| c.rods).collect();
    assert_eq!(ml_edges, g.edges());
    assert!(
        ml.contacts
            .iter()
            .all(|c| c.params.iter().all(|s| s.abs() <= 0.5))
    );
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
    // The saved graph compresses the same way through `rgc compress`: with
    // the sample's seed and runs, every run ends with the same number of
    // nodes as on the sample's own graph, and the reported runs' bodies are
    // the same rods with the same classes.
    let c = json(&[
        "compress",
        "--edges",
        path.to_str().unwrap(),
        "--json",
        "--seed",
        "9",
        "--runs",
        "3",
        "--rules",
        "paper",
    ]);
    assert_eq!(c["nodes"], first["n_rods"]);
    assert_eq!(c["contacts"], first["n_contacts"]);
    let own = rgc::sample::sample(&rgc::sample::SampleOptions {
        rods: rgc::rods::RodParams::new(10.0, 4.0, 12.0).unwrap().into(),
        seed: 9,
        runs: 3,
        rules: rgc::engine::RuleSet::Paper,
        criterion: rgc::spanning::Criterion::Faces,
        truth: false,
    })
    .unwrap();
    let per_run: Vec<usize> = own.runs.iter().map(|r| r.components).collect();
    assert_eq!(c["components_per_run"], serde_json::json!(per_run));
    let k = first["reported_run"].as_u64().unwrap() as usize;
    assert_eq!(first["components"], serde_json::json!(per_run[k]));
    let best = c["reported_run"].as_u64().unwrap() as usize;
    let body_list = |bodies: &[rgc::body::Body]| -> Value {
        bodies
            .iter()
            .map(|b| serde_json::json!({ "rods": b.rods, "class": b.class }))
            .collect()
    };
    let strip = |list: &Value| -> Value {
        list.as_array()
            .unwrap()
            .iter()
            .map(|b| serde_json::json!({ "rods": b["rods"], "class": b["class"] }))
            .collect()
    };
    assert_eq!(strip(&c["bodies"]), body_list(&own.runs[best].bodies));
    assert_eq!(strip(&bodies["bodies"]), body_list(&own.runs[k].bodies));
    assert!(
        own.runs.iter().any(|r| !r.bodies.is_empty()),
        "a graph with bodies, so that the comparison says something"
    );
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
    let dir = crate::scratch("cli-bad-input");
    let bad = dir.join("bad.txt");
    std::fs::write(&bad, "0 1\n1 x\n").unwrap();
    fails(&["compress", "--edges", bad.to_str().unwrap()], "line 2");
    std::fs::write(&bad, "0 1\n2 2\n").unwrap();
    fails(&["compress", "--edges", bad.to_str().unwrap()], "line 2");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A CSV table without its last column (`seconds` in the audit tables,
/// which no run repeats).
fn without_last_column(table: &str) -> Vec<String> {
    table
        .lines()
        .map(|l| l.rsplit_once(',').map_or(l, |(head, _)| head).to_string())
        .collect()
}

/// The committed table of `results/`, without timings.
fn committed(name: &str) -> Vec<String> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("results")
        .join(name);
    without_last_column(&std::fs::read_to_string(path).unwrap())
}

/// Runs `rgc audit` with tables and rule files in `dir`.
fn audit_into(dir: &std::path::Path, extra: &[&str], threads: Option<&str>) -> String {
    let d = dir.to_str().unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rgc"));
    cmd.args(["audit", "--results", d, "--rules-dir", d])
        .args(extra);
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    let out = cmd.output().expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn audit_writes_its_tables_and_rule_files() {
    let dir = crate::scratch("cli-audit");
    let text = audit_into(&dir, &["--max-rods", "7", "--max-components", "3"], None);
    assert!(
        text.contains("27 base motif examples compress as expected"),
        "{text}"
    );
    assert!(
        text.contains("Rods-only motifs") && text.contains("Mixed motifs"),
        "{text}"
    );
    let rods = std::fs::read_to_string(dir.join("audit-rods.csv")).unwrap();
    let rows = without_last_column(&rods);
    assert_eq!(rows.len(), 7, "header and sizes 2..=7: {rods}");
    // Six rods: 112 connected graphs, 61 with minimum degree 2 (geng), 55 of
    // them Maxwell; 45 rigid, 2 component-dependent (the prism, K_{3,3}), 8
    // flexible; the engine compresses 44, misses 1 rigid motif (irreducible)
    // and compresses nothing falsely.
    assert_eq!(rows[5], "rods,6,112,61,55,45,2,8,0,44,1,1,0");
    // Seven rods: the engine falsely compresses 2 patterns under `sound`
    // (K_{3,4} is one of them).
    let seven: Vec<&str> = rows[6].split(',').collect();
    assert_eq!(seven[..4], ["rods", "7", "853", "507"]);
    assert_eq!(seven[12], "2", "{}", rows[6]);
    // The same numbers as the committed audit (sizes 2 to 7 of rods, 2 and 3
    // components of mixed motifs).
    assert_eq!(rows, committed("audit-rods.csv")[..7]);
    let mixed = std::fs::read_to_string(dir.join("audit-mixed.csv")).unwrap();
    assert_eq!(
        without_last_column(&mixed),
        committed("audit-mixed.csv")[..3]
    );
    // The irreducible missed motif of six rods is written as a rule that
    // loads (re-verified by exact rank), and is the committed one.
    let rules = rgc::rule_file::load_rules(&[dir.join("rods-6.json")]).unwrap();
    assert_eq!(rules.len(), 1);
    let committed_rules =
        rgc::rule_file::load_rules(&[
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs/rods-6.json")
        ])
        .unwrap();
    assert_eq!(rules[0].canonical, committed_rules[0].canonical);
    assert!(
        !dir.join("rods-7.json").exists(),
        "nothing irreducible at seven rods"
    );
    // A rods-only rerun rewrites the rods table (when forced: it was made
    // with other parameters) and keeps the mixed one.
    audit_into(
        &dir,
        &["--max-rods", "4", "--max-components", "0", "--force"],
        None,
    );
    let rods = std::fs::read_to_string(dir.join("audit-rods.csv")).unwrap();
    assert_eq!(rods.lines().count(), 4, "header and sizes 2..=4: {rods}");
    assert_eq!(
        std::fs::read_to_string(dir.join("audit-mixed.csv")).unwrap(),
        mixed
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn audit_results_do_not_depend_on_the_thread_count() {
    let args = ["--max-rods", "7", "--max-components", "3"];
    let (one, two) = (
        crate::scratch("cli-audit-1-thread"),
        crate::scratch("cli-audit-2-threads"),
    );
    audit_into(&one, &args, Some("1"));
    audit_into(&two, &args, Some("2"));
    for table in ["audit-rods.csv", "audit-mixed.csv"] {
        let read = |d: &std::path::Path| {
            without_last_column(&std::fs::read_to_string(d.join(table)).unwrap())
        };
        assert_eq!(read(&one), read(&two), "{table}");
    }
    let files = |d: &std::path::Path| {
        let mut names: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().ends_with(".json"))
            .collect();
        names.sort();
        names
    };
    assert_eq!(files(&one), files(&two));
    assert!(!files(&one).is_empty());
    for name in files(&one) {
        assert_eq!(
            std::fs::read(one.join(&name)).unwrap(),
            std::fs::read(two.join(&name)).unwrap(),
            "{name:?}"
        );
    }
    for d in [one, two] {
        std::fs::remove_dir_all(d).unwrap();
    }
}

/// A small threshold study's arguments, with some options replaced or added.
fn threshold_args<'a>(out: &'a str, changes: &[(&'a str, &'a str)]) -> Vec<&'a str> {
    let mut options = vec![
        ("--gamma", "10"),
        ("--boxes", "3,3.5,4"),
        ("--sequences", "40"),
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
    let base = crate::scratch("cli-threshold-kill");
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
        text.contains("120 sequences run in") && text.contains("(0 found done)"),
        "{text}"
    );
    assert!(
        text.contains("threshold rho_c = ") && text.contains("nu = "),
        "{text}"
    );

    // Killed as soon as its first record is on disk, with 119 sequences to go.
    let mut child = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(threshold_args(k, &[]))
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let records = killed.join("records.jsonl");
    let started = std::time::Instant::now();
    while !std::fs::read_to_string(&records).is_ok_and(|t| t.contains('\n')) {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the study ended before its first record was seen"
        );
        assert!(started.elapsed().as_secs() < 120, "no records appear");
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert!(!status.success(), "the study finished before it was killed");
    // Complete lines only: a line cut by the kill is not a record.
    let before = std::fs::read_to_string(&records)
        .unwrap()
        .matches('\n')
        .count();
    assert!(
        (1..120).contains(&before),
        "{before} records before the kill"
    );
    assert!(
        !killed.join("summary.json").exists(),
        "a killed study is not analysed"
    );

    // The same command resumes: it finds the records of before the kill and
    // runs only the rest.
    let out = rgc(&threshold_args(k, &[]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(&format!("{} sequences run in", 120 - before))
            && text.contains(&format!("({before} found done)")),
        "{before} records before the kill: {text}"
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
    let dir = crate::scratch("cli-threshold-bad");
    let d = dir.to_str().unwrap();
    fails(&threshold_args(d, &[("--shard", "3/2")]), "shard \"3/2\"");
    fails(
        &threshold_args(d, &[("--boxes", "1,2,3")]),
        "box 1 is too small",
    );
    fails(
        &threshold_args(d, &[("--sequences", "0")]),
        "--sequences must be at least 1",
    );
    // The old spelling of `--sequences` still works, for existing scripts.
    fails(
        &["threshold", "--quiet", "--realizations", "0", "--out", d],
        "--sequences must be at least 1",
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
        &threshold_args(d, &[("--boxes", "3,4"), ("--sequences", "8")]),
        "nu needs at least 3 box sizes, got 2",
    );
    // Refused before any sequence runs: nothing was written.
    assert!(!dir.join("records.jsonl").exists());
    let missing = dir.join("no-such-study");
    fails(&["merge", missing.to_str().unwrap()], "study.json");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn aspect_ratios_chart_thresholds_of_finished_studies() {
    let base = crate::scratch("cli-aspect-ratios");
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
    // Two studies with intervals give the exponent an interval around it.
    let fit: Value =
        serde_json::from_str(&std::fs::read_to_string(stem.with_extension("json")).unwrap())
            .unwrap();
    assert_eq!(fit["rows"].as_array().unwrap().len(), 2);
    let free = &fit["fit"]["free"];
    let m = free["m"].as_f64().unwrap();
    let (lo, hi) = (
        free["m_interval"][0].as_f64().unwrap(),
        free["m_interval"][1].as_f64().unwrap(),
    );
    assert!(lo < m && m < hi, "{free}");
    let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
    assert!(
        svg.contains("Contact threshold against"),
        "a contact study is titled so"
    );
    // Each study's contact numbers at its threshold, over all boxes and per
    // box, against Maxwell's count.
    let contacts = std::fs::read_to_string(base.join("vex-contacts.csv")).unwrap();
    assert_eq!(contacts.lines().count(), 1 + 2 * (1 + 3), "{contacts}");
    let md = std::fs::read_to_string(base.join("vex-contacts.md")).unwrap();
    assert!(md.contains("| contact | 10 | all |"), "{md}");
    assert!(md.contains("| contact | 20 | 5 |"), "{md}");
    // Contact percolation sits far below Maxwell's count.
    assert_eq!(md.matches(" | -").count(), 8, "{md}");
    // Another kind goes beside, with its own fit, not into the first's.
    let out = rgc(&[
        "aspect-ratios",
        &dirs[0],
        &dirs[1],
        "--beside",
        &dirs[2],
        "--out",
        stem.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let both: Value =
        serde_json::from_str(&std::fs::read_to_string(stem.with_extension("json")).unwrap())
            .unwrap();
    assert_eq!(both["fit"], fit["fit"]);
    assert_eq!(both["beside"][0]["kind"], "rigid");
    assert_eq!(both["beside"][0]["rows"].as_array().unwrap().len(), 1);
    let csv = std::fs::read_to_string(stem.with_extension("csv")).unwrap();
    assert_eq!(
        csv.lines().filter(|l| l.ends_with(",rigid")).count(),
        1,
        "{csv}"
    );
    let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
    assert!(svg.contains("3D-RGC: threshold with its interval"));
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

/// A file of the repository, read-only.
fn repo(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Runs a command that must succeed and returns its stdout.
fn stdout_of(args: &[&str]) -> String {
    let out = rgc(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn check_gives_the_exact_verdicts_of_known_motifs() {
    // K_{2,4} of rods (3D6): rigid on its one component.
    let v = json(&["check", "--graph6", "E]r?", "--json"]);
    assert_eq!(
        (&v["class"], &v["dof"], &v["rigid"]),
        (&"rigid".into(), &0.into(), &true.into())
    );
    // The rod prism: rigid only when all six rods share a plane.
    let prism = json(&["check", "--graph6", "E{Sw", "--json"]);
    assert_eq!(prism["class"], "component-dependent");
    assert_eq!(prism["dof"], 1);
    assert_eq!(prism["rigid"], false);
    let dofs: Vec<u64> = prism["components"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["component"] == true)
        .map(|c| c["dof"].as_u64().unwrap())
        .collect();
    assert!(dofs.contains(&0) && dofs.contains(&1), "{prism}");
    // A 4-cycle of rods flexes.
    let cycle = json(&["check", "--graph6", "Cl", "--json"]);
    assert_eq!(
        (&cycle["class"], &cycle["rigid"]),
        (&"flexible".into(), &false.into())
    );
    // Floats agree with the exact verdict away from special positions.
    let svd = json(&["check", "--graph6", "E{Sw", "--method", "svd", "--json"]);
    assert_eq!(
        (&svd["class"], &svd["dof"]),
        (&prism["class"], &prism["dof"])
    );
    assert_eq!(svd["method"], "svd");
    // Every rule of a rule file, as a list: all rigid (they were verified
    // when written, and are again now).
    let rules = json(&[
        "check",
        "--motif",
        repo("motifs/rods-8.json").to_str().unwrap(),
        "--json",
    ]);
    let list = rules.as_array().unwrap();
    assert_eq!(list.len(), 13);
    assert!(list.iter().all(|v| v["class"] == "rigid" && v["dof"] == 0));
    // The summary names the pattern, its class and DOF, one line per component.
    let text = stdout_of(&["check", "--graph6", "E{Sw"]);
    let first = text.lines().next().unwrap();
    assert!(
        first.starts_with("E{Sw: component-dependent (DOF 1, rank "),
        "{text}"
    );
    assert_eq!(
        text.lines().count(),
        1 + prism["components"].as_array().unwrap().len(),
        "{text}"
    );
    fails(
        &["check", "--graph6", "E{Sw", "--method", "lu"],
        "invalid value",
    );
}

#[test]
fn rules_writes_the_committed_base_rules() {
    let dir = crate::scratch("cli-rules");
    let path = dir.join("base.json");
    let text = stdout_of(&["rules", "--out", path.to_str().unwrap()]);
    assert_eq!(
        std::fs::read(&path).unwrap(),
        std::fs::read(repo("motifs/base.json")).unwrap(),
        "the base rules differ from motifs/base.json"
    );
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        format!(
            "59 base motif rules written to {}; 3 variants the published conditions accept are refuted by exact rank:",
            path.display()
        )
    );
    // The refuted variants: 3D2A between two planar bodies, whatever rods
    // the contacts share (a hinge on the planes' common line).
    assert_eq!(lines.len(), 4, "{text}");
    for l in &lines[1..] {
        assert!(
            l.starts_with(
                "  3D2A component-dependent (DOF Some(1)): {\"kinds\":[\"planar\",\"planar\"]"
            ),
            "{l}"
        );
    }
    // The committed record of the same command says the same.
    let committed = std::fs::read_to_string(repo("results/base-rules.txt")).unwrap();
    assert_eq!(
        text.replace(path.to_str().unwrap(), "motifs/base.json"),
        committed
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn enumerate_lists_the_graphs_geng_lists() {
    let canonical = |text: &str| -> std::collections::BTreeSet<String> {
        text.lines()
            .map(|l| rgc::enumerate::canonical_graph6(&rgc::graph::io::parse_graph6(l).unwrap()))
            .collect()
    };
    let out = stdout_of(&[
        "enumerate",
        "--nodes",
        "7",
        "--min-degree",
        "2",
        "--maxwell",
    ]);
    assert_eq!(out.lines().count(), 467);
    let geng = std::fs::read_to_string(repo("graphs/maxwell-mindeg2-n7.g6")).unwrap();
    assert_eq!(canonical(&out), canonical(&geng));
    for (args, count) in [
        (vec!["--nodes", "6"], "112"),
        (vec!["--nodes", "7"], "853"),
        (vec!["--nodes", "6", "--min-degree", "2"], "61"),
        (vec!["--nodes", "5", "--min-degree", "2", "--maxwell"], "7"),
        (vec!["--nodes", "6", "--min-edges", "14"], "2"),
        (vec!["--nodes", "6", "--max-edges", "5"], "6"),
    ] {
        let mut a = vec!["enumerate", "--count"];
        a.extend(args.iter().copied());
        assert_eq!(stdout_of(&a).trim(), count, "{a:?}");
    }
    fails(&["enumerate", "--nodes", "13"], "13");
}

/// Records of a study directory by (box, seed): their critical number of rods.
fn criticals(dir: &str) -> std::collections::BTreeMap<(u64, u64), (f64, u64)> {
    std::fs::read_to_string(std::path::Path::new(dir).join("records.jsonl"))
        .unwrap()
        .lines()
        .map(|l| {
            let r: Value = serde_json::from_str(l).unwrap();
            let l = r["box"].as_f64().unwrap();
            (
                (l.to_bits(), r["seed"].as_u64().unwrap()),
                (l, r["rigid_critical"].as_u64().unwrap()),
            )
        })
        .collect()
}

#[test]
fn compare_runs_the_three_rule_sets_on_the_same_rods() {
    let dir = crate::scratch("cli-compare");
    let (studies, results) = (dir.join("studies"), dir.join("results"));
    let text = stdout_of(&[
        "compare",
        "--gamma",
        "5",
        "--boxes",
        "2.5,3,3.5",
        "--sequences",
        "12",
        "--bootstrap",
        "20",
        "--extended",
        repo("motifs/rods-6.json").to_str().unwrap(),
        "--studies",
        studies.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        text.starts_with("# Rigidity threshold, gamma 5: paper base against sound base against sound + extended motifs"),
        "{text}"
    );
    let md = std::fs::read_to_string(results.join("compare-base-extended.md")).unwrap();
    assert_eq!(text.trim_end(), md.trim_end());
    let report: Value = serde_json::from_str(
        &std::fs::read_to_string(results.join("compare-base-extended.json")).unwrap(),
    )
    .unwrap();
    let v = report["variants"].as_array().unwrap();
    let field = |k: &str| v.iter().map(|x| x[k].clone()).collect::<Vec<_>>();
    assert_eq!(
        field("label"),
        ["paper base", "sound base", "sound + extended"].map(Value::from)
    );
    assert_eq!(field("rules"), ["paper", "sound", "sound"].map(Value::from));
    assert_eq!(field("motif_rules"), [0, 0, 1].map(Value::from));
    // `realizations`: the stored key of the sequences each variant analyses.
    assert_eq!(field("realizations"), [12, 12, 12].map(Value::from));
    // Three studies of 36 sequences each, on the same rod sequences.
    assert_eq!(std::fs::read_dir(&studies).unwrap().count(), 3);
    let runs: Vec<_> = v
        .iter()
        .map(|x| criticals(x["study"].as_str().unwrap()))
        .collect();
    for r in &runs {
        assert_eq!(r.len(), 36);
        assert!(r.keys().eq(runs[0].keys()), "the same sequences");
    }
    // Thresholds relative to the first variant, and paired differences of
    // each sequence's critical density to the variant before, recomputed
    // from the records.
    let t0 = v[0]["threshold"]["value"].as_f64().unwrap();
    for (k, x) in v.iter().enumerate() {
        let t = x["threshold"]["value"].as_f64().unwrap();
        assert!((x["relative_difference"].as_f64().unwrap() - (t - t0) / t0).abs() < 1e-12);
        if k == 0 {
            assert!(x["paired_difference"].is_null());
            continue;
        }
        assert_eq!(x["paired_with"], v[k - 1]["label"]);
        let diffs: Vec<f64> = runs[k]
            .iter()
            .map(|(key, &(l, n))| (n as f64 - runs[k - 1][key].1 as f64) / l.powi(3))
            .collect();
        let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
        let paired = x["paired_difference"]["value"].as_f64().unwrap();
        assert!((paired - mean).abs() < 1e-12, "{paired} vs {mean}");
    }
    // The CSV holds the same numbers, one line per variant.
    let csv = std::fs::read_to_string(results.join("compare-base-extended.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 4);
    assert!(
        lines[0].starts_with("label,family,rules,motif_rules,runs,method,realizations,threshold,")
    );
    for (line, x) in lines[1..].iter().zip(v) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[0], x["label"].as_str().unwrap());
        let t: f64 = cells[7].parse().unwrap();
        assert!((t - x["threshold"]["value"].as_f64().unwrap()).abs() < 1e-6);
    }
    let svg = std::fs::read_to_string(results.join("compare-base-extended.svg")).unwrap();
    assert!(svg.contains("sound + extended"));
    let png = std::fs::read(results.join("compare-base-extended.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tradeoff_measures_every_family_of_variants() {
    let dir = crate::scratch("cli-tradeoff");
    // Small rule files under the names the trade-off reads: the committed
    // six-rod rule, and two rules each of the larger sets.
    let motifs = dir.join("motifs");
    std::fs::create_dir_all(&motifs).unwrap();
    for (name, keep) in [("rods-6", 1), ("rods-8", 2), ("mixed-4", 2)] {
        let file = repo(&format!("motifs/{name}.json"));
        let mut f: Value = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        f["rules"].as_array_mut().unwrap().truncate(keep);
        std::fs::write(motifs.join(format!("{name}.json")), f.to_string()).unwrap();
    }
    let (studies, results) = (dir.join("studies"), dir.join("results"));
    let text = stdout_of(&[
        "tradeoff",
        "--gamma",
        "5",
        "--boxes",
        "2.5,3,3.5",
        "--sequences",
        "20",
        "--bootstrap",
        "20",
        // A seed whose tiny truth study still fits a scaling law.
        "--seed",
        "2",
        "--runs-list",
        "1,2",
        "--motifs-dir",
        motifs.to_str().unwrap(),
        "--studies",
        studies.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        text.starts_with("# Speed against accuracy, rigidity threshold, gamma 5"),
        "{text}"
    );
    let report: Value = serde_json::from_str(
        &std::fs::read_to_string(results.join("speed-accuracy.json")).unwrap(),
    )
    .unwrap();
    let v = report["variants"].as_array().unwrap();
    let field = |k: &str| v.iter().map(|x| x[k].clone()).collect::<Vec<_>>();
    assert_eq!(
        field("label"),
        [
            "truth",
            "K=1",
            "K=2",
            "+rods<=6 (=<=7)",
            "+rods<=8",
            "+rods<=8 +mixed<=4",
            "R=5",
            "R=10",
            "fixed K=1",
            "fixed K=10"
        ]
        .map(Value::from)
    );
    assert_eq!(
        field("runs"),
        [1, 1, 2, 1, 1, 1, 1, 1, 1, 10].map(Value::from)
    );
    assert_eq!(
        field("motif_rules"),
        [0, 0, 0, 1, 3, 5, 0, 0, 0, 0].map(Value::from)
    );
    // `realizations`: the stored key of the sequences each variant analyses.
    assert_eq!(
        field("realizations"),
        [20, 20, 20, 20, 20, 20, 5, 10, 20, 20].map(Value::from)
    );
    assert_eq!(
        field("method"),
        [
            "nested", "nested", "nested", "nested", "nested", "nested", "nested", "nested",
            "fixed", "fixed"
        ]
        .map(Value::from)
    );
    // The sequence subsets read the K=1 study: eight studies for ten variants.
    assert_eq!(std::fs::read_dir(&studies).unwrap().count(), 8);
    assert_eq!(v[6]["study"], v[1]["study"]);
    assert_eq!(v[7]["study"], v[1]["study"]);
    assert!(v[6]["cpu_seconds"].as_f64() < v[7]["cpu_seconds"].as_f64());
    // Several runs per system measure how often one run misses.
    for (k, x) in v.iter().enumerate() {
        let several = x["runs"].as_u64().unwrap() > 1;
        assert_eq!(
            !x["single_run_miss_rate"].is_null(),
            several,
            "{}",
            x["label"]
        );
        // The nested protocol checks a fresh compression per sequence;
        // truth, per sequence it decided (in boxes this small, forced
        // planes often wrap three box directions: undecided).
        let checks = if x["method"] == "nested" {
            3 * x["realizations"].as_u64().unwrap()
        } else {
            0
        };
        let fresh = x["fresh_checks"].as_u64().unwrap();
        if k == 0 {
            assert!(fresh > checks / 2 && fresh <= checks, "truth: {fresh}");
        } else {
            assert_eq!(fresh, checks, "{}", x["label"]);
        }
        // Every nested variant is paired with truth on the same sequences;
        // the fixed protocol has no critical density per sequence, so only
        // its threshold is compared.
        let paired = !x["paired_difference"].is_null();
        assert_eq!(paired, (1..=7).contains(&k), "{}", x["label"]);
        assert_eq!(
            !x["threshold_difference"].is_null(),
            k > 0,
            "{}",
            x["label"]
        );
        if k > 0 {
            assert_eq!(x["paired_with"], "truth");
        }
    }
    // The studies hold the sequences each variant analyses, K = 2 with two
    // runs recorded per compression.
    for x in v {
        let records = std::fs::read_to_string(
            std::path::Path::new(x["study"].as_str().unwrap()).join("records.jsonl"),
        )
        .unwrap();
        assert!(records.lines().count() as u64 >= 3 * x["realizations"].as_u64().unwrap());
    }
    let csv = std::fs::read_to_string(results.join("speed-accuracy.csv")).unwrap();
    assert_eq!(csv.lines().count(), 11);
    for ext in ["md", "svg", "png"] {
        assert!(
            results.join(format!("speed-accuracy.{ext}")).exists(),
            "{ext}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stability_reproduces_the_committed_study() {
    let dir = crate::scratch("cli-stability");
    let text = stdout_of(&["stability", "--out", dir.to_str().unwrap()]);
    assert_eq!(
        text.trim_end(),
        format!(
            "104 rows written to {}/rank-stability.{{csv,svg,png}}",
            dir.display()
        )
    );
    let csv = std::fs::read_to_string(dir.join("rank-stability.csv")).unwrap();
    // Every fraction as committed (the median gap, the last column, is a
    // float that moves with the rank's arithmetic).
    assert_eq!(without_last_column(&csv), committed("rank-stability.csv"));
    // Never a wrong decided verdict.
    for line in csv.lines().skip(1) {
        assert_eq!(line.split(',').nth(7), Some("0.0000"), "{line}");
    }
    let svg = std::fs::read_to_string(dir.join("rank-stability.svg")).unwrap();
    assert!(svg.contains("nearly parallel rods"));
    let png = std::fs::read(dir.join("rank-stability.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn truth_json_has_the_contract_fields() {
    // K_{3,4}: no forced plane, flexible by one degree of freedom.
    let v = json(&["truth", "--graph6", "F?~v_", "--json"]);
    assert_eq!(v["method"], "exact");
    assert_eq!(v["dof"], 1);
    assert_eq!(v["trivial_motions"], 6);
    assert_eq!(v["rank"], 35);
    assert_eq!(v["clusters"].as_array().unwrap().len(), 0);
    assert!(v["spanning"].is_null(), "a graph has no box to span");
    // K_{4,4}: no construction order, decided in floats with its gap.
    let v = json(&["truth", "--graph6", "G?~vf_", "--json"]);
    assert_eq!(v["method"], "float");
    assert_eq!(v["dof"], 1);
    assert!(v["gap"].as_f64().unwrap() >= 1e6);
    assert!(v["reason"].as_str().unwrap().contains("decided in floats"));
    // A generated system: the box is fixed, clusters say how they span.
    let v = json(&[
        "truth",
        "--gamma",
        "23",
        "--box",
        "3",
        "--density",
        "42",
        "--seed",
        "2",
        "--json",
    ]);
    assert_eq!(v["trivial_motions"], 3);
    assert_eq!(v["criterion"], "wrap");
    assert_eq!(v["twins_agree"], true);
    let clusters = v["clusters"].as_array().unwrap();
    let first = &clusters[0];
    assert!(first["rods"].as_array().unwrap().len() > 100);
    assert_eq!(v["spanning"], first["spans"]["wrap"]);
    assert!(v["seconds"].as_f64().unwrap() >= 0.0);
}

#[test]
fn truth_and_bias_refuse_bad_input() {
    fails(&["truth", "--graph6", "~~~"], "graph6");
    fails(
        &["truth", "--gamma", "0.5", "--box", "3", "--density", "30"],
        "gamma must be at least",
    );
    fails(&["truth", "--gamma", "23"], "--box");
    fails(
        &["bias", "--scan-sequences", "2", "--scan-boxes", "7"],
        "--scan-boxes",
    );
    fails(
        &["bias", "--scan-sequences", "2", "--scan-width", "1.5"],
        "--scan-width",
    );
    fails(
        &["bias", "--sequences", "6", "--scan-sequences", "7"],
        "--scan-sequences",
    );
}

#[test]
fn certified_compression_splits_what_truth_refutes() {
    // Sound compresses this 7-rod graph to one body; truth finds two clusters.
    for (rules, nodes) in [("sound", 1), ("certified", 2)] {
        let v = json(&[
            "compress", "--graph6", "FEhvO", "--rules", rules, "--runs", "64", "--json",
        ]);
        assert_eq!(v["components"], nodes, "{rules}");
    }
}

/// Spawns `args` and SIGKILLs it once the record files of `dir` hold
/// `target` complete lines; returns how many they hold after the kill.
fn kill_after(args: &[&str], dir: &std::path::Path, target: usize) -> usize {
    let lines = || -> usize {
        std::fs::read_dir(dir).map_or(0, |entries| {
            entries
                .flatten()
                .filter(|e| {
                    let name = e.file_name().to_string_lossy().into_owned();
                    name.starts_with("records") && name.ends_with(".jsonl")
                })
                .map(|e| std::fs::read_to_string(e.path()).map_or(0, |t| t.matches('\n').count()))
                .sum()
        })
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while lines() < target {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before {target} records"
        );
        assert!(started.elapsed().as_secs() < 120, "no records appear");
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    child.kill().unwrap();
    assert!(
        !child.wait().unwrap().success(),
        "it finished before the kill"
    );
    lines()
}

/// A gamma 98 study killed three times at seeded random points resumes to
/// the byte-identical `summary.json` of an uninterrupted run, and so do two
/// shards merged after one of them was killed and rerun.
#[test]
fn a_gamma_98_study_killed_three_times_and_a_killed_shard_resume_to_the_same_summary() {
    use rand::{RngExt, SeedableRng};
    let base = crate::scratch("cli-kill-98");
    let at = |d: &str| base.join(d);
    let args = |out: &std::path::Path, extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = [
            "threshold",
            "--quiet",
            "--gamma",
            "98",
            "--boxes",
            "2.1,2.3,2.5",
            "--sequences",
            "16",
            "--bootstrap",
            "30",
            "--out",
        ]
        .map(String::from)
        .to_vec();
        a.push(out.to_str().unwrap().into());
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |a: &[String]| {
        let out = rgc(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let summary = |d: &std::path::Path| std::fs::read_to_string(d.join("summary.json")).unwrap();
    let whole = at("whole");
    run(&args(&whole, &[]));
    // The study's peak memory goes beside its times (Linux reports it).
    let timing: Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("timing.json")).unwrap()).unwrap();
    let peak = timing["peak_rss_mib"].as_f64().unwrap();
    assert!(peak > 1.0 && peak < 4096.0, "peak {peak} MiB");
    // Every record carries the process CPU spent since the one before, and
    // the study's CPU time is their sum.
    let records = std::fs::read_to_string(whole.join("records.jsonl")).unwrap();
    let cpu: Vec<f64> = records
        .lines()
        .map(|l| {
            serde_json::from_str::<Value>(l).unwrap()["cpu_seconds"]
                .as_f64()
                .unwrap()
        })
        .collect();
    assert_eq!(cpu.len(), 48);
    let total: f64 = cpu.iter().sum();
    assert!(total > 0.0 && cpu.iter().all(|&c| c >= 0.0), "{cpu:?}");
    assert!((timing["cpu_seconds"].as_f64().unwrap() - total).abs() < 1e-6 * total.max(1.0));

    let killed = at("killed");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(98);
    let mut done = 0;
    for _ in 0..3 {
        let target = done + rng.random_range(1..=10);
        let a = args(&killed, &[]);
        let now = kill_after(
            &a.iter().map(String::as_str).collect::<Vec<_>>(),
            &killed,
            target,
        );
        assert!(
            now >= target && now < 48,
            "{now} records after a kill aiming at {target}"
        );
        done = now;
    }
    assert!(!killed.join("summary.json").exists());
    run(&args(&killed, &[]));
    assert_eq!(summary(&whole), summary(&killed));

    let shards = at("shards");
    run(&args(&shards, &["--shard", "0/2"]));
    let a = args(&shards, &["--shard", "1/2"]);
    let now = kill_after(
        &a.iter().map(String::as_str).collect::<Vec<_>>(),
        &shards,
        20,
    );
    // Shard 0 holds 24 records; shard 1 is killed before its own 24.
    assert!(now < 48, "{now}");
    run(&a);
    let merged = at("merged");
    let out = rgc(&[
        "merge",
        shards.to_str().unwrap(),
        "--bootstrap",
        "30",
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(summary(&whole), summary(&merged));
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn truth_over_the_memory_limit_is_refused_before_its_front_with_the_sizes() {
    // gamma 48, L 5: its largest front needs about 10 MB; 8 MB (above the
    // 6.6 MB its rods and contacts are estimated to need up front) is
    // refused with exit 2, one line naming the front and the bytes.
    fails(
        &[
            "truth",
            "--gamma",
            "48",
            "--box",
            "5",
            "--density",
            "78",
            "--memory-limit",
            "8M",
        ],
        "over the memory limit: truth refused this system: its elimination reached a dense front of",
    );
    fails(
        &[
            "truth",
            "--gamma",
            "23",
            "--box",
            "5",
            "--density",
            "34",
            "--memory-limit",
            "3X",
        ],
        "unknown unit",
    );
    fails(
        &[
            "truth",
            "--gamma",
            "23",
            "--box",
            "5",
            "--density",
            "34",
            "--memory-limit=0G",
        ],
        "a memory limit must be positive",
    );
    let ok = rgc(&[
        "truth",
        "--gamma",
        "48",
        "--box",
        "5",
        "--density",
        "78",
        "--memory-limit",
        "2G",
    ]);
    assert_eq!(ok.status.code(), Some(0));
}

#[test]
fn a_truth_study_stops_at_the_memory_limit_and_keeps_no_false_record() {
    let dir = std::env::temp_dir().join(format!("rgc-cli-memory-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("study");
    let out = out.to_str().unwrap();
    fails(
        &[
            "threshold",
            "--kind",
            "truth",
            "--gamma",
            "23",
            "--boxes",
            "3,4,5",
            "--sequences",
            "5",
            "--memory-limit",
            "20K",
            "--quiet",
            "--out",
            out,
        ],
        "over the memory limit: truth of the first",
    );
    let records = std::fs::read_to_string(dir.join("study/records.jsonl")).unwrap_or_default();
    assert_eq!(
        records.lines().count(),
        0,
        "no record of a refused sequence"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A small truth study (gamma 23, boxes 3, 4, 5, six sequences each, seed
/// 3: about 4 s) written to `dir`; returns what it printed.
fn small_truth_study(dir: &std::path::Path) -> String {
    let out = rgc(&[
        "threshold",
        "--kind",
        "truth",
        "--gamma",
        "23",
        "--boxes",
        "3,4,5",
        "--sequences",
        "6",
        "--seed",
        "3",
        "--quiet",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn a_truth_study_killed_midway_resumes_to_the_same_summary() {
    // The whole study, then a copy cut after 7 of its 18 records with the
    // 8th torn halfway (a kill while appending), resumed by the same
    // command: the summary is the same, the records are the same sequences.
    let root = std::env::temp_dir().join(format!("rgc-cli-resume-truth-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let (whole, cut) = (root.join("whole"), root.join("cut"));
    let run = small_truth_study;
    run(&whole);
    let records = std::fs::read_to_string(whole.join("records.jsonl")).unwrap();
    let lines: Vec<&str> = records.lines().collect();
    assert_eq!(lines.len(), 18);
    std::fs::create_dir_all(&cut).unwrap();
    std::fs::copy(whole.join("study.json"), cut.join("study.json")).unwrap();
    let torn = format!(
        "{}\n{}",
        lines[..7].join("\n"),
        &lines[7][..lines[7].len() / 2]
    );
    std::fs::write(cut.join("records.jsonl"), torn).unwrap();
    let said = run(&cut);
    assert!(
        said.contains("11 sequences run") && said.contains("7 found done"),
        "{said}"
    );
    let summary = |dir: &std::path::Path| -> Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
    };
    assert_eq!(summary(&whole), summary(&cut));
    let criticals = |dir: &std::path::Path| {
        let mut v: Vec<(String, Value)> = std::fs::read_to_string(dir.join("records.jsonl"))
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str::<Value>(l).unwrap())
            .map(|r| {
                (
                    format!("{}/{}", r["box"], r["index"]),
                    r["rigid_critical"].clone(),
                )
            })
            .collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        v
    };
    assert_eq!(criticals(&whole), criticals(&cut));
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn transition_reports_the_jump_per_box_and_the_share_above_the_threshold() {
    let root = std::env::temp_dir().join(format!("rgc-cli-transition-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let study = root.join("study");
    small_truth_study(&study);
    let prefix = root.join("transition");
    let v = json(&[
        "transition",
        study.to_str().unwrap(),
        "--bins",
        "4",
        "--out",
        prefix.to_str().unwrap(),
        "--json",
    ]);
    let t = &v[0];
    assert_eq!(t["gamma"], 23.0);
    let jumps = t["jumps"].as_array().unwrap();
    assert_eq!(jumps.len(), 3, "{t}");
    for j in jumps {
        let (mean, lo, hi) = (
            j["mean"].as_f64().unwrap(),
            j["min"].as_f64().unwrap(),
            j["max"].as_f64().unwrap(),
        );
        assert!(lo <= mean && mean <= hi && hi <= 1.0, "{j}");
        assert!(j["sequences"].as_u64().unwrap() <= 6);
        assert!(j["at_critical"].as_f64().unwrap() > mean, "{j}");
    }
    let shares = t["shares"].as_array().unwrap();
    assert!(!shares.is_empty() && shares.len() <= 4);
    assert!(
        shares.iter().all(|s| s["box_len"] == 5.0),
        "the largest box by default"
    );
    for ext in ["json", "csv", "svg", "png"] {
        assert!(root.join(format!("transition.{ext}")).exists(), "{ext}");
    }
    let csv = std::fs::read_to_string(root.join("transition.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "a header and a row per box");
    // Files are not replaced without --force; a compression study has no
    // largest true clusters.
    fails(
        &[
            "transition",
            study.to_str().unwrap(),
            "--out",
            prefix.to_str().unwrap(),
        ],
        "exists",
    );
    let spec = std::fs::read_to_string(study.join("study.json")).unwrap();
    let rigid = root.join("rigid");
    std::fs::create_dir_all(&rigid).unwrap();
    std::fs::write(
        rigid.join("study.json"),
        spec.replace("\"truth\"", "\"rigid\""),
    )
    .unwrap();
    fails(
        &["transition", rigid.to_str().unwrap()],
        "a --kind truth study",
    );
    fails(
        &["transition", study.to_str().unwrap(), "--box", "7"],
        "box 7 has no records",
    );
    let _ = std::fs::remove_dir_all(&root);
}

/// Usage errors are two lines (clap's own ran to five or six): the error,
/// naming the flag, with clap's suggestion or the possible values on it,
/// then where to read more; exit code 2. Help still prints whole, exit 0.
#[test]
fn usage_errors_are_two_lines_naming_the_flag() {
    let cases: [(&[&str], &str, &str); 5] = [
        (
            &["sample", "--gamma", "23", "--sed", "3"],
            "rgc: error: unexpected argument '--sed' found (did you mean '--seed'?)",
            "sample",
        ),
        (
            &["render", "--gamma", "23"],
            "rgc: error: missing the required argument --out <OUT>",
            "render",
        ),
        (
            &["sample", "--rules", "papr"],
            "rgc: error: invalid value 'papr' for '--rules <RULES>' (did you mean 'paper'?) (possible values: sound, paper, certified)",
            "sample",
        ),
        (
            &["compress"],
            "rgc: error: missing the required argument <--graph6 <GRAPH6>|--edges <EDGES>>",
            "compress",
        ),
        (
            &["samplx"],
            "rgc: error: unrecognized subcommand 'samplx' (did you mean 'sample'?)",
            "",
        ),
    ];
    for (args, first, sub) in cases {
        let out = rgc(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        let hint = if sub.is_empty() {
            "see 'rgc --help'".to_string()
        } else {
            format!("see 'rgc {sub} --help'")
        };
        assert_eq!(err, format!("{first}\n{hint}\n"), "{args:?}");
        assert!(out.stdout.is_empty());
    }
    let help = rgc(&["sample", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    let text = String::from_utf8_lossy(&help.stdout);
    assert!(text.contains("Usage: rgc sample") && text.contains("--save-vtk"));
}
