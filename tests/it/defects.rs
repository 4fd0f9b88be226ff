//! The defects of issues 8 and 23, found by trying the tool as a new user
//! would: each test here fails without its fix. Every test works in its own
//! scratch folder, named by the process and the test.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

use crate::cli::succeeds;
use rgc::audit::{self, AuditOptions};
use rgc::engine::{Engine, Motif, RuleSet};
use rgc::graph::io::parse_graph6;
use rgc::spanning::Criterion;
use rgc::threshold::fss::Protocol;
use rgc::threshold::study::StudySpec;
use rgc::threshold::variants;

const REPO: &str = env!("CARGO_MANIFEST_DIR");

fn rgc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .current_dir(REPO)
        .output()
        .expect("the binary runs")
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rgc-defects-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs a command that must be refused before it does any work: exit code
/// 2, nothing on stdout, and on stderr one line (no progress before it)
/// holding `needle`.
fn refused(args: &[&str], needle: &str) {
    let out = rgc(args);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
    assert_eq!(err.lines().count(), 1, "{args:?}: one line, no work: {err}");
    assert!(out.stdout.is_empty(), "{args:?}: {}", text(&out.stdout));
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A small and fast contact study's arguments.
fn contact_study<'a>(out: &'a str, more: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "threshold",
        "--kind",
        "contact",
        "--gamma",
        "10",
        "--boxes",
        "3,3.5,4",
        "--bootstrap",
        "20",
        "--quiet",
        "--out",
        out,
    ];
    args.extend(more);
    args
}

/// A small and fast comparison's arguments, with options replaced or added.
fn small_compare<'a>(studies: &'a str, results: &'a str, changes: &[&'a str]) -> Vec<&'a str> {
    let mut options = vec![
        ("--boxes", "3,3.5,4"),
        ("--sequences", "6"),
        ("--bootstrap", "20"),
        ("--extended", "motifs/rods-6.json"),
        ("--studies", studies),
        ("--results", results),
    ];
    let mut flags = Vec::new();
    let mut k = 0;
    while k < changes.len() {
        let flag = changes[k];
        match changes.get(k + 1).filter(|v| !v.starts_with("--")) {
            Some(&value) => {
                match options.iter_mut().find(|o| o.0 == flag) {
                    Some(o) => o.1 = value,
                    None => options.push((flag, value)),
                }
                k += 2;
            }
            None => {
                flags.push(flag);
                k += 1;
            }
        }
    }
    let mut args = vec!["compare"];
    args.extend(options.into_iter().flat_map(|(f, v)| [f, v]));
    args.extend(flags);
    args
}

// Defect 1: small runs failed after all the work.

#[test]
fn studies_too_small_for_the_fit_are_refused_before_any_sequence() {
    let dir = scratch("too-small");
    let out = dir.join("study");
    let o = s(&out);
    refused(
        &[
            "threshold",
            "--boxes",
            "4,5",
            "--sequences",
            "20",
            "--out",
            o,
        ],
        "nu needs at least 3 box sizes, got 2",
    );
    refused(
        &[
            "threshold",
            "--boxes",
            "4,5,6",
            "--sequences",
            "3",
            "--out",
            o,
        ],
        "needs at least 5 sequences, got 3",
    );
    assert!(!out.exists(), "nothing was written");
    // tradeoff analyses a quarter of the sequences in one variant.
    let (studies, results) = (dir.join("studies"), dir.join("results"));
    refused(
        &[
            "tradeoff",
            "--sequences",
            "8",
            "--studies",
            s(&studies),
            "--results",
            s(&results),
        ],
        "this design needs --sequences 20 or more",
    );
    refused(
        &small_compare(s(&studies), s(&results), &["--sequences", "4"]),
        "needs at least 5 sequences, got 4",
    );
    assert!(!studies.exists() && !results.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_failed_scaling_fit_keeps_and_prints_the_per_box_results() {
    let dir = scratch("failed-fit");
    let study = dir.join("study");
    // Seed 4 gives a Delta rho that grows from L = 3 to L = 4: no nu.
    let args = contact_study(s(&study), &["--sequences", "5", "--seed", "4"]);
    let out = rgc(&args);
    assert_eq!(out.status.code(), Some(2), "the analysis still failed");
    let err = text(&out.stderr);
    assert!(
        err.contains("cannot analyse") && err.contains("per-box results"),
        "{err}"
    );
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("warning: the scaling analysis failed"),
        "{stdout}"
    );
    for row in ["     3      5 ", "   3.5      5 ", "     4      5 "] {
        assert!(stdout.contains(row), "{row:?} in {stdout}");
    }
    let boxes = std::fs::read_to_string(study.join("boxes.csv")).unwrap();
    let lines: Vec<&str> = boxes.lines().collect();
    assert!(lines[0].starts_with("box_len,realizations,mu,s,delta_rho"));
    assert_eq!(lines.len(), 4, "{boxes}");
    for line in &lines[1..] {
        let mu: f64 = line.split(',').nth(2).unwrap().parse().unwrap();
        assert!(mu > 0.0, "{line}");
    }
    let records = std::fs::read_to_string(study.join("records.csv")).unwrap();
    assert_eq!(records.lines().count(), 16);
    // merge --json says the same as JSON.
    let out = rgc(&["merge", s(&study), "--bootstrap", "20", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&out.stdout).expect("stdout is JSON");
    assert_eq!(v["summary"], Value::Null);
    assert_eq!(v["per_box"]["boxes"].as_array().unwrap().len(), 3);
    std::fs::remove_dir_all(dir).unwrap();
}

// Defect 2: an unwritable output path lost finished results.

#[test]
fn unwritable_outputs_are_refused_before_the_work() {
    let dir = scratch("unwritable");
    // A path under a plain file cannot be written, whoever runs the test.
    let file = dir.join("plain");
    std::fs::write(&file, "").unwrap();
    let bad = file.join("out");
    let b = s(&bad);
    let ok = dir.join("ok");
    for (flag, other) in [("--results", "--rules-dir"), ("--rules-dir", "--results")] {
        refused(
            &[
                "audit",
                "--max-rods",
                "6",
                "--max-components",
                "0",
                flag,
                b,
                other,
                s(&ok),
            ],
            "plain",
        );
    }
    let contacts = dir.join("contacts.txt");
    refused(
        &[
            "sample",
            "--gamma",
            "23",
            "--box",
            "5",
            "--density",
            "40",
            "--save-contacts",
            s(&contacts),
            "--save-bodies",
            b,
        ],
        "plain",
    );
    assert!(!contacts.exists(), "the sample was not drawn");
    refused(
        &["bench", "--max-rods", "5000", "--repeat", "1", "--out", b],
        "plain",
    );
    let studies = dir.join("studies");
    refused(&small_compare(s(&studies), b, &[]), "plain");
    refused(&small_compare(b, s(&ok), &[]), "plain");
    assert!(!studies.exists(), "no study ran");
    refused(
        &["compress", "--graph6", "E]r?", "--save-bodies", b],
        "plain",
    );
    refused(&["rules", "--out", b], "plain");
    // The stability study takes 6 s on two idle cores; refused, it takes none.
    let started = std::time::Instant::now();
    refused(&["stability", "--out", b], "plain");
    assert!(
        started.elapsed().as_secs_f64() < 3.0,
        "{:?}",
        started.elapsed()
    );
    std::fs::remove_dir_all(dir).unwrap();
}

// Defect 5: exploratory runs overwrote committed outputs.

#[test]
fn an_audit_never_replaces_files_made_with_other_parameters_unless_forced() {
    let dir = scratch("audit-replace");
    let d = s(&dir);
    let audit = |more: &[&str]| {
        let mut args = vec![
            "audit",
            "--max-components",
            "0",
            "--results",
            d,
            "--rules-dir",
            d,
        ];
        args.extend(more);
        args.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |more: &[&str]| rgc(&audit(more).iter().map(|a| a.as_str()).collect::<Vec<_>>());
    assert!(run(&["--max-rods", "6"]).status.success());
    let read = |name: &str| std::fs::read(dir.join(name)).unwrap();
    let (table, rules) = (read("audit-rods.csv"), read("rods-6.json"));
    for other in [
        &["--max-rods", "6", "--rules", "paper"][..],
        &["--max-rods", "5"],
        &["--max-rods", "6", "--runs", "2"],
    ] {
        let args = audit(other);
        refused(
            &args.iter().map(|a| a.as_str()).collect::<Vec<_>>(),
            "would replace files made with other parameters",
        );
    }
    assert_eq!(read("rods-6.json"), rules);
    assert_eq!(read("audit-rods.csv"), table);
    // The same parameters may replace their own files.
    assert!(run(&["--max-rods", "6"]).status.success());
    assert_eq!(read("rods-6.json"), rules);
    // Forced, another audit replaces them.
    let out = run(&["--max-rods", "5", "--rules", "paper", "--force"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = String::from_utf8(read("audit-rods.csv")).unwrap();
    assert_eq!(table.lines().count(), 5, "header and sizes 2..=5: {table}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_committed_audit_files_are_kept_from_exploratory_runs_only() {
    let (results, motifs) = (
        Path::new(REPO).join("results"),
        Path::new(REPO).join("motifs"),
    );
    // The default audit reproduces the committed files, so it may replace them.
    audit::check_outputs(&AuditOptions::default(), &results, &motifs).unwrap();
    let paper = AuditOptions {
        max_rods: 6,
        rules: RuleSet::Paper,
        ..AuditOptions::default()
    };
    let err = audit::check_outputs(&paper, &results, &motifs)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("audit-rods.csv") && err.contains("rods-6.json"),
        "{err}"
    );
    // A table from before the JSON beside it is judged by its sizes.
    let dir = scratch("audit-legacy");
    std::fs::copy(results.join("audit-rods.csv"), dir.join("audit-rods.csv")).unwrap();
    let six = AuditOptions {
        max_rods: 6,
        max_components: 0,
        ..AuditOptions::default()
    };
    let err = audit::check_outputs(&six, &dir, &dir)
        .unwrap_err()
        .to_string();
    assert!(err.contains("holds sizes [2, 3, 4, 5, 6, 7, 8]"), "{err}");
    let eight = AuditOptions {
        max_components: 0,
        ..AuditOptions::default()
    };
    audit::check_outputs(&eight, &dir, &dir).unwrap();
    std::fs::remove_dir_all(dir).unwrap();
}

// Defect 6: study directory names left out gamma, boxes, seed and criterion.

#[test]
fn study_directories_are_named_by_every_parameter_and_old_ones_still_resolve() {
    let base = StudySpec::new(23.0, vec![4.0, 5.0, 6.0], 100, Criterion::Wrap, 1);
    assert_eq!(
        variants::study_name(&base),
        "rigid-sound-base-k1-nested-r100-g23-L4_5_6-wrap-s1"
    );
    let others = [
        StudySpec {
            gamma: 30.0,
            ..base.clone()
        },
        StudySpec {
            boxes: vec![4.0, 5.0, 6.5],
            ..base.clone()
        },
        StudySpec {
            seed: 2,
            ..base.clone()
        },
        StudySpec {
            criterion: Criterion::Faces,
            ..base.clone()
        },
        StudySpec {
            method: Protocol::Fixed,
            ..base.clone()
        },
        StudySpec {
            method: Protocol::Fixed,
            grid_points: 8,
            ..base.clone()
        },
    ];
    let mut names: Vec<String> = std::iter::once(&base)
        .chain(&others)
        .map(variants::study_name)
        .collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), 1 + others.len(), "{names:?}");
    // The committed studies, named before, are still where the defaults look.
    let root = Path::new(REPO).join("results/studies");
    let paper = StudySpec {
        rules: RuleSet::Paper,
        ..base.clone()
    };
    assert_eq!(
        variants::study_dir(&root, &paper),
        root.join("rigid-paper-base-k1-nested-r100")
    );
    let paper30 = StudySpec {
        gamma: 30.0,
        ..paper
    };
    assert_eq!(
        variants::study_dir(&root, &paper30),
        root.join("rigid-paper-base-k1-nested-r100-g30-L4_5_6-wrap-s1")
    );
}

#[test]
fn compare_at_another_gamma_runs_beside_the_first_and_keeps_its_results() {
    let dir = scratch("compare-gamma");
    let studies = dir.join("studies");
    let (r10, r12) = (dir.join("r10"), dir.join("r12"));
    succeeds(&small_compare(
        s(&studies),
        s(&r10),
        &["--gamma", "10", "--quiet"],
    ));
    succeeds(&small_compare(
        s(&studies),
        s(&r12),
        &["--gamma", "12", "--quiet"],
    ));
    assert_eq!(std::fs::read_dir(&studies).unwrap().count(), 6);
    // Another experiment does not silently replace the first one's results.
    let first = std::fs::read(r10.join("compare-base-extended.json")).unwrap();
    refused(
        &small_compare(s(&studies), s(&r10), &["--gamma", "12"]),
        "holds the results of another experiment (template.gamma 10.0 vs 12.0); \
         choose another --results, or --force to replace them",
    );
    assert_eq!(
        std::fs::read(r10.join("compare-base-extended.json")).unwrap(),
        first
    );
    succeeds(&small_compare(
        s(&studies),
        s(&r10),
        &["--gamma", "12", "--quiet", "--force"],
    ));
    std::fs::remove_dir_all(dir).unwrap();
}

// Defect 9: degenerate parameters were accepted.

#[test]
fn degenerate_parameters_are_refused_naming_the_parameter() {
    let dir = scratch("degenerate");
    let d = dir.join("study");
    let o = s(&d);
    let sample = |gamma: &'static str, density: &'static str| {
        vec![
            "sample",
            "--gamma",
            gamma,
            "--box",
            "5",
            "--density",
            density,
        ]
    };
    refused(
        &sample("23", "1e-9"),
        "density 0.000000001 in a box of side 5 gives no rods",
    );
    refused(&sample("0.1", "40"), "gamma must be at least 1");
    refused(&sample("0.99", "40"), "gamma must be at least 1");
    succeeds(&sample("1", "1"));
    for n in ["0", "1"] {
        refused(
            &["threshold", "--bootstrap", n, "--out", o],
            "--bootstrap must be at least 2",
        );
        refused(
            &["merge", o, "--bootstrap", n],
            "--bootstrap must be at least 2",
        );
    }
    let (studies, results) = (dir.join("studies"), dir.join("results"));
    let (st, re) = (s(&studies), s(&results));
    refused(
        &small_compare(st, re, &["--bootstrap", "0"]),
        "--bootstrap must be at least 2",
    );
    refused(
        &small_compare(st, re, &["--runs", "0"]),
        "--runs must be at least 1",
    );
    refused(
        &[
            "tradeoff",
            "--runs-list",
            "0,1",
            "--studies",
            st,
            "--results",
            re,
        ],
        "variant \"K=0\": --runs must be at least 1",
    );
    refused(
        &["threshold", "--boxes=-4,5,6", "--out", o],
        "box must be a positive finite number",
    );
    refused(
        &[
            "threshold",
            "--protocol",
            "fixed",
            "--grid-points",
            "1",
            "--out",
            o,
        ],
        "--grid-points must be at least 2",
    );
    refused(
        &["bench", "--max-rods", "10"],
        "--max-rods 10 leaves no reference system",
    );
    assert!(!d.exists() && !studies.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

// Defect 13: output a script can read.

#[test]
fn compress_prints_a_summary_and_the_bodies_only_on_request() {
    let dir = scratch("compress-summary");
    let edges = dir.join("contacts.txt");
    succeeds(&[
        "sample",
        "--gamma",
        "23",
        "--box",
        "6",
        "--density",
        "45",
        "--save-contacts",
        s(&edges),
    ]);
    let out = succeeds(&["compress", "--edges", s(&edges)]);
    let stdout = text(&out.stdout);
    assert_eq!(stdout.lines().count(), 2, "{stdout}");
    assert!(
        stdout.starts_with("9720 rods, ") && stdout.contains("largest body"),
        "{stdout}"
    );
    let saved = dir.join("bodies.json");
    let out = succeeds(&["compress", "--graph6", "E]r?", "--save-bodies", s(&saved)]);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("1 bodies (0 planar, 1 spatial); largest body 6 rods"),
        "{stdout}"
    );
    assert!(!stdout.contains("[0, 1, 2"), "no rod lists: {stdout}");
    let v: Value = serde_json::from_slice(&std::fs::read(&saved).unwrap()).unwrap();
    assert_eq!(
        v["bodies"][0]["rods"],
        serde_json::json!([0, 1, 2, 3, 4, 5])
    );
    let v: Value =
        serde_json::from_slice(&succeeds(&["compress", "--graph6", "E]r?", "--json"]).stdout)
            .unwrap();
    assert_eq!(
        (v["n_bodies"].as_u64(), v["largest_body_rods"].as_u64()),
        (Some(1), Some(6))
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn threshold_merge_and_compare_print_json_and_nothing_else() {
    let dir = scratch("json");
    let study = dir.join("study");
    let out = succeeds(&contact_study(s(&study), &["--sequences", "20", "--json"]));
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    let threshold = v["summary"]["fss"]["threshold"]["value"].as_f64().unwrap();
    assert!(threshold > 0.0);
    assert_eq!(v["run"]["ran"], 60);
    assert!(!v["files"].as_array().unwrap().is_empty());
    let out = succeeds(&["merge", s(&study), "--bootstrap", "20", "--json"]);
    let v: Value = serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(
        v["summary"]["fss"]["threshold"]["value"].as_f64(),
        Some(threshold)
    );
    let (studies, results) = (dir.join("studies"), dir.join("results"));
    let out = succeeds(&small_compare(
        s(&studies),
        s(&results),
        &["--gamma", "10", "--json"],
    ));
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(v["variants"].as_array().unwrap().len(), 3);
    let written: Value =
        serde_json::from_slice(&std::fs::read(results.join("compare-base-extended.json")).unwrap())
            .unwrap();
    assert_eq!(v, written);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_audit_writes_its_false_compressions_with_the_motifs_that_made_them() {
    let dir = scratch("false-compressions");
    let d = s(&dir);
    succeeds(&[
        "audit",
        "--max-rods",
        "7",
        "--max-components",
        "0",
        "--results",
        d,
        "--rules-dir",
        d,
    ]);
    // Two seven-rod patterns are falsely compressed (results/audit-rods.csv).
    let g6 = std::fs::read_to_string(dir.join("falsely-compressed-rods.g6")).unwrap();
    assert_eq!(g6.lines().count(), 2, "{g6}");
    let part: Value =
        serde_json::from_slice(&std::fs::read(dir.join("audit-rods.json")).unwrap()).unwrap();
    let found = part["falsely_compressed"].as_array().unwrap();
    assert_eq!(found.len(), 2);
    let engine = Engine::base(RuleSet::Sound);
    for (f, line) in found.iter().zip(g6.lines()) {
        assert_eq!(f["graph6"], line);
        let g = parse_graph6(line).unwrap();
        let exact = rgc::rigidity::check_exact(
            &rgc::pattern::Pattern::from_graph(&g).unwrap(),
            rgc::rule_file::RULE_SEED,
        )
        .unwrap();
        assert_eq!(f["class"], exact.class.as_str());
        assert_ne!(exact.class, "rigid");
        // The recorded run compresses it to one node by the recorded motifs.
        let c = engine
            .compress(&g, &[], f["run"].as_u64().unwrap())
            .unwrap();
        assert_eq!(c.components, 1);
        assert_eq!(serde_json::to_value(&c.sequence).unwrap(), f["sequence"]);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_compression_records_its_motifs_in_order() {
    // K_{2,4}: two rods touching the same four, one 3D6 and then the rest.
    let g = parse_graph6("E]r?").unwrap();
    let c = Engine::base(RuleSet::Sound).compress(&g, &[], 1).unwrap();
    assert_eq!(c.components, 1);
    assert_eq!(c.sequence.first(), Some(&Motif::D6));
    let m = c.motifs;
    let total = m.community + m.d2b + m.d2a + m.d3a + m.d3b + m.d4 + m.d6 + m.rules;
    assert_eq!(c.sequence.len(), total as usize);
    let d6 = c.sequence.iter().filter(|&&x| x == Motif::D6).count();
    assert_eq!(d6, m.d6 as usize);
    assert_eq!(serde_json::to_value(Motif::D2B).unwrap(), "3D2B");
}

/// Issue 23, defect 1: a rod given twice with its direction reversed is the
/// same rod, also when an axis component is exactly zero (-0.0 and 0.0
/// differ bit for bit).
#[test]
fn a_rod_given_twice_reversed_is_refused_whatever_the_signed_zeros() {
    let dir = scratch("reversed");
    for (i, (a, b)) in [
        ("1,0,0", "-1,0,0"),
        ("0,1,0", "0,-1,-0"),
        ("1,2,0", "-1,-2,0"),
    ]
    .iter()
    .enumerate()
    {
        let csv = dir.join(format!("d{i}.csv"));
        std::fs::write(
            &csv,
            format!("x,y,z,dx,dy,dz,length,radius\n1,1,1,{a},1,0.02\n1,1,1,{b},1,0.02\n"),
        )
        .unwrap();
        refused(
            &["truth", "--rods", s(&csv), "--box", "4"],
            "line 3: the same rod as line 2 (same centre and axis line)",
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 23, defect 2: input that was silently ignored or overwritten.
#[test]
fn ignored_or_overwritten_input_is_refused() {
    let dir = scratch("ignored");
    let csv = dir.join("rods.csv");
    std::fs::write(&csv, "x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,0.02\n").unwrap();
    refused(
        &[
            "truth",
            "--rods",
            s(&csv),
            "--box",
            "4",
            "--lammps-columns",
            "x=xu",
        ],
        "--lammps-columns applies to LAMMPS dumps;",
    );
    let twice = dir.join("twice.csv");
    std::fs::write(
        &twice,
        "x,y,z,dx,dy,dz,length,radius,x\n1,1,1,1,0,0,1,0.02,2\n",
    )
    .unwrap();
    refused(
        &["truth", "--rods", s(&twice), "--box", "4"],
        "line 1: the header names the column \"x\" twice",
    );
    let dump = dir.join("rods.dump");
    std::fs::write(&dump, "ITEM: TIMESTEP\n0\n").unwrap();
    refused(
        &[
            "truth",
            "--rods",
            s(&dump),
            "--box",
            "4",
            "--lammps-columns",
            "x=xu,x=xs",
        ],
        "LAMMPS column mapping: \"x\" is given twice",
    );
    let out = dir.join("x.json");
    refused(
        &[
            "sample",
            "--gamma",
            "23",
            "--box",
            "3",
            "--density",
            "30",
            "--save-bodies",
            s(&out),
            "--save-rods",
            s(&out),
        ],
        "--save-rods and --save-bodies both write",
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 23, defect 7: a rods file with a header and no rods is refused,
/// not run on an empty system.
#[test]
fn a_rods_file_without_rods_is_refused() {
    let dir = scratch("empty-file");
    let csv = dir.join("empty.csv");
    std::fs::write(&csv, "x,y,z,dx,dy,dz,length,radius\n# nothing\n").unwrap();
    refused(
        &["truth", "--rods", s(&csv), "--box", "4"],
        "the file holds no rods",
    );
    let json = dir.join("empty.json");
    std::fs::write(&json, r#"{"box": [4, 4, 4], "rods": []}"#).unwrap();
    refused(&["sample", "--rods", s(&json)], "the file holds no rods");
    // Defect 6: a bare list says what a rods JSON file is.
    std::fs::write(&json, "[]").unwrap();
    refused(
        &["sample", "--rods", s(&json), "--box", "4"],
        "line 1: a rods JSON file is an object {\"box\": [LX, LY, LZ]",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 23, defect 6: plain-text output names criteria, rule sets and
/// methods as the command line spells them, not by Rust's debug names.
#[test]
fn plain_text_output_uses_the_command_line_names() {
    let sample = [
        "sample",
        "--gamma",
        "23",
        "--box",
        "3",
        "--density",
        "30",
        "--truth",
    ];
    let out = text(&succeeds(&sample).stdout);
    for needle in ["contact spanning (wrap):", "rules sound)", "truth (exact):"] {
        assert!(out.contains(needle), "{needle:?} in {out}");
    }
    let truth = [
        "truth",
        "--gamma",
        "23",
        "--box",
        "3",
        "--density",
        "30",
        "--criterion",
        "faces",
    ];
    let out = text(&succeeds(&truth).stdout);
    for needle in [
        "spanning (faces):",
        "method: exact in F_q for q = ",
        "realizations agree: true",
    ] {
        assert!(out.contains(needle), "{needle:?} in {out}");
    }
    for debug in ["Wrap", "Faces", "Sound", "Exact"] {
        assert!(!out.contains(debug), "{debug} in {out}");
    }
}

/// Issue 23, defect 6: huge numbers in messages are short, not 300 digits.
#[test]
fn huge_numbers_in_messages_are_short() {
    let dir = scratch("huge");
    refused(
        &[
            "sample",
            "--gamma",
            "23",
            "--box",
            "1e300",
            "--density",
            "40",
        ],
        "density 40 in a box of side 1.0000e300 means inf rods",
    );
    let csv = dir.join("wide.csv");
    std::fs::write(
        &csv,
        "x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1e300,0.02\n",
    )
    .unwrap();
    refused(
        &["truth", "--rods", s(&csv), "--box", "4"],
        "2 (l + 2r) = 2.0000e300, so that",
    );
    // A rod as wide: refused as wider than long, its radius short too.
    std::fs::write(&csv, "x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,1e300\n").unwrap();
    refused(
        &["truth", "--rods", s(&csv), "--box", "4"],
        "line 2: radius 1.0000e300 is more than half the length 1",
    );
    let out = rgc(&["truth", "--rods", s(&csv), "--box", "4"]);
    assert!(text(&out.stderr).len() < 250, "{}", text(&out.stderr));
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 23, defect 3: an `--out` prefix that is a directory is refused,
/// not written as the hidden files `DIR/.png` and `DIR/.svg`.
#[test]
fn an_out_prefix_that_is_a_directory_is_refused() {
    let dir = scratch("out-dir");
    let slash = format!("{}/", s(&dir));
    for out in [slash.as_str(), s(&dir)] {
        refused(
            &[
                "render",
                "--gamma",
                "23",
                "--box",
                "3",
                "--density",
                "30",
                "--out",
                out,
            ],
            "is a directory: give a file name prefix",
        );
        refused(
            &["transition", "results/g48-truth", "--out", out],
            "is a directory: give a file name prefix",
        );
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 23, defect 3: `--save-vtk` writes XML PolyData, which VTK reads as
/// `.vtp` only; a legacy `.vtk` name is refused before the work.
#[test]
fn a_vtk_file_must_be_named_vtp() {
    let dir = scratch("vtk-name");
    let legacy = dir.join("rods.vtk");
    refused(
        &[
            "sample",
            "--gamma",
            "23",
            "--box",
            "3",
            "--density",
            "30",
            "--save-vtk",
            s(&legacy),
        ],
        "--save-vtk writes VTK XML PolyData: name the file .vtp",
    );
    assert!(!legacy.exists());
    let xml = dir.join("rods.VTP");
    succeeds(&[
        "sample",
        "--gamma",
        "23",
        "--box",
        "3",
        "--density",
        "30",
        "--save-vtk",
        s(&xml),
    ]);
    assert_eq!(crate::vtk::read_vtp(&xml).pieces.len(), 2);
    std::fs::remove_dir_all(dir).unwrap();
}
