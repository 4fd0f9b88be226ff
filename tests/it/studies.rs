//! Threshold studies from the command line: resumed after a kill to the
//! uninterrupted results, shards merged, bad parameters refused, and the
//! commands that read finished studies (aspect ratios, compare, tradeoff,
//! stability). Truth studies have their own module, `truth_studies`.

use std::process::Command;

use serde_json::Value;

use crate::audits::{committed, without_last_column};
use crate::cli::{fails, repo, rgc, stdout_of};

/// A small threshold study's arguments, with some options replaced or added.
pub(crate) fn threshold_args<'a>(out: &'a str, changes: &[(&'a str, &'a str)]) -> Vec<&'a str> {
    let mut options = vec![
        ("--gamma", "10"),
        ("--boxes", "3,3.5,4"),
        ("--sequences", "40"),
        ("--runs", "2"),
        ("--bootstrap", "40"),
    ];
    for &(flag, value) in changes {
        match options.iter_mut().find(|o| o.0 == flag) {
            Some(o) => o.1 = value,
            None => options.push((flag, value)),
        }
    }
    threshold(out, &options)
}

/// `rgc threshold --quiet --out OUT` with these options.
pub(crate) fn threshold<'a>(out: &'a str, options: &[(&'a str, &'a str)]) -> Vec<&'a str> {
    let mut args = vec!["threshold", "--quiet", "--out", out];
    args.extend(options.iter().flat_map(|&(f, v)| [f, v]));
    args
}

#[test]
fn threshold_killed_mid_run_resumes_to_the_uninterrupted_results() {
    let base = crate::scratch("cli-threshold-kill");
    let (whole, killed) = (base.join("whole"), base.join("killed"));
    let (w, k) = (whole.to_str().unwrap(), killed.to_str().unwrap());
    let text = stdout_of(&threshold_args(w, &[]));
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
    let text = stdout_of(&threshold_args(k, &[]));
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
        stdout_of(&args);
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
    // Another kind goes beside, with its own fit, not into the first's; the
    // files of the first run are replaced only when asked.
    let beside = [
        "aspect-ratios",
        &dirs[0],
        &dirs[1],
        "--beside",
        &dirs[2],
        "--out",
        stem.to_str().unwrap(),
    ];
    let exists = format!(
        "{} exists; choose another --out, or --force",
        stem.with_extension("csv").display()
    );
    fails(&beside, &exists);
    let out = rgc(&[&beside[..], &["--force"]].concat());
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
            "--force",
        ],
        "is a Rigid study",
    );
    std::fs::remove_dir_all(&base).unwrap();
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
    for (name, keep) in [
        ("rods-6", 1),
        ("rods-8", 2),
        ("mixed-4", 2),
        ("rods-9", 1),
        ("rods-10", 1),
        ("mined", 1),
    ] {
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
    // Named by the aspect ratio, so those of other aspect ratios stay.
    let report: Value = serde_json::from_str(
        &std::fs::read_to_string(results.join("speed-accuracy-g5.json")).unwrap(),
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
            "+rods<=10",
            "+rods<=10 +mixed<=4",
            "+mined",
            "+mined +rods<=10 +mixed<=4",
            "R=5",
            "R=10",
            "fixed K=1",
            "fixed K=10"
        ]
        .map(Value::from)
    );
    assert_eq!(
        field("runs"),
        [1, 1, 2, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 10].map(Value::from)
    );
    assert_eq!(
        field("motif_rules"),
        [0, 0, 0, 1, 3, 5, 5, 7, 1, 8, 0, 0, 0, 0].map(Value::from)
    );
    // `realizations`: the stored key of the sequences each variant analyses.
    assert_eq!(
        field("realizations"),
        [20, 20, 20, 20, 20, 20, 20, 20, 20, 20, 5, 10, 20, 20].map(Value::from)
    );
    assert_eq!(
        field("method"),
        [
            "nested", "nested", "nested", "nested", "nested", "nested", "nested", "nested",
            "nested", "nested", "nested", "nested", "fixed", "fixed"
        ]
        .map(Value::from)
    );
    // The sequence subsets read the K=1 study: twelve studies for fourteen variants.
    assert_eq!(std::fs::read_dir(&studies).unwrap().count(), 12);
    assert_eq!(v[10]["study"], v[1]["study"]);
    assert_eq!(v[11]["study"], v[1]["study"]);
    // Their CPU is that of the sequences they read of the K=1 study.
    let k1 = std::path::Path::new(v[1]["study"].as_str().unwrap());
    for (k, n) in [(10, 5), (11, 10), (1, 20)] {
        let cpu = v[k]["cpu_seconds"].as_f64().unwrap();
        assert!(
            (cpu - crate::cpu_of_first(k1, n)).abs() < 1e-9,
            "{}: {cpu}",
            v[k]["label"]
        );
    }
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
        assert_eq!(paired, (1..=11).contains(&k), "{}", x["label"]);
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
    let csv = std::fs::read_to_string(results.join("speed-accuracy-g5.csv")).unwrap();
    assert_eq!(csv.lines().count(), 15);
    for ext in ["md", "svg", "png"] {
        assert!(
            results.join(format!("speed-accuracy-g5.{ext}")).exists(),
            "{ext}"
        );
    }

    // Side by side with the committed experiment of gamma 23: each bias in
    // percent of its own truth's threshold, each CPU over its truth's.
    std::fs::copy(
        repo("results/speed-accuracy.json"),
        results.join("speed-accuracy.json"),
    )
    .unwrap();
    let results_arg = results.to_str().unwrap();
    let md = stdout_of(&["tradeoff", "--combine", "23,5", "--results", results_arg]);
    assert!(
        md.starts_with("# Speed against accuracy across aspect ratios"),
        "{md}"
    );
    let k1 = &v[1];
    let expected = 100.0 * k1["paired_difference"]["value"].as_f64().unwrap()
        / v[0]["threshold"]["value"].as_f64().unwrap();
    let row = md.lines().find(|l| l.starts_with("| K=1 |")).unwrap();
    let cells: Vec<&str> = row.split(" | ").collect();
    assert!(
        cells[3].starts_with(&format!("{expected:+.1}%")),
        "{row} against {expected}"
    );
    let cpu = k1["cpu_seconds"].as_f64().unwrap() / v[0]["cpu_seconds"].as_f64().unwrap();
    assert_eq!(
        cells[4].trim_end_matches(" |"),
        format!("{cpu:.3}"),
        "{row}"
    );
    // Variants only one aspect ratio has get a dash in the other's columns.
    let committed: Value = serde_json::from_str(
        &std::fs::read_to_string(repo("results/speed-accuracy.json")).unwrap(),
    )
    .unwrap();
    let n23 = committed["variants"].as_array().unwrap().len();
    let csv = std::fs::read_to_string(results.join("speed-accuracy-gammas.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + n23 + 14);
    assert!(csv.starts_with(
        "gamma,variant,family,sequences,bias,bias_lo,bias_hi,cpu_seconds,cpu_over_truth\n"
    ));
    let svg = std::fs::read_to_string(results.join("speed-accuracy-gammas.svg")).unwrap();
    assert!(svg.contains("γ = 5") && svg.contains("γ = 23"));
    // An aspect ratio without its experiment, or an experiment of another one.
    fails(
        &["tradeoff", "--combine", "23,48", "--results", results_arg],
        "speed-accuracy-g48.json: No such file or directory (os error 2) (rgc tradeoff --gamma 48 makes it)",
    );
    std::fs::copy(
        results.join("speed-accuracy.json"),
        results.join("speed-accuracy-g48.json"),
    )
    .unwrap();
    fails(
        &["tradeoff", "--combine", "5,48", "--results", results_arg],
        "speed-accuracy-g48.json: made at gamma 23, not 48",
    );
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
    assert_eq!(
        without_last_column(&csv),
        without_last_column(&committed("rank-stability.csv").join("\n"))
    );
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

/// Spawns `args` and SIGKILLs it once the record files of `dir` hold
/// `target` complete lines; returns how many they hold after the kill.
pub fn kill_after(args: &[&str], dir: &std::path::Path, target: usize) -> usize {
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
    // Seed 2: seed 1's sequences extrapolate to a negative threshold, which
    // the analysis refuses (issue 31), so that study has no summary.
    let study = [
        ("--gamma", "98"),
        ("--boxes", "2.1,2.3,2.5"),
        ("--sequences", "16"),
        ("--bootstrap", "30"),
        ("--seed", "2"),
    ];
    let shard = |k| [&study[..], &[("--shard", k)]].concat();
    let path = |d: &std::path::Path| d.to_str().unwrap().to_string();
    let run = |a: &[&str]| {
        stdout_of(a);
    };
    let summary = |d: &std::path::Path| std::fs::read_to_string(d.join("summary.json")).unwrap();
    let whole = at("whole");
    run(&threshold(&path(&whole), &study));
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
        let now = kill_after(&threshold(&path(&killed), &study), &killed, target);
        assert!(
            now >= target && now < 48,
            "{now} records after a kill aiming at {target}"
        );
        done = now;
    }
    assert!(!killed.join("summary.json").exists());
    run(&threshold(&path(&killed), &study));
    assert_eq!(summary(&whole), summary(&killed));

    let shards = at("shards");
    let shards_path = path(&shards);
    run(&threshold(&shards_path, &shard("0/2")));
    let a = threshold(&shards_path, &shard("1/2"));
    let now = kill_after(&a, &shards, 20);
    // Shard 0 holds 24 records; shard 1 is killed before its own 24.
    assert!(now < 48, "{now}");
    run(&a);
    let merged = at("merged");
    stdout_of(&[
        "merge",
        shards.to_str().unwrap(),
        "--bootstrap",
        "30",
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(summary(&whole), summary(&merged));
    std::fs::remove_dir_all(&base).unwrap();
}
