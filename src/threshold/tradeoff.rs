//! Speed against accuracy across aspect ratios: the `rgc tradeoff`
//! experiments of several aspect ratios read back from their files and set
//! side by side, every variant's bias as a share of its own truth's
//! threshold and its CPU as a multiple of truth's on the same sequences, so
//! that aspect ratios compare on one scale.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::experiment::Experiment;
use super::variants::VariantOutcome;
use crate::output::cell;
use crate::stamp::Stamp;
use crate::{Error, Result};

/// The file stem of one aspect ratio's experiment: the default aspect ratio
/// (23) keeps the name its experiment was first committed under.
pub fn name(gamma: f64) -> String {
    if gamma == 23.0 {
        "speed-accuracy".into()
    } else {
        format!("speed-accuracy-g{gamma}")
    }
}

/// The file stem of the experiments side by side.
pub const GAMMAS: &str = "speed-accuracy-gammas";

/// One aspect ratio's experiment, read back.
#[derive(Clone, Debug)]
pub struct Panel {
    pub gamma: f64,
    pub command: String,
    /// Truth first, as every `rgc tradeoff` experiment has it.
    pub outcomes: Vec<VariantOutcome>,
}

impl Panel {
    fn truth(&self) -> &VariantOutcome {
        &self.outcomes[0]
    }

    /// Variant `k`'s difference to truth as a share of truth's threshold,
    /// with its interval where it has one (zero for truth itself).
    pub fn relative_bias(&self, k: usize) -> Option<(f64, Option<f64>, Option<f64>)> {
        if k == 0 {
            return Some((0.0, None, None));
        }
        let t = self.truth().threshold.value;
        let d = self.outcomes[k].difference()?;
        Some((d.value / t, d.lo.map(|v| v / t), d.hi.map(|v| v / t)))
    }

    /// A variant's CPU as a multiple of truth's on the same sequences.
    pub fn cpu_ratio(&self, o: &VariantOutcome) -> f64 {
        o.cpu_seconds / self.truth().cpu_seconds
    }
}

/// Reads the experiment of each aspect ratio in `gammas` from `dir`, in
/// that order; each must be a finished `rgc tradeoff` experiment whose
/// first variant is truth and whose template has that aspect ratio.
pub fn read(dir: &Path, gammas: &[f64]) -> Result<Vec<Panel>> {
    if gammas.len() < 2 {
        return Err(Error::Parameter(
            "side by side needs at least two aspect ratios".into(),
        ));
    }
    gammas
        .iter()
        .map(|&gamma| {
            let path = dir.join(format!("{}.json", name(gamma)));
            let text = std::fs::read_to_string(&path).map_err(|e| {
                Error::Analysis(format!(
                    "{}: {e} (rgc tradeoff --gamma {gamma} makes it)",
                    path.display()
                ))
            })?;
            let file: Stamp<Experiment> = serde_json::from_str(&text).map_err(|e| {
                Error::Analysis(format!("{}: not an experiment: {e}", path.display()))
            })?;
            let wrong = |what: String| Error::Analysis(format!("{}: {what}", path.display()));
            if file.made.template.gamma != gamma {
                return Err(wrong(format!(
                    "made at gamma {}, not {gamma}",
                    file.made.template.gamma
                )));
            }
            let truth = file.made.variants.first();
            if !truth.is_some_and(|t| t.label == "truth" && t.cpu_seconds > 0.0) {
                return Err(wrong("its first variant is not truth".into()));
            }
            Ok(Panel {
                gamma,
                command: file.command,
                outcomes: file.made.variants,
            })
        })
        .collect()
}

/// One variant of one aspect ratio, as the side-by-side table has it.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub gamma: f64,
    pub variant: String,
    pub family: String,
    pub sequences: u64,
    /// Bias against truth as a share of truth's threshold, with its interval.
    #[serde(serialize_with = "cell::fixed_opt::<5, _>")]
    pub bias: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<5, _>")]
    pub bias_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<5, _>")]
    pub bias_hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<1, _>")]
    pub cpu_seconds: f64,
    #[serde(serialize_with = "cell::fixed::<4, _>")]
    pub cpu_over_truth: f64,
}

/// Every variant of every panel, truth included (bias zero, CPU ratio one).
pub fn rows(panels: &[Panel]) -> Vec<Row> {
    panels
        .iter()
        .flat_map(|p| {
            p.outcomes.iter().enumerate().map(move |(k, o)| {
                let bias = p.relative_bias(k);
                Row {
                    gamma: p.gamma,
                    variant: o.label.clone(),
                    family: o.family.clone(),
                    sequences: o.sequences,
                    bias: bias.map(|b| b.0),
                    bias_lo: bias.and_then(|b| b.1),
                    bias_hi: bias.and_then(|b| b.2),
                    cpu_seconds: o.cpu_seconds,
                    cpu_over_truth: p.cpu_ratio(o),
                }
            })
        })
        .collect()
}

/// The variants in rows, the aspect ratios in columns: bias in percent of
/// truth's threshold with its interval, and CPU over truth's.
pub fn markdown(panels: &[Panel], command: &str) -> String {
    let mut labels: Vec<&str> = Vec::new();
    for o in panels.iter().flat_map(|p| &p.outcomes) {
        if !labels.contains(&o.label.as_str()) {
            labels.push(&o.label);
        }
    }
    let percent = |v: f64| format!("{:+.1}%", 100.0 * v);
    let mut md = format!(
        "# Speed against accuracy across aspect ratios\n\nMade by `{command}` from the experiments of\n\n"
    );
    for p in panels {
        md += &format!("- gamma {}: `{}`\n", p.gamma, p.command);
    }
    md += "\nEach cell: the variant's critical density minus truth's on the same sequences (paired where nested, else of thresholds), \
           in percent of truth's threshold, with its 95% interval; and its CPU as a multiple of truth's.\n\n| variant |";
    for p in panels {
        md += &format!(" gamma {} bias | CPU / truth |", p.gamma);
    }
    md += &format!("\n|---|{}\n", "---|---|".repeat(panels.len()));
    for label in labels {
        md += &format!("| {label} |");
        for p in panels {
            match p.outcomes.iter().position(|o| o.label == label) {
                Some(0) => md += " 0 | 1 |",
                Some(k) => {
                    let o = &p.outcomes[k];
                    let bias = match p.relative_bias(k) {
                        Some((v, Some(lo), Some(hi))) => {
                            format!("{} [{}, {}]", percent(v), percent(lo), percent(hi))
                        }
                        Some((v, _, _)) => percent(v),
                        None => "—".into(),
                    };
                    md += &format!(" {bias} | {:.3} |", p.cpu_ratio(o));
                }
                None => md += " — | — |",
            }
        }
        md += "\n";
    }
    md
}

/// The paths `dir/GAMMAS.{md,csv,svg,png}`.
pub fn paths(dir: &Path) -> [PathBuf; 4] {
    ["md", "csv", "svg", "png"].map(|ext| dir.join(format!("{GAMMAS}.{ext}")))
}
