//! Two studies of the same sequences compared sequence by sequence.
//!
//! Extrapolated thresholds carry intervals wider than the shifts between
//! rule sets, but two studies with the same seed run the same rods: on each
//! sequence, the critical density of one minus the other's cancels the
//! sample-to-sample spread, leaving the shift itself. This is how `bias`
//! measures every variant against truth, how `compare` reports each variant
//! against the one before, and what `rgc paired` computes for any two
//! finished studies.

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use super::fss::{Estimate, Protocol};
use super::sequence::{Kind, Record};
use super::study::{self, StudySpec};
use crate::math::stats;
use crate::output::{self, cell};
use crate::rods::excluded_volume;
use crate::{Error, Result};

/// `(reference, other)` critical densities of the sequences both have (by
/// box and seed), in `other`'s order; sequences either left undecided are
/// left out.
pub fn pairs(reference: (Kind, &[Record]), other: (Kind, &[Record])) -> Vec<(f64, f64)> {
    let (rk, rr) = reference;
    let (ok, or) = other;
    let critical: FxHashMap<(u64, u64), usize> = rr
        .iter()
        .filter_map(|r| Some(((r.box_len.to_bits(), r.seed), r.critical(rk)?)))
        .collect();
    or.iter()
        .filter_map(|r| {
            let c = critical.get(&(r.box_len.to_bits(), r.seed))?;
            let v = r.box_len.powi(3);
            Some((*c as f64 / v, r.critical(ok)? as f64 / v))
        })
        .collect()
}

/// Mean with a 95% normal interval, from two values on.
pub fn mean_interval(d: &[f64]) -> Option<Estimate> {
    if d.len() < 2 {
        return None;
    }
    let (mean, sd) = stats::mean_sd(d);
    let half = 1.96 * sd / (d.len() as f64).sqrt();
    Some(Estimate {
        value: mean,
        lo: Some(mean - half),
        hi: Some(mean + half),
    })
}

/// The paired difference (other minus reference) over some sequences.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Difference {
    /// The box, or none for all boxes together.
    #[serde(rename = "box")]
    pub box_len: Option<f64>,
    /// Sequences both studies have.
    pub sequences: usize,
    /// Mean of (other's critical density - reference's), with a 95% normal interval.
    pub mean: Estimate,
    /// The same in mean contact number units (times the excluded volume).
    pub mean_vex: Estimate,
    /// The reference's mean critical density over these sequences.
    #[serde(default)]
    pub reference_mean: f64,
    /// The shift as a share of `reference_mean` (0.18 is 18% above it).
    #[serde(default)]
    pub relative: Estimate,
    /// Sequences where the other study first spans below the reference, and above it.
    pub below: usize,
    pub above: usize,
}

impl Difference {
    /// Of the pairs, from two on.
    pub fn of(box_len: Option<f64>, pairs: &[(f64, f64)], gamma: f64) -> Option<Difference> {
        let mean = mean_interval(&pairs.iter().map(|(r, o)| o - r).collect::<Vec<_>>())?;
        let reference_mean = pairs.iter().map(|(r, _)| r).sum::<f64>() / pairs.len() as f64;
        let scaled = |k: f64| Estimate {
            value: k * mean.value,
            lo: mean.lo.map(|x| k * x),
            hi: mean.hi.map(|x| k * x),
        };
        Some(Difference {
            box_len,
            sequences: pairs.len(),
            mean_vex: scaled(excluded_volume(gamma)),
            reference_mean,
            relative: scaled(1.0 / reference_mean),
            mean,
            below: pairs.iter().filter(|(r, o)| o < r).count(),
            above: pairs.iter().filter(|(r, o)| o > r).count(),
        })
    }
}

/// Two studies compared: per box they share, then over all their shared sequences.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    pub gamma: f64,
    pub seed: u64,
    pub boxes: Vec<Difference>,
    pub all: Difference,
}

/// Checks that two studies ran the same sequences and each has one critical
/// number per sequence, then compares them.
pub fn compare(
    reference: (&StudySpec, &[Record]),
    other: (&StudySpec, &[Record]),
) -> Result<Comparison> {
    let (rs, os) = (reference.0, other.0);
    let bad = |m: String| Err(Error::Parameter(m));
    for s in [rs, os] {
        if s.method != Protocol::Nested {
            return bad(format!(
                "a study of the {:?} protocol has no critical number per sequence: paired differences need nested studies",
                s.method
            ));
        }
    }
    if rs.gamma != os.gamma || rs.seed != os.seed {
        return bad(format!(
            "the studies ran different sequences (gamma {} seed {} against gamma {} seed {}): paired differences need the same gamma and seed",
            rs.gamma, rs.seed, os.gamma, os.seed
        ));
    }
    let shared: Vec<f64> = rs
        .boxes
        .iter()
        .copied()
        .filter(|l| os.boxes.contains(l))
        .collect();
    let boxes: Vec<Difference> = shared
        .iter()
        .filter_map(|&l| {
            let in_box = |records: &[Record]| -> Vec<Record> {
                records.iter().filter(|r| r.box_len == l).cloned().collect()
            };
            let (r, o) = (in_box(reference.1), in_box(other.1));
            Difference::of(Some(l), &pairs((rs.kind, &r), (os.kind, &o)), rs.gamma)
        })
        .collect();
    let all = pairs((rs.kind, reference.1), (os.kind, other.1));
    let Some(all) = Difference::of(None, &all, rs.gamma) else {
        return bad(format!(
            "the studies share fewer than two decided sequences (boxes {:?} against {:?})",
            rs.boxes, os.boxes
        ));
    };
    Ok(Comparison {
        gamma: rs.gamma,
        seed: rs.seed,
        boxes,
        all,
    })
}

/// The comparison of two finished study directories (`rgc paired`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pairing {
    pub reference: String,
    pub other: String,
    #[serde(flatten)]
    pub comparison: Comparison,
}

impl Pairing {
    /// `other - reference`, each by its directory's name.
    pub fn label(&self) -> String {
        let name = |p: &str| {
            Path::new(p)
                .file_name()
                .map_or(p.to_string(), |n| n.to_string_lossy().into_owned())
        };
        format!("{} - {}", name(&self.other), name(&self.reference))
    }
}

/// Reads the studies in `reference` and `other` and compares them.
pub fn of_dirs(reference: &Path, other: &Path) -> Result<Pairing> {
    let read = |dir: &Path| -> Result<(StudySpec, Vec<Record>)> {
        let spec = study::read_spec(dir)?;
        let records = study::in_study_order(&spec, study::read_records(dir, &spec)?);
        Ok((spec, records))
    };
    let (rs, rr) = read(reference)?;
    let (os, or) = read(other)?;
    Ok(Pairing {
        reference: reference.display().to_string(),
        other: other.display().to_string(),
        comparison: compare((&rs, &rr), (&os, &or))?,
    })
}

/// One CSV row: a pairing in one box, or over all boxes (`box` empty).
#[derive(Serialize)]
struct Row<'a> {
    reference: &'a str,
    other: &'a str,
    gamma: f64,
    #[serde(rename = "box", serialize_with = "cell::fixed_opt::<1, _>")]
    box_len: Option<f64>,
    sequences: usize,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    mean: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    mean_vex: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    lo_vex: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    hi_vex: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    reference_mean: f64,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    relative: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    relative_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    relative_hi: Option<f64>,
    below: usize,
    above: usize,
}

/// Writes `PREFIX.json` (with the command that made it), `PREFIX.csv` and
/// `PREFIX.md` atomically; the paths written.
pub fn write(prefix: &Path, pairings: &[Pairing], command: &str) -> Result<Vec<PathBuf>> {
    let with = |ext: &str| output::with_extension(prefix, ext);
    let (json, csv, md) = (with("json"), with("csv"), with("md"));
    let doc = serde_json::json!({ "command": command, "pairings": pairings });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("pairings serialize"),
    )?;
    let rows = pairings.iter().flat_map(|p| {
        let c = &p.comparison;
        c.boxes.iter().chain([&c.all]).map(move |d| Row {
            reference: &p.reference,
            other: &p.other,
            gamma: c.gamma,
            box_len: d.box_len,
            sequences: d.sequences,
            mean: d.mean.value,
            lo: d.mean.lo,
            hi: d.mean.hi,
            mean_vex: d.mean_vex.value,
            lo_vex: d.mean_vex.lo,
            hi_vex: d.mean_vex.hi,
            reference_mean: d.reference_mean,
            relative: d.relative.value,
            relative_lo: d.relative.lo,
            relative_hi: d.relative.hi,
            below: d.below,
            above: d.above,
        })
    });
    output::write_csv(&csv, rows)?;
    output::write_atomic(&md, markdown(pairings, command))?;
    Ok(vec![json, csv, md])
}

/// One table per pairing: the shift per box and over all boxes, in density,
/// in `rho V_ex` and as a share of the reference, with the sequences that
/// moved down and up.
pub fn markdown(pairings: &[Pairing], command: &str) -> String {
    let interval = |e: &Estimate, k: f64, digits: usize| match (e.lo, e.hi) {
        (Some(lo), Some(hi)) => format!(
            "{:+.digits$} [{:+.digits$}, {:+.digits$}]",
            k * e.value,
            k * lo,
            k * hi
        ),
        _ => format!("{:+.digits$}", k * e.value),
    };
    let mut s = String::from("# Paired shifts of the critical density\n\n");
    s += "Each study minus its reference on the same sequences (same seed, same rods): the mean shift of the critical density with a 95% normal interval (1.96 sd / sqrt n), the same in `rho V_ex`, as a share of the reference's mean critical density, and the sequences that moved down and up. Sequences either study left undecided are left out.\n\n";
    s += &format!("Made by `{command}`.\n");
    for p in pairings {
        let c = &p.comparison;
        s += &format!(
            "\n## {} (gamma {}, seed {})\n\n| box | sequences | reference mean | shift | shift x V_ex | share | below | above |\n|---|---|---|---|---|---|---|---|\n",
            p.label(),
            c.gamma,
            c.seed
        );
        for d in c.boxes.iter().chain([&c.all]) {
            s += &format!(
                "| {} | {} | {:.3} | {} | {} | {}% | {} | {} |\n",
                d.box_len.map_or("all".into(), |l| l.to_string()),
                d.sequences,
                d.reference_mean,
                interval(&d.mean, 1.0, 3),
                interval(&d.mean_vex, 1.0, 4),
                interval(&d.relative, 100.0, 1),
                d.below,
                d.above
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spanning::Criterion;

    /// A record with only what pairing reads: box, seed and critical numbers.
    fn record(box_len: f64, seed: u64, contact: usize, rigid: Option<usize>) -> Record {
        Record {
            box_len,
            index: 0,
            seed,
            contact_critical: contact,
            rigid_critical: rigid,
            steps: vec![],
            fresh: None,
            fixed: vec![],
            contacts: vec![],
            undecided: rigid.is_none().then_some(2 * contact),
            seconds: 0.0,
            peak_rss_mib: 0.0,
            cpu_seconds: None,
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + b.abs())
    }

    #[test]
    fn the_interval_is_1_96_sample_sd_over_root_n() {
        // Mean 4, sample variance (9 + 4 + 1 + 0 + 36) / 4 = 12.5: half-width
        // 1.96 sqrt(12.5 / 5). The population variance (10) would give 1.96 sqrt(2).
        let e = mean_interval(&[1.0, 2.0, 3.0, 4.0, 10.0]).unwrap();
        let half = 1.96 * 2.5f64.sqrt();
        assert_eq!(e.value, 4.0);
        assert!(close(e.lo.unwrap(), 4.0 - half), "{e:?}");
        assert!(close(e.hi.unwrap(), 4.0 + half), "{e:?}");
        // Two values 0 and 2: sd sqrt(2), half-width 1.96 sqrt(2) / sqrt(2).
        let e = mean_interval(&[0.0, 2.0]).unwrap();
        assert_eq!(e.value, 1.0);
        assert!(
            close(e.lo.unwrap(), -0.96) && close(e.hi.unwrap(), 2.96),
            "{e:?}"
        );
        // No spread, no width.
        let e = mean_interval(&[3.0; 4]).unwrap();
        assert_eq!((e.lo, e.hi), (Some(3.0), Some(3.0)));
        // One value or none: no interval, no estimate.
        assert_eq!(mean_interval(&[5.0]), None);
        assert_eq!(mean_interval(&[]), None);
    }

    #[test]
    fn pairs_match_box_and_seed_and_leave_out_undecided_sequences() {
        let reference = vec![
            record(4.0, 1, 50, Some(128)),
            record(4.0, 2, 50, None),
            record(4.0, 3, 50, Some(192)),
            record(5.0, 4, 90, Some(250)),
        ];
        let other = vec![
            record(4.0, 3, 60, Some(64)),
            record(4.0, 2, 50, Some(100)),
            record(4.0, 1, 40, None),
            record(5.0, 1, 40, Some(100)),
            record(5.0, 4, 80, Some(375)),
        ];
        let p = pairs((Kind::Truth, &reference), (Kind::Rigid, &other));
        // Seed 3 in box 4 and seed 4 in box 5, in `other`'s order; seed 2
        // (undecided in the reference), seed 1 in box 4 (undecided in
        // `other`) and seed 1 in box 5 (not in the reference's box 5) are out.
        assert_eq!(p, vec![(3.0, 1.0), (2.0, 3.0)]);
        // The contact kind pairs the contact critical numbers, decided or not.
        let p = pairs((Kind::Contact, &reference), (Kind::Contact, &other));
        assert_eq!(
            p,
            vec![
                (50.0 / 64.0, 60.0 / 64.0),
                (50.0 / 64.0, 50.0 / 64.0),
                (50.0 / 64.0, 40.0 / 64.0),
                (90.0 / 125.0, 80.0 / 125.0)
            ]
        );
    }

    #[test]
    fn a_difference_counts_signs_and_scales_by_the_excluded_volume() {
        let pairs = [(1.0, 2.0), (2.0, 1.0), (3.0, 3.0), (0.0, 4.0)];
        let d = Difference::of(Some(4.0), &pairs, 10.0).unwrap();
        assert_eq!(
            (d.box_len, d.sequences, d.below, d.above),
            (Some(4.0), 4, 1, 2)
        );
        // Differences 1, -1, 0, 4: mean 1, sample variance (0 + 4 + 1 + 9) / 3.
        let half = 1.96 * (14.0f64 / 3.0).sqrt() / 2.0;
        assert_eq!(d.mean.value, 1.0);
        assert!(close(d.mean.hi.unwrap(), 1.0 + half));
        let vex = excluded_volume(10.0);
        assert!(close(d.mean_vex.value, vex));
        assert!(close(d.mean_vex.lo.unwrap(), (1.0 - half) * vex));
        assert!(close(d.mean_vex.hi.unwrap(), (1.0 + half) * vex));
        // References 1, 2, 3, 0: mean 1.5, so the shift is 2/3 of it.
        assert_eq!(d.reference_mean, 1.5);
        assert!(close(d.relative.value, 1.0 / 1.5));
        assert!(close(d.relative.lo.unwrap(), (1.0 - half) / 1.5));
        assert!(close(d.relative.hi.unwrap(), (1.0 + half) / 1.5));
        assert_eq!(Difference::of(None, &pairs[..1], 10.0), None);
    }

    #[test]
    fn the_markdown_has_one_row_per_box_and_one_for_all() {
        let d = |box_len| Difference::of(box_len, &[(10.0, 11.0), (10.0, 13.0)], 10.0).unwrap();
        let pairing = Pairing {
            reference: "results/g10-truth".into(),
            other: "results/g10-rigid-sound".into(),
            comparison: Comparison {
                gamma: 10.0,
                seed: 1,
                boxes: vec![d(Some(4.0)), d(Some(5.0))],
                all: d(None),
            },
        };
        assert_eq!(pairing.label(), "g10-rigid-sound - g10-truth");
        let md = markdown(&[pairing], "rgc paired a b");
        assert!(md.contains("Made by `rgc paired a b`."), "{md}");
        assert!(
            md.contains("## g10-rigid-sound - g10-truth (gamma 10, seed 1)"),
            "{md}"
        );
        // Shifts 1 and 3: mean 2, sd sqrt 2, half-width 1.96; 20% of 10.
        let row = "| 4 | 2 | 10.000 | +2.000 [+0.040, +3.960] |";
        assert!(md.contains(row), "{md}");
        assert!(md.contains("| +20.0 [+0.4, +39.6]% | 0 | 2 |"), "{md}");
        assert_eq!(md.matches("| all | 2 |").count(), 1, "{md}");
        assert_eq!(md.lines().filter(|l| l.starts_with("| ")).count(), 4);
    }

    #[test]
    fn compare_needs_two_shared_decided_sequences() {
        let truth = StudySpec {
            kind: Kind::Truth,
            ..StudySpec::new(10.0, vec![3.0, 4.0], 5, Criterion::Wrap, 7)
        };
        let rigid = StudySpec::new(10.0, vec![4.0, 5.0], 5, Criterion::Wrap, 7);
        let mut reference = vec![
            record(3.0, 1, 30, Some(40)),
            record(3.0, 2, 30, Some(40)),
            record(4.0, 1, 50, Some(128)),
            record(4.0, 2, 50, None),
        ];
        let other = vec![
            record(4.0, 1, 50, Some(192)),
            record(4.0, 2, 50, Some(128)),
            record(5.0, 1, 90, Some(250)),
        ];
        // Box 4 is the only one both have, and its second sequence is
        // undecided in the reference: one pair.
        let err = compare((&truth, &reference), (&rigid, &other))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(
                "the studies share fewer than two decided sequences (boxes [3.0, 4.0] against [4.0, 5.0])"
            ),
            "{err}"
        );
        // Decided, it pairs: 192 - 128 and 128 - 128 rods in a box of 64.
        reference[3] = record(4.0, 2, 50, Some(128));
        let c = compare((&truth, &reference), (&rigid, &other)).unwrap();
        assert_eq!(c.all.sequences, 2);
        assert_eq!(c.all.mean.value, 0.5);
        assert_eq!((c.all.below, c.all.above), (0, 1));
        assert_eq!(c.boxes.len(), 1);
        assert_eq!(c.boxes[0].box_len, Some(4.0));
        assert_eq!(c.boxes[0].mean, c.all.mean);
    }
}
