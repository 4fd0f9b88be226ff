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

mod rods {
    use rgc::plot::rods::{Groups, SIZE, View, rods_pixels};
    use rgc::rods::RodParams;
    use rgc::sample::{SampleOptions, sample};
    use rgc::spanning::Criterion;

    /// The README's example at a quarter of its rods: gamma 23, box 4, density 40.
    fn example() -> rgc::sample::Sample {
        sample(&SampleOptions {
            rods: RodParams::new(23.0, 4.0, 40.0).unwrap().into(),
            seed: 2,
            runs: 1,
            rules: rgc::engine::RuleSet::Sound,
            criterion: Criterion::Wrap,
            truth: false,
        })
        .unwrap()
    }

    #[test]
    fn a_rod_picture_shows_its_rods_and_highlights_one_body() {
        let s = example();
        let bodies = s.reported_bodies(Criterion::Wrap);
        let px = rods_pixels(&s.system, &Groups::bodies(&bodies), View::default()).unwrap();
        assert_eq!(px.len(), (SIZE.0 * SIZE.1 * 3) as usize);
        let pixels: Vec<&[u8]> = px.chunks(3).collect();
        let white = pixels.iter().filter(|p| p == &&[255, 255, 255]).count();
        let red = pixels.iter().filter(|p| p == &&[214, 39, 40]).count();
        // Not blank, not filled: rods cover some of the picture, and the
        // highlighted body's colour is there.
        let inked = pixels.len() - white;
        assert!(
            inked > pixels.len() / 20 && inked < pixels.len() * 9 / 10,
            "{inked} of {} pixels inked",
            pixels.len()
        );
        assert!(red > 1000, "{red} pixels of the highlighted body");
        // Without bodies nothing is red: the colour means the chosen body.
        let none = rgc::sample::ReportedBodies {
            bodies: vec![],
            ..bodies.clone()
        };
        let px = rods_pixels(&s.system, &Groups::bodies(&none), View::default()).unwrap();
        assert_eq!(px.chunks(3).filter(|p| p == &[214, 39, 40]).count(), 0);
        // A view that cannot be is refused.
        let bad = View {
            azimuth: 0.0,
            elevation: 120.0,
        };
        let err = rods_pixels(&s.system, &Groups::bodies(&bodies), bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("elevation within -90..90"), "{err}");
    }

    /// With its truth, the picture highlights the largest true rigid
    /// cluster: more red than the engine's largest body, since truth finds
    /// more rods rigid together.
    #[test]
    fn a_rod_picture_of_the_truth_highlights_the_true_rigid_cluster() {
        let s = example();
        let t = rgc::truth::of_system(
            &s.system,
            &s.contacts,
            &s.graph,
            Criterion::Wrap,
            rgc::truth::TruthOptions::seeded(2),
        );
        let body = s.reported_bodies(Criterion::Wrap);
        let largest_body = body.bodies.first().map_or(0, |b| b.rods.len());
        assert!(
            t.clusters[0].rods.len() > largest_body,
            "truth finds no more"
        );
        // Strong red, anti-aliased or not (a group this large is drawn one
        // pixel wide); the faded groups' pale colours stay out.
        let red = |g: &Groups| {
            let px = rods_pixels(&s.system, g, View::default()).unwrap();
            px.chunks(3)
                .filter(|p| p[0] >= 180 && p[1] <= 140 && p[2] <= 140)
                .count()
        };
        let (true_red, body_red) = (
            red(&Groups::true_clusters(&t, Criterion::Wrap)),
            red(&Groups::bodies(&body)),
        );
        assert!(
            true_red > body_red,
            "{true_red} red pixels against {body_red}"
        );
    }

    #[test]
    fn render_writes_a_png_and_an_svg_of_the_picture_size() {
        let dir = super::scratch("render");
        let prefix = dir.join("rods");
        let out = crate::cli::rgc(&[
            "render",
            "--gamma",
            "23",
            "--box",
            "4",
            "--density",
            "40",
            "--seed",
            "2",
            "--out",
            prefix.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let png = std::fs::read(dir.join("rods.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        // IHDR: width and height, big-endian, after the chunk length and type.
        let dim = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().unwrap());
        assert_eq!((dim(16), dim(20)), SIZE);
        let svg = std::fs::read_to_string(dir.join("rods.svg")).unwrap();
        assert!(svg.contains("spanning body") || svg.contains("largest body"));
        let s = example();
        let lines = svg.matches("<polyline").count() + svg.matches("<path").count();
        assert!(
            lines >= s.system.len(),
            "{lines} lines for {} rods",
            s.system.len()
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
