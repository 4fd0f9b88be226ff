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
/// the boxes `boxes`, in parallel over numbers of rods. Sequences where truth
/// was undecided have no critical number to scan around: they are left out,
/// as [`measure`] leaves them out of every pair.
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
        memory_limit: None,
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
        let seq = super::sequence::Sequence::new(template.gamma, r.box_len, to, r.seed)?;
        let spans: Vec<Option<bool>> = (from..=to)
            .into_par_iter()
            .map(|n| super::sequence::truth_spanning(&setup, &seq, n))
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
    use super::*;
    use crate::progress::Silent;
    use crate::spanning::Criterion;
    use crate::threshold::fss::ContactPoint;
    use crate::threshold::sequence::Step;
    use crate::threshold::study::MotifSet;

    /// A nested record that [`Record::check`] accepts: the bisection of the
    /// nested protocol (first guess `2 n_c`, growth 1.25, then halving)
    /// replayed on "spans from `n_r` rods on".
    fn nested(box_len: f64, index: u64, seed: u64, n_c: usize, n_r: usize) -> Record {
        let (mut lo, mut hi, mut probe) = (n_c - 1, None, 2 * n_c);
        let mut steps = Vec::new();
        loop {
            let n = match hi {
                None => probe,
                Some(h) if h - lo > 1 => lo + (h - lo) / 2,
                Some(_) => break,
            };
            let spans = n >= n_r;
            steps.push(Step::new(n, spans, usize::from(spans)));
            if spans {
                hi = Some(n);
            } else {
                lo = n;
                if hi.is_none() {
                    probe = (n as f64 * 1.25).ceil() as usize;
                }
            }
        }
        assert_eq!(hi, Some(n_r), "the search ends at the critical number");
        Record {
            box_len,
            index,
            seed,
            contact_critical: n_c,
            rigid_critical: Some(n_r),
            steps,
            fresh: Some(Step::new(n_r, true, 1)),
            fixed: vec![],
            contacts: vec![ContactPoint {
                density: n_r as f64 / box_len.powi(3),
                c0: 4.0,
                c1: 4.5,
                c2: 5.0,
            }],
            undecided: None,
            seconds: 1.0,
            peak_rss_mib: 0.0,
            cpu_seconds: None,
        }
    }

    /// A truth record undecided at its first guess (`2 n_c` rods).
    fn undecided(box_len: f64, index: u64, seed: u64, n_c: usize) -> Record {
        Record {
            rigid_critical: None,
            steps: vec![],
            fresh: None,
            contacts: vec![],
            undecided: Some(2 * n_c),
            ..nested(box_len, index, seed, n_c, 2 * n_c)
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + b.abs())
    }

    /// Mean and half-width `1.96 sd / sqrt(n)` (sample sd), written out.
    fn expected(d: &[f64]) -> (f64, f64) {
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
        (mean, 1.96 * var.sqrt() / n.sqrt())
    }

    fn assert_estimate(e: Estimate, d: &[f64]) {
        let (mean, half) = expected(d);
        assert!(close(e.value, mean), "{e:?} against mean {mean}");
        assert!(close(e.lo.unwrap(), mean - half), "{e:?} half {half}");
        assert!(close(e.hi.unwrap(), mean + half), "{e:?} half {half}");
    }

    const BOXES: [f64; 3] = [4.0, 8.0, 16.0];
    /// Per box: truth's critical numbers of five sequences (`None`:
    /// undecided) and the variant's shift from them in units of the box
    /// volume, so each paired difference is that shift exactly.
    const TRUTH: [[Option<usize>; 5]; 3] = [
        [Some(200), Some(210), Some(220), Some(230), None],
        [Some(1000), Some(1100), Some(1200), Some(1300), Some(1400)],
        [Some(5000), Some(5100), Some(5200), Some(5300), Some(5400)],
    ];
    const SHIFT: [[f64; 5]; 3] = [
        [-1.0, 0.0, 1.0, 2.0, 3.0],
        [1.0, 2.0, 1.0, 2.0, 1.5],
        [0.0; 5],
    ];
    const CONTACT: [usize; 3] = [100, 500, 3000];

    fn template() -> StudySpec {
        StudySpec::new(10.0, BOXES.to_vec(), 5, Criterion::Wrap, 3)
    }

    /// Truth's and the variant's records, with the seeds of `template`.
    fn records(template: &StudySpec) -> (Vec<Record>, Vec<Record>) {
        let (mut truth, mut variant) = (Vec::new(), Vec::new());
        for (b, &l) in BOXES.iter().enumerate() {
            let v = l.powi(3);
            for i in 0..5 {
                let seed = template.sequence_seed(l, i as u64);
                let n_c = CONTACT[b];
                let t = match TRUTH[b][i] {
                    Some(n_r) => nested(l, i as u64, seed, n_c, n_r),
                    None => undecided(l, i as u64, seed, n_c),
                };
                truth.push(Record {
                    cpu_seconds: Some(2.0),
                    ..t
                });
                let base = TRUTH[b][i].unwrap_or(240);
                let n_r = (base as f64 + SHIFT[b][i] * v) as usize;
                variant.push(Record {
                    cpu_seconds: Some(0.5),
                    ..nested(l, i as u64, seed, n_c, n_r)
                });
            }
        }
        (truth, variant)
    }

    #[test]
    fn hand_made_records_pass_the_study_check() {
        let (truth, variant) = records(&template());
        for r in &truth {
            r.check(Kind::Truth, Protocol::Nested, 1, None).unwrap();
        }
        for r in &variant {
            r.check(Kind::Rigid, Protocol::Nested, 1, None).unwrap();
        }
    }

    #[test]
    fn box_bias_is_the_paired_mean_with_signs_counted() {
        let template = template();
        let (truth, variant) = records(&template);
        // Box 4: the undecided truth sequence is left out of the pairs.
        let b = box_bias(4.0, 10.0, &truth, &variant).unwrap();
        assert_eq!((b.box_len, b.sequences, b.below, b.above), (4.0, 4, 1, 2));
        assert_eq!(b.bias.value, 0.5);
        assert_estimate(b.bias, &[-1.0, 0.0, 1.0, 2.0]);
        let half = 1.96 * (5.0f64 / 3.0).sqrt() / 2.0;
        assert!(close(b.bias.hi.unwrap() - 0.5, half));
        // Box 8: all above truth.
        let b = box_bias(8.0, 10.0, &truth, &variant).unwrap();
        assert_eq!((b.sequences, b.below, b.above), (5, 0, 5));
        assert_eq!(b.bias.value, 1.5);
        assert!(close(b.bias.hi.unwrap(), 1.5 + 1.96 * 0.5 / 5f64.sqrt()));
        // Box 16: the same critical numbers, no bias, no sign, no width.
        let b = box_bias(16.0, 10.0, &truth, &variant).unwrap();
        assert_eq!((b.sequences, b.below, b.above), (5, 0, 0));
        assert_eq!(
            b.bias,
            Estimate {
                value: 0.0,
                lo: Some(0.0),
                hi: Some(0.0)
            }
        );
        // A box no record has, and a box with a single pair: no bias.
        assert_eq!(box_bias(5.0, 10.0, &truth, &variant), None);
        let one: Vec<Record> = variant
            .iter()
            .filter(|r| r.box_len == 4.0)
            .skip(3)
            .cloned()
            .collect();
        assert_eq!(one.len(), 2, "index 3 and the undecided index 4");
        assert_eq!(box_bias(4.0, 10.0, &truth, &one), None);
        // Pairs are by box and seed: truth records of another seed pair nothing.
        let reseeded: Vec<Record> = truth
            .iter()
            .map(|r| Record {
                seed: r.seed ^ 1,
                ..r.clone()
            })
            .collect();
        assert_eq!(box_bias(8.0, 10.0, &reseeded, &variant), None);
    }

    #[test]
    fn paired_leaves_out_undecided_sequences_on_either_side() {
        let template = template();
        let (truth, mut variant) = records(&template);
        assert_eq!(paired(&truth, &variant).len(), 14);
        // The variant undecided too (certified rules can be): one pair fewer.
        let k = variant.iter().position(|r| r.box_len == 8.0).unwrap();
        variant[k] = undecided(8.0, 0, variant[k].seed, 500);
        let pairs = paired(&truth, &variant);
        assert_eq!(pairs.len(), 13);
        // Densities, in the variant's order: truth 200 rods in 64, the variant 136.
        assert_eq!(pairs[0], (200.0 / 64.0, 136.0 / 64.0));
    }

    #[test]
    fn measure_pairs_hand_made_studies_exactly() {
        let root = std::env::temp_dir().join(format!("rgc-bias-measure-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let template = template();
        let design = Design {
            variants: vec![
                Variant {
                    kind: Kind::Truth,
                    ..Variant::sound_base("truth", "truth", 5)
                },
                Variant::sound_base("sound", "rules", 5),
            ],
            pairing: variants::Pairing::First,
        };
        let (truth, variant) = records(&template);
        // Each variant's study directory, holding its records: nothing is left to run.
        for (v, records) in design.variants.iter().zip([&truth, &variant]) {
            let spec = StudySpec {
                kind: v.kind,
                rules: v.rules,
                motifs: MotifSet::default(),
                runs: v.runs,
                method: v.method,
                sequences: v.sequences,
                ..template.clone()
            };
            let dir = variants::study_dir(&root, &spec);
            std::fs::create_dir_all(&dir).unwrap();
            let lines: String = records
                .iter()
                .map(|r| serde_json::to_string(r).unwrap() + "\n")
                .collect();
            std::fs::write(dir.join("records.jsonl"), lines).unwrap();
        }
        let (out, truth_back) = measure(&template, &design, &root, 2, &Silent).unwrap();
        assert_eq!(truth_back, truth);
        assert_eq!(out.len(), 2);
        let (t, v) = (&out[0], &out[1]);
        assert_eq!((t.label.as_str(), t.kind), ("truth", Kind::Truth));
        assert!(t.boxes.is_empty());
        assert_eq!((t.bias, t.false_span_share), (None, None));
        assert_eq!(t.undecided, 1);
        assert_eq!(t.cpu_seconds, 15.0 * 2.0);
        assert_eq!((v.label.as_str(), v.kind), ("sound", Kind::Rigid));
        assert_eq!(v.undecided, 0);
        assert_eq!(v.cpu_seconds, 15.0 * 0.5);
        // Per box, as box_bias computes it.
        let per_box: Vec<(f64, usize, usize, usize)> = v
            .boxes
            .iter()
            .map(|b| (b.box_len, b.sequences, b.below, b.above))
            .collect();
        assert_eq!(
            per_box,
            vec![(4.0, 4, 1, 2), (8.0, 5, 0, 5), (16.0, 5, 0, 0)]
        );
        assert_estimate(v.boxes[0].bias, &[-1.0, 0.0, 1.0, 2.0]);
        assert_estimate(v.boxes[1].bias, &SHIFT[1]);
        assert_estimate(v.boxes[2].bias, &SHIFT[2]);
        // Over all boxes: the 14 decided pairs, one of them below truth.
        let all: Vec<f64> = [&SHIFT[0][..4], &SHIFT[1][..], &SHIFT[2][..]].concat();
        assert_eq!(all.len(), 14);
        assert_estimate(v.bias.unwrap(), &all);
        assert!(close(v.bias.unwrap().value, 9.5 / 14.0));
        assert_eq!(v.false_span_share, Some(1.0 / 14.0));
        // The CSV: the per-box false-span share is below / sequences.
        let csv = csv(&out);
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(
            rows.len(),
            1 + 1 + 4,
            "header, truth's total, 3 boxes and the total"
        );
        let share = |row: &str| row.split(',').nth(11).unwrap().to_string();
        assert_eq!(share(rows[2]), "0.2500");
        assert_eq!(share(rows[3]), "0.0000");
        assert_eq!(share(rows[5]), "0.0714");
        std::fs::remove_dir_all(&root).unwrap();
    }

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
        let err = scan(&spec, &truth, &[4.0], 1, 0.1, &Silent)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("no truth sequence of box 4 to scan: the box must be one of the study's"),
            "{err}"
        );
        // Sequences beyond the first `sequences` are not scanned either.
        let later = vec![nested(3.0, 1, seed, 3, 3)];
        assert!(scan(&spec, &later, &[3.0], 1, 0.1, &Silent).is_err());
    }

    #[test]
    fn scan_windows_reach_from_one_rod_on() {
        // A handful of rods in a box of side 3 spans nowhere: the window is
        // critical -+ ceil(critical * width) (at least 1), never below 1 rod.
        let spec = spec_at(3.0);
        let seed = spec.sequence_seed(3.0, 0);
        let truth = vec![nested(3.0, 0, seed, 3, 3)];
        let s = scan(&spec, &truth, &[3.0], 1, 0.1, &Silent).unwrap();
        assert_eq!(s.len(), 1);
        let s = &s[0];
        assert_eq!((s.critical, s.from, s.to), (3, 2, 4));
        assert_eq!((s.first_spanning, &s.drops[..]), (None, &[][..]));
        assert!(s.undecided.is_empty());
        let truth = vec![nested(3.0, 0, seed, 1, 1)];
        let s = &scan(&spec, &truth, &[3.0], 1, 0.5, &Silent).unwrap()[0];
        assert_eq!((s.from, s.to), (1, 2));
        let truth = vec![nested(3.0, 0, seed, 10, 10)];
        let s = &scan(&spec, &truth, &[3.0], 1, 0.25, &Silent).unwrap()[0];
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
        let s = scan(&spec, &truth, &[3.0], 2, 0.1, &Silent).unwrap();
        assert_eq!(s.iter().map(|s| s.index).collect::<Vec<_>>(), vec![1]);
        // The decided sequence scans as it does alone.
        let alone = scan(&spec, &truth[1..], &[3.0], 2, 0.1, &Silent).unwrap();
        assert_eq!(s, alone);
        // A box whose scanned sequences are all undecided scans none, without
        // error: the box is one of the study's.
        let s = scan(&spec, &truth, &[3.0], 1, 0.1, &Silent).unwrap();
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
