//! A bias study's measurements as the tables a person reads: CSV, one row
//! per variant and box, and Markdown, one row per variant.

use serde::Serialize;

use super::outcome::VariantBias;
use crate::engine::RuleSet;
use crate::output::{self, cell};
use crate::threshold::fss::Estimate;
use crate::threshold::sequence::Kind;

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
