//! Studies from a row (or signac) workspace: `rgc workspace slice` reads a
//! directory's value, runs its slice, resumes after a kill and marks it
//! done; `rgc workspace merge` merges one study. The committed example
//! (`examples/row/`) runs through row itself in the local shell to the
//! summary of the same study run in one process, and row's Slurm script
//! for a built-in cluster is the committed one. Row is installed once into
//! `target/row` (`cargo install row --version 1.1.0 --locked`: 86 s on two
//! idle cores, 250 s on two busy ones) and reused; where it cannot be
//! installed, its tests say why and skip.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use crate::cli::{fails, repo, stdout_of};
use crate::studies::kill_after;

/// The row release the example and its Slurm script are made with.
const ROW_VERSION: &str = "1.1.0";

/// The row binary in `target/row`, installed on first use; why not, where
/// it cannot be installed (no network, no cargo).
fn row() -> Result<&'static Path, &'static str> {
    static ROW: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    ROW.get_or_init(|| {
        let root = repo("target/row");
        let bin = root.join("bin/row");
        let version = || {
            Command::new(&bin).arg("--version").output().is_ok_and(|o| {
                String::from_utf8_lossy(&o.stdout).trim() == format!("row {ROW_VERSION}")
            })
        };
        if version() {
            return Ok(bin);
        }
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let started = std::time::Instant::now();
        let out = Command::new(&cargo)
            .args([
                "install",
                "row",
                "--version",
                ROW_VERSION,
                "--locked",
                "--root",
            ])
            .arg(&root)
            .output()
            .map_err(|e| format!("cannot run {cargo}: {e}"))?;
        if !out.status.success() || !version() {
            let err = String::from_utf8_lossy(&out.stderr);
            let last = err
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("");
            return Err(format!("`cargo install row` failed: {last}"));
        }
        eprintln!(
            "installed row {ROW_VERSION} into {} in {:.0} s",
            root.display(),
            started.elapsed().as_secs_f64()
        );
        Ok(bin)
    })
    .as_ref()
    .map(PathBuf::as_path)
    .map_err(String::as_str)
}

/// Row in `project`, its own configuration (none) and rgc on its path.
fn row_in(row: &Path, project: &Path, args: &[&str]) -> Output {
    let bin = Path::new(env!("CARGO_BIN_EXE_rgc")).parent().unwrap();
    let path = std::env::join_paths(std::iter::once(bin.to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let out = Command::new(row)
        .args(args)
        .current_dir(project)
        .env("PATH", path)
        .env("ROW_HOME", project.join("home"))
        .env("ROW_NO_PROGRESS", "true")
        .env("ROW_COLOR", "never")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "row {args:?}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A row project with the example's workflow and the workspaces that
/// `examples/row/create-workspace.sh` makes of each `(study, shards, values)`.
fn project(dir: &Path, studies: &[(&str, &str, &[&str])]) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(
        repo("examples/row/workflow.toml"),
        dir.join("workflow.toml"),
    )
    .unwrap();
    for (study, shards, values) in studies {
        let out = Command::new("bash")
            .arg(repo("examples/row/create-workspace.sh"))
            .args([study, shards])
            .args(*values)
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Each action's completed and eligible directories, from `row show status`.
fn status(row: &Path, project: &Path) -> Vec<(String, u64, u64)> {
    let out = row_in(row, project, &["show", "status"]);
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (
                f[0].to_string(),
                f[1].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect()
}

const RIGID: [&str; 4] = ["gamma=10", "boxes=[3,3.5,4]", "sequences=40", "runs=2"];
const CONTACT: [&str; 4] = [
    "kind=contact",
    "gamma=10",
    "boxes=[3,3.5,4]",
    "sequences=40",
];

#[test]
fn the_row_example_runs_two_studies_to_the_summaries_of_one_process() {
    let row = match row() {
        Ok(row) => row,
        Err(why) => return eprintln!("skipped: {why}"),
    };
    let base = crate::scratch("row-example");
    let p = base.join("project");
    project(&p, &[("g10", "3", &RIGID), ("c10", "2", &CONTACT)]);
    let slice = p.join("workspace/g10-1");

    // A slice killed midway, by hand, before row runs it: no product yet.
    let killed = kill_after(
        &["workspace", "slice", "--quiet", slice.to_str().unwrap()],
        &slice,
        5,
    );
    assert!(killed < 40, "{killed}");
    assert!(!slice.join("slice.json").exists());
    assert_eq!(
        status(row, &p),
        [("slice".into(), 0, 5), ("merge".into(), 0, 0)]
    );

    // The first submit runs the five slices (the killed one resumes), the
    // second the two merges, one per study; then nothing is left.
    let first = row_in(row, &p, &["submit", "--cluster", "none", "--yes"]);
    let text = String::from_utf8_lossy(&first.stdout);
    assert!(
        text.contains(&format!(
            "The slice 1/3 of workspace/g10-1: {} sequences run in",
            40 - killed
        )) && text.contains(&format!("({killed} found done); slice.json written.")),
        "{text}"
    );
    assert_eq!(
        status(row, &p),
        [("slice".into(), 5, 0), ("merge".into(), 0, 5)]
    );
    let second = row_in(row, &p, &["submit", "--cluster", "none", "--yes"]);
    let text = String::from_utf8_lossy(&second.stdout);
    assert_eq!(
        text.matches("Merged 120 sequences from").count(),
        2,
        "{text}"
    );
    assert_eq!(
        status(row, &p),
        [("slice".into(), 5, 0), ("merge".into(), 5, 0)]
    );
    let third = row_in(row, &p, &["submit", "--cluster", "none", "--yes"]);
    assert!(
        String::from_utf8_lossy(&third.stderr).contains("There are no eligible jobs to submit.")
    );

    // Each merged study is byte for byte the same study run in one process.
    for (name, values, dirs) in [
        (
            "rigid-sound-base-k2-nested-r40-g10-L3_3.5_4-wrap-s1",
            &RIGID,
            3,
        ),
        (
            "contact-sound-base-k1-nested-r40-g10-L3_3.5_4-wrap-s1",
            &CONTACT,
            2,
        ),
    ] {
        let one = base.join(name);
        let mut args = vec!["threshold", "--quiet", "--out", one.to_str().unwrap()];
        let flags: Vec<String> = values
            .iter()
            .map(|v| {
                let (k, v) = v.split_once('=').unwrap();
                format!("--{k}={}", v.trim_matches(['[', ']']))
            })
            .collect();
        args.extend(flags.iter().map(String::as_str));
        stdout_of(&args);
        let merged = p.join("studies").join(name);
        let read = |d: &Path| std::fs::read(d.join("summary.json")).unwrap();
        assert_eq!(read(&one), read(&merged), "{name}");
        let label = if values == &RIGID { "g10" } else { "c10" };
        for i in 0..dirs {
            let marker =
                std::fs::read_to_string(p.join(format!("workspace/{label}-{i}/merged.json")))
                    .unwrap();
            let v: serde_json::Value = serde_json::from_str(&marker).unwrap();
            assert_eq!(v["study"], format!("studies/{name}"));
            assert_eq!(v["sequences"], 120);
        }
    }

    // A finished slice exits at once and touches nothing.
    let records = slice.join("records-1-of-3.jsonl");
    let before = std::fs::read(&records).unwrap();
    let text = stdout_of(&["workspace", "slice", slice.to_str().unwrap()]);
    assert!(text.contains("is done (slice.json)"), "{text}");
    assert_eq!(std::fs::read(&records).unwrap(), before);
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn row_dry_run_gives_the_committed_slurm_script() {
    let row = match row() {
        Ok(row) => row,
        Err(why) => return eprintln!("skipped: {why}"),
    };
    let base = crate::scratch("row-dry-run");
    // The README's workspace: gamma 23, six boxes, 2000 sequences in 32 slices.
    project(
        &base,
        &[(
            "g23",
            "32",
            &["gamma=23", "boxes=[5,6,7,8,10,12]", "sequences=2000"],
        )],
    );
    let out = row_in(
        row,
        &base,
        &["submit", "--dry-run", "--cluster", "anvil", "-n", "1"],
    );
    // The script calls row back by its absolute path; the committed one says `row`.
    let exe = row.canonicalize().unwrap();
    let script = String::from_utf8(out.stdout)
        .unwrap()
        .replace(exe.to_str().unwrap(), "row");
    let committed = std::fs::read_to_string(repo("examples/row/slurm-dry-run.sh")).unwrap();
    assert_eq!(script, committed);
    assert!(
        !base.join("workspace/g23-0/study.json").exists(),
        "a dry run runs nothing"
    );
    std::fs::remove_dir_all(&base).unwrap();
}

/// Writes `text` as `dir/value.json` in a new directory.
fn value(dir: &Path, file: &str, text: &str) -> String {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join(file), text).unwrap();
    dir.to_str().unwrap().to_string()
}

#[test]
fn workspace_slices_refuse_bad_values_and_read_signac_statepoints() {
    let base = crate::scratch("workspace-values");
    let study = r#""gamma": 10, "boxes": [3, 3.5, 4], "sequences": 40, "kind": "contact""#;
    for (text, needle) in [
        ("{", "value.json: not JSON"),
        (
            "[1, 2]",
            "value.json: expected a JSON object of the study's parameters",
        ),
        (
            &format!(r#"{{{study}, "kinds": "rigid"}}"#),
            r#"unknown key "kinds" (rgc reads gamma, boxes, sequences, kind,"#,
        ),
        (
            r#"{"boxes": [3, 3.5, 4], "sequences": 40}"#,
            "value.json: no gamma (at /gamma)",
        ),
        (
            r#"{"gamma": 10, "boxes": "3,3.5,4", "sequences": 40}"#,
            r#"/boxes (boxes): invalid type: string "3,3.5,4", expected a sequence"#,
        ),
        (
            r#"{"gamma": 10, "boxes": [3, 3.5, 4], "sequences": 40, "kind": "rigd"}"#,
            "/kind (kind): unknown variant `rigd`, expected one of `contact`, `rigid`, `truth`",
        ),
        (
            &format!(r#"{{{study}, "shard": "3/3"}}"#),
            r#"/shard: shard "3/3": expected i/n with 0 <= i < n"#,
        ),
        (
            &format!(r#"{{{study}, "shard": 1}}"#),
            "/shard (shard): invalid type: integer `1`, expected a string",
        ),
        (
            r#"{"gamma": 10, "boxes": [3, 4, 4], "sequences": 40}"#,
            "value.json: box sizes repeat: [3.0, 4.0, 4.0]",
        ),
    ] {
        let dir = value(&base.join("bad"), "value.json", text);
        fails(&["workspace", "slice", &dir], needle);
        assert!(!base.join("bad/study.json").exists(), "{text}");
    }
    fails(
        &["workspace", "slice", "--pointer", "gamma", "x"],
        r#"--pointer "gamma": expected NAME=/json/pointer"#,
    );
    fails(
        &["workspace", "slice", "--pointer", "gama=/g", "x"],
        r#"--pointer "gama=/g": no parameter "gama""#,
    );

    // A signac statepoint of its own layout, read through pointers.
    let signac = value(
        &base.join("signac"),
        "signac_statepoint.json",
        r#"{"aspect": 10, "geometry": {"L": [3, 3.5, 4]}, "n": 40, "kind": "contact"}"#,
    );
    let args = [
        "workspace",
        "slice",
        "--quiet",
        "--value-file",
        "signac_statepoint.json",
        "--pointer",
        "gamma=/aspect",
        "--pointer",
        "boxes=/geometry/L",
        "--pointer",
        "sequences=/n",
        &signac,
    ];
    let text = stdout_of(&args);
    assert!(
        text.contains("slice 0/1 of") && text.contains("120 sequences run in"),
        "{text}"
    );
    let done: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(base.join("signac/slice.json")).unwrap())
            .unwrap();
    assert_eq!(done["records"], "records.jsonl");
    assert_eq!(done["sequences"], 120);
    // A value changed after its slice was done is refused, not rerun.
    value(
        &base.join("signac"),
        "signac_statepoint.json",
        r#"{"aspect": 10, "geometry": {"L": [3, 3.5, 4]}, "n": 41, "kind": "contact"}"#,
    );
    fails(&args, "slice.json: made from another value");

    // Merge refuses a study with a slice missing, and two studies at once,
    // and marks no directory merged.
    let shard = |name: &str, s: &str, gamma: u32| {
        let text = format!(
            r#"{{"gamma": {gamma}, "boxes": [3, 3.5, 4], "sequences": 40, "kind": "contact", "shard": "{s}"}}"#
        );
        let dir = value(&base.join(name), "value.json", &text);
        stdout_of(&["workspace", "slice", "--quiet", &dir]);
    };
    shard("a0", "0/2", 10);
    shard("b0", "0/2", 11);
    shard("b1", "1/2", 11);
    let studies = base.join("studies");
    let merge = |dirs: &[&'static str]| {
        let mut args = vec![
            "workspace",
            "merge",
            "--workspace",
            base.to_str().unwrap(),
            "--studies",
            studies.to_str().unwrap(),
        ];
        args.extend(dirs);
        args
    };
    fails(
        &merge(&["a0"]),
        "60 sequence(s) missing from the shards (box 3 #1,",
    );
    fails(&merge(&["a0", "b0", "b1"]), "a different study from");
    assert!(!base.join("a0/merged.json").exists());
    stdout_of(&merge(&["b0", "b1"]));
    assert!(base.join("b1/merged.json").exists());
    std::fs::remove_dir_all(&base).unwrap();
}
