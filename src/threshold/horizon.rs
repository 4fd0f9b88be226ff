//! The motif horizon: how 3D-RGC's bias against the exact truth changes as
//! its motif set grows. Each variant is a finished study of the truth
//! study's own sequences (same aspect ratio and seed) with some rule files;
//! its paired bias against truth, its CPU per sequence, its number of rules
//! and its largest motif (in nodes, and among rods-only motifs in rods) are
//! read back, and the rods-only series (base, rods up to 8, up to 10) is
//! extrapolated to the motif size that would halve the base set's bias.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::fss::Estimate;
use super::paired::{self, Difference};
use super::sequence::{Kind, Record};
use super::study::{self, MotifSet, StudySpec};
use crate::engine::CompiledRule;
use crate::output::{self, cell};
use crate::rule_file;
use crate::{Error, Result};

/// The largest rods-only motif the base motifs cover: the audit finds no
/// rigid rods-only pattern of up to 5 rods that they miss.
pub const BASE_RODS: usize = 5;

/// One variant measured against truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Variant {
    pub gamma: f64,
    /// The rule files' names joined by `+`, or `base`.
    pub label: String,
    pub study: String,
    pub rules: usize,
    /// The most nodes (rods or bodies) of any loaded rule, and of the rods-only ones.
    pub largest_nodes: usize,
    pub largest_rods: usize,
    /// Whether every loaded rule is rods-only (the series extrapolated).
    pub rods_only: bool,
    /// Its critical density minus truth's, over all shared sequences and per box.
    pub bias: Difference,
    pub boxes: Vec<Difference>,
    /// CPU seconds per sequence (the records' process CPU summed over the
    /// shared sequences' boxes), and truth's on the same sequences.
    pub cpu_per_sequence: f64,
    pub truth_cpu_per_sequence: f64,
}

/// The rods-only series of one aspect ratio, fitted.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Trend {
    pub gamma: f64,
    /// `(largest rods-only motif, relative bias)` of the series, by size.
    pub points: Vec<(usize, f64)>,
    /// The bias falls by this share of truth's density per added motif
    /// rod, from the smallest to the largest size (a straight line).
    pub slope: f64,
    /// The motif size at which that line reaches half the smallest
    /// size's bias; `None` when the bias does not fall.
    pub halving_size_linear: Option<f64>,
    /// The same for an exponential decay through the two ends (the bias
    /// halves every this many added rods); `None` when it does not fall.
    pub halving_rods_exponential: Option<f64>,
}

/// A finished study with its records.
fn read(dir: &Path) -> Result<(StudySpec, Vec<Record>)> {
    let spec = study::read_spec(dir)?;
    let records = study::in_study_order(&spec, study::read_records(dir, &spec)?);
    Ok((spec, records))
}

/// The rules a variant study was made with, loaded from its files and
/// checked against the study's digest (a changed file would mislabel it).
fn motifs(dir: &Path, set: &MotifSet) -> Result<Vec<CompiledRule>> {
    let files: Vec<PathBuf> = set.files.iter().map(PathBuf::from).collect();
    let rules = rule_file::load_rules(&files)?;
    let now = MotifSet::of(&rules, &files);
    if now.digest != set.digest {
        return Err(Error::Parameter(format!(
            "{}: its rule files {:?} now hold other rules (digest {} against the study's {})",
            dir.display(),
            set.files,
            now.digest,
            set.digest
        )));
    }
    Ok(rules.iter().map(CompiledRule::new).collect())
}

/// CPU seconds per record over the records of `boxes`.
fn cpu_per_sequence(records: &[Record], boxes: &[f64]) -> f64 {
    let chosen: Vec<&Record> = records
        .iter()
        .filter(|r| boxes.contains(&r.box_len))
        .collect();
    let total: f64 = chosen
        .iter()
        .map(|r| r.cpu_seconds.unwrap_or(r.seconds))
        .sum();
    total / chosen.len().max(1) as f64
}

/// Measures every variant study in `variants` against the truth study of
/// its aspect ratio among `truths`.
pub fn measure(truths: &[PathBuf], variants: &[PathBuf]) -> Result<Vec<Variant>> {
    let truths: Vec<(PathBuf, StudySpec, Vec<Record>)> = truths
        .iter()
        .map(|d| read(d).map(|(s, r)| (d.clone(), s, r)))
        .collect::<Result<_>>()?;
    if let Some((d, s, _)) = truths.iter().find(|(_, s, _)| s.kind != Kind::Truth) {
        return Err(Error::Parameter(format!(
            "{} is a {:?} study, not a truth study (--kind truth)",
            d.display(),
            s.kind
        )));
    }
    variants
        .iter()
        .map(|dir| {
            let (spec, records) = read(dir)?;
            let Some((_, tspec, trecords)) = truths
                .iter()
                .find(|(_, t, _)| t.gamma == spec.gamma && t.seed == spec.seed)
            else {
                return Err(Error::Parameter(format!(
                    "{}: no truth study of gamma {} and seed {} was given",
                    dir.display(),
                    spec.gamma,
                    spec.seed
                )));
            };
            let c = paired::compare((tspec, trecords), (&spec, &records))?;
            let rules = motifs(dir, &spec.motifs)?;
            let stems: Vec<String> = spec
                .motifs
                .files
                .iter()
                .map(|f| {
                    Path::new(f)
                        .file_stem()
                        .map_or(f.clone(), |s| s.to_string_lossy().into_owned())
                })
                .collect();
            let shared: Vec<f64> = c.boxes.iter().filter_map(|b| b.box_len).collect();
            Ok(Variant {
                gamma: spec.gamma,
                label: if stems.is_empty() {
                    "base".into()
                } else {
                    stems.join("+")
                },
                study: dir.display().to_string(),
                rules: rules.len(),
                largest_nodes: rules.iter().map(|r| r.n_nodes()).max().unwrap_or(0),
                largest_rods: rules
                    .iter()
                    .filter(|r| r.rods_only())
                    .map(|r| r.n_nodes())
                    .max()
                    .unwrap_or(BASE_RODS)
                    .max(BASE_RODS),
                rods_only: rules.iter().all(|r| r.rods_only()),
                bias: c.all,
                boxes: c.boxes,
                cpu_per_sequence: cpu_per_sequence(&records, &shared),
                truth_cpu_per_sequence: cpu_per_sequence(trecords, &shared),
            })
        })
        .collect()
}

/// The rods-only series of each aspect ratio (two sizes or more), fitted.
pub fn trends(variants: &[Variant]) -> Vec<Trend> {
    let mut gammas: Vec<f64> = variants.iter().map(|v| v.gamma).collect();
    gammas.sort_by(f64::total_cmp);
    gammas.dedup();
    gammas
        .into_iter()
        .filter_map(|gamma| {
            let mut points: Vec<(usize, f64)> = variants
                .iter()
                .filter(|v| v.gamma == gamma && v.rods_only)
                .map(|v| (v.largest_rods, v.bias.relative.value))
                .collect();
            points.sort_by_key(|p| p.0);
            points.dedup_by_key(|p| p.0);
            let (&(n0, b0), &(n1, b1)) = (points.first()?, points.last()?);
            if n1 == n0 {
                return None;
            }
            let slope = (b0 - b1) / (n1 - n0) as f64;
            let falls = b1 < b0 && b1 > 0.0;
            Some(Trend {
                gamma,
                slope,
                halving_size_linear: falls.then(|| n0 as f64 + b0 / 2.0 / slope),
                halving_rods_exponential: falls
                    .then(|| (n1 - n0) as f64 * std::f64::consts::LN_2 / (b0 / b1).ln()),
                points,
            })
        })
        .collect()
}

/// One CSV row: a variant over all boxes.
#[derive(Serialize)]
struct Row<'a> {
    gamma: f64,
    label: &'a str,
    rules: usize,
    largest_nodes: usize,
    largest_rods: usize,
    sequences: usize,
    #[serde(serialize_with = "cell::fixed::<4, _>")]
    bias: f64,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    bias_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    bias_hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<5, _>")]
    relative: f64,
    below: usize,
    #[serde(serialize_with = "cell::fixed::<3, _>")]
    cpu_per_sequence: f64,
    #[serde(serialize_with = "cell::fixed::<3, _>")]
    truth_cpu_per_sequence: f64,
    study: &'a str,
}

fn row(v: &Variant) -> Row<'_> {
    let Estimate { value, lo, hi } = v.bias.mean;
    Row {
        gamma: v.gamma,
        label: &v.label,
        rules: v.rules,
        largest_nodes: v.largest_nodes,
        largest_rods: v.largest_rods,
        sequences: v.bias.sequences,
        bias: value,
        bias_lo: lo,
        bias_hi: hi,
        relative: v.bias.relative.value,
        below: v.bias.below,
        cpu_per_sequence: v.cpu_per_sequence,
        truth_cpu_per_sequence: v.truth_cpu_per_sequence,
        study: &v.study,
    }
}

/// Writes `PREFIX.json` (with the command that made it) and `PREFIX.csv`.
pub fn write(
    prefix: &Path,
    variants: &[Variant],
    trends: &[Trend],
    command: &str,
) -> Result<Vec<PathBuf>> {
    let with = |ext: &str| output::with_extension(prefix, ext);
    let (json, csv) = (with("json"), with("csv"));
    let doc = serde_json::json!({ "command": command, "variants": variants, "trends": trends });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("variants serialize"),
    )?;
    output::write_csv(&csv, variants.iter().map(row).collect::<Vec<_>>())?;
    Ok(vec![json, csv])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn variant(largest_rods: usize, relative: f64, rods_only: bool) -> Variant {
        let d = Difference {
            box_len: None,
            sequences: 10,
            mean: Estimate {
                value: relative * 30.0,
                lo: None,
                hi: None,
            },
            mean_vex: Estimate {
                value: 0.0,
                lo: None,
                hi: None,
            },
            reference_mean: 30.0,
            relative: Estimate {
                value: relative,
                lo: None,
                hi: None,
            },
            below: 0,
            above: 10,
        };
        Variant {
            gamma: 23.0,
            label: String::new(),
            study: String::new(),
            rules: 0,
            largest_nodes: largest_rods,
            largest_rods,
            rods_only,
            bias: d,
            boxes: Vec::new(),
            cpu_per_sequence: 0.0,
            truth_cpu_per_sequence: 0.0,
        }
    }

    #[test]
    fn the_rods_only_series_extrapolates_to_the_halving_size() {
        // 0.18 at 5 rods, 0.16 at 10: 0.004 per rod, so half (0.09) at 27.5
        // rods on the line; the exponential halves every 5 ln 2 / ln(9/8).
        let v = [
            variant(5, 0.18, true),
            variant(10, 0.16, true),
            variant(8, 0.01, false),
        ];
        let [t]: [Trend; 1] = trends(&v).try_into().unwrap();
        assert_eq!(t.points, vec![(5, 0.18), (10, 0.16)]);
        assert!((t.slope - 0.004).abs() < 1e-12);
        assert!((t.halving_size_linear.unwrap() - 27.5).abs() < 1e-9);
        let e = 5.0 * std::f64::consts::LN_2 / (0.18f64 / 0.16).ln();
        assert!((t.halving_rods_exponential.unwrap() - e).abs() < 1e-9);
        // A bias that does not fall has no halving size.
        let flat = [variant(5, 0.18, true), variant(10, 0.18, true)];
        let [t]: [Trend; 1] = trends(&flat).try_into().unwrap();
        assert_eq!(
            (t.halving_size_linear, t.halving_rods_exponential),
            (None, None)
        );
    }
}
