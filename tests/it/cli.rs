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

pub fn json(args: &[&str]) -> Value {
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
pub fn repo(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Runs a command that must succeed and returns its output.
pub fn succeeds(args: &[&str]) -> Output {
    let out = rgc(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs a command that must succeed and returns its stdout.
pub fn stdout_of(args: &[&str]) -> String {
    String::from_utf8(succeeds(args).stdout).unwrap()
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
    // It resists every strain of its box, each alone too.
    let six = serde_json::json!(["xx", "yy", "zz", "yz", "xz", "xy"]);
    assert_eq!(
        v["strains"],
        serde_json::json!({"considered": six, "rank": 6, "resisted": six})
    );
}

#[test]
fn truth_prints_the_strain_rank_or_why_it_has_none() {
    // The generated system above, and one too sparse to resist anything.
    let generated = |density| {
        let args = ["--gamma", "23", "--box", "3", "--density", density];
        stdout_of(&[&["truth", "--seed", "2"][..], &args].concat())
    };
    let text = generated("42");
    assert!(
        text.contains(
            "strain rank 6 of the 6 strains of the periodic box; resisted alone: xx yy zz yz xz xy\n"
        ),
        "{text}"
    );
    let text = generated("20");
    assert!(
        text.contains("strain rank 0 of the 6 strains of the periodic box; resisted alone: none\n"),
        "{text}"
    );
    let text = stdout_of(&["truth", "--graph6", "F?~v_"]);
    assert!(
        text.contains(
            "strain rank unknown: no periodic axis: a finite framework has no box to strain\n"
        ),
        "{text}"
    );
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

#[test]
fn truth_memory_limits_are_sizes_and_a_limit_with_room_finishes() {
    // The refusal itself, its sizes and the peak: tests/it/memory.rs.
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
