//! The order of the rigidity transition, from the records of a truth study
//! (MODEL §10): how much the largest true rigid cluster grows at the one
//! rod that makes truth span, and how large it is above the threshold.
//!
//! In random graphs and in 3-D central-force networks the giant rigid
//! cluster appears discontinuously: a finite fraction of the nodes at once.
//! If the jump stays finite as the box grows, the transition is first order
//! and finite-size scaling with an exponent `nu` is not the right analysis;
//! if it shrinks, the transition is continuous. Every truth record keeps
//! the largest true cluster of each bisection step, so both the jump and
//! the spanning cluster's share above the threshold (`P_inf`) come from the
//! records alone.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::sequence::{Kind, Record};
use super::study;
use crate::{Error, Result, output};

/// The transition of one finished or partial truth study.
#[derive(Clone, Debug, Serialize)]
pub struct Transition {
    pub study: String,
    pub gamma: f64,
    pub jumps: Vec<Jump>,
    /// `P_inf` above the threshold, in the box asked for (by default the
    /// largest).
    pub shares: Vec<Share>,
}

/// The transition of the truth study in `dir`, with `P_inf` in `bins` bins
/// for box `box_len` (the study's largest box with records if `None`).
pub fn of_dir(dir: &Path, box_len: Option<f64>, bins: usize) -> Result<Transition> {
    let spec = study::read_spec(dir)?;
    if spec.kind != Kind::Truth {
        return Err(Error::Parameter(format!(
            "{} is a {:?} study: the order of the transition needs truth's largest clusters (a --kind truth study)",
            dir.display(),
            spec.kind
        )));
    }
    let records: Vec<Record> = study::read_records(dir, &spec)?.into_values().collect();
    let present = boxes(&records);
    let Some(&largest) = present.last() else {
        return Err(Error::Analysis(format!(
            "{} has no records yet",
            dir.display()
        )));
    };
    let l = box_len.unwrap_or(largest);
    if !present.contains(&l) {
        return Err(Error::Parameter(format!(
            "box {l} has no records in {} (boxes with records: {present:?})",
            dir.display()
        )));
    }
    Ok(Transition {
        study: dir.display().to_string(),
        gamma: spec.gamma,
        jumps: jumps(&records),
        shares: shares(&records, l, bins),
    })
}

/// Writes `PREFIX.json` (with the command that made it) and `PREFIX.csv`
/// (one row per study and box: the jump).
pub fn write(prefix: &Path, all: &[Transition], command: &str) -> Result<Vec<PathBuf>> {
    let with = |ext: &str| output::with_extension(prefix, ext);
    let (json, csv) = (with("json"), with("csv"));
    let doc = serde_json::json!({ "command": command, "transitions": all });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("transitions serialize"),
    )?;
    #[derive(Serialize)]
    struct Row<'a> {
        study: &'a str,
        gamma: f64,
        box_len: f64,
        sequences: usize,
        jump_mean: f64,
        jump_sd: f64,
        jump_half_width: f64,
        jump_min: f64,
        jump_max: f64,
        share_at_critical: f64,
    }
    let rows = all.iter().flat_map(|t| {
        t.jumps.iter().map(move |j| Row {
            study: &t.study,
            gamma: t.gamma,
            box_len: j.box_len,
            sequences: j.sequences,
            jump_mean: j.mean,
            jump_sd: j.sd,
            jump_half_width: j.half_width,
            jump_min: j.min,
            jump_max: j.max,
            share_at_critical: j.at_critical,
        })
    });
    output::write_csv(&csv, rows)?;
    Ok(vec![json, csv])
}

/// The jump at the critical number, over the sequences of one box.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Jump {
    pub box_len: f64,
    /// Sequences with both the step below the critical number and the one
    /// at it.
    pub sequences: usize,
    /// Mean over sequences of the largest cluster's fraction of the rods at
    /// the critical number minus that one rod below, with its standard
    /// deviation and the half-width of its 95% interval (1.96 sd / sqrt n).
    pub mean: f64,
    pub sd: f64,
    pub half_width: f64,
    pub min: f64,
    pub max: f64,
    /// Mean fraction of the rods in the largest cluster at the critical
    /// number (what the spanning cluster holds when it first spans).
    pub at_critical: f64,
}

/// Share of the rods in the largest true cluster at spanning steps, in one
/// bin of density.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Share {
    pub box_len: f64,
    /// Density at the bin's centre, rods per unit volume.
    pub density: f64,
    pub steps: usize,
    pub mean: f64,
    pub sd: f64,
}

/// The jump of each box of `records` (boxes in increasing order); a box
/// without a sequence that has both steps is left out.
pub fn jumps(records: &[Record]) -> Vec<Jump> {
    boxes(records)
        .into_iter()
        .filter_map(|l| {
            let pairs: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| r.box_len == l)
                .filter_map(|r| {
                    let n = r.rigid_critical?;
                    let (below, at) = r.jump()?;
                    Some((below as f64 / (n - 1) as f64, at as f64 / n as f64))
                })
                .collect();
            let d: Vec<f64> = pairs.iter().map(|(b, a)| a - b).collect();
            let (mean, sd) = mean_sd(&d)?;
            Some(Jump {
                box_len: l,
                sequences: d.len(),
                mean,
                sd,
                half_width: 1.96 * sd / (d.len() as f64).sqrt(),
                min: d.iter().copied().fold(f64::INFINITY, f64::min),
                max: d.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                at_critical: pairs.iter().map(|p| p.1).sum::<f64>() / pairs.len() as f64,
            })
        })
        .collect()
}

/// The largest cluster's share of the rods at every spanning step of the
/// records of box `box_len`, binned by density into `bins` equal bins from
/// the lowest to the highest spanning density: `P_inf` above the threshold,
/// as far as the bisections reached.
pub fn shares(records: &[Record], box_len: f64, bins: usize) -> Vec<Share> {
    let volume = box_len.powi(3);
    let points: Vec<(f64, f64)> = records
        .iter()
        .filter(|r| r.box_len == box_len)
        .flat_map(|r| &r.steps)
        .filter(|s| s.spans)
        .filter_map(|s| Some((s.n as f64 / volume, s.largest? as f64 / s.n as f64)))
        .collect();
    if points.is_empty() || bins == 0 {
        return Vec::new();
    }
    let lo = points.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let hi = points.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
    let width = ((hi - lo) / bins as f64).max(f64::MIN_POSITIVE);
    (0..bins)
        .filter_map(|b| {
            let inside: Vec<f64> = points
                .iter()
                .filter(|p| ((p.0 - lo) / width).floor().min((bins - 1) as f64) as usize == b)
                .map(|p| p.1)
                .collect();
            let (mean, sd) = mean_sd(&inside).or_else(|| inside.first().map(|&v| (v, 0.0)))?;
            Some(Share {
                box_len,
                density: lo + (b as f64 + 0.5) * width,
                steps: inside.len(),
                mean,
                sd,
            })
        })
        .collect()
}

/// The box sides of `records`, increasing.
fn boxes(records: &[Record]) -> Vec<f64> {
    let mut b: Vec<f64> = records.iter().map(|r| r.box_len).collect();
    b.sort_by(f64::total_cmp);
    b.dedup();
    b
}

/// Mean and sample standard deviation; `None` below two values.
fn mean_sd(v: &[f64]) -> Option<(f64, f64)> {
    if v.len() < 2 {
        return None;
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    Some((mean, var.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::threshold::sequence::Step;

    /// A truth record of box `l` whose steps are `(n, spans, largest)`.
    fn record(l: f64, critical: usize, steps: &[(usize, bool, usize)]) -> Record {
        let mut r: Record = serde_json::from_value(serde_json::json!({
            "box": l, "index": 0, "seed": 1, "contact_critical": 10,
            "rigid_critical": critical, "steps": [], "fresh": null, "fixed": [],
            "contacts": [], "seconds": 0.0
        }))
        .expect("a record");
        r.steps = steps
            .iter()
            .map(|&(n, spans, largest)| Step {
                largest: Some(largest),
                ..Step::new(n, spans, usize::from(spans))
            })
            .collect();
        r
    }

    #[test]
    fn the_jump_is_the_share_at_the_critical_number_minus_one_rod_below() {
        // Box 2: jumps 40/100 - 9/99 and 50/101 - 20/100; box 3 has one
        // sequence without the step below, which is left out.
        let records = vec![
            record(
                2.0,
                100,
                &[(120, true, 70), (99, false, 9), (100, true, 40)],
            ),
            record(2.0, 101, &[(100, false, 20), (101, true, 50)]),
            record(3.0, 300, &[(300, true, 90)]),
        ];
        let j = jumps(&records);
        assert_eq!(j.len(), 1);
        let d: [f64; 2] = [0.4 - 9.0 / 99.0, 50.0 / 101.0 - 0.2];
        let mean = (d[0] + d[1]) / 2.0;
        let sd = ((d[0] - mean).powi(2) + (d[1] - mean).powi(2)).sqrt();
        assert_eq!((j[0].box_len, j[0].sequences), (2.0, 2));
        assert!((j[0].mean - mean).abs() < 1e-12);
        assert!((j[0].sd - sd).abs() < 1e-12);
        assert!((j[0].half_width - 1.96 * sd / 2f64.sqrt()).abs() < 1e-12);
        assert!((j[0].at_critical - (0.4 + 50.0 / 101.0) / 2.0).abs() < 1e-12);
        assert_eq!((j[0].min, j[0].max), (d[1].min(d[0]), d[1].max(d[0])));
    }

    #[test]
    fn shares_bin_the_spanning_steps_by_density() {
        // Box 2 (volume 8): spanning steps at 80, 88 and 96 rods (densities
        // 10, 11, 12) with shares 0.5, 0.25 and 0.75; the step that does not
        // span is no point. Two bins: [10, 11) and [11, 12].
        let records = vec![
            record(2.0, 80, &[(80, true, 40), (79, false, 1)]),
            record(2.0, 88, &[(88, true, 22), (96, true, 72)]),
        ];
        let s = shares(&records, 2.0, 2);
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].steps, s[0].mean, s[0].density), (1, 0.5, 10.5));
        assert_eq!((s[1].steps, s[1].mean, s[1].density), (2, 0.5, 11.5));
        assert!((s[1].sd - 0.25f64.hypot(0.25) / 1.0f64.sqrt()).abs() < 1e-12);
        assert!(shares(&records, 3.0, 2).is_empty());
    }
}
