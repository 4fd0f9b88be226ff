//! `rgc horizon` on the committed studies: the paired bias of each motif
//! set against truth, its rules and largest motif, and the refusals.

use crate::cli::{fails, rgc};
use rgc::threshold::horizon::{self, BASE_RODS};

#[test]
fn the_committed_variants_are_measured_against_their_truth_study() {
    let variants = horizon::measure(
        &["results/g23-truth".into(), "results/g48-truth".into()],
        &[
            "results/g23-rigid-sound".into(),
            "results/g23-rigid-sound-extended".into(),
            "results/g48-rigid-sound".into(),
        ],
    )
    .unwrap();
    let [base, extended, g48]: [_; 3] = variants.try_into().unwrap();
    // As `results/truth-bias.md` has it: +6.01 over 997 sequences, 18.0%.
    assert_eq!(
        (base.label.as_str(), base.rules, base.bias.sequences),
        ("base", 0, 997)
    );
    assert!(
        (base.bias.mean.value - 6.01).abs() < 0.005,
        "{:?}",
        base.bias
    );
    assert!((base.bias.relative.value - 0.180).abs() < 0.001);
    assert_eq!((base.largest_rods, base.rods_only), (BASE_RODS, true));
    assert_eq!(extended.label, "rods-6+rods-8+mixed-4");
    assert_eq!((extended.rules, extended.largest_rods), (138, 8));
    assert!(!extended.rods_only);
    assert!(extended.bias.mean.value < base.bias.mean.value);
    assert_eq!((g48.gamma, g48.bias.sequences), (48.0, 400));
    assert!(base.truth_cpu_per_sequence > base.cpu_per_sequence);
}

#[test]
fn the_command_writes_its_tables_and_charts_and_refuses_unmatched_studies() {
    let dir = crate::scratch("horizon");
    let prefix = dir.join("h").display().to_string();
    let o = rgc(&[
        "horizon",
        "--truth",
        "results/g23-truth",
        "--variants",
        "results/g23-rigid-sound,results/g23-rigid-sound-extended",
        "--out",
        &prefix,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for ext in ["json", "csv", "svg", "png"] {
        assert!(dir.join(format!("h.{ext}")).exists(), "{ext}");
    }
    let csv = std::fs::read_to_string(dir.join("h.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    fails(
        &[
            "horizon",
            "--truth",
            "results/g23-truth",
            "--variants",
            "results/g48-rigid-sound",
            "--out",
            &prefix,
        ],
        "no truth study of gamma 48 and seed 1 was given",
    );
    fails(
        &[
            "horizon",
            "--truth",
            "results/g23-rigid-sound",
            "--variants",
            "results/g23-rigid-sound",
            "--out",
            &prefix,
        ],
        "is a Rigid study, not a truth study",
    );
    std::fs::remove_dir_all(&dir).ok();
}
