//! The forced-plane scan: the transition it measures, determinism across
//! thread counts, and the command's refusals.

use std::path::Path;
use std::process::{Command, Output};

use rgc::progress::Silent;
use rgc::rods;
use rgc::threshold::planes::{self, Crossing, GammaScan, ScanSpec};
use rgc::threshold::report::Summary;

const GAMMA: f64 = 23.0;
const BOX: f64 = 3.2;

fn scan_in(spec: &ScanSpec, threads: usize) -> GammaScan {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| planes::scan(spec, &Silent))
        .unwrap()
}

#[test]
fn forced_planes_are_small_at_c_2_and_force_the_system_flat_at_density_70() {
    let low = 2.0 / rods::excluded_volume(GAMMA);
    for seed in 1..=3 {
        let s = planes::measure(GAMMA, BOX, low, seed).unwrap();
        assert!(!s.unrealizable, "{s:?}");
        assert!(s.fraction < 0.1, "{s:?}");
        assert!(s.largest_heavy <= s.largest && s.largest_heavy <= s.heavy_rods);
        let high = planes::measure(GAMMA, BOX, 70.0, seed).unwrap();
        assert!(high.unrealizable, "{high:?}");
        assert!(high.fraction > 0.9, "{high:?}");
        // Where the periodic closure stopped is a lower bound of the class.
        assert!(high.stopped_at.unwrap() <= high.largest, "{high:?}");
    }
}

#[test]
fn the_scan_rises_through_the_transition_and_ignores_the_thread_count() {
    let spec = ScanSpec::from_contact_numbers(GAMMA, BOX, &[2.0, 3.0, 5.0, 5.5], 3);
    let one = scan_in(&spec, 1);
    let two = scan_in(&spec, 2);
    assert_eq!(one.systems, two.systems);
    assert_eq!(one.points, two.points);
    assert_eq!(one.systems.len(), 12);
    let f: Vec<f64> = one.points.iter().map(|p| p.mean_fraction).collect();
    assert!(f[0] < 0.1 && f[3] > 0.9, "{f:?}");
    assert!(f[0] <= f[2] && f[1] <= f[3], "{f:?}");
    assert_eq!(one.points[3].unrealizable_share, 1.0);
    // Both transitions lie between c = 3 and c = 5.
    for c in [one.percolation, one.flat] {
        let Crossing::Within { contact_number, .. } = c else {
            panic!("{c:?}")
        };
        assert!(contact_number > 3.0 && contact_number <= 5.0, "{c:?}");
    }
}

fn rgc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn planes_in(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "planes",
        "--gamma",
        "23",
        "--box",
        "3.2",
        "--contact-numbers",
        "2,5",
        "--results",
        dir.to_str().unwrap(),
        "--thresholds",
        dir.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    rgc(&args)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn the_command_writes_its_files_and_refuses_to_replace_another_scan() {
    let dir = crate::scratch("planes-cli");
    // A committed rigidity threshold to mark, read as the summary it is.
    let study = dir.join("g23-rigid-sound");
    std::fs::create_dir_all(&study).unwrap();
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/g23-rigid-sound");
    std::fs::copy(committed.join("summary.json"), study.join("summary.json")).unwrap();
    let summary: Summary =
        serde_json::from_str(&std::fs::read_to_string(study.join("summary.json")).unwrap())
            .unwrap();
    let out = planes_in(&dir, &["--seeds", "2", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["command"].as_str().unwrap().starts_with("rgc planes"));
    assert_eq!(v["parameters"]["seeds"], 2);
    let scan = &v["scans"][0];
    assert_eq!(
        scan["references"]["rigidity"]["density"],
        summary.fss.threshold.value
    );
    assert!(scan["references"]["contact"].is_null());
    assert_eq!(scan["systems"].as_array().unwrap().len(), 4);
    for ext in ["json", "csv", "svg", "png"] {
        assert!(dir.join(format!("forced-planes.{ext}")).is_file(), "{ext}");
    }
    let csv = std::fs::read_to_string(dir.join("forced-planes.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(
        csv.starts_with("gamma,box,density,contact_number,"),
        "{csv}"
    );
    let json = std::fs::read_to_string(dir.join("forced-planes.json")).unwrap();

    // Other parameters: refused, nothing replaced.
    let out = planes_in(&dir, &["--seeds", "3"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        format!(
            "rgc: error: invalid parameter: {} holds the results of another scan \
             (parameters.seeds 2 vs 3); choose another --results, or --force to replace them\n",
            dir.join("forced-planes.json").display()
        )
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("forced-planes.json")).unwrap(),
        json
    );
    // The same parameters may rerun; --force replaces.
    assert!(planes_in(&dir, &["--seeds", "2"]).status.success());
    let out = planes_in(&dir, &["--seeds", "3", "--force"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("forced-planes.json")).unwrap())
            .unwrap();
    assert_eq!(v["parameters"]["seeds"], 3);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_parameters_fail_before_any_work() {
    let dir = crate::scratch("planes-bad");
    for (extra, needle) in [
        (&["--gamma", "0.5"][..], "gamma must be at least 1"),
        (&["--box", "2"][..], "box 2 is too small"),
        (&["--box", "3.2,4"][..], "2 boxes for 3 aspect ratios"),
        (&["--seeds", "0"][..], "at least one seed"),
        (&["--contact-numbers", "3,2"][..], "densities must increase"),
    ] {
        let mut args = vec!["planes", "--results", dir.to_str().unwrap(), "--quiet"];
        args.extend_from_slice(extra);
        let out = rgc(&args);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        let err = stderr(&out);
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!dir.join("forced-planes.json").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// A committed threshold is read as a whole study summary: a file that
/// only looks like one is refused, naming what it lacks, before any work.
#[test]
fn a_summary_that_is_not_a_study_summary_is_refused() {
    let dir = crate::scratch("planes-summary");
    let study = dir.join("g23-rigid-sound");
    std::fs::create_dir_all(&study).unwrap();
    std::fs::write(study.join("summary.json"), r#"{"threshold": 39.3}"#).unwrap();
    let err = planes::references(&dir, 23.0).unwrap_err().to_string();
    assert_eq!(
        err,
        format!(
            "study {}: not a study summary: missing field `study` at line 1 column 19",
            study.join("summary.json").display()
        )
    );
    let out = planes_in(&dir, &[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("not a study summary"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.join("forced-planes.json").exists());
    std::fs::remove_dir_all(dir).unwrap();
}
