//! Truth studies from the command line: refused at the memory limit with no
//! false record, resumed after a kill, read by `transition` (the jump per
//! box, the Binder cumulant at fixed densities), an undecided step recorded
//! and passed, and the solid criterion on the wrap study's sequences.

use serde_json::Value;

use crate::cli::{fails, json, rgc, stdout_of};
use crate::studies::{threshold, threshold_args};

#[test]
fn a_truth_study_stops_at_the_memory_limit_and_keeps_no_false_record() {
    let dir = std::env::temp_dir().join(format!("rgc-cli-memory-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("study");
    let out = out.to_str().unwrap();
    fails(
        &threshold(
            out,
            &[
                ("--kind", "truth"),
                ("--gamma", "23"),
                ("--boxes", "3,4,5"),
                ("--sequences", "5"),
                ("--memory-limit", "20K"),
            ],
        ),
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
    stdout_of(&threshold(
        dir.to_str().unwrap(),
        &[
            ("--kind", "truth"),
            ("--gamma", "23"),
            ("--boxes", "3,4,5"),
            ("--sequences", "6"),
            ("--seed", "3"),
        ],
    ))
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
    for ext in ["json", "csv", "histogram.csv", "svg", "png"] {
        assert!(root.join(format!("transition.{ext}")).exists(), "{ext}");
    }
    // Every sequence of a box with a jump is in its histogram.
    let bins = std::fs::read_to_string(root.join("transition.histogram.csv")).unwrap();
    for j in jumps {
        let l = j["box_len"].as_f64().unwrap();
        let counted: u64 = bins
            .lines()
            .skip(1)
            .map(|row| row.split(',').collect::<Vec<_>>())
            .filter(|c| c[1].parse::<f64>().unwrap() == l)
            .map(|c| c[4].parse::<u64>().unwrap())
            .sum();
        assert_eq!(counted, j["sequences"].as_u64().unwrap(), "box {l}");
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
    // Studies of one aspect ratio are read as one, each box from one study.
    fails(
        &[
            "transition",
            study.to_str().unwrap(),
            study.to_str().unwrap(),
        ],
        "box 3 of gamma 23 is in both",
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_fixed_truth_study_at_given_densities_gives_the_binder_cumulant() {
    let root = crate::scratch("cli-binder");
    let study = root.join("fixed");
    let s = study.to_str().unwrap();
    let base = [
        ("--kind", "truth"),
        ("--gamma", "23"),
        ("--boxes", "3,4,5"),
        ("--sequences", "4"),
        ("--seed", "2"),
    ];
    let with = |extra: &[(&'static str, &'static str)]| {
        let mut o = base.to_vec();
        o.extend_from_slice(extra);
        o
    };
    fails(
        &threshold(
            s,
            &with(&[("--protocol", "nested"), ("--grid-densities", "30,34")]),
        ),
        "--grid-densities needs --protocol fixed",
    );
    fails(
        &threshold(
            s,
            &with(&[("--protocol", "fixed"), ("--grid-densities", "34,30")]),
        ),
        "--grid-densities must be two or more increasing positive densities",
    );
    // The analysis fails on so few sequences; the records are written.
    let _ = rgc(&threshold(
        s,
        &with(&[("--protocol", "fixed"), ("--grid-densities", "30,34,38")]),
    ));
    let grid: Value =
        serde_json::from_str(&std::fs::read_to_string(study.join("grid.json")).unwrap()).unwrap();
    assert_eq!(
        grid["boxes"][1]["rods"],
        serde_json::json!([1920, 2176, 2432]),
        "density x 64"
    );
    let v = json(&["transition", s, "--json"]);
    let cells = v[0]["binder"].as_array().unwrap();
    assert_eq!(cells.len(), 9, "three boxes, three densities: {v}");
    // Each cumulant is 1 - <P^4> / 3 <P^2>^2 of the records' shares.
    let records: Vec<Value> = std::fs::read_to_string(study.join("records.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    for c in cells {
        assert_eq!(c["sequences"], 4);
        let l = c["box_len"].as_f64().unwrap();
        let n = (c["density"].as_f64().unwrap() * l.powi(3)).round() as u64;
        let p: Vec<f64> = records
            .iter()
            .filter(|r| r["box"].as_f64() == Some(l))
            .flat_map(|r| r["fixed"].as_array().unwrap())
            .filter(|s| s["n"].as_u64() == Some(n))
            .map(|s| s["largest"].as_f64().unwrap() / n as f64)
            .collect();
        let moment = |k: i32| p.iter().map(|x| x.powi(k)).sum::<f64>() / p.len() as f64;
        let u = 1.0 - moment(4) / (3.0 * moment(2).powi(2));
        assert!(
            (c["cumulant"].as_f64().unwrap() - u).abs() < 1e-12,
            "{c} {u}"
        );
    }
    assert_eq!(cells[8]["density"], 38.0);
    // Deep in the rigid phase the share is narrowly spread: U near 2/3.
    assert!(cells[8]["cumulant"].as_f64().unwrap() > 0.6);
    let _ = std::fs::remove_dir_all(&root);
}

/// Where the model has no realization (rho 50 at gamma 23, where forced
/// planes percolate), truth has no verdict: a fixed study records that step
/// as undecided, without a cluster, and goes on; the Binder cumulant counts
/// only the decided sequences.
#[test]
fn a_fixed_truth_study_records_an_undecided_density_and_goes_on() {
    let root = crate::scratch("cli-fixed-undecided");
    let study = root.join("fixed");
    let s = study.to_str().unwrap();
    // The analysis fails on so few sequences; the records are written.
    let _ = rgc(&threshold(
        s,
        &[
            ("--kind", "truth"),
            ("--protocol", "fixed"),
            ("--grid-densities", "34,50"),
            ("--gamma", "23"),
            ("--boxes", "2.5,3,3.5"),
            ("--sequences", "4"),
            ("--seed", "1"),
        ],
    ));
    let records: Vec<Value> = std::fs::read_to_string(study.join("records.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(records.len(), 12);
    let steps: Vec<&Value> = records
        .iter()
        .flat_map(|r| r["fixed"].as_array().unwrap())
        .collect();
    assert_eq!(steps.len(), 24);
    let undecided: Vec<&&Value> = steps.iter().filter(|s| s["undecided"] == true).collect();
    assert_eq!(undecided.len(), 2, "{records:?}");
    for u in &undecided {
        assert_eq!((&u["spans"], u.get("largest")), (&Value::Bool(false), None));
    }
    let v = json(&["transition", s, "--json"]);
    let at_50: Vec<u64> = v[0]["binder"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["density"].as_f64().unwrap() > 49.0)
        .map(|c| c["sequences"].as_u64().unwrap())
        .collect();
    assert_eq!(at_50, [4, 4, 2]);
    let _ = std::fs::remove_dir_all(&root);
}

/// Each record of a study's `records.jsonl`, by box and index.
fn records_by_sequence(dir: &std::path::Path) -> std::collections::BTreeMap<String, Value> {
    std::fs::read_to_string(dir.join("records.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .map(|r| (format!("{}/{}", r["box"], r["index"]), r))
        .collect()
}

#[test]
fn a_solid_truth_study_bisects_the_strain_rank_on_the_wrap_studys_sequences() {
    // The small truth study under wrap and under solid: the same sequences
    // (seeds, contact critical numbers), every solid step spanning exactly
    // when its strain rank is 6, the critical number the first such step
    // of the bisection; and `rgc paired` compares the two sequence by
    // sequence. (Equal critical numbers are possible, not certain: on
    // these 18 sequences solidity always came later than the wrap.)
    let root = crate::scratch("cli-solid-study");
    let (wrap, solid) = (root.join("wrap"), root.join("solid"));
    small_truth_study(&wrap);
    stdout_of(&threshold(
        solid.to_str().unwrap(),
        &[
            ("--kind", "truth"),
            ("--gamma", "23"),
            ("--boxes", "3,4,5"),
            ("--sequences", "6"),
            ("--seed", "3"),
            ("--criterion", "solid"),
        ],
    ));
    let (w, s) = (records_by_sequence(&wrap), records_by_sequence(&solid));
    assert_eq!(s.len(), 18);
    assert_eq!(w.keys().collect::<Vec<_>>(), s.keys().collect::<Vec<_>>());
    for (key, r) in &s {
        for field in ["seed", "contact_critical"] {
            assert_eq!(r[field], w[key][field], "{key} {field}");
        }
        let critical = r["rigid_critical"].as_u64().unwrap();
        for step in r["steps"].as_array().unwrap() {
            let rank = step["strain_rank"].as_u64().unwrap();
            assert_eq!(step["spans"].as_bool(), Some(rank == 6), "{key}: {step}");
            let n = step["n"].as_u64().unwrap();
            assert_eq!(rank == 6, n >= critical, "{key}: {step} against {critical}");
        }
        let steps = r["steps"].as_array().unwrap();
        let at = |n: u64| steps.iter().any(|t| t["n"].as_u64() == Some(n));
        assert!(at(critical) && at(critical - 1), "{key}: {steps:?}");
    }
    let prefix = root.join("paired");
    stdout_of(&[
        "paired",
        wrap.to_str().unwrap(),
        solid.to_str().unwrap(),
        "--out",
        prefix.to_str().unwrap(),
    ]);
    let paired: Value =
        serde_json::from_str(&std::fs::read_to_string(root.join("paired.json")).unwrap()).unwrap();
    let all = &paired["pairings"][0]["all"];
    assert_eq!(all["sequences"], 18);
    let above = s
        .iter()
        .filter(|(k, r)| r["rigid_critical"].as_u64() > w[*k]["rigid_critical"].as_u64())
        .count();
    assert_eq!(all["above"].as_u64(), Some(above as u64));
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn solid_is_refused_outside_truth() {
    for kind in ["rigid", "contact"] {
        fails(
            &threshold_args("unused", &[("--kind", kind), ("--criterion", "solid")]),
            &format!(
                "rgc: error: invalid parameter: --criterion solid needs the exact truth \
                 (truth studies and `rgc truth`), not a {kind} study (use --kind truth)\n"
            ),
        );
    }
    let out = crate::scratch("cli-solid-render").join("r.png");
    for command in [&["sample"][..], &["render", "--out", out.to_str().unwrap()]] {
        fails(
            &[
                command,
                &[
                    "--gamma",
                    "23",
                    "--box",
                    "3",
                    "--density",
                    "20",
                    "--criterion",
                    "solid",
                ][..],
            ]
            .concat(),
            "rgc: error: invalid parameter: --criterion solid needs the exact truth \
             (truth studies and `rgc truth`), not a sample's contacts and bodies\n",
        );
    }
    assert!(!out.exists(), "nothing rendered");
    std::fs::remove_dir_all(out.parent().unwrap()).unwrap();
}
