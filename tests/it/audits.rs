//! The coverage audit from the command line: its tables and rule files,
//! the committed ones reproduced, and the same results on any thread count.

use std::process::Command;

/// A CSV table without its last column (a float that moves with the
/// arithmetic, as the median gap of the stability table).
pub fn without_last_column(table: &str) -> Vec<String> {
    table
        .lines()
        .map(|l| l.rsplit_once(',').map_or(l, |(head, _)| head).to_string())
        .collect()
}

/// The committed table of `results/`, by line.
pub fn committed(name: &str) -> Vec<String> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("results")
        .join(name);
    lines(&std::fs::read_to_string(path).unwrap())
}

fn lines(table: &str) -> Vec<String> {
    table.lines().map(String::from).collect()
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
    let rows = lines(&rods);
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
    assert_eq!(lines(&mixed), committed("audit-mixed.csv")[..3]);
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
        let read = |d: &std::path::Path| lines(&std::fs::read_to_string(d.join(table)).unwrap());
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

/// The main job, `rgc audit` on its defaults in a copy of the repository's
/// `results/` and `motifs/`, leaves every committed file it writes as it
/// was, byte for byte (its timings go to stderr), so a newcomer's first
/// command leaves `git status` clean. 2.3 s wall on two idle cores (8.6 s
/// while other builds ran), 14 MB peak: the default audit itself is the test.
#[test]
fn the_default_audit_rewrites_the_committed_files_byte_for_byte() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let copy = crate::scratch("cli-audit-default");
    let written = [
        "results/audit-rods.csv",
        "results/audit-mixed.csv",
        "results/audit-rods.json",
        "results/audit-mixed.json",
        "results/falsely-compressed-rods.g6",
        "motifs/rods-6.json",
        "motifs/rods-8.json",
        "motifs/mixed-4.json",
    ];
    for dir in ["results", "motifs"] {
        std::fs::create_dir_all(copy.join(dir)).unwrap();
    }
    for file in written {
        std::fs::copy(repo.join(file), copy.join(file)).unwrap();
    }
    let before: Vec<std::time::SystemTime> = written
        .iter()
        .map(|f| std::fs::metadata(copy.join(f)).unwrap().modified().unwrap())
        .collect();
    let out = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .arg("audit")
        .current_dir(&copy)
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    for (file, before) in written.iter().zip(before) {
        let path = copy.join(file);
        assert_ne!(
            std::fs::metadata(&path).unwrap().modified().unwrap(),
            before,
            "{file} was rewritten"
        );
        assert_eq!(
            std::fs::read(&path).unwrap(),
            std::fs::read(repo.join(file)).unwrap(),
            "{file}"
        );
    }
    // stdout is the committed results/audit.txt; the seconds are on stderr.
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        std::fs::read_to_string(repo.join("results/audit.txt")).unwrap()
    );
    // Rules one kind's table keeps that the other kind's smaller rules
    // reduce are reported, not silently kept (as `rgc rules --check`).
    assert!(
        String::from_utf8_lossy(&out.stdout)
            .contains("Across kinds, 60 of the 138 rules written are reduced to one node"),
    );
    let timing = err.lines().last().unwrap_or_default();
    assert!(
        timing.contains("Seconds by size: rods 2 ") && timing.contains("; mixed 2 "),
        "{err}"
    );
    std::fs::remove_dir_all(&copy).unwrap();
}

/// A rule and a larger one it makes redundant: the irreducible six-rod
/// motif, and it with a seventh rod touching two of its rods (which 3D2B
/// joins to the body the smaller rule makes). The larger is reported, the
/// smaller not, whatever the order of the file; alone the larger is
/// missed by the base engine, so it is the smaller rule that reduces it.
#[test]
fn a_rule_made_redundant_by_a_smaller_one_is_reported() {
    use rgc::pattern::PatternContact;
    use rgc::progress::Silent;
    use rgc::rule_file::{Provenance, Rule, load_rules, write_rules};
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let six = load_rules(&[repo.join("motifs/rods-6.json")])
        .unwrap()
        .remove(0);
    let mut seven = six.pattern.clone();
    seven.kinds.push(rgc::pattern::NodeKind::Rod);
    // Rods 0 and 3 of the six share no contact: no new triangle.
    assert!(
        !seven
            .contacts
            .iter()
            .any(|c| c.nodes == [0, 3] || c.nodes == [3, 0])
    );
    for end in [0, 3] {
        seven.contacts.push(PatternContact {
            nodes: [end, 6],
            rods: [0, 0],
        });
    }
    let seven = Rule::new("seven".into(), seven, Provenance::default()).unwrap();
    let base = rgc::engine::RuleSet::Sound;
    assert_eq!(
        rgc::audit::redundant(std::slice::from_ref(&seven), base, 8, &Silent).unwrap(),
        []
    );
    let found = rgc::audit::redundant(&[seven.clone(), six.clone()], base, 8, &Silent).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        (found[0].id.as_str(), found[0].nodes, found[0].contacts),
        ("seven", 7, 10)
    );
    assert_eq!(
        found[0].sequence,
        [rgc::engine::Motif::Rule, rgc::engine::Motif::D2B]
    );
    // From the command line, the file's rules in the other order.
    let dir = crate::scratch("rules-check");
    let file = dir.join("rules.json");
    write_rules(&file, &[six, seven]).unwrap();
    assert_eq!(
        crate::cli::stdout_of(&["rules", "--check", file.to_str().unwrap()]),
        format!(
            "2 rules of {}, rules sound, 8 motif orders: 1 redundant:\n  seven (7 nodes, 10 contacts): one node in motif order {} by rule, 3D2B\n",
            file.display(),
            found[0].run
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--extended` writes its tables where it is told and only the rule files
/// above the default audit's sizes: a default audit's rule file in the
/// same directory is neither refused nor rewritten (without `--extended`
/// the same sizes are refused: that file was made by another command).
#[test]
fn the_extended_audit_leaves_the_default_rule_files_alone() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = crate::scratch("cli-audit-extended");
    let six = dir.join("rods-6.json");
    std::fs::copy(repo.join("motifs/rods-6.json"), &six).unwrap();
    let before = std::fs::metadata(&six).unwrap().modified().unwrap();
    let small = ["--max-rods", "6", "--max-components", "3"];
    let text = audit_into(&dir, &[&small[..], &["--extended"]].concat(), None);
    assert!(
        text.ends_with(&format!(
            "Rule files: none (none missed above the default audit's sizes).\nFalsely compressed patterns, with the motifs that compressed each: {d}/audit-rods.json, {d}/falsely-compressed-rods.g6, {d}/audit-mixed.json.\n",
            d = dir.display()
        )),
        "{text}"
    );
    assert_eq!(
        lines(&std::fs::read_to_string(dir.join("audit-rods.csv")).unwrap()),
        committed("audit-rods.csv")[..6]
    );
    assert_eq!(std::fs::metadata(&six).unwrap().modified().unwrap(), before);
    assert_eq!(
        std::fs::read(&six).unwrap(),
        std::fs::read(repo.join("motifs/rods-6.json")).unwrap()
    );
    let d = dir.to_str().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(["audit", "--results", d, "--rules-dir", d])
        .args(small)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains(&format!(
            "{} was made by `rgc audit --max-rods 8 --max-components 4 --rules sound`",
            six.display()
        )),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The committed extended audit (`rgc audit --extended`): its tables repeat
/// the default audit's up to the default sizes, its rule files are the
/// sizes above them and name its command, and rerunning it would replace
/// only its own files.
#[test]
fn the_committed_extended_audit_extends_the_default_one() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let extended = rgc::audit::AuditOptions::extended();
    for (kind, rows) in [("rods", 10), ("mixed", 5)] {
        let table = committed(&format!("audit-extended/audit-{kind}.csv"));
        let default = committed(&format!("audit-{kind}.csv"));
        assert_eq!(table.len(), rows, "{kind}: header and sizes 2..");
        assert_eq!(table[..default.len()], default[..], "{kind}");
    }
    for (file, size) in [("rods-9", 9), ("rods-10", 10), ("mixed-5", 5)] {
        let text = std::fs::read_to_string(repo.join(format!("motifs/{file}.json"))).unwrap();
        let rules: rgc::rule_file::RuleFile = serde_json::from_str(&text).unwrap();
        let irreducible: u64 = committed(if file.starts_with("rods") {
            "audit-extended/audit-rods.csv"
        } else {
            "audit-extended/audit-mixed.csv"
        })
        .iter()
        .find(|row| row.split(',').nth(1) == Some(&size.to_string()))
        .and_then(|row| row.split(',').nth(11).map(|n| n.parse().unwrap()))
        .unwrap();
        assert_eq!(rules.rules.len() as u64, irreducible, "{file}");
        assert!(
            rules
                .rules
                .iter()
                .all(|r| r.provenance.command.as_deref() == Some(&extended.command())),
            "{file}"
        );
    }
    rgc::audit::check_outputs(
        &extended,
        &repo.join("results/audit-extended"),
        &repo.join("motifs"),
    )
    .unwrap();
}
