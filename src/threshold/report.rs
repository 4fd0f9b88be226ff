//! From a finished study's records to its answers: finite-size scaling,
//! what motif order did, and the files a person reads (`summary.json`, CSV
//! tables, charts). Everything here is a function of the records alone, so
//! a resumed or sharded study reports exactly what an uninterrupted one does.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use super::fss::{self, BoxAlone, BoxData, Fss, FssOptions, Observation, Protocol, pi_curve};
use super::sequence::{Kind, Record};
use super::study::spec::StudySpec;
use crate::math::stats::mean_sd;
use crate::output::{self, cell};
use crate::rods::excluded_volume;
use crate::{Error, Result};

/// What motif order did to a study's compressions (MODEL §8: where
/// compression order breaks monotonicity).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OrderEffects {
    /// Compressions that found a spanning body with some run.
    pub spanning_compressions: usize,
    /// Fraction of single runs of those that found none: how often one run
    /// misses what `runs` runs find (0 with one run).
    pub single_run_miss_rate: Option<f64>,
    /// Nested: sequences checked by a fresh compression (no carried
    /// bodies) at their rigid critical number, and how many of those fresh
    /// compressions did not span although the bisection's did: the
    /// spanning body was found only thanks to bodies carried from a smaller
    /// system, a non-monotone step of a memoryless engine.
    pub fresh_checks: usize,
    pub fresh_misses: usize,
    /// Fixed: sequences whose spanning goes from yes back to no as the
    /// density grows, and the number of such steps.
    // Keeps its stored key, so existing summaries (`summary.json`) read back.
    #[serde(rename = "nonmonotone_realizations")]
    pub nonmonotone_sequences: usize,
    pub nonmonotone_steps: usize,
    /// Truth kind: sequences where truth was undecided before their
    /// critical number (left out of the analysis).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub undecided: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// The contact critical density of a box: its mean and spread over sequences.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxSummary {
    #[serde(rename = "box")]
    pub box_len: f64,
    // Keeps its stored key, so existing summaries (`summary.json`) read back.
    #[serde(rename = "realizations")]
    pub sequences: usize,
    /// Mean and standard deviation of the density at which each sequence
    /// first spans by contacts (exact, every protocol).
    pub contact_critical_mean: f64,
    pub contact_critical_sd: f64,
    /// Same for rigid spanning (rigid kind, nested).
    pub rigid_critical_mean: Option<f64>,
    pub rigid_critical_sd: Option<f64>,
}

/// Everything `summary.json` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub study: StudySpec,
    /// Isotropic excluded volume of a rod, and the threshold in units of
    /// `1 / V_ex` (the mean contact number it implies).
    pub excluded_volume: f64,
    pub threshold_times_vex: f64,
    pub boxes: Vec<BoxSummary>,
    pub fss: Fss,
    pub order: OrderEffects,
}

/// The `summary.json` of the finished study in `dir`.
pub fn read_summary(dir: &Path) -> Result<Summary> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::Study {
        path,
        reason: format!("not a study summary: {e}"),
    })
}

/// The observations finite-size scaling works on, one [`BoxData`] per box.
pub fn observations(spec: &StudySpec, records: &[Record]) -> Vec<BoxData> {
    spec.boxes
        .iter()
        .map(|&l| {
            let volume = l.powi(3);
            let observations = records
                .iter()
                .filter(|r| r.box_len == l)
                .map(|r| Observation {
                    critical: match spec.method {
                        Protocol::Nested => r.critical(spec.kind).map(|n| n as f64 / volume),
                        Protocol::Fixed => None,
                    },
                    // A step without a verdict (truth where the model has
                    // no realization) is no observation.
                    fixed: r
                        .fixed
                        .iter()
                        .filter(|s| !s.undecided)
                        .map(|s| (s.n as f64 / volume, s.spans))
                        .collect(),
                    contacts: r.contacts.clone(),
                    undecided: r.undecided.is_some(),
                })
                .collect();
            BoxData {
                box_len: l,
                observations,
            }
        })
        .collect()
}

/// What motif order did, from the records.
pub fn order_effects(spec: &StudySpec, records: &[Record]) -> OrderEffects {
    let mut o = OrderEffects::default();
    let (mut runs_spanning, mut runs_total) = (0usize, 0usize);
    for r in records {
        for s in r.steps.iter().chain(&r.fixed).chain(&r.fresh) {
            if s.spans && spec.kind == Kind::Rigid {
                o.spanning_compressions += 1;
                runs_spanning += s.runs_spanning;
                runs_total += spec.runs;
            }
        }
        o.undecided += usize::from(r.undecided.is_some());
        if let Some(fresh) = r.fresh {
            o.fresh_checks += 1;
            o.fresh_misses += usize::from(!fresh.spans);
        }
        let drops = r
            .fixed
            .windows(2)
            .filter(|w| w[0].spans && !w[1].spans)
            .count();
        o.nonmonotone_steps += drops;
        o.nonmonotone_sequences += usize::from(drops > 0);
    }
    o.single_run_miss_rate =
        (runs_total > 0 && spec.runs > 1).then(|| 1.0 - runs_spanning as f64 / runs_total as f64);
    o
}

/// Analyses a complete study.
pub fn summarize(spec: &StudySpec, records: &[Record], bootstrap: usize) -> Result<Summary> {
    let data = observations(spec, records);
    let opts = FssOptions {
        protocol: spec.method,
        bootstrap,
        seed: spec.seed,
        ..FssOptions::default()
    };
    let fss = fss::analyse(&data, &opts)?;
    let boxes = spec
        .boxes
        .iter()
        .map(|&l| {
            let volume = l.powi(3);
            let of_box: Vec<&Record> = records.iter().filter(|r| r.box_len == l).collect();
            let contact: Vec<f64> = of_box
                .iter()
                .map(|r| r.contact_critical as f64 / volume)
                .collect();
            let rigid: Vec<f64> = of_box
                .iter()
                .filter_map(|r| r.rigid_critical.map(|n| n as f64 / volume))
                .collect();
            let (cm, cs) = mean_sd(&contact);
            let rigid_stats = (!rigid.is_empty()).then(|| mean_sd(&rigid));
            BoxSummary {
                box_len: l,
                sequences: of_box.len(),
                contact_critical_mean: cm,
                contact_critical_sd: cs,
                rigid_critical_mean: rigid_stats.map(|s| s.0),
                rigid_critical_sd: rigid_stats.map(|s| s.1),
            }
        })
        .collect();
    let vex = excluded_volume(spec.gamma);
    Ok(Summary {
        study: spec.clone(),
        excluded_volume: vex,
        threshold_times_vex: fss.threshold.value * vex,
        boxes,
        order: order_effects(spec, records),
        fss,
    })
}

/// A row of `records.csv`: one sequence, densities to 6 places.
#[derive(Serialize)]
struct RecordRow {
    #[serde(rename = "box", serialize_with = "cell::display")]
    box_len: f64,
    index: u64,
    seed: u64,
    contact_critical: usize,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    contact_critical_density: f64,
    rigid_critical: Option<usize>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    rigid_critical_density: Option<f64>,
    compressions: usize,
    fresh_spans: Option<bool>,
    #[serde(serialize_with = "cell::fixed::<4, _>")]
    seconds: f64,
}

/// Per-sequence table: one row per record.
fn records_csv(records: &[Record]) -> Vec<u8> {
    output::csv(records.iter().map(|r| {
        let v = r.box_len.powi(3);
        RecordRow {
            box_len: r.box_len,
            index: r.index,
            seed: r.seed,
            contact_critical: r.contact_critical,
            contact_critical_density: r.contact_critical as f64 / v,
            rigid_critical: r.rigid_critical,
            rigid_critical_density: r.rigid_critical.map(|n| n as f64 / v),
            compressions: r.steps.len() + r.fixed.len(),
            fresh_spans: r.fresh.map(|s| s.spans),
            seconds: r.seconds,
        }
    }))
}

/// How long a study took, kept apart from `summary.json` (which must not
/// depend on the machine).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// CPU seconds the study cost: the process CPU time its records carry,
    /// and for records older than that field their wall time on their
    /// thread (the same on a machine that was not shared).
    pub cpu_seconds: f64,
    /// Summed wall time of the sequences on their threads.
    #[serde(default)]
    pub sequence_seconds: f64,
    /// Summed wall time of the sequences of each box.
    pub per_box: Vec<(f64, f64)>,
    /// The largest peak resident memory of the processes that wrote the
    /// records (MiB; 0 where none was recorded).
    #[serde(default)]
    pub peak_rss_mib: f64,
}

pub fn timing(spec: &StudySpec, records: &[Record]) -> Timing {
    Timing {
        cpu_seconds: records
            .iter()
            .map(|r| r.cpu_seconds.unwrap_or(r.seconds))
            .sum(),
        sequence_seconds: records.iter().map(|r| r.seconds).sum(),
        per_box: spec
            .boxes
            .iter()
            .map(|&l| {
                let s = records
                    .iter()
                    .filter(|r| r.box_len == l)
                    .map(|r| r.seconds)
                    .sum();
                (l, s)
            })
            .collect(),
        peak_rss_mib: records.iter().map(|r| r.peak_rss_mib).fold(0.0, f64::max),
    }
}

/// A row of `boxes.csv`, before its `rho_x_{x}` cells.
#[derive(Serialize)]
struct BoxRow {
    #[serde(serialize_with = "cell::display")]
    box_len: f64,
    // Keeps its stored column name, so `boxes.csv` reads as before.
    #[serde(rename = "realizations")]
    sequences: usize,
    #[serde(serialize_with = "cell::display")]
    mu: f64,
    #[serde(serialize_with = "cell::display_opt")]
    mu_lo: Option<f64>,
    #[serde(serialize_with = "cell::display_opt")]
    mu_hi: Option<f64>,
    #[serde(serialize_with = "cell::display")]
    s: f64,
    #[serde(serialize_with = "cell::display")]
    delta_rho: f64,
    #[serde(serialize_with = "cell::display_opt")]
    delta_rho_lo: Option<f64>,
    #[serde(serialize_with = "cell::display_opt")]
    delta_rho_hi: Option<f64>,
    #[serde(serialize_with = "cell::display")]
    log_likelihood: f64,
}

/// A row of `pi.csv`.
#[derive(Serialize)]
struct PiRow {
    #[serde(serialize_with = "cell::display")]
    box_len: f64,
    #[serde(serialize_with = "cell::display")]
    density: f64,
    #[serde(serialize_with = "cell::display")]
    pi: f64,
    n: usize,
    #[serde(serialize_with = "cell::display")]
    fitted: f64,
}

/// A row of `rho_x.csv`.
#[derive(Serialize)]
struct RhoXRow {
    #[serde(serialize_with = "cell::display")]
    box_len: f64,
    #[serde(serialize_with = "cell::display")]
    x: f64,
    #[serde(serialize_with = "cell::display")]
    rho_x: f64,
    #[serde(serialize_with = "cell::display_opt")]
    rho_x_lo: Option<f64>,
    #[serde(serialize_with = "cell::display_opt")]
    rho_x_hi: Option<f64>,
    #[serde(serialize_with = "cell::display")]
    l_pow_minus_inv_nu: f64,
    #[serde(serialize_with = "cell::display")]
    fitted: f64,
}

/// Writes `boxes.csv` (one row per box size), `pi.csv` (empirical and
/// fitted spanning probability) and `rho_x.csv` (the extrapolated points)
/// into `dir`, which must exist.
pub fn write_scaling_tables(fss: &Fss, data: &[BoxData], dir: &Path) -> Result<()> {
    let more: Vec<String> = fss.xs.iter().map(|x| format!("rho_x_{x}")).collect();
    let boxes = fss.boxes.iter().map(|b| {
        let row = BoxRow {
            box_len: b.box_len,
            sequences: b.sequences,
            mu: b.mu,
            mu_lo: b.mu_interval.map(|i| i.0),
            mu_hi: b.mu_interval.map(|i| i.1),
            s: b.s,
            delta_rho: b.delta_rho,
            delta_rho_lo: b.delta_rho_interval.map(|i| i.0),
            delta_rho_hi: b.delta_rho_interval.map(|i| i.1),
            log_likelihood: b.log_likelihood,
        };
        (
            row,
            b.rho_x.iter().map(|&r| cell::Shown(r)).collect::<Vec<_>>(),
        )
    });
    output::write_atomic(&dir.join("boxes.csv"), output::csv_with_more(&more, boxes))?;

    let mut pi = Vec::new();
    for b in &fss.boxes {
        let Some(d) = data.iter().find(|d| d.box_len == b.box_len) else {
            continue;
        };
        let fit = b.logistic();
        pi.extend(
            pi_curve(d, fss.protocol)
                .into_iter()
                .map(|(rho, frac, n)| PiRow {
                    box_len: b.box_len,
                    density: rho,
                    pi: frac,
                    n,
                    fitted: fit.cdf(rho),
                }),
        );
    }
    output::write_csv(&dir.join("pi.csv"), pi)?;

    let mut rx = Vec::new();
    for b in &fss.boxes {
        let t = fss.scaled(b.box_len);
        for (j, (&x, &r)) in fss.xs.iter().zip(&b.rho_x).enumerate() {
            let iv = b.rho_x_intervals.get(j);
            rx.push(RhoXRow {
                box_len: b.box_len,
                x,
                rho_x: r,
                rho_x_lo: iv.map(|i| i.0),
                rho_x_hi: iv.map(|i| i.1),
                l_pow_minus_inv_nu: t,
                fitted: fss.threshold.value + fss.slopes[j] * t,
            });
        }
    }
    output::write_csv(&dir.join("rho_x.csv"), rx)
}

/// What [`write_study`] computed and wrote.
pub struct StudyReport {
    pub summary: Summary,
    /// The per-box observations the scaling analysis used (for charts).
    pub data: Vec<BoxData>,
    pub files: Vec<PathBuf>,
}

/// Writes `summary.json`, `timing.json`, `records.csv` and the scaling
/// tables into `dir`.
pub fn write_study(
    dir: &Path,
    spec: &StudySpec,
    records: &[Record],
    bootstrap: usize,
) -> Result<StudyReport> {
    let summary = summarize(spec, records, bootstrap)?;
    let data = observations(spec, records);
    let mut files = Vec::new();
    let mut put = |name: &str, text: Vec<u8>| -> Result<()> {
        let path = dir.join(name);
        output::write_atomic(&path, text)?;
        files.push(path);
        Ok(())
    };
    put(
        "summary.json",
        (serde_json::to_string_pretty(&summary).expect("summaries serialize") + "\n").into(),
    )?;
    put(
        "timing.json",
        (serde_json::to_string_pretty(&timing(spec, records)).expect("timings serialize") + "\n")
            .into(),
    )?;
    put("records.csv", records_csv(records))?;
    write_scaling_tables(&summary.fss, &data, dir)?;
    files.extend(["boxes.csv", "pi.csv", "rho_x.csv"].map(|n| dir.join(n)));
    Ok(StudyReport {
        summary,
        data,
        files,
    })
}

/// What [`write_per_box`] wrote: a study whose scaling analysis failed,
/// reported box by box.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PerBoxReport {
    /// Why the analysis across box sizes failed.
    pub error: String,
    pub boxes: Vec<BoxAlone>,
    pub files: Vec<PathBuf>,
}

/// A row of the per-box `boxes.csv`: the columns of the full table that a
/// box's own fit gives, empty where that fit failed.
#[derive(Default, Serialize)]
struct PerBoxRow {
    #[serde(serialize_with = "cell::display")]
    box_len: f64,
    // Keeps its stored column name, so `boxes.csv` reads as before.
    #[serde(rename = "realizations")]
    sequences: usize,
    #[serde(serialize_with = "cell::display_opt")]
    mu: Option<f64>,
    #[serde(serialize_with = "cell::display_opt")]
    s: Option<f64>,
    #[serde(serialize_with = "cell::display_opt")]
    delta_rho: Option<f64>,
    #[serde(serialize_with = "cell::display_opt")]
    log_likelihood: Option<f64>,
}

/// Writes what a study's records give without the analysis across box
/// sizes, which failed with `error`: `records.csv`, `timing.json` and
/// `boxes.csv` with each box's own logistic fit where it converges (and
/// why not where it does not), so that a failed fit never hides the
/// sequences' work.
pub fn write_per_box(
    dir: &Path,
    spec: &StudySpec,
    records: &[Record],
    error: &str,
) -> Result<PerBoxReport> {
    let xs = FssOptions::default().xs;
    let boxes = fss::fit_each_box(&observations(spec, records), spec.method, &xs);
    let mut more: Vec<String> = xs.iter().map(|x| format!("rho_x_{x}")).collect();
    more.push("error".into());
    let rows = boxes.iter().map(|b| {
        let row = PerBoxRow {
            box_len: b.box_len,
            sequences: b.sequences,
            mu: b.fit.map(|f| f.mu),
            s: b.fit.map(|f| f.s),
            delta_rho: b.delta_rho,
            log_likelihood: b.fit.map(|f| f.log_likelihood),
        };
        let mut cells: Vec<String> = (0..xs.len())
            .map(|k| b.rho_x.get(k).map_or(String::new(), f64::to_string))
            .collect();
        cells.push(b.error.clone().unwrap_or_default());
        (row, cells)
    });
    let table = output::csv_with_more(&more, rows);
    let mut files = Vec::new();
    for (name, bytes) in [
        ("records.csv", records_csv(records)),
        (
            "timing.json",
            (serde_json::to_string_pretty(&timing(spec, records)).expect("timings serialize")
                + "\n")
                .into_bytes(),
        ),
        ("boxes.csv", table),
    ] {
        let path = dir.join(name);
        output::write_atomic(&path, bytes)?;
        files.push(path);
    }
    Ok(PerBoxReport {
        error: error.to_string(),
        boxes,
        files,
    })
}

impl PerBoxReport {
    /// The warning printed beside the per-box results.
    pub fn warning(&self) -> String {
        format!("the scaling analysis failed: {}", self.error)
    }

    /// The error the command still ends with: the analysis failed, and
    /// where the per-box results are.
    pub fn failure(&self) -> Error {
        Error::Analysis(format!(
            "{} (the per-box results are in {})",
            self.error,
            file_list(&self.files)
        ))
    }
}

/// Files as one comma-separated line, as the commands print them.
pub fn file_list(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|f| f.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// What a finished study's analysis came to.
pub enum Concluded {
    /// Finite-size scaling worked: the summary and every table (boxed: the
    /// summary is large).
    Full(Box<StudyReport>),
    /// It failed: each box's own fit instead, with why.
    PerBox(PerBoxReport),
}

/// Writes a finished study's results into `dir`: [`write_study`] when the
/// scaling analysis works; when it fails for want of data (an
/// [`Error::Analysis`], such as a width that grows with the box so that no
/// nu exists), [`write_per_box`] instead. A failed fit across box sizes
/// must neither lose the sequences' work, which may be hours of runs, nor
/// pass for a threshold: callers print the per-box results with
/// [`PerBoxReport::warning`] and still fail with [`PerBoxReport::failure`].
/// Any other error (a file that cannot be written) is returned as it is.
pub fn conclude(
    dir: &Path,
    spec: &StudySpec,
    records: &[Record],
    bootstrap: usize,
) -> Result<Concluded> {
    match write_study(dir, spec, records, bootstrap) {
        Ok(full) => Ok(Concluded::Full(Box::new(full))),
        Err(Error::Analysis(why)) => write_per_box(dir, spec, records, &why).map(Concluded::PerBox),
        Err(e) => Err(e),
    }
}
