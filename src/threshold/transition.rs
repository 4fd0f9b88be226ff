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
use crate::math::stats::{self, line, mean_sd, percentile_interval};
use crate::{Error, Result, output};

/// Bootstrap resamples of the sequences of each box, drawn from stream `b`
/// of a fixed seed: the intervals are the same on every run.
const RESAMPLES: usize = 2000;
const BOOTSTRAP_SEED: u64 = 1;

/// Width of a bin of the jump's histogram, as a share of the rods.
pub const HISTOGRAM_BIN: f64 = 0.01;

/// The decay of the mean jump is fitted over every box and over this many
/// of the largest boxes (where there are more).
const LARGEST_BOXES: usize = 3;

/// The transition of one aspect ratio: one truth study, or several whose
/// boxes differ (the large boxes run apart from the small ones).
#[derive(Clone, Debug, Serialize)]
pub struct Transition {
    pub study: String,
    pub gamma: f64,
    pub jumps: Vec<Jump>,
    /// How the mean jump falls with the box: a power law fitted over every
    /// box, then over the largest boxes alone (none with fewer than three
    /// boxes).
    pub decay: Vec<Decay>,
    /// `P_inf` above the threshold, in the box asked for (by default the
    /// largest).
    pub shares: Vec<Share>,
    /// The Binder cumulant of the largest cluster's share at the densities
    /// of fixed-protocol truth studies, per box.
    pub binder: Vec<Binder>,
    /// How the mean critical density still moves over the largest boxes
    /// (none with fewer than three boxes).
    pub drift: Option<Drift>,
}

/// The mean of the sequences' own critical densities against the box side
/// over the three largest boxes, as a straight line. Where the
/// transition is discontinuous, finite-size scaling with an exponent `nu`
/// does not apply; the mean critical density of the largest boxes is then
/// the threshold's estimate, and a slope whose interval holds 0 says it no
/// longer moves at these sizes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Drift {
    pub boxes: Vec<f64>,
    /// Rods per unit volume per rod length of box side, with its 95%
    /// bootstrap interval (sequences resampled within each box).
    pub slope: f64,
    pub interval: (f64, f64),
}

/// The Binder cumulant `U = 1 - <P^4> / (3 <P^2>^2)` of `P`, the largest
/// true cluster's share of the rods, at one density in one box. Where `P`
/// is narrowly spread about a finite value (deep in the rigid phase) `U`
/// tends to 2/3; curves of `U` against density for growing boxes cross at
/// a continuous transition, and dip below zero, deeper as the box grows,
/// where two phases coexist (a discontinuous one).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Binder {
    pub box_len: f64,
    pub density: f64,
    pub sequences: usize,
    /// The mean of `P`.
    pub mean: f64,
    pub cumulant: f64,
    /// The 95% bootstrap interval of the cumulant.
    pub interval: (f64, f64),
}

/// The mean jump against the box side as `mean jump ~ L^(-x)`: a
/// continuous transition has `x = beta / nu > 0`; a discontinuous one a
/// finite limit, so `x` falls towards 0 over the largest boxes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Decay {
    pub boxes: Vec<f64>,
    /// The exponent `x` (minus the slope of the log of the mean jump against ln L), with
    /// its 95% bootstrap interval (sequences resampled within each box).
    pub exponent: f64,
    pub interval: (f64, f64),
    pub r2: f64,
}

/// The transitions of the truth studies in `dirs`, one per aspect ratio
/// (studies of one aspect ratio must not share a box), with `P_inf` in
/// `bins` bins for box `box_len` (each aspect ratio's largest box with
/// records if `None`).
pub fn of_dirs(dirs: &[PathBuf], box_len: Option<f64>, bins: usize) -> Result<Vec<Transition>> {
    let mut groups: Vec<(f64, Vec<String>, Vec<Record>)> = Vec::new();
    for dir in dirs {
        let (gamma, records) = truth_records(dir)?;
        let name = dir.display().to_string();
        match groups.iter_mut().find(|g| g.0 == gamma) {
            Some((_, names, all)) => {
                // A box of nested records, or of fixed ones, comes from one study.
                let of = |records: &[Record], fixed: bool| -> Vec<f64> {
                    let kept: Vec<Record> = records
                        .iter()
                        .filter(|r| r.fixed.is_empty() != fixed)
                        .cloned()
                        .collect();
                    boxes(&kept)
                };
                let shared = [false, true].into_iter().find_map(|fixed| {
                    let theirs = of(all, fixed);
                    of(&records, fixed).into_iter().find(|l| theirs.contains(l))
                });
                if let Some(l) = shared {
                    return Err(Error::Parameter(format!(
                        "box {l} of gamma {gamma} is in both {} and {name}: give each box once",
                        names.join(" and ")
                    )));
                }
                names.push(name);
                all.extend(records);
            }
            None => groups.push((gamma, vec![name], records)),
        }
    }
    groups
        .into_iter()
        .map(|(gamma, names, records)| {
            let present = boxes(&records);
            let largest = *present.last().expect("each study has records");
            let l = box_len.unwrap_or(largest);
            if !present.contains(&l) {
                return Err(Error::Parameter(format!(
                    "box {l} has no records in {} (boxes with records: {present:?})",
                    names.join(" and ")
                )));
            }
            let per_box = by_box(&records);
            let jumps = jumps_of(&per_box);
            Ok(Transition {
                study: names.join(" + "),
                gamma,
                decay: decay(&per_box, &jumps),
                drift: drift(&per_box),
                jumps,
                shares: shares(&records, l, bins),
                binder: binder(&records),
            })
        })
        .collect()
}

/// A truth study's aspect ratio and records.
fn truth_records(dir: &Path) -> Result<(f64, Vec<Record>)> {
    let spec = study::read_spec(dir)?;
    if spec.kind != Kind::Truth {
        return Err(Error::Parameter(format!(
            "{} is a {:?} study: the order of the transition needs truth's largest clusters (a --kind truth study)",
            dir.display(),
            spec.kind
        )));
    }
    let records: Vec<Record> = study::read_records(dir, &spec)?.into_values().collect();
    if records.is_empty() {
        return Err(Error::Analysis(format!(
            "{} has no records yet",
            dir.display()
        )));
    }
    Ok((spec.gamma, records))
}

/// Writes `PREFIX.json` (with the command that made it), `PREFIX.csv`
/// (one row per aspect ratio and box: the jump), `PREFIX.histogram.csv`
/// (the jump's histogram per box) and, where fixed-protocol studies give
/// one, `PREFIX.binder.csv` (the Binder cumulant per box and density).
pub fn write(prefix: &Path, all: &[Transition], command: &str) -> Result<Vec<PathBuf>> {
    let with = |ext: &str| output::with_extension(prefix, ext);
    let (json, csv, histogram) = (with("json"), with("csv"), with("histogram.csv"));
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
        jump_lo: f64,
        jump_hi: f64,
        jump_min: f64,
        jump_max: f64,
        share_before: f64,
        share_at_critical: f64,
        /// Sequences whose records carry the strain rank, and those of
        /// them with all six strains resisted one rod below and at the
        /// critical rod.
        strain_known: usize,
        solid_before: usize,
        solid_at: usize,
        critical_density: f64,
        critical_lo: f64,
        critical_hi: f64,
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
            jump_lo: j.interval.0,
            jump_hi: j.interval.1,
            jump_min: j.min,
            jump_max: j.max,
            share_before: j.before,
            share_at_critical: j.at_critical,
            strain_known: j.strain_at.iter().sum(),
            solid_before: j.strain_before[6],
            solid_at: j.strain_at[6],
            critical_density: j.critical_density,
            critical_lo: j.critical_interval.0,
            critical_hi: j.critical_interval.1,
        })
    });
    output::write_csv(&csv, rows)?;
    #[derive(Serialize)]
    struct Bin {
        gamma: f64,
        box_len: f64,
        jump_from: f64,
        jump_to: f64,
        sequences: usize,
    }
    let bins = all.iter().flat_map(|t| {
        t.jumps.iter().flat_map(move |j| {
            j.histogram.iter().enumerate().map(move |(b, &count)| Bin {
                gamma: t.gamma,
                box_len: j.box_len,
                jump_from: b as f64 * HISTOGRAM_BIN,
                jump_to: (b + 1) as f64 * HISTOGRAM_BIN,
                sequences: count,
            })
        })
    });
    output::write_csv(&histogram, bins)?;
    let mut files = vec![json, csv, histogram];
    if all.iter().any(|t| !t.binder.is_empty()) {
        #[derive(Serialize)]
        struct Cell {
            gamma: f64,
            box_len: f64,
            density: f64,
            sequences: usize,
            mean_share: f64,
            cumulant: f64,
            cumulant_lo: f64,
            cumulant_hi: f64,
        }
        let cells = all.iter().flat_map(|t| {
            t.binder.iter().map(move |b| Cell {
                gamma: t.gamma,
                box_len: b.box_len,
                density: b.density,
                sequences: b.sequences,
                mean_share: b.mean,
                cumulant: b.cumulant,
                cumulant_lo: b.interval.0,
                cumulant_hi: b.interval.1,
            })
        });
        let path = with("binder.csv");
        output::write_csv(&path, cells)?;
        files.push(path);
    }
    Ok(files)
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
    /// The 95% bootstrap interval of the mean (percentiles of
    /// 2,000 resamples of the sequences).
    pub interval: (f64, f64),
    pub min: f64,
    pub max: f64,
    /// Mean fraction of the rods in the largest cluster one rod below the
    /// critical number, and at it (what the spanning cluster holds when it
    /// first spans).
    pub before: f64,
    pub at_critical: f64,
    /// Sequences by jump, in bins of [`HISTOGRAM_BIN`] from 0.
    pub histogram: Vec<usize>,
    /// Sequences by strain rank (0 to 6) one rod below the critical
    /// number and at it, among those whose records carry it.
    pub strain_before: [usize; 7],
    pub strain_at: [usize; 7],
    /// The mean of the sequences' own critical densities (rods per unit
    /// volume), an estimate of the threshold that assumes no exponent, with
    /// its 95% bootstrap interval.
    pub critical_density: f64,
    pub critical_interval: (f64, f64),
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

/// One sequence at its critical rod: the largest cluster's share one rod
/// below and at it, and the strain ranks there when known.
struct AtCritical {
    before: f64,
    at: f64,
    strains: Option<(u8, u8)>,
    /// The critical number over the box volume.
    density: f64,
}

impl AtCritical {
    fn of(r: &Record) -> Option<Self> {
        let n = r.rigid_critical?;
        let (below, at) = r.jump()?;
        let strain = |m| {
            r.steps
                .iter()
                .find(|s| s.n == m)
                .and_then(|s| s.strain_rank)
        };
        Some(AtCritical {
            before: below as f64 / (n - 1) as f64,
            at: at as f64 / n as f64,
            strains: strain(n - 1).zip(strain(n)),
            density: n as f64 / r.box_len.powi(3),
        })
    }

    fn jump(&self) -> f64 {
        self.at - self.before
    }
}

/// Each box's sequences at their critical rods, boxes in increasing order.
fn by_box(records: &[Record]) -> Vec<(f64, Vec<AtCritical>)> {
    boxes(records)
        .into_iter()
        .map(|l| {
            let seqs = records
                .iter()
                .filter(|r| r.box_len == l)
                .filter_map(AtCritical::of)
                .collect();
            (l, seqs)
        })
        .collect()
}

/// The bootstrap over the sequences of each group: `f` on [`RESAMPLES`]
/// resamples ([`stats::bootstrap`]).
fn resampled<T>(values: &[Vec<f64>], f: impl FnMut(&[Vec<f64>]) -> Option<T>) -> Vec<T> {
    stats::bootstrap(values, RESAMPLES, BOOTSTRAP_SEED, f)
}

/// The mean of `v`.
fn average(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// The jump of each box of `records` (boxes in increasing order); a box
/// with fewer than two sequences that have both steps is left out.
pub fn jumps(records: &[Record]) -> Vec<Jump> {
    jumps_of(&by_box(records))
}

/// [`jumps`] of the sequences at their critical rods, by box.
fn jumps_of(per_box: &[(f64, Vec<AtCritical>)]) -> Vec<Jump> {
    per_box
        .iter()
        .filter_map(|&(l, ref seqs)| {
            let d: Vec<f64> = seqs.iter().map(AtCritical::jump).collect();
            let (mean, sd) = (d.len() >= 2).then(|| mean_sd(&d))?;
            let interval = mean_interval(&d);
            let densities: Vec<f64> = seqs.iter().map(|s| s.density).collect();
            let max = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let mut histogram = vec![0; (max / HISTOGRAM_BIN).floor() as usize + 1];
            for x in &d {
                histogram[(x.max(0.0) / HISTOGRAM_BIN).floor() as usize] += 1;
            }
            let (mut strain_before, mut strain_at) = ([0; 7], [0; 7]);
            for (b, a) in seqs.iter().filter_map(|s| s.strains) {
                strain_before[usize::from(b.min(6))] += 1;
                strain_at[usize::from(a.min(6))] += 1;
            }
            let n = seqs.len() as f64;
            Some(Jump {
                box_len: l,
                sequences: d.len(),
                mean,
                sd,
                half_width: 1.96 * sd / n.sqrt(),
                interval,
                min: d.iter().copied().fold(f64::INFINITY, f64::min),
                max,
                before: seqs.iter().map(|s| s.before).sum::<f64>() / n,
                at_critical: seqs.iter().map(|s| s.at).sum::<f64>() / n,
                histogram,
                strain_before,
                strain_at,
                critical_density: average(&densities),
                critical_interval: mean_interval(&densities),
            })
        })
        .collect()
}

/// A statistic `f` of the means of the groups `per_box`, and its 95%
/// bootstrap interval (each group resampled on its own).
fn of_means(per_box: &[Vec<f64>], f: impl Fn(&[f64]) -> Option<f64>) -> Option<(f64, (f64, f64))> {
    let means = |groups: &[Vec<f64>]| groups.iter().map(|v| average(v)).collect::<Vec<_>>();
    let value = f(&means(per_box))?;
    let mut boot = resampled(per_box, |r| f(&means(r)));
    Some((value, percentile_interval(&mut boot, 0.95)?))
}

/// The 95% bootstrap interval of the mean of `v`.
fn mean_interval(v: &[f64]) -> (f64, f64) {
    of_means(&[v.to_vec()], |m| Some(m[0]))
        .expect("resamples")
        .1
}

/// The [`Drift`] of the mean critical density over the [`LARGEST_BOXES`]
/// largest boxes of `per_box` that have at least two sequences.
fn drift(per_box: &[(f64, Vec<AtCritical>)]) -> Option<Drift> {
    let kept: Vec<(f64, Vec<f64>)> = per_box
        .iter()
        .filter(|(_, seqs)| seqs.len() >= 2)
        .map(|(l, seqs)| (*l, seqs.iter().map(|s| s.density).collect()))
        .collect();
    let largest = kept.get(kept.len().checked_sub(LARGEST_BOXES)?..)?;
    let lens: Vec<f64> = largest.iter().map(|v| v.0).collect();
    let values: Vec<Vec<f64>> = largest.iter().map(|v| v.1.clone()).collect();
    let (slope, interval) = of_means(&values, |means| {
        let points: Vec<(f64, f64)> = lens.iter().copied().zip(means.iter().copied()).collect();
        line(&points).map(|f| f.beta[1])
    })?;
    Some(Drift {
        boxes: lens,
        slope,
        interval,
    })
}

/// The Binder cumulant of each box and density of the fixed-protocol
/// records among `records` (steps without truth, below contact spanning,
/// are left out).
pub fn binder(records: &[Record]) -> Vec<Binder> {
    let mut cells: Vec<((f64, usize), Vec<f64>)> = Vec::new();
    for r in records {
        for s in &r.fixed {
            let Some(largest) = s.largest else { continue };
            let p = largest as f64 / s.n as f64;
            match cells.iter_mut().find(|c| c.0 == (r.box_len, s.n)) {
                Some(c) => c.1.push(p),
                None => cells.push(((r.box_len, s.n), vec![p])),
            }
        }
    }
    cells.sort_by(|a, b| a.0.0.total_cmp(&b.0.0).then(a.0.1.cmp(&b.0.1)));
    let cumulant = |p: &[f64]| {
        let moment = |k: i32| p.iter().map(|x| x.powi(k)).sum::<f64>() / p.len() as f64;
        let (m2, m4) = (moment(2), moment(4));
        (m2 > 0.0).then(|| 1.0 - m4 / (3.0 * m2 * m2))
    };
    cells
        .into_iter()
        .filter(|c| c.1.len() >= 2)
        .filter_map(|((l, n), p)| {
            let u = cumulant(&p)?;
            let mut boot = resampled(std::slice::from_ref(&p), |r| cumulant(&r[0]));
            Some(Binder {
                box_len: l,
                density: n as f64 / l.powi(3),
                sequences: p.len(),
                mean: average(&p),
                cumulant: u,
                interval: percentile_interval(&mut boot, 0.95)?,
            })
        })
        .collect()
}

/// The power-law decay of the mean jump over every box of `jumps`, and
/// over the [`LARGEST_BOXES`] largest where there are more boxes than that.
fn decay(per_box: &[(f64, Vec<AtCritical>)], jumps: &[Jump]) -> Vec<Decay> {
    let values: Vec<(f64, Vec<f64>)> = per_box
        .iter()
        .filter(|(l, _)| jumps.iter().any(|j| j.box_len == *l))
        .map(|(l, seqs)| (*l, seqs.iter().map(AtCritical::jump).collect()))
        .collect();
    power_decay(&values)
}

/// A per-sequence quantity's mean as `~ L^(-x)` over boxes (`values`: each
/// box side with its sequences' values, boxes increasing): over every box
/// when there are at least three, and over the three largest
/// where there are more boxes than that. None where a mean is not
/// positive.
pub fn power_decay(values: &[(f64, Vec<f64>)]) -> Vec<Decay> {
    decays(values, Some, positive_ln)
}

/// The same for the geometric mean, for a positive quantity that spans
/// orders of magnitude between sequences, whose arithmetic mean a few of
/// them decide. None where a value is not positive.
pub fn geometric_decay(values: &[(f64, Vec<f64>)]) -> Vec<Decay> {
    decays(values, positive_ln, Some)
}

/// The logarithm of a positive number.
fn positive_ln(x: f64) -> Option<f64> {
    (x > 0.0).then(|| x.ln())
}

/// The decays of the boxes' means of `value` of each sequence's value,
/// each mean's logarithm given by `log`.
fn decays(
    values: &[(f64, Vec<f64>)],
    value: fn(f64) -> Option<f64>,
    log: fn(f64) -> Option<f64>,
) -> Vec<Decay> {
    let fit = |values: &[(f64, Vec<f64>)]| -> Option<Decay> {
        let lens: Vec<f64> = values.iter().map(|v| v.0).collect();
        let slope = |means: &[f64]| -> Option<(f64, f64)> {
            let points: Vec<(f64, f64)> = lens
                .iter()
                .zip(means)
                .map(|(l, &m)| Some((l.ln(), log(m)?)))
                .collect::<Option<_>>()?;
            line(&points).map(|f| (-f.beta[1], f.r2))
        };
        let per_box: Vec<Vec<f64>> = values
            .iter()
            .map(|v| v.1.iter().map(|&x| value(x)).collect::<Option<Vec<f64>>>())
            .collect::<Option<_>>()?;
        let (exponent, interval) = of_means(&per_box, |m| slope(m).map(|s| s.0))?;
        let means: Vec<f64> = per_box.iter().map(|v| average(v)).collect();
        let r2 = slope(&means)?.1;
        Some(Decay {
            boxes: lens,
            exponent,
            interval,
            r2,
        })
    };
    let mut out = Vec::new();
    if values.len() >= 3 {
        out.extend(fit(values));
    }
    if values.len() > LARGEST_BOXES {
        out.extend(fit(&values[values.len() - LARGEST_BOXES..]));
    }
    out
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
            let (mean, sd) = (!inside.is_empty()).then(|| mean_sd(&inside))?;
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

    /// A record of box `l` that jumps from `below` to `at` rods in the
    /// largest cluster at critical number 100, with strain ranks.
    fn jumping(l: f64, below: usize, at: usize, strains: (u8, u8)) -> Record {
        let mut r = record(l, 100, &[(99, false, below), (100, true, at)]);
        r.steps[0].strain_rank = Some(strains.0);
        r.steps[1].strain_rank = Some(strains.1);
        r
    }

    #[test]
    fn jumps_count_their_histogram_and_strain_ranks() {
        // Jumps 0.30 - 0.00, 0.31 - 0.00 and 0.05 - 0.00 (below: 0 rods).
        let records = vec![
            jumping(4.0, 0, 30, (0, 6)),
            jumping(4.0, 0, 31, (0, 0)),
            jumping(4.0, 0, 5, (3, 6)),
        ];
        let j = &jumps(&records)[0];
        assert_eq!(j.histogram.len(), 32);
        assert_eq!(j.histogram.iter().sum::<usize>(), 3);
        assert_eq!(
            (j.histogram[5], j.histogram[30], j.histogram[31]),
            (1, 1, 1)
        );
        assert_eq!(j.strain_before, [2, 0, 0, 1, 0, 0, 0]);
        assert_eq!(j.strain_at, [1, 0, 0, 0, 0, 0, 2]);
        assert_eq!((j.before, j.at_critical), (0.0, 0.66 / 3.0));
        // The bootstrap interval lies within the jumps and holds the mean;
        // it is the same on every call.
        let (lo, hi) = j.interval;
        assert!(
            0.05 <= lo && lo < j.mean && j.mean < hi && hi <= 0.31,
            "{lo} {hi}"
        );
        assert_eq!(jumps(&records)[0].interval, j.interval);
    }

    #[test]
    fn the_decay_fits_the_mean_jump_as_a_power_of_the_box() {
        // Mean jumps 0.2 (L / 4)^-1 at L = 4, 5, 8, 10: exponent 1 over all
        // boxes and over the three largest, with no spread to resample.
        let records: Vec<Record> = [4.0, 5.0, 8.0, 10.0]
            .iter()
            .flat_map(|&l: &f64| {
                let at = (20.0 * 4.0 / l).round() as usize;
                [jumping(l, 0, at, (0, 0)), jumping(l, 0, at, (0, 0))]
            })
            .collect();
        let d = decay(&by_box(&records), &jumps(&records));
        assert_eq!(d.len(), 2);
        assert_eq!(d[0].boxes, vec![4.0, 5.0, 8.0, 10.0]);
        assert_eq!(d[1].boxes, vec![5.0, 8.0, 10.0]);
        for fit in &d {
            assert!((fit.exponent - 1.0).abs() < 1e-12, "{fit:?}");
            assert!((fit.interval.0 - 1.0).abs() < 1e-12 && (fit.interval.1 - 1.0).abs() < 1e-12);
            assert!(fit.r2 > 1.0 - 1e-12);
        }
        // Two boxes fit no decay.
        assert!(decay(&by_box(&records[..4]), &jumps(&records[..4])).is_empty());
    }

    #[test]
    fn the_critical_density_is_the_mean_of_the_sequences_and_drifts_by_a_line() {
        // Critical numbers n at L = 2, 3, 4, 5, two sequences each: densities
        // (12, 14), 9, 8 and 7 (n / L^3); over the three largest boxes the
        // mean falls by 1 per unit of L, with no spread to resample.
        let critical = |l: f64, n: usize| record(l, n, &[(n - 1, false, 0), (n, true, 5)]);
        let records = vec![
            critical(2.0, 96),
            critical(2.0, 112),
            critical(3.0, 243),
            critical(3.0, 243),
            critical(4.0, 512),
            critical(4.0, 512),
            critical(5.0, 875),
            critical(5.0, 875),
        ];
        let j = jumps(&records);
        let means: Vec<f64> = j.iter().map(|j| j.critical_density).collect();
        assert_eq!(means, vec![13.0, 9.0, 8.0, 7.0]);
        let (lo, hi) = j[0].critical_interval;
        assert!(
            (12.0..13.0).contains(&lo) && hi > 13.0 && hi <= 14.0,
            "{lo} {hi}"
        );
        assert_eq!(j[1].critical_interval, (9.0, 9.0));
        let d = drift(&by_box(&records)).expect("three boxes");
        assert_eq!(d.boxes, vec![3.0, 4.0, 5.0]);
        assert!((d.slope + 1.0).abs() < 1e-12, "{d:?}");
        assert!((d.interval.0 + 1.0).abs() < 1e-12 && (d.interval.1 + 1.0).abs() < 1e-12);
        // Two boxes have no drift.
        assert_eq!(drift(&by_box(&records[4..])), None);
    }

    #[test]
    fn the_binder_cumulant_is_two_thirds_for_one_value_and_one_third_for_two() {
        // Box 2 (volume 8), 80 rods: every sequence holds 40 (P = 1/2);
        // 96 rods: half hold none, half 48 (P = 0 or 1/2).
        let fixed = |largest: [usize; 2]| {
            let mut r = record(2.0, 80, &[]);
            r.rigid_critical = None;
            r.fixed = [(80, largest[0]), (96, largest[1])]
                .map(|(n, l)| Step {
                    largest: Some(l),
                    ..Step::new(n, l > 0, usize::from(l > 0))
                })
                .to_vec();
            r
        };
        let records = vec![
            fixed([40, 0]),
            fixed([40, 48]),
            fixed([40, 0]),
            fixed([40, 48]),
        ];
        let b = binder(&records);
        assert_eq!(b.len(), 2);
        assert_eq!((b[0].density, b[0].sequences, b[0].mean), (10.0, 4, 0.5));
        assert!((b[0].cumulant - 2.0 / 3.0).abs() < 1e-12);
        assert!((b[0].interval.0 - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!((b[1].density, b[1].mean), (12.0, 0.25));
        assert!((b[1].cumulant - 1.0 / 3.0).abs() < 1e-12);
        let (lo, hi) = b[1].interval;
        // A resample of one 48 in four has U = -1/3; of 48s alone, 2/3.
        assert!((-1.0 / 3.0 - 1e-12..1.0 / 3.0).contains(&lo), "{lo}");
        assert!(1.0 / 3.0 < hi && hi <= 2.0 / 3.0 + 1e-12, "{hi}");
        // Nested records have no fixed steps: no cumulant.
        assert!(binder(&[jumping(4.0, 0, 30, (0, 6))]).is_empty());
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
