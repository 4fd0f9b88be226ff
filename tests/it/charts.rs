//! The charts of variants against each other: both files of each chart are
//! written and carry the title and every variant's label, and no variants
//! is an error rather than a panic.

use std::path::{Path, PathBuf};

use rgc::Error;
use rgc::engine::RuleSet;
use rgc::plot::{compare_chart, speed_accuracy_chart};
use rgc::threshold::fss::{Estimate, Protocol};
use rgc::threshold::variants::VariantOutcome;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rgc-charts-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn estimate(value: f64, half: f64) -> Estimate {
    Estimate {
        value,
        lo: Some(value - half),
        hi: Some(value + half),
    }
}

/// Ten variants in four families, spread like a real trade-off: more CPU
/// time, narrower intervals.
fn outcomes() -> Vec<VariantOutcome> {
    let rows: [(&str, &str, f64, f64, f64, f64); 10] = [
        ("runs", "1 run", 0.812, 0.020, 1.72, 40.0),
        ("runs", "2 runs", 0.806, 0.018, 1.70, 75.0),
        ("runs", "4 runs", 0.803, 0.017, 1.69, 150.0),
        ("runs", "8 runs", 0.802, 0.017, 1.69, 290.0),
        ("motifs", "base", 0.815, 0.019, 1.74, 35.0),
        ("motifs", "+ motifs", 0.797, 0.018, 1.66, 60.0),
        // `realizations`: the stored family name of the sequence-count variants.
        ("realizations", "100/box", 0.808, 0.040, 1.80, 20.0),
        ("realizations", "400/box", 0.804, 0.009, 1.71, 160.0),
        ("method", "fixed", 0.810, 0.060, 1.62, 500.0),
        ("method", "nested", 0.803, 0.017, 1.70, 150.0),
    ];
    let first = rows[0].2;
    rows.iter()
        .map(|&(family, label, t, half, nu, cpu)| VariantOutcome {
            label: label.into(),
            family: family.into(),
            rules: RuleSet::Sound,
            motif_rules: 0,
            runs: 1,
            method: Protocol::Nested,
            sequences: 100,
            threshold: estimate(t, half),
            interval_width: Some(2.0 * half),
            nu: estimate(nu, 0.1),
            relative_difference: (t - first) / first,
            paired_difference: None,
            paired_with: None,
            threshold_difference: Some(estimate(t - first, half)),
            cpu_seconds: cpu,
            single_run_miss_rate: None,
            fresh_misses: 0,
            fresh_checks: 0,
            study: String::new(),
        })
        .collect()
}

fn assert_written(svg: &Path, png: &Path, title: &str, labels: &[VariantOutcome]) {
    let text = std::fs::read_to_string(svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains(title));
    for o in labels {
        assert!(
            text.contains(&o.label),
            "{} lacks {:?}",
            svg.display(),
            o.label
        );
    }
    let bytes = std::fs::read(png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 10_000);
}

#[test]
fn both_charts_are_written_with_title_and_labels() {
    let dir = scratch("written");
    let all = outcomes();
    // Six variants: as many as the comparison is meant to show.
    let some = &all[..6];
    let (svg, png) = (dir.join("compare.svg"), dir.join("compare.png"));
    compare_chart(some, "Rods-8 variants", &svg, &png).unwrap();
    assert_written(&svg, &png, "Rods-8 variants", some);
    let (svg, png) = (dir.join("tradeoff.svg"), dir.join("tradeoff.png"));
    speed_accuracy_chart(&all, "Rods-8 trade-off", &svg, &png).unwrap();
    assert_written(&svg, &png, "Rods-8 trade-off", &all);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn no_variants_is_an_error() {
    let dir = scratch("empty");
    let (svg, png) = (dir.join("c.svg"), dir.join("c.png"));
    for chart in [compare_chart, speed_accuracy_chart] {
        match chart(&[], "nothing", &svg, &png) {
            Err(Error::Analysis(m)) => assert!(m.contains("no variants"), "{m}"),
            other => panic!("expected an analysis error, got {other:?}"),
        }
    }
    assert!(!svg.exists() && !png.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cpu_time_that_cannot_go_on_a_log_axis_is_an_error() {
    let dir = scratch("cpu");
    let mut some = outcomes();
    some[3].cpu_seconds = 0.0;
    let (svg, png) = (dir.join("t.svg"), dir.join("t.png"));
    match speed_accuracy_chart(&some, "zero", &svg, &png) {
        Err(Error::Analysis(m)) => assert!(m.contains("8 runs"), "{m}"),
        other => panic!("expected an analysis error, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_single_variant_without_intervals_still_charts() {
    let dir = scratch("bare");
    let mut one = outcomes();
    one.truncate(1);
    one[0].threshold.lo = None;
    one[0].threshold.hi = None;
    one[0].nu.lo = None;
    one[0].nu.hi = None;
    one[0].interval_width = None;
    for (name, chart) in [
        (
            "c",
            compare_chart as fn(&[VariantOutcome], &str, &Path, &Path) -> rgc::Result<()>,
        ),
        ("t", speed_accuracy_chart),
    ] {
        let (svg, png) = (
            dir.join(format!("{name}.svg")),
            dir.join(format!("{name}.png")),
        );
        chart(&one, "one variant", &svg, &png).unwrap();
        assert_written(&svg, &png, "one variant", &one);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
