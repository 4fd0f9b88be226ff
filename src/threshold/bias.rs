//! Every 3D-RGC variant against the exact truth (MODEL §10), on the same
//! nested sequences: the accuracy axis of the speed-accuracy trade-off.
//!
//! Extrapolated thresholds from small boxes have intervals wider than the
//! differences between variants, so the primary figure is paired: on each
//! sequence, the critical density at which the variant first spans minus
//! the one at which truth does, averaged per box with a 95% interval. A
//! variant that spans below truth on a sequence has claimed a rigid span
//! that does not exist: its share is the rate of false rigid spans.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use super::fss::{Estimate, Protocol};
use super::paired::{self, Difference};
use super::report;
use super::sequence::{Kind, Record};
use super::study::StudySpec;
use super::variants::{self, Design, Pairing, Variant};
use crate::engine::RuleSet;
use crate::output::{self, cell};
use crate::progress::Progress;
use crate::{Error, Result};

/// Truth first, then every variant it measures, each paired with truth:
/// the paper's and the sound base motifs, certified compression, 10 and
/// 40 runs per system, the sound base motifs with the `extended` rule files
/// (enumerated), and with the `mined` ones (found in real systems, where
/// truth saw rigidity the engine missed).
pub fn truth_design(sequences: u64, extended: &[PathBuf], mined: &[PathBuf]) -> Design {
    let v = |label: &str, family: &str| Variant::sound_base(label, family, sequences);
    Design {
        variants: vec![
            Variant {
                kind: Kind::Truth,
                ..v("truth", "truth")
            },
            Variant {
                rules: RuleSet::Paper,
                ..v("paper", "rules")
            },
            v("sound", "rules"),
            Variant {
                rules: RuleSet::Certified,
                ..v("certified", "rules")
            },
            Variant {
                runs: 10,
                ..v("sound K=10", "runs")
            },
            Variant {
                runs: 40,
                ..v("sound K=40", "runs")
            },
            Variant {
                motifs: extended.to_vec(),
                ..v("sound + extended", "motifs")
            },
            Variant {
                motifs: mined.to_vec(),
                ..v("sound + mined", "motifs")
            },
        ],
        pairing: Pairing::First,
    }
}

/// The paired bias of one variant in one box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxBias {
    #[serde(rename = "box")]
    pub box_len: f64,
    /// Sequences both the variant and truth have.
    pub sequences: usize,
    /// Mean over sequences of (variant's critical density - truth's), with
    /// a 95% normal interval.
    pub bias: Estimate,
    /// Sequences where the variant first spans below truth (false rigid
    /// spans), and above it (rigidity it misses at truth's critical density).
    pub below: usize,
    pub above: usize,
}

/// What one variant measured against truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantBias {
    pub label: String,
    pub family: String,
    pub kind: Kind,
    pub rules: RuleSet,
    pub motif_rules: usize,
    pub runs: usize,
    pub sequences: u64,
    /// The paired bias per box (empty for truth itself).
    pub boxes: Vec<BoxBias>,
    /// The paired bias over all boxes' sequences.
    pub bias: Option<Estimate>,
    /// Share of sequences where it spans below truth.
    pub false_span_share: Option<f64>,
    /// The finite-size-scaling threshold, where the fit succeeds.
    pub threshold: Option<Estimate>,
    /// CPU seconds of its sequences (all boxes).
    pub cpu_seconds: f64,
    /// Sequences where truth (or certification) was undecided, left out.
    pub undecided: usize,
    pub study: String,
}

/// Runs (or resumes) the design's studies on `template`'s sequences and
/// measures every variant against the first, which must be truth. Returns
/// the measurements and truth's records.
pub fn measure(
    template: &StudySpec,
    design: &Design,
    root: &Path,
    bootstrap: usize,
    progress: &dyn Progress,
) -> Result<(Vec<VariantBias>, Vec<Record>)> {
    check_design(design)?;
    let (specs, dirs, of_variant) =
        variants::run_studies(template, &design.variants, root, progress)?;
    let mut truth: Vec<Record> = Vec::new();
    let mut out = Vec::new();
    for (i, (v, &k)) in design.variants.iter().zip(&of_variant).enumerate() {
        let spec = &specs[k];
        let records = variants::variant_records(spec, &dirs[k], v.sequences)?;
        let subset = StudySpec {
            sequences: v.sequences,
            ..spec.clone()
        };
        let threshold = report::summarize(&subset, &records, bootstrap)
            .ok()
            .map(|s| s.fss.threshold);
        let cpu_seconds = report::timing(&subset, &records).cpu_seconds;
        if i == 0 {
            truth = records.clone();
        }
        let boxes: Vec<BoxBias> = if i == 0 {
            Vec::new()
        } else {
            template
                .boxes
                .iter()
                .filter_map(|&l| box_bias(l, template.gamma, &truth, &records))
                .collect()
        };
        let pairs: Vec<(f64, f64)> = if i == 0 {
            Vec::new()
        } else {
            paired(&truth, &records)
        };
        let bias = paired::mean_interval(&pairs.iter().map(|(t, v)| v - t).collect::<Vec<_>>());
        let false_span_share = (!pairs.is_empty())
            .then(|| pairs.iter().filter(|(t, v)| v < t).count() as f64 / pairs.len() as f64);
        out.push(VariantBias {
            label: v.label.clone(),
            family: v.family.clone(),
            kind: v.kind,
            rules: v.rules,
            motif_rules: spec.motifs.rules,
            runs: v.runs,
            sequences: v.sequences,
            boxes,
            bias,
            false_span_share,
            threshold,
            cpu_seconds,
            undecided: records.iter().filter(|r| r.undecided.is_some()).count(),
            study: dirs[k].display().to_string(),
        });
    }
    Ok((out, truth))
}

/// The design must measure against truth: truth first, the nested
/// protocol everywhere (a paired critical density needs one per sequence).
pub fn check_design(design: &Design) -> Result<()> {
    match design.variants.first() {
        Some(v) if v.kind == Kind::Truth => {}
        _ => {
            return Err(Error::Parameter(
                "a bias design measures against truth: its first variant must be of kind truth"
                    .into(),
            ));
        }
    }
    if let Some(v) = design
        .variants
        .iter()
        .find(|v| v.method != Protocol::Nested)
    {
        return Err(Error::Parameter(format!(
            "variant {:?}: paired critical densities need the nested protocol",
            v.label
        )));
    }
    Ok(())
}

/// `(truth, variant)` critical densities of the sequences both have.
fn paired(truth: &[Record], records: &[Record]) -> Vec<(f64, f64)> {
    paired::pairs((Kind::Truth, truth), (Kind::Rigid, records))
}

fn box_bias(box_len: f64, gamma: f64, truth: &[Record], records: &[Record]) -> Option<BoxBias> {
    let mine: Vec<Record> = records
        .iter()
        .filter(|r| r.box_len == box_len)
        .cloned()
        .collect();
    let d = Difference::of(Some(box_len), &paired(truth, &mine), gamma)?;
    Some(BoxBias {
        box_len,
        sequences: d.sequences,
        bias: d.mean,
        below: d.below,
        above: d.above,
    })
}

/// One CSV row: a variant in one box, or over all boxes (`box` empty).
#[derive(Serialize)]
struct Row<'a> {
    variant: &'a str,
    family: &'a str,
    kind: Kind,
    rules: RuleSet,
    motif_rules: usize,
    runs: usize,
    #[serde(rename = "box", serialize_with = "cell::fixed_opt::<1, _>")]
    box_len: Option<f64>,
    sequences: usize,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    bias: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    bias_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    bias_hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    false_span_share: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<4, _>")]
    threshold: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<1, _>")]
    cpu_seconds: f64,
}

/// The measurements as CSV: per variant, one row per box and one over all.
pub fn csv(out: &[VariantBias]) -> String {
    let mut rows = Vec::new();
    for v in out {
        let row = |box_len, sequences, bias: Option<Estimate>, share| Row {
            variant: &v.label,
            family: &v.family,
            kind: v.kind,
            rules: v.rules,
            motif_rules: v.motif_rules,
            runs: v.runs,
            box_len,
            sequences,
            bias: bias.map(|b| b.value),
            bias_lo: bias.and_then(|b| b.lo),
            bias_hi: bias.and_then(|b| b.hi),
            false_span_share: share,
            threshold: v.threshold.map(|t| t.value),
            cpu_seconds: v.cpu_seconds,
        };
        for b in &v.boxes {
            rows.push(row(
                Some(b.box_len),
                b.sequences,
                Some(b.bias),
                Some(b.below as f64 / b.sequences as f64),
            ));
        }
        let n = v.boxes.iter().map(|b| b.sequences).sum();
        rows.push(row(None, n, v.bias, v.false_span_share));
    }
    String::from_utf8(output::csv(rows)).expect("CSV of UTF-8 is UTF-8")
}

/// `value [lo, hi]` to 3 places, with signs for a difference, or a dash.
fn show(e: Option<Estimate>, signed: bool) -> String {
    let f = |x: f64| {
        if signed {
            format!("{x:+.3}")
        } else {
            format!("{x:.3}")
        }
    };
    match e {
        Some(Estimate {
            value,
            lo: Some(lo),
            hi: Some(hi),
        }) => format!("{} [{}, {}]", f(value), f(lo), f(hi)),
        Some(e) => f(e.value),
        None => "—".into(),
    }
}

/// The measurements as a Markdown table: one row per variant, the paired
/// bias per box and over all, false spans, threshold and CPU time.
pub fn markdown(title: &str, command: &str, out: &[VariantBias], boxes: &[f64]) -> String {
    let mut md = format!("# {title}\n\nMade by `{command}`.\n\n");
    md += "Bias: critical density of the variant minus that of truth on the same \
           sequence (rods per unit volume), mean with a 95% interval. \
           False spans: sequences where the variant spans below truth.\n\n";
    let mut head = vec!["variant".to_string()];
    head.extend(boxes.iter().map(|l| format!("bias L={l}")));
    head.extend(
        ["bias, all boxes", "false spans", "threshold (FSS)", "CPU s"]
            .iter()
            .map(|s| s.to_string()),
    );
    md += &format!("| {} |\n|{}\n", head.join(" | "), "---|".repeat(head.len()));
    for v in out {
        let mut cells = vec![v.label.clone()];
        for &l in boxes {
            let b = v.boxes.iter().find(|b| b.box_len == l);
            cells.push(b.map_or("—".into(), |b| show(Some(b.bias), true)));
        }
        cells.push(show(v.bias, true));
        cells.push(
            v.false_span_share
                .map_or("—".into(), |s| format!("{:.1}%", 100.0 * s)),
        );
        cells.push(show(v.threshold, false));
        cells.push(format!("{:.0}", v.cpu_seconds));
        md += &format!("| {} |\n", cells.join(" | "));
    }
    for v in out.iter().filter(|v| v.undecided > 0) {
        md += &format!(
            "\n{}: truth was undecided (no realization of the model: forced coincident \
             contacts, or forced planes holding three box directions) in {} of its {} \
             sequences, left out of every pair.\n",
            v.label,
            v.undecided,
            v.sequences * boxes.len() as u64
        );
    }
    md
}

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
/// the boxes `boxes`, in parallel over numbers of rods.
pub fn scan(
    template: &StudySpec,
    truth: &[Record],
    boxes: &[f64],
    sequences: u64,
    half_width: f64,
    progress: &dyn Progress,
) -> Result<Vec<Scan>> {
    use rayon::prelude::*;
    let setup = super::sequence::Setup {
        kind: Kind::Truth,
        gamma: template.gamma,
        criterion: template.criterion,
        engine: crate::engine::Engine::base(RuleSet::Sound),
        runs: 1,
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
    let total = chosen.len() as u64;
    progress.start("monotonicity scan", total);
    let mut out = Vec::with_capacity(chosen.len());
    for r in chosen {
        let critical = r
            .critical(Kind::Truth)
            .ok_or_else(|| Error::Analysis("a truth record without a critical number".into()))?;
        let w = ((critical as f64 * half_width).ceil() as usize).max(1);
        let (from, to) = (critical.saturating_sub(w).max(1), critical + w);
        let seq = super::sequence::Sequence::new(template.gamma, r.box_len, to, r.seed)?;
        let spans: Vec<Option<bool>> = (from..=to)
            .into_par_iter()
            .map(|n| super::sequence::truth_spanning(&setup, &seq, n))
            .collect();
        let decided: Vec<(usize, bool)> = spans
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.map(|s| (from + i, s)))
            .collect();
        out.push(Scan {
            box_len: r.box_len,
            index: r.index,
            seed: r.seed,
            critical,
            from,
            to,
            first_spanning: decided.iter().find(|d| d.1).map(|d| d.0),
            drops: decided
                .windows(2)
                .filter(|w| w[0].1 && !w[1].1)
                .map(|w| w[1].0)
                .collect(),
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
