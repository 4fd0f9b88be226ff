//! Truth's monotonicity scan: truth at every number of rods around each
//! sequence's critical number, which the bisection assumes monotone.

use serde::{Deserialize, Serialize};

use crate::engine::RuleSet;
use crate::output;
use crate::progress::Progress;
use crate::threshold::sequence::{Kind, Record};
use crate::threshold::study::StudySpec;
use crate::{Error, Result};

/// Truth at every number of rods around one sequence's critical number:
/// whether truth spanning is monotone in the number of rods, which the
/// bisection assumes. A new rod can close a triangle and force rods into one
/// plane, a special position where a rigid cluster may flex.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scan {
    #[serde(rename = "box")]
    pub box_len: f64,
    pub index: u64,
    pub seed: u64,
    /// The critical number the bisection found.
    pub critical: usize,
    /// The numbers of rods scanned, `from..=to`.
    pub from: usize,
    pub to: usize,
    /// The first number of rods in the window that spans.
    pub first_spanning: Option<usize>,
    /// Numbers of rods that do not span although the last decided one
    /// below does.
    pub drops: Vec<usize>,
    /// Numbers of rods where truth was undecided (skipped).
    pub undecided: Vec<usize>,
}

/// Evaluates truth at every number of rods within `half_width` (a fraction)
/// of the critical number of each of the first `sequences` truth records of
/// the boxes `boxes`, in parallel over numbers of rods. Sequences where truth
/// was undecided have no critical number to scan around: they are left out,
/// as [`measure`](super::measure::measure) leaves them out of every pair.
pub fn scan(
    template: &StudySpec,
    truth: &[Record],
    boxes: &[f64],
    sequences: u64,
    half_width: f64,
    memory_limit: Option<u64>,
    progress: &dyn Progress,
) -> Result<Vec<Scan>> {
    use rayon::prelude::*;
    let setup = crate::threshold::sequence::Setup {
        kind: Kind::Truth,
        gamma: template.gamma,
        criterion: template.criterion,
        engine: crate::engine::Engine::base(RuleSet::Sound),
        runs: 1,
        memory_limit,
    };
    let chosen: Vec<&Record> = truth
        .iter()
        .filter(|r| boxes.contains(&r.box_len) && r.index < sequences)
        .collect();
    for &l in boxes {
        if !chosen.iter().any(|r| r.box_len == l) {
            return Err(Error::Parameter(format!(
                "no truth sequence of box {l} to scan: the box must be one of the study's"
            )));
        }
    }
    let decided: Vec<(&Record, usize)> = chosen
        .iter()
        .filter_map(|r| Some((*r, r.critical(Kind::Truth)?)))
        .collect();
    let total = decided.len() as u64;
    progress.start("monotonicity scan", total);
    let mut out = Vec::with_capacity(decided.len());
    for (r, critical) in decided {
        let w = ((critical as f64 * half_width).ceil() as usize).max(1);
        let (from, to) = (critical.saturating_sub(w).max(1), critical + w);
        let seq = crate::threshold::sequence::Sequence::new(template.gamma, r.box_len, to, r.seed)?;
        let spans: Vec<Option<bool>> = (from..=to)
            .into_par_iter()
            .map(|n| crate::threshold::sequence::truth_spanning(&setup, &seq, n))
            .collect();
        let (first_spanning, drops) = spanning_drops(&spans);
        out.push(Scan {
            box_len: r.box_len,
            index: r.index,
            seed: r.seed,
            critical,
            from,
            to,
            first_spanning: first_spanning.map(|i| from + i),
            drops: drops.into_iter().map(|i| from + i).collect(),
            undecided: spans
                .iter()
                .enumerate()
                .filter(|(_, s)| s.is_none())
                .map(|(i, _)| from + i)
                .collect(),
        });
        progress.advance(1);
    }
    progress.finish();
    Ok(out)
}

/// Over truth's spanning verdicts at consecutive numbers of rods (`None`:
/// undecided), the position of the first that spans, and the positions that
/// do not span although the last decided one before them does. Undecided
/// steps are skipped: a drop is counted between the decided verdicts on
/// either side of them, at the position of the one after.
fn spanning_drops(spans: &[Option<bool>]) -> (Option<usize>, Vec<usize>) {
    let decided: Vec<(usize, bool)> = spans
        .iter()
        .enumerate()
        .filter_map(|(i, s)| s.map(|s| (i, s)))
        .collect();
    let first = decided.iter().find(|d| d.1).map(|d| d.0);
    let drops = decided
        .windows(2)
        .filter(|w| w[0].1 && !w[1].1)
        .map(|w| w[1].0)
        .collect();
    (first, drops)
}

/// One line on the scans: sequences, rods evaluated, drops from spanning
/// back to not spanning, and how often the bisection's answer is the first
/// spanning number of rods of the window.
pub fn scan_summary(scans: &[Scan]) -> String {
    let evaluated: usize = scans.iter().map(|s| s.to - s.from + 1).sum();
    let drops: usize = scans.iter().map(|s| s.drops.len()).sum();
    let with_drops = scans.iter().filter(|s| !s.drops.is_empty()).count();
    let undecided: usize = scans.iter().map(|s| s.undecided.len()).sum();
    let agree = scans
        .iter()
        .filter(|s| s.first_spanning == Some(s.critical))
        .count();
    format!(
        "Truth monotonicity: {} sequences scanned at every number of rods ({evaluated} truth evaluations); \
         {drops} steps go from spanning back to not spanning, in {with_drops} sequences; \
         the bisection's critical number is the first spanning one in {agree} of {} sequences; \
         {undecided} evaluations undecided.",
        scans.len(),
        scans.len()
    )
}

#[derive(Serialize)]
struct ScanRow {
    #[serde(rename = "box")]
    box_len: f64,
    index: u64,
    seed: u64,
    critical: usize,
    from: usize,
    to: usize,
    first_spanning: Option<usize>,
    drops: usize,
    /// The numbers of rods that drop, separated by spaces.
    drop_rods: String,
    undecided: usize,
}

/// The scans as CSV, one row per sequence.
pub fn scan_csv(scans: &[Scan]) -> String {
    let rows = scans.iter().map(|s| ScanRow {
        box_len: s.box_len,
        index: s.index,
        seed: s.seed,
        critical: s.critical,
        from: s.from,
        to: s.to,
        first_spanning: s.first_spanning,
        drops: s.drops.len(),
        drop_rods: s
            .drops
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(" "),
        undecided: s.undecided.len(),
    });
    String::from_utf8(output::csv(rows)).expect("CSV of UTF-8 is UTF-8")
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::{nested, undecided};
    use super::*;
    use crate::progress::Silent;
    use crate::spanning::Criterion;

    fn spec_at(box_len: f64) -> StudySpec {
        StudySpec {
            kind: Kind::Truth,
            ..StudySpec::new(23.0, vec![box_len], 1, Criterion::Wrap, 1)
        }
    }

    #[test]
    fn scan_refuses_a_box_without_truth_records() {
        let spec = spec_at(3.0);
        let seed = spec.sequence_seed(3.0, 0);
        let truth = vec![nested(3.0, 0, seed, 3, 3)];
        let err = scan(&spec, &truth, &[4.0], 1, 0.1, None, &Silent)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("no truth sequence of box 4 to scan: the box must be one of the study's"),
            "{err}"
        );
        // Sequences beyond the first `sequences` are not scanned either.
        let later = vec![nested(3.0, 1, seed, 3, 3)];
        assert!(scan(&spec, &later, &[3.0], 1, 0.1, None, &Silent).is_err());
    }

    #[test]
    fn scan_windows_reach_from_one_rod_on() {
        // A handful of rods in a box of side 3 spans nowhere: the window is
        // critical -+ ceil(critical * width) (at least 1), never below 1 rod.
        let spec = spec_at(3.0);
        let seed = spec.sequence_seed(3.0, 0);
        let truth = vec![nested(3.0, 0, seed, 3, 3)];
        let s = scan(&spec, &truth, &[3.0], 1, 0.1, None, &Silent).unwrap();
        assert_eq!(s.len(), 1);
        let s = &s[0];
        assert_eq!((s.critical, s.from, s.to), (3, 2, 4));
        assert_eq!((s.first_spanning, &s.drops[..]), (None, &[][..]));
        assert!(s.undecided.is_empty());
        let truth = vec![nested(3.0, 0, seed, 1, 1)];
        let s = &scan(&spec, &truth, &[3.0], 1, 0.5, None, &Silent).unwrap()[0];
        assert_eq!((s.from, s.to), (1, 2));
        let truth = vec![nested(3.0, 0, seed, 10, 10)];
        let s = &scan(&spec, &truth, &[3.0], 1, 0.25, None, &Silent).unwrap()[0];
        assert_eq!((s.from, s.to), (7, 13));
    }

    #[test]
    fn scan_leaves_out_undecided_truth_records() {
        // Truth is undecided on some sequences (1 of 300 in the committed
        // bias study); `measure` leaves them out of every pair, and `scan`
        // leaves them out of the scan rather than failing the whole run.
        let spec = StudySpec {
            sequences: 2,
            ..spec_at(3.0)
        };
        let truth = vec![
            undecided(3.0, 0, spec.sequence_seed(3.0, 0), 3),
            nested(3.0, 1, spec.sequence_seed(3.0, 1), 3, 3),
        ];
        let s = scan(&spec, &truth, &[3.0], 2, 0.1, None, &Silent).unwrap();
        assert_eq!(s.iter().map(|s| s.index).collect::<Vec<_>>(), vec![1]);
        // The decided sequence scans as it does alone.
        let alone = scan(&spec, &truth[1..], &[3.0], 2, 0.1, None, &Silent).unwrap();
        assert_eq!(s, alone);
        // A box whose scanned sequences are all undecided scans none, without
        // error: the box is one of the study's.
        let s = scan(&spec, &truth, &[3.0], 1, 0.1, None, &Silent).unwrap();
        assert!(s.is_empty());
    }

    #[test]
    fn spanning_drops_on_hand_made_verdicts() {
        let (t, f, u) = (Some(true), Some(false), None);
        // Nothing to scan, or all undecided.
        assert_eq!(spanning_drops(&[]), (None, vec![]));
        assert_eq!(spanning_drops(&[u, u, u]), (None, vec![]));
        // Monotone: no drop, first spanning at the switch.
        assert_eq!(spanning_drops(&[f, f, t, t, t]), (Some(2), vec![]));
        // Never spanning.
        assert_eq!(spanning_drops(&[f, f, f, f]), (None, vec![]));
        // Spanning from the start, and spanning once only at the end.
        assert_eq!(spanning_drops(&[t, t, t]), (Some(0), vec![]));
        assert_eq!(spanning_drops(&[f, f, f, t]), (Some(3), vec![]));
        // One drop: at the step that stops spanning.
        assert_eq!(spanning_drops(&[f, t, f, t, t]), (Some(1), vec![2]));
        // Spanning from the start, then dropping at the last step.
        assert_eq!(spanning_drops(&[t, t, f]), (Some(0), vec![2]));
        // Several drops; a run of non-spanning steps drops once.
        assert_eq!(
            spanning_drops(&[f, t, f, f, t, f, t, t, f]),
            (Some(1), vec![2, 5, 8])
        );
        // Undecided steps are skipped: a drop across them is counted at the
        // next decided step, and none is counted into or out of them.
        assert_eq!(spanning_drops(&[f, t, u, f, t]), (Some(1), vec![3]));
        assert_eq!(spanning_drops(&[f, t, u, u, t, f]), (Some(1), vec![5]));
        assert_eq!(spanning_drops(&[f, u, t, u, t]), (Some(2), vec![]));
        assert_eq!(spanning_drops(&[u, t, f, u]), (Some(1), vec![2]));
        assert_eq!(spanning_drops(&[u, u, t, u, f, u, t]), (Some(2), vec![4]));
        // An undecided step is never the first spanning one.
        assert_eq!(spanning_drops(&[u, f, u, t]), (Some(3), vec![]));
    }

    fn hand_scan(index: u64, critical: usize, first: Option<usize>, drops: Vec<usize>) -> Scan {
        Scan {
            box_len: 3.0,
            index,
            seed: 7,
            critical,
            from: critical - 10,
            to: critical + 10,
            first_spanning: first,
            drops,
            undecided: if index == 2 { vec![95, 96] } else { vec![] },
        }
    }

    #[test]
    fn scan_summary_and_csv_count_drops() {
        let scans = vec![
            hand_scan(0, 100, Some(100), vec![]),
            hand_scan(1, 100, Some(98), vec![101, 105]),
            hand_scan(2, 100, Some(100), vec![103]),
        ];
        let s = scan_summary(&scans);
        assert!(
            s.contains("3 sequences scanned at every number of rods (63 truth evaluations)"),
            "{s}"
        );
        assert!(
            s.contains("3 steps go from spanning back to not spanning, in 2 sequences"),
            "{s}"
        );
        assert!(
            s.contains("the first spanning one in 2 of 3 sequences; 2 evaluations undecided"),
            "{s}"
        );
        let csv = scan_csv(&scans);
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(
            rows[0],
            "box,index,seed,critical,from,to,first_spanning,drops,drop_rods,undecided"
        );
        assert_eq!(rows[2], "3.0,1,7,100,90,110,98,2,101 105,0");
        assert_eq!(rows[3], "3.0,2,7,100,90,110,100,1,103,2");
    }
}
