//! The stamp every results file starts with: the fields the check names,
//! its refusal and `--force`, the round trip, and the committed results
//! read into their types and written back byte for byte.

use std::path::{Path, PathBuf};

use rgc::mine;
use rgc::stamp::{self, Nothing, Parameters, Stamp};
use rgc::threshold::bias;
use rgc::threshold::experiment::{BiasReport, Experiment, MadeBy, MonotoneReport, VariantKey};
use rgc::threshold::planes::{self, Report};
use rgc::threshold::report::Summary;

fn committed(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("results")
        .join(name)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

/// A scan's stamp: gammas 23 (and 48), box 5 (and 6).
fn scan(seeds: u64, gammas: &[f64]) -> Stamp<planes::Made> {
    let params = planes::Parameters::new(gammas.to_vec(), &[5.0], seeds, vec![2.0, 3.0]).unwrap();
    planes::stamp("rgc planes", &params)
}

#[test]
fn differences_name_every_field_that_differs_in_path_order() {
    let (a, b) = (scan(4, &[23.0]), scan(2, &[23.0, 48.0]));
    assert_eq!(
        stamp::differences(&a.made, &b.made),
        [
            "parameters.boxes [5.0] vs [5.0,5.0]",
            "parameters.gammas [23.0] vs [23.0,48.0]",
            "parameters.seeds 4 vs 2",
        ]
    );
    assert!(stamp::differences(&a, &a).is_empty());
    // The command is a field like any other here; the check leaves it out.
    let other = Stamp::new(None, "rgc planes --quiet", a.made.clone());
    assert_eq!(
        stamp::differences(&a, &other),
        [
            "command rgc planes vs rgc planes --quiet",
            "format rgc-forced-planes/1 vs none"
        ]
    );
    // Lists of objects: element by element, or their lengths.
    let key = |label: &str, runs| VariantKey {
        label: label.into(),
        rules: rgc::engine::RuleSet::Sound,
        runs,
        method: rgc::threshold::fss::Protocol::Nested,
        sequences: 100,
    };
    let spec = rgc::threshold::study::StudySpec::new(
        23.0,
        vec![4.0, 5.0],
        100,
        rgc::spanning::Criterion::Wrap,
        1,
    );
    let made = |gamma: f64, variants: Vec<VariantKey>| Experiment {
        template: rgc::threshold::study::StudySpec {
            gamma,
            ..spec.clone()
        },
        variants,
    };
    let first = made(23.0, vec![key("K=1", 1), key("K=10", 10)]);
    assert_eq!(
        stamp::differences(&first, &made(48.0, vec![key("K=1", 1), key("K=10", 40)])),
        ["template.gamma 23.0 vs 48.0", "variants[1].runs 10 vs 40"]
    );
    assert_eq!(
        stamp::differences(&first, &made(23.0, vec![key("K=1", 1)])),
        ["variants 2 vs 1 entries"]
    );
}

#[test]
fn the_check_refuses_a_file_made_otherwise_unless_forced() {
    let dir = crate::scratch("stamp-check");
    let path = dir.join("forced-planes.json");
    let made = scan(4, &[23.0]);
    // No file: nothing to lose.
    made.check_replace(&path, "scan", false).unwrap();
    std::fs::write(&path, stamp::json(&made)).unwrap();
    // The same parameters under another command line may replace it.
    Stamp::new(
        made.format.as_deref(),
        "rgc planes --quiet",
        made.made.clone(),
    )
    .check_replace(&path, "scan", false)
    .unwrap();
    let other = scan(2, &[23.0, 48.0]);
    let err = other.check_replace(&path, "scan", false).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "invalid parameter: {} holds the results of another scan (parameters.boxes [5.0] vs \
             [5.0,5.0], parameters.gammas [23.0] vs [23.0,48.0], parameters.seeds 4 vs 2); \
             choose another --results, or --force to replace them",
            path.display()
        )
    );
    other.check_replace(&path, "scan", true).unwrap();
    // Another format is another way of making it.
    let newer = Stamp::new(Some("rgc-forced-planes/2"), "rgc planes", made.made.clone());
    let err = newer.check_replace(&path, "scan", false).unwrap_err();
    assert!(
        err.to_string()
            .contains("(format rgc-forced-planes/1 vs rgc-forced-planes/2)"),
        "{err}"
    );
    // A file that is not this kind's is refused, naming why, unless forced.
    std::fs::write(&path, "{\"command\": \"rgc compare\", \"template\": {}}\n").unwrap();
    let err = made.check_replace(&path, "scan", false).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "invalid parameter: {} does not hold scan results (missing field `parameters` \
             at line 1 column 42); choose another --results, or --force to replace them",
            path.display()
        )
    );
    made.check_replace(&path, "scan", true).unwrap();
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_stamp_round_trips_and_leads_its_file() {
    let made = scan(4, &[23.0, 48.0]);
    let text = stamp::json(&made);
    assert!(
        text.starts_with(
            "{\n  \"format\": \"rgc-forced-planes/1\",\n  \"command\": \"rgc planes\",\n  \"parameters\": {"
        ),
        "{text}"
    );
    assert_eq!(
        serde_json::from_str::<Stamp<planes::Made>>(&text).unwrap(),
        made
    );
    // Without a format there is no key for it, and none comes back.
    let bare = Stamp::new(None, "rgc bias", Nothing {});
    let text = stamp::json_sorted(&bare);
    assert_eq!(text, "{\n  \"command\": \"rgc bias\"\n}\n");
    assert_eq!(serde_json::from_str::<Stamp<Nothing>>(&text).unwrap(), bare);
    let wrapped: Stamp<Parameters<u64>> =
        serde_json::from_str(r#"{"command": "c", "parameters": 7, "rest": [1]}"#).unwrap();
    assert_eq!(wrapped.made.parameters, 7);
    assert_eq!(wrapped.format, None);
}

/// Every kind of committed results file that carries a stamp, read into its
/// type, is written again byte for byte; so is every study summary.
#[test]
fn committed_results_read_into_their_types_and_write_back_unchanged() {
    let text = read(&committed("mined-motifs.json"));
    let mined: mine::Report = serde_json::from_str(&text).unwrap();
    assert_eq!(mined.stamp.format.as_deref(), Some(mine::FORMAT));
    assert_eq!(stamp::json(&mined), text);

    let text = read(&committed("forced-planes.json"));
    let planes: Report = serde_json::from_str(&text).unwrap();
    assert_eq!(planes.stamp.made.parameters.seeds, 4);
    assert_eq!(stamp::json(&planes), text);

    for name in ["compare-base-extended.json", "speed-accuracy.json"] {
        let text = read(&committed(name));
        let experiment: Stamp<Experiment> = serde_json::from_str(&text).unwrap();
        assert!(!experiment.made.variants.is_empty(), "{name}");
        assert_eq!(stamp::json_sorted(&experiment), text, "{name}");
    }

    // The gamma 23 bias, and those of gamma 48 and 98 in their folders.
    for dir in ["", "g48-bias/", "g98-bias/"] {
        let text = read(&committed(&format!("{dir}truth-vs-rgc.json")));
        let bias: BiasReport = serde_json::from_str(&text).unwrap();
        assert!(bias.monotonicity.is_some(), "{dir}");
        assert_eq!(bias.variants.len(), bias.stamp.made.made_by.design.len());
        assert_eq!(stamp::json_sorted(&bias), text, "{dir}");

        let text = read(&committed(&format!("{dir}truth-monotone.json")));
        let monotone: MonotoneReport = serde_json::from_str(&text).unwrap();
        assert!(!monotone.scans.is_empty(), "{dir}");
        assert_eq!(stamp::json_sorted(&monotone), text, "{dir}");
    }

    let mut summaries = 0;
    for entry in std::fs::read_dir(committed("")).unwrap() {
        let path = entry.unwrap().path().join("summary.json");
        if path.is_file() {
            let text = read(&path);
            let summary: Summary =
                serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert_eq!(
                serde_json::to_string_pretty(&summary).unwrap() + "\n",
                text,
                "{}",
                path.display()
            );
            summaries += 1;
        }
    }
    assert_eq!(summaries, 16);
}

/// Rerunning a committed command may replace its results; changing what
/// made them is refused, naming the change.
#[test]
fn committed_results_refuse_a_run_made_otherwise() {
    let path = committed("forced-planes.json");
    let there: Stamp<planes::Made> = serde_json::from_str(&read(&path)).unwrap();
    let p = &there.made.parameters;
    let again = planes::Parameters::new(
        vec![23.0, 48.0, 98.0],
        &[5.0, 6.0, 7.0],
        4,
        planes::default_contact_numbers(),
    )
    .unwrap();
    assert_eq!(*p, again);
    let scan = |p: &planes::Parameters| planes::stamp("rgc planes", p);
    scan(&again).check_replace(&path, "scan", false).unwrap();
    let fewer = planes::Parameters {
        seeds: 3,
        ..again.clone()
    };
    let err = scan(&fewer)
        .check_replace(&path, "scan", false)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("holds the results of another scan (parameters.seeds 4 vs 3);"),
        "{err}"
    );

    let path = committed("mined-motifs.json");
    let there: Stamp<mine::Made> = serde_json::from_str(&read(&path)).unwrap();
    let nowhere = path.with_file_name("no-such-rule-file.json");
    let params = there.made.parameters.clone();
    mine::check_replace(&path, &nowhere, &mine::stamp("rgc mine", &params), false).unwrap();
    let smaller = mine::Parameters {
        systems: 5,
        ..params
    };
    let err = mine::check_replace(&path, &nowhere, &mine::stamp("rgc mine", &smaller), false)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("another mining run (parameters.systems 20 vs 5);"),
        "{err}"
    );

    let path = committed("compare-base-extended.json");
    let there: Stamp<Experiment<VariantKey>> = serde_json::from_str(&read(&path)).unwrap();
    there.check_replace(&path, "experiment", false).unwrap();
    let mut more = there.clone();
    more.made.variants[1].runs = 10;
    let err = more.check_replace(&path, "experiment", false).unwrap_err();
    assert!(
        err.to_string()
            .contains("another experiment (variants[1].runs 1 vs 10);"),
        "{err}"
    );

    // The bias file's plan is what `truth_design` makes for its command.
    let path = committed("truth-vs-rgc.json");
    let there: Stamp<MadeBy> = serde_json::from_str(&read(&path)).unwrap();
    let plan = &there.made.made_by;
    let motifs = |label: &str| {
        let v = plan.design.iter().find(|v| v.label == label).unwrap();
        v.motifs.clone()
    };
    let design = bias::truth_design(100, &motifs("sound + extended"), &motifs("sound + mined"));
    let asked = Stamp::new(None, "rgc bias", MadeBy::of(&plan.template, &design));
    assert_eq!(asked.made, there.made);
    asked.check_replace(&path, "experiment", false).unwrap();
    let elsewhere = rgc::threshold::study::StudySpec {
        gamma: 48.0,
        ..plan.template.clone()
    };
    let err = Stamp::new(None, "rgc bias", MadeBy::of(&elsewhere, &design))
        .check_replace(&path, "experiment", false)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("another experiment (made_by.template.gamma 23.0 vs 48.0);"),
        "{err}"
    );
}
