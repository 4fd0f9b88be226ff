//! Every 3D-RGC variant against the exact truth (MODEL §10), on the same
//! nested sequences: the accuracy axis of the speed-accuracy trade-off.
//!
//! Extrapolated thresholds from small boxes have intervals wider than the
//! differences between variants, so the primary figure is paired: on each
//! sequence, the critical density at which the variant first spans minus
//! the one at which truth does, averaged per box with a 95% interval. A
//! variant that spans below truth on a sequence has claimed a rigid span
//! that does not exist: its share is the rate of false rigid spans.

use std::path::Path;

use super::design::check_design;
use super::outcome::{BoxBias, VariantBias};
use crate::Result;
use crate::progress::Progress;
use crate::threshold::paired::{self, Difference};
use crate::threshold::report;
use crate::threshold::sequence::{Kind, Record};
use crate::threshold::study::StudySpec;
use crate::threshold::variants::{self, Design};

/// Runs (or resumes) the design's studies on `template`'s sequences and
/// measures every variant against the first, which must be truth. Returns
/// the measurements and truth's records.
pub fn measure(
    template: &StudySpec,
    design: &Design,
    root: &Path,
    memory_limit: Option<u64>,
    bootstrap: usize,
    progress: &dyn Progress,
) -> Result<(Vec<VariantBias>, Vec<Record>)> {
    check_design(design)?;
    let (specs, dirs, of_variant) =
        variants::run_studies(template, &design.variants, root, memory_limit, progress)?;
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

#[cfg(test)]
mod tests {
    use super::super::fixtures::{nested, undecided};
    use super::super::table::csv;
    use super::*;
    use crate::progress::Silent;
    use crate::spanning::Criterion;
    use crate::threshold::fss::Estimate;
    use crate::threshold::fss::Protocol;
    use crate::threshold::study::MotifSet;
    use crate::threshold::variants::Variant;

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
        let (out, truth_back) = measure(&template, &design, &root, None, 2, &Silent).unwrap();
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
}
