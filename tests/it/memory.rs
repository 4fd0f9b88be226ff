//! The memory limit is a limit (issue 31): every large step is checked
//! against what the process holds now and what the step adds, so a refused
//! run ends with one line naming both, exit code 2, and a peak within 5% or
//! 20 MB of the limit; sizes read from input are checked before they are
//! allocated; an address-space limit (`ulimit -v`) ends in the same refusal,
//! never in an allocation abort (SIGABRT, exit 134).

use std::process::{Command, Output};

use rgc::bench::{LimitRow, TruthSystem, within_limit};
use serde_json::Value;

const RGC: &str = env!("CARGO_BIN_EXE_rgc");

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `rgc args` under `ulimit -v kib` (none: no such limit).
fn rgc_under(kib: Option<u64>, args: &[&str]) -> Output {
    let limit = kib.map_or(String::new(), |k| format!("ulimit -v {k} && "));
    Command::new("sh")
        .args(["-c", &format!("{limit}exec \"$0\" \"$@\""), RGC])
        .args(args)
        .output()
        .expect("sh runs")
}

/// Checks a refusal: exit code 2 (not an abort), one line, nothing on
/// stdout, holding every one of `needles`; returns the line.
fn refused(out: &Output, needles: &[&str]) -> String {
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(out.stdout.is_empty(), "{}", text(&out.stdout));
    for needle in needles {
        assert!(err.contains(needle), "{err:?} lacks {needle:?}");
    }
    err
}

/// Bytes of a size as `usage::size` writes it (`6.02 MiB`).
fn bytes(size: &str) -> f64 {
    let (number, unit) = size.trim().split_once(' ').expect("number and unit");
    let scale = match unit {
        "B" => 1u64,
        "KiB" => 1 << 10,
        "MiB" => 1 << 20,
        "GiB" => 1 << 30,
        other => panic!("unit {other}"),
    };
    number.parse::<f64>().unwrap() * scale as f64
}

/// The size after `before` in `line`, up to the next comma.
fn size_after(line: &str, before: &str) -> f64 {
    let rest = &line[line.find(before).expect(before) + before.len()..];
    bytes(rest.split(',').next().unwrap())
}

#[test]
fn truth_over_its_limit_names_what_it_holds_and_what_the_front_needs() {
    // The issue's command on a smaller system: gamma 48, L 5 peaks near
    // 33 MiB; under 32 MiB a dense front is refused, and the held size
    // and the front's need pass the limit together.
    let args = [
        "truth",
        "--gamma",
        "48",
        "--box",
        "5",
        "--density",
        "78",
        "--seed",
        "1",
        "--memory-limit",
        "32M",
    ];
    let err = refused(
        &rgc_under(None, &args),
        &[
            "rgc: error: over the memory limit: truth refused this system: the dense front of ",
            " of its elimination needs about ",
            ", the process holds ",
            ", over the limit of 32.0 MiB (--memory-limit)",
        ],
    );
    let need = size_after(&err, "needs about ");
    let held = size_after(&err, "the process holds ");
    assert!(need > 0.0 && held + need > 32.0 * 1024.0 * 1024.0, "{err}");
    assert!(held <= 32.0 * 1024.0 * 1024.0, "{err}");
}

/// The system of the moduli's memory tests: gamma 23, L 3, density 45.
const MODULI_SYSTEM: [&str; 8] = [
    "--gamma",
    "23",
    "--box",
    "3",
    "--density",
    "45",
    "--seed",
    "1",
];

#[test]
fn moduli_over_their_limit_refuse_the_projection_or_the_factor_before_they_start() {
    // gamma 23, L 3: truth and the projection fit in 60 MiB, the sparse
    // QR of the springs (sized by faer's symbolic step) does not; at
    // gamma 98, L 5 an unguarded factor of 9 GiB was killed by the kernel.
    let mut args = vec!["moduli", "--solver", "qr"];
    args.extend_from_slice(&MODULI_SYSTEM);
    args.extend_from_slice(&["--memory-limit", "60M"]);
    let err = refused(
        &rgc_under(None, &args),
        &[
            "rgc: error: over the memory limit: the sparse QR of the 13577 x 6330 spring matrix needs about ",
            ", over the limit of 60.0 MiB (--memory-limit)",
        ],
    );
    let need = size_after(&err, "needs about ");
    let held = size_after(&err, "the process holds ");
    assert!(held + need > 60.0 * 1024.0 * 1024.0, "{err}");
    assert!(held <= 60.0 * 1024.0 * 1024.0, "{err}");
    // Under 32 MiB the projection that gives the springs their
    // realization is refused before it starts (it peaks near 41 MiB).
    args[12] = "32M";
    let err = refused(
        &rgc_under(None, &args),
        &[
            "rgc: error: over the memory limit: the projection of the 1055 core rods onto their line model needs about ",
            ", over the limit of 32.0 MiB (--memory-limit)",
        ],
    );
    let need = size_after(&err, "needs about ");
    assert!(need > 16.0 * 1024.0 * 1024.0, "{err}");
}

#[test]
fn moduli_whose_qr_is_over_the_limit_are_relaxed_by_lsmr_within_it() {
    // The system above: under 60 MiB the QR is refused, and by default the
    // relaxation falls back to LSMR, whose preconditioner (the Cholesky
    // factor of the normal equations) fits; its moduli are the QR's.
    let run = |extra: &[&str]| -> Value {
        let mut args = vec!["moduli", "--json"];
        args.extend_from_slice(&MODULI_SYSTEM);
        args.extend_from_slice(extra);
        let out = rgc_under(None, &args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        serde_json::from_slice(&out.stdout).expect("one JSON object")
    };
    let lsmr = run(&["--memory-limit", "60M"]);
    let qr = run(&["--solver", "qr"]);
    assert_eq!(lsmr["conditioning"]["solver"], "lsmr");
    assert_eq!(qr["conditioning"]["solver"], "qr");
    assert_eq!(lsmr["conditioning"]["settled"], true);
    for key in ["shear", "bulk", "born_shear"] {
        let (a, b) = (lsmr[key].as_f64().unwrap(), qr[key].as_f64().unwrap());
        assert!(
            (a / b - 1.0).abs() < 1e-8,
            "{key}: {a} by LSMR, {b} by the QR"
        );
    }
}

#[test]
fn the_peak_stays_within_the_limit_whether_refused_or_finished() {
    // The same work as `rgc truth --memory-limit`, in a child process whose
    // peak resident size (VmHWM) it reports: refused at the rods, refused
    // at a front, and finished, each within 5% or 20 MB of its limit.
    let system: TruthSystem = "48,78,5,1".parse().unwrap();
    let exe = std::path::Path::new(RGC);
    let mib = 1u64 << 20;
    let rows: Vec<LimitRow> = [8 * mib, 32 * mib, 200 * mib]
        .into_iter()
        .map(|limit| system.under_limit_in_child(exe, limit).unwrap())
        .collect();
    for r in &rows {
        assert!(r.within, "{r:?}");
        assert!(
            within_limit(
                (r.peak_mib * mib as f64) as u64,
                (r.limit_mib * mib as f64) as u64
            ),
            "{r:?}"
        );
    }
    let reason = |r: &LimitRow| r.refused.clone().unwrap_or_default();
    assert!(
        reason(&rows[0]).contains("the system of 9750 rods (about 1.349e4 contacts) needs about"),
        "{:?}",
        rows[0]
    );
    assert!(
        reason(&rows[1]).starts_with("the dense front of "),
        "{:?}",
        rows[1]
    );
    assert_eq!(rows[2].refused, None, "{:?}", rows[2]);
    assert!(rows[2].peak_mib > 20.0, "{:?}", rows[2]);
    // The rule itself: 5% or 20 MB over, the larger.
    assert!(within_limit(1_050_000_000, 1_000_000_000));
    assert!(!within_limit(1_050_000_001, 1_000_000_000));
    assert!(within_limit(120_000_000, 100_000_000));
    assert!(!within_limit(120_000_001, 100_000_000));
}

#[test]
fn an_edge_list_naming_a_huge_node_is_refused_before_anything_is_allocated() {
    // 50 million rods declared by three edges: truth would hold about 7
    // GB, the compression 3.4 GB. Under a 400 MB address space nothing
    // of that size may be allocated: the refusal comes first, exit 2.
    let dir = crate::scratch("memory-huge-node");
    let path = dir.join("huge.txt");
    std::fs::write(&path, "# nodes 49999999\n0 1\n1 2\n0 2\n").unwrap();
    let edges = path.to_str().unwrap();
    let ulimit = Some(400_000);
    refused(
        &rgc_under(ulimit, &["truth", "--edges", edges, "--memory-limit", "1G"]),
        &[
            "over the memory limit: truth on 49999999 rods and 3 contacts needs about ",
            "over the limit of 1.00 GiB (--memory-limit)",
        ],
    );
    refused(
        &rgc_under(
            ulimit,
            &["compress", "--edges", edges, "--memory-limit", "1G"],
        ),
        &[
            "over the memory limit: 1 compression(s) of 49999999 rods and 3 contacts needs about ",
            "over the limit of 1.00 GiB (--memory-limit)",
        ],
    );
    for cmd in ["truth", "compress"] {
        refused(
            &rgc_under(ulimit, &[cmd, "--edges", edges]),
            &["of address space, the process holds ", "(ulimit -v)"],
        );
    }
    // The same three edges among 5000 rods run under the same limits.
    std::fs::write(&path, "# nodes 5000\n0 1\n1 2\n0 2\n").unwrap();
    for cmd in ["truth", "compress"] {
        let out = rgc_under(ulimit, &[cmd, "--edges", edges, "--memory-limit", "1G"]);
        assert!(out.status.success(), "{cmd}: {}", text(&out.stderr));
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn an_address_space_limit_refuses_truth_instead_of_aborting() {
    // gamma 23, L 8 needs about 60 MB resident, but faer's matrix products
    // reserve twice the last-level cache of address space on their first
    // use: it used to abort there ("memory allocation of N bytes failed").
    // Under 300 MB the realization is refused, with or without a resident
    // limit; under 600 MB, where that reservation does not fit (here 960
    // MiB), the first front that multiplies matrices.
    let args = ["truth", "--gamma", "23", "--box", "8", "--density", "40"];
    let needles = [
        "rgc: error: over the memory limit: truth refused this system: ",
        " of address space, the process holds ",
        "(ulimit -v)",
    ];
    for limit in [None, Some("100M")] {
        let mut all = args.to_vec();
        all.extend(limit.map(|l| ["--memory-limit", l]).into_iter().flatten());
        refused(&rgc_under(Some(300_000), &all), &needles);
    }
    // `sample --truth` takes the same refusal, not a report of it.
    let sample = [
        "sample",
        "--gamma",
        "23",
        "--box",
        "8",
        "--density",
        "40",
        "--truth",
    ];
    for args in [&args[..], &sample[..]] {
        let out = rgc_under(Some(600_000), args);
        if rgc::usage::product_scratch() > 600_000 * 1024 {
            let err = refused(&out, &needles);
            assert!(err.contains("the dense front of "), "{err}");
        } else {
            assert!(out.status.code() == Some(0), "{}", text(&out.stderr));
        }
    }
}

#[test]
fn every_study_refuses_a_step_over_its_limit() {
    // The process alone holds more than 8 MiB, so the first step of each
    // study is refused: a compression for `threshold` and `compare`,
    // truth (the first variant) for `bias`, truth of the first side for
    // `stiffening`; no record is kept.
    let dir = crate::scratch("studies-under-a-limit");
    let study = ["--gamma", "23", "--boxes", "3,4,5", "--sequences", "5"];
    let limit = ["--memory-limit", "8M", "--quiet"];
    let out = |sub: &str| dir.join(sub).to_string_lossy().into_owned();
    let th = out("th");
    let mut threshold = vec!["threshold", "--out", &th];
    threshold.extend(study.iter().chain(&limit));
    let line = refused(
        &rgc_under(None, &threshold),
        &[
            "1 compression(s) of ",
            "over the limit of 8.00 MiB (--memory-limit)",
        ],
    );
    assert!(
        line.starts_with("rgc: error: over the memory limit: "),
        "{line}"
    );
    let records = std::fs::read_to_string(dir.join("th/records.jsonl")).unwrap_or_default();
    assert!(records.is_empty(), "{records}");
    let (s, r) = (out("s"), out("r"));
    for (sub, needle) in [
        ("bias", "truth of the first "),
        ("compare", "1 compression(s) of "),
    ] {
        let mut args = vec![sub, "--studies", &s, "--results", &r];
        args.extend(study.iter().chain(&limit));
        refused(&rgc_under(None, &args), &[needle, "(--memory-limit)"]);
    }
    // The stiffening of a committed truth study: truth of its first side.
    let st = out("st");
    let mut stiffening = vec!["stiffening", "results/g23-truth", "--out", &st];
    stiffening.extend(["--boxes", "5", "--sequences", "1"].iter().chain(&limit));
    refused(
        &rgc_under(None, &stiffening),
        &["truth refused this system: ", "(--memory-limit)"],
    );
    let lines = std::fs::read_to_string(dir.join("st/stiffening.jsonl")).unwrap_or_default();
    assert!(lines.is_empty(), "{lines}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A system too large for the memory it may use is refused before any rod
/// is drawn, on one line naming the estimate and the budget: a limit given
/// with `--memory-limit` (`sample`, `render`, `truth`), or an address-space
/// limit (`ulimit -v`), under which it used to abort with "memory
/// allocation failed".
#[test]
fn a_system_too_large_for_memory_is_refused_up_front() {
    let dir = crate::scratch("memory-estimate");
    let big = ["--gamma", "23", "--box", "60", "--density", "40"];
    let png = dir.join("big");
    for (cmd, more) in [
        ("sample", vec![]),
        ("render", vec!["--out", png.to_str().unwrap()]),
        ("truth", vec![]),
    ] {
        let args = [&[cmd][..], &big, &more, &["--memory-limit", "100M"]].concat();
        refused(
            &rgc_under(None, &args),
            &[
                "rgc: error: over the memory limit: the system of 8640000 rods (about 1.391e7 \
                 contacts) needs about 5.81 GiB, the process holds ",
                ", over the limit of 100 MiB (--memory-limit); take a smaller box or density",
            ],
        );
    }
    assert!(!dir.join("big.png").exists());
    // The same box at a density that fits runs under the same limit.
    crate::cli::succeeds(&[
        "sample",
        "--gamma",
        "23",
        "--box",
        "6",
        "--density",
        "40",
        "--memory-limit",
        "100M",
    ]);

    refused(
        &rgc_under(Some(400_000), &[&["sample"][..], &big].concat()),
        &[
            " of address space, the process holds ",
            ", over its address-space limit of 391 MiB (ulimit -v)",
        ],
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The check counts what the process holds: a limit below it refuses even
/// the smallest estimate, one with room for the estimate passes; the
/// estimate grows with rods, contacts and thickness.
#[test]
fn the_memory_check_compares_the_estimate_and_the_process_with_the_limit() {
    use rgc::rods::RodParams;
    use rgc::sample::{Rods, memory_estimate};

    let rods = Rods::from(RodParams::new(23.0, 5.0, 40.0).unwrap());
    let e = rods.memory_estimate();
    assert_eq!(e.rods, 5000);
    // Philipse: rho V_ex (N - 1) / N contacts per rod, halved.
    let expected = 0.5 * 5000.0 * RodParams::new(23.0, 5.0, 40.0).unwrap().expected_c0();
    assert!(
        (e.contacts - expected).abs() < 1e-6 * expected,
        "{}",
        e.contacts
    );
    let held = rgc::usage::held().map_or(0, |h| h.resident);
    assert!(
        rods.check_memory(Some(held + e.bytes + (256 << 20)))
            .is_ok()
    );
    assert!(rods.check_memory(None).is_ok());
    let err = rods.check_memory(Some(e.bytes)).unwrap_err().to_string();
    assert!(
        err.starts_with("over the memory limit: the system of 5000 rods"),
        "{err}"
    );
    assert!(memory_estimate(2000, 0.0, 0.0) > memory_estimate(1000, 0.0, 0.0));
    assert!(memory_estimate(1000, 10.0, 0.0) > memory_estimate(1000, 0.0, 0.0));
    assert!(memory_estimate(1000, 0.0, 0.1) > memory_estimate(1000, 0.0, 0.0));
}
