//! Rule files: round trips, and clear errors for malformed or hostile files
//! (wrong types, huge sizes, duplicate ids, forged canonical forms, patterns
//! that are not rigid); files given twice and rules repeated, dropped with
//! a message; a fuzz of the reader that must never panic.

use proptest::prelude::*;
use std::path::{Path, PathBuf};

use rgc::pattern::{NodeKind, Pattern, PatternContact};
use rgc::rule_file::{Dropped, Provenance, Rule, load, load_rules, write_rules};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rgc-rulefiles-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn triangle() -> Pattern {
    let c = |a: u8, b: u8| PatternContact {
        nodes: [a, b],
        rods: [0, 0],
    };
    Pattern {
        kinds: vec![NodeKind::Rod; 3],
        contacts: vec![c(0, 1), c(1, 2), c(0, 2)],
    }
}

fn rule(id: &str) -> Rule {
    Rule::new(id.into(), triangle(), Provenance::default()).unwrap()
}

fn error_of(path: &Path) -> String {
    load_rules(&[path.to_path_buf()]).unwrap_err().to_string()
}

#[test]
fn rules_round_trip_through_files_and_directories() {
    let d = dir("roundtrip");
    write_rules(&d.join("a.json"), &[rule("a")]).unwrap();
    write_rules(
        &d.join("b.json"),
        &[Rule::new("b".into(), k4(), Provenance::default()).unwrap()],
    )
    .unwrap();
    std::fs::write(d.join("notes.txt"), "not a rule file").unwrap();
    let loaded = load_rules(std::slice::from_ref(&d)).unwrap();
    assert_eq!(
        loaded.iter().map(|r| r.id.as_str()).collect::<Vec<_>>(),
        ["a", "b"]
    );
    assert_eq!(loaded[0], rule("a"));
    std::fs::remove_dir_all(&d).unwrap();
}

/// Four rods pairwise in contact: rigid, and another pattern than the triangle.
fn k4() -> Pattern {
    rods_pattern(&[(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])
}

#[test]
fn a_rule_set_loaded_twice_is_read_once() {
    let d = dir("twice");
    let (a, b) = (d.join("a.json"), d.join("b.json"));
    write_rules(&a, &[rule("a")]).unwrap();
    write_rules(
        &b,
        &[Rule::new("b".into(), k4(), Provenance::default()).unwrap()],
    )
    .unwrap();
    let ids = |rules: &[Rule]| rules.iter().map(|r| r.id.clone()).collect::<Vec<_>>();
    // A directory and a file in it: the file is read once, where the
    // directory lists it.
    let loaded = load(&[d.clone(), a.clone()]).unwrap();
    assert_eq!(ids(&loaded.rules), ["a", "b"]);
    assert_eq!(
        loaded.dropped,
        [Dropped::File {
            path: a.clone(),
            first: a.clone()
        }]
    );
    assert_eq!(
        loaded.dropped[0].to_string(),
        format!(
            "rule file {} is given twice: its rules are loaded once",
            a.display()
        )
    );
    // The same file by another path.
    let again = d.join(".").join("a.json");
    let loaded = load(&[a.clone(), b.clone(), again.clone()]).unwrap();
    assert_eq!(ids(&loaded.rules), ["a", "b"]);
    assert_eq!(
        loaded.dropped[0].to_string(),
        format!(
            "rule file {} is {} given again: its rules are loaded once",
            again.display(),
            a.display()
        )
    );
    // A copy is another file: its rules repeat ids, which is refused.
    let copy = d.join("copy.json");
    std::fs::copy(&a, &copy).unwrap();
    assert_eq!(
        load(&[a.clone(), copy.clone()]).unwrap_err().to_string(),
        format!(
            "invalid parameter: rule file {}: duplicate rule id \"a\" (also in {})",
            copy.display(),
            a.display()
        )
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_repeated_rule_is_dropped_with_a_message() {
    let d = dir("repeated");
    let (a, c) = (d.join("a.json"), d.join("c.json"));
    let k4 = Rule::new("k".into(), k4(), Provenance::default()).unwrap();
    write_rules(&a, &[rule("a")]).unwrap();
    // The triangle again under another id (its nodes in another order),
    // within c.json and across the two files.
    let turned = rods_pattern(&[(1, 2), (2, 0), (1, 0)]);
    assert_ne!(turned, triangle());
    let turned = Rule::new("c".into(), turned, Provenance::default()).unwrap();
    assert_eq!(turned.canonical, rule("a").canonical);
    write_rules(&c, &[turned, k4.clone(), rule("t")]).unwrap();
    let loaded = load(&[a.clone(), c.clone()]).unwrap();
    assert_eq!(loaded.rules, [rule("a"), k4.clone()]);
    let dropped = |id: &str| Dropped::Rule {
        id: id.into(),
        file: c.clone(),
        kept: "a".into(),
        kept_file: a.clone(),
    };
    assert_eq!(loaded.dropped, [dropped("c"), dropped("t")]);
    assert_eq!(
        loaded.dropped[0].to_string(),
        format!(
            "rule c ({}) has the pattern of rule a ({}): dropped",
            c.display(),
            a.display()
        )
    );
    // Within one file the first is kept.
    let loaded = load(std::slice::from_ref(&c)).unwrap();
    assert_eq!(
        loaded
            .rules
            .iter()
            .map(|r| r.id.as_str())
            .collect::<Vec<_>>(),
        ["c", "k"]
    );
    assert_eq!(loaded.dropped.len(), 1);
    // The command line says so on stderr, one line each, and runs.
    let mut args = vec!["compress", "--graph6", "E]r?"];
    for p in [&a, &c, &a] {
        args.extend(["--motifs", p.to_str().unwrap()]);
    }
    let out = crate::cli::succeeds(&args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("rgc: warning: "))
        .collect();
    assert_eq!(
        warnings,
        [
            format!(
                "rgc: warning: rule file {} is given twice: its rules are loaded once",
                a.display()
            ),
            format!(
                "rgc: warning: rule c ({}) has the pattern of rule a ({}): dropped",
                c.display(),
                a.display()
            ),
            format!(
                "rgc: warning: rule t ({}) has the pattern of rule a ({}): dropped",
                c.display(),
                a.display()
            ),
        ],
        "{stderr}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

/// Rules are checked in parallel, but the error is the first a check in
/// file order meets.
#[test]
fn the_first_bad_rule_is_named() {
    let d = dir("first-bad");
    let f = d.join("r.json");
    let cycle = rods_pattern(&[(0, 1), (1, 2), (2, 3), (3, 0)]);
    let mut not_rigid = serde_json::to_value(rule("x")).unwrap();
    not_rigid["pattern"] = serde_json::to_value(&cycle).unwrap();
    not_rigid["canonical"] = rgc::rule_file::canonical_form(&cycle).into();
    let mut forged = serde_json::to_value(rule("y")).unwrap();
    forged["canonical"] = "rrr:forged".into();
    let good = serde_json::to_value(rule("g")).unwrap();
    for (rules, named) in [
        ([&good, &not_rigid, &forged], "rule x is not rigid"),
        ([&good, &forged, &not_rigid], "rule y: canonical form"),
    ] {
        let file = serde_json::json!({ "format": rgc::rule_file::RULE_FORMAT, "rules": rules });
        std::fs::write(&f, file.to_string()).unwrap();
        for _ in 0..4 {
            let err = error_of(&f);
            assert!(err.contains(named), "{err}");
        }
    }
    // A file that cannot be read comes after the rules read before it.
    let missing = d.join("missing.json");
    let err = load(&[f.clone(), missing]).unwrap_err().to_string();
    assert!(err.contains("rule y: canonical form"), "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn hostile_rule_files_get_clear_errors() {
    let d = dir("hostile");
    let f = d.join("r.json");
    let good = serde_json::to_value(rgc::rule_file::RuleFile {
        format: rgc::rule_file::RULE_FORMAT.into(),
        rules: vec![rule("t")],
    })
    .unwrap();
    let write = |v: &serde_json::Value| std::fs::write(&f, v.to_string()).unwrap();

    std::fs::write(&f, "{ not json").unwrap();
    assert!(error_of(&f).contains("rule file"), "{}", error_of(&f));

    let mut v = good.clone();
    v["format"] = "rgc-rules/99".into();
    write(&v);
    assert!(error_of(&f).contains("is not \"rgc-rules/1\""));

    let mut v = good.clone();
    v["rules"][0]["pattern"]["kinds"][0] = 7.into();
    write(&v);
    assert!(error_of(&f).contains("rule file"));

    let mut v = good.clone();
    let r = v["rules"][0].clone();
    v["rules"] = serde_json::json!([r, r]);
    write(&v);
    assert!(error_of(&f).contains("duplicate rule id \"t\""));

    let mut v = good.clone();
    v["rules"][0]["canonical"] = "rrr:forged".into();
    write(&v);
    assert!(error_of(&f).contains("does not match its pattern"));

    // A 4-cycle of rods claimed rigid: refused, it would create false rigidity.
    let c = |a: u8, b: u8| PatternContact {
        nodes: [a, b],
        rods: [0, 0],
    };
    let cycle = Pattern {
        kinds: vec![NodeKind::Rod; 4],
        contacts: vec![c(0, 1), c(1, 2), c(2, 3), c(3, 0)],
    };
    let mut v = good.clone();
    v["rules"][0]["pattern"] = serde_json::to_value(&cycle).unwrap();
    v["rules"][0]["canonical"] = rgc::rule_file::canonical_form(&cycle).into();
    write(&v);
    assert!(
        error_of(&f).contains("not rigid on every realization component"),
        "{}",
        error_of(&f)
    );

    let mut v = good.clone();
    v["rules"][0]["pattern"]["kinds"] = serde_json::json!(vec!["rod"; 500]);
    write(&v);
    assert!(
        error_of(&f).contains("a pattern has 1 to 24 nodes, got 500"),
        "{}",
        error_of(&f)
    );
    assert_eq!(
        error_of(&f).matches("invalid parameter").count(),
        1,
        "{}",
        error_of(&f)
    );

    let mut v = good.clone();
    v["rules"][0]["pattern"]["contacts"][0]["nodes"] = serde_json::json!([0, 9]);
    write(&v);
    assert!(error_of(&f).contains("outside"), "{}", error_of(&f));

    // Larger than a rule file may be: refused before it is read.
    let big = std::fs::File::create(&f).unwrap();
    big.set_len(rgc::rule_file::MAX_RULE_FILE_BYTES + 1)
        .unwrap();
    assert!(error_of(&f).contains("larger than"));

    assert!(error_of(&d.join("missing.json")).contains("missing.json"));
    std::fs::remove_dir_all(&d).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Arbitrary bytes as a rule file: an error or rules, never a panic.
    #[test]
    fn arbitrary_files_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let d = dir("fuzz-bytes");
        let f = d.join(format!("{}.json", bytes.len()));
        std::fs::write(&f, &bytes).unwrap();
        let _ = load_rules(&[f]);
    }

    /// Valid files with one field replaced by an arbitrary JSON scalar.
    #[test]
    fn mutated_rule_files_never_panic(field in 0usize..8, n in any::<i64>(), s in ".{0,12}") {
        let d = dir("fuzz-fields");
        let f = d.join(format!("{field}-{n}.json"));
        let mut v = serde_json::to_value(rgc::rule_file::RuleFile {
            format: rgc::rule_file::RULE_FORMAT.into(),
            rules: vec![rule("t")],
        }).unwrap();
        let slot = match field {
            0 => &mut v["rules"][0]["pattern"]["kinds"][1],
            1 => &mut v["rules"][0]["pattern"]["contacts"][0]["nodes"][1],
            2 => &mut v["rules"][0]["pattern"]["contacts"][1]["rods"][0],
            3 => &mut v["rules"][0]["id"],
            4 => &mut v["rules"][0]["verdict"]["dof"],
            5 => &mut v["rules"][0]["pattern"]["contacts"],
            6 => &mut v["rules"],
            _ => &mut v["format"],
        };
        *slot = if n % 2 == 0 { n.into() } else { s.clone().into() };
        std::fs::write(&f, v.to_string()).unwrap();
        let _ = load_rules(&[f]);
    }
}

fn rods_pattern(edges: &[(u8, u8)]) -> Pattern {
    let n = edges.iter().map(|&(a, b)| a.max(b)).max().unwrap() as usize + 1;
    Pattern {
        kinds: vec![NodeKind::Rod; n],
        contacts: edges
            .iter()
            .map(|&(a, b)| PatternContact {
                nodes: [a, b],
                rods: [0, 0],
            })
            .collect(),
    }
}

/// The rod prism and K_{3,3}: rigid on one realization component (all rods
/// in one plane), flexible on the other.
fn component_dependent() -> [(&'static str, Pattern); 2] {
    let prism: Vec<(u8, u8)> = rgc::engine::examples::PRISM
        .iter()
        .map(|&(a, b)| (a as u8, b as u8))
        .collect();
    let k33: Vec<(u8, u8)> = (0..3).flat_map(|a| (3..6).map(move |b| (a, b))).collect();
    [("prism", rods_pattern(&prism)), ("k33", rods_pattern(&k33))]
}

#[test]
fn component_dependent_patterns_are_refused_as_rules() {
    let d = dir("component-dependent");
    for (name, p) in component_dependent() {
        let expected = format!(
            "rule {name} is not rigid on every realization component (exact rank: component-dependent, 1 DOF): loading it would create false rigidity"
        );
        let err = Rule::new(name.into(), p.clone(), Provenance::default()).unwrap_err();
        assert_eq!(err.to_string(), format!("invalid parameter: {expected}"));
        // A file that claims the pattern rigid, with its true canonical form
        // and a forged verdict, is refused when it is loaded.
        let mut forged = serde_json::to_value(rgc::rule_file::RuleFile {
            format: rgc::rule_file::RULE_FORMAT.into(),
            rules: vec![rule(name)],
        })
        .unwrap();
        forged["rules"][0]["pattern"] = serde_json::to_value(&p).unwrap();
        forged["rules"][0]["canonical"] = rgc::rule_file::canonical_form(&p).into();
        let f = d.join(format!("{name}.json"));
        std::fs::write(&f, forged.to_string()).unwrap();
        assert_eq!(
            error_of(&f),
            format!("invalid parameter: rule file {}: {expected}", f.display())
        );
        // The command line says the same in one line, with exit code 2.
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rgc"))
            .args([
                "compress",
                "--graph6",
                "E]r?",
                "--motifs",
                f.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            stderr.trim_end(),
            format!(
                "rgc: error: invalid parameter: rule file {}: {expected}",
                f.display()
            )
        );
    }
    std::fs::remove_dir_all(&d).unwrap();
}

fn committed(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("motifs")
        .join(file)
}

/// The committed rule files load, every rule re-verified by exact rank with
/// the verdict it stores; `base.json` is the built-in base rules.
#[test]
fn committed_rule_files_are_verified_on_load() {
    let counts = [
        ("base.json", 56),
        ("rods-6.json", 1),
        ("rods-8.json", 13),
        ("mixed-4.json", 124),
        ("mined.json", 20),
        ("mined-g48.json", 20),
        ("mined-g98.json", 20),
        ("rods-9.json", 313),
        ("rods-10.json", 1118),
        ("mixed-5.json", 1738),
    ];
    for (file, count) in counts {
        let rules = load_rules(&[committed(file)]).unwrap();
        assert_eq!(rules.len(), count, "{file}");
        for r in &rules {
            let v = rgc::rigidity::check_exact(&r.pattern, r.verdict.seed).unwrap();
            assert_eq!(
                (v.class.as_str(), v.dof),
                ("rigid", Some(0)),
                "{file} {}",
                r.id
            );
            assert_eq!(v.components, r.verdict.components, "{file} {}", r.id);
            assert_eq!(r.canonical, rgc::rule_file::canonical_form(&r.pattern));
        }
    }
    // The whole directory, in name order: base.json repeats three
    // patterns under two variant ids each, mined-11 (and mined-g98-19) is
    // base-3D2A-2-11, the audit found mined-10 again among the mixed motifs
    // of 5 components (and mined-g48-8), the three minings share 8
    // patterns, and mining at gamma 98 found rods-6-0.
    let all = load(&[Path::new(env!("CARGO_MANIFEST_DIR")).join("motifs")]).unwrap();
    let dropped: Vec<(&str, &str)> = all
        .dropped
        .iter()
        .map(|d| match d {
            Dropped::Rule { id, kept, .. } => (id.as_str(), kept.as_str()),
            other => panic!("{other}"),
        })
        .collect();
    assert_eq!(
        dropped,
        [
            ("base-3D2A-5-1", "base-3D2A-4-10"),
            ("base-3D2A-6-10", "base-3D2A-3-1"),
            ("base-3D2A-8-10", "base-3D2A-7-1"),
            ("mined-g98-9", "mined-g48-6"),
            ("mined-g98-19", "base-3D2A-2-11"),
            ("mined-0", "mined-g48-0"),
            ("mined-1", "mined-g48-12"),
            ("mined-7", "mined-g98-1"),
            ("mined-11", "base-3D2A-2-11"),
            ("mined-14", "mined-g48-3"),
            ("mined-15", "mined-g98-0"),
            ("mined-19", "mined-g48-14"),
            ("mixed-5-10", "mined-g48-8"),
            ("mixed-5-15", "mined-10"),
            ("rods-6-0", "mined-g98-11"),
        ]
    );
    assert_eq!(
        all.rules.len(),
        59 + 1 + 13 + 124 + 20 + 20 + 20 + 313 + 1118 + 1738 - 15
    );
    let (mut base, _) = rgc::engine::shapes::base_rules().unwrap();
    base.retain(|r| !dropped[..3].iter().any(|(id, _)| r.id == *id));
    assert_eq!(load_rules(&[committed("base.json")]).unwrap(), base);
    // Verification happens on load: one committed rule turned into the prism
    // (with a matching canonical form) is refused, naming the rule.
    let d = dir("tampered");
    let mut file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(committed("rods-8.json")).unwrap()).unwrap();
    let (_, prism) = component_dependent()[0].clone();
    let id = file["rules"][3]["id"].as_str().unwrap().to_string();
    file["rules"][3]["pattern"] = serde_json::to_value(&prism).unwrap();
    file["rules"][3]["canonical"] = rgc::rule_file::canonical_form(&prism).into();
    let f = d.join("rods-8.json");
    std::fs::write(&f, file.to_string()).unwrap();
    let err = error_of(&f);
    assert!(
        err.contains(&format!(
            "rule {id} is not rigid on every realization component"
        )),
        "{err}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}
