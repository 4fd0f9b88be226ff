//! `rgc locality`: at a committed truth study's true critical number, the
//! spanning true cluster against a compression's bodies, and the minimal
//! rigid sets joining two of its nodes; resumable, one line per sequence.

use crate::cli::{fails, rgc};
use rgc::threshold::locality::{self, SequenceLocality};
use rgc::threshold::sequence::Record;

const STUDY: &str = "results/g23-truth";

/// The committed record of the first sequence of box 5.
fn first_record() -> Record {
    let text = std::fs::read_to_string(format!("{STUDY}/records.jsonl")).unwrap();
    text.lines()
        .map(|l| serde_json::from_str::<Record>(l).unwrap())
        .find(|r| r.box_len == 5.0 && r.index == 0)
        .expect("box 5, sequence 0 is committed")
}

#[test]
fn the_spanning_cluster_is_probed_at_the_true_critical_number_and_resumes() {
    let dir = crate::scratch("locality");
    let out = dir.join("probe");
    let args = |extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = ["locality", STUDY, "--boxes", "5", "--sequences", "1"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        a.extend(
            [
                "--max-radius",
                "2",
                "--max-ball-rods",
                "600",
                "--quiet",
                "--out",
            ]
            .map(String::from),
        );
        a.push(out.display().to_string());
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |extra: &[&str]| {
        let a = args(extra);
        let o = rgc(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let printed = run(&[]);
    assert!(printed.contains("    23     5    1 "), "{printed}");
    let lines = out.join("locality.jsonl");
    let all = locality::read(&lines).unwrap();
    let [s]: [SequenceLocality; 1] = all.try_into().expect("one sequence");
    let r = first_record();
    assert_eq!(
        (s.box_len, s.index, s.rods),
        (5.0, 0, r.rigid_critical.unwrap())
    );
    // The cluster at the critical number is the largest the study recorded there.
    let at = r
        .steps
        .iter()
        .find(|x| x.n == s.rods)
        .expect("a step at the critical number");
    assert_eq!(Some(s.cluster_rods), at.largest);
    assert!(
        s.largest_body <= s.covered_rods && s.covered_rods < s.cluster_rods,
        "{s:?}"
    );
    assert!(
        s.cluster_nodes > 1 && s.cluster_nodes <= s.cluster_rods,
        "{s:?}"
    );
    assert_eq!(
        s.pairs,
        s.found + s.beyond_radius + s.beyond_rods + s.exhausted
    );
    assert!(!s.sets.is_empty() && s.sets.len() <= s.found, "{s:?}");
    for set in &s.sets {
        assert!(
            set.nodes >= 2 && set.nodes <= set.rods && set.rods <= 600,
            "{set:?}"
        );
        assert!(set.radius <= 2, "{set:?}");
    }
    // A rerun finds the sequence done; a line cut by a kill is probed again.
    let before = std::fs::read_to_string(&lines).unwrap();
    run(&[]);
    assert_eq!(std::fs::read_to_string(&lines).unwrap(), before);
    std::fs::write(&lines, &before[..before.len() / 2]).unwrap();
    run(&["--summary", &dir.join("sum").display().to_string()]);
    let [again]: [SequenceLocality; 1] = locality::read(&lines).unwrap().try_into().unwrap();
    assert_eq!(
        SequenceLocality {
            seconds: s.seconds,
            ..again
        },
        s
    );
    let csv = std::fs::read_to_string(dir.join("sum.csv")).unwrap();
    assert!(csv.starts_with("gamma,box,sequences,"), "{csv}");
    // Another search is refused in the same directory.
    let mut other = args(&[]);
    other[9] = "3".into();
    fails(
        &other.iter().map(String::as_str).collect::<Vec<_>>(),
        "holds another measurement",
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn only_truth_studies_are_probed() {
    let out = crate::scratch("locality-rigid");
    fails(
        &[
            "locality",
            "results/g23-rigid-sound",
            "--out",
            &out.display().to_string(),
        ],
        "is a Rigid study: the locality of missed rigidity needs a truth study (--kind truth)",
    );
    fails(
        &[
            "locality",
            STUDY,
            "--boxes",
            "4",
            "--out",
            &out.display().to_string(),
        ],
        "box 4 is not one of results/g23-truth's boxes",
    );
}
