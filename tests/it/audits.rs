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
    let timing = err.lines().last().unwrap_or_default();
    assert!(
        timing.contains("Seconds by size: rods 2 ") && timing.contains("; mixed 2 "),
        "{err}"
    );
    std::fs::remove_dir_all(&copy).unwrap();
}
