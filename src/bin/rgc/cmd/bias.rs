//! `rgc bias`: every 3D-RGC variant against the exact truth on the same
//! sequences; writes `truth-vs-rgc.{json,md,csv,svg,png}`.

use std::path::PathBuf;

use clap::Args;
use serde_json::json;

use rgc::threshold::bias::{self, VariantBias};
use rgc::threshold::fss;
use rgc::threshold::variants::{self, Design};
use rgc::{Error, Result, output};

use crate::args::{ExtendedArgs, VariantArgs};
use crate::progress::Reporter;

#[derive(Args)]
#[command(mut_arg("boxes", |a| a.default_value("3,4,5")))]
pub struct BiasArgs {
    #[command(flatten)]
    common: VariantArgs,
    #[command(flatten)]
    extended: ExtendedArgs,
    /// Rule files of motifs mined from real systems (`rgc mine`).
    #[arg(long, value_delimiter = ',', default_value = "motifs/mined.json")]
    mined: Vec<PathBuf>,
    /// Also evaluate truth at every number of rods around the critical
    /// number of this many sequences per scanned box (is it monotone?);
    /// writes `truth-monotone.{json,csv}`.
    #[arg(long, default_value_t = 0)]
    scan_sequences: u64,
    /// Boxes to scan (each one of --boxes).
    #[arg(long, value_delimiter = ',', default_value = "3,4")]
    scan_boxes: Vec<f64>,
    /// Half-width of the scanned window, as a fraction of the critical number.
    #[arg(long, default_value_t = 0.1)]
    scan_width: f64,
}

const NAME: &str = "truth-vs-rgc";

/// What made an experiment file: the template and the variants, compared
/// before an existing file is replaced.
fn made_by(template: &serde_json::Value, design: &Design) -> serde_json::Value {
    let variants: Vec<serde_json::Value> = design
        .variants
        .iter()
        .map(|v| {
            json!({
                "label": v.label, "kind": v.kind, "rules": v.rules, "runs": v.runs,
                "motifs": v.motifs, "sequences": v.sequences,
            })
        })
        .collect();
    json!({ "template": template, "design": variants })
}

/// Refuses to replace an experiment file that another experiment made
/// (an unreadable file is an error, a missing one is fine).
fn check_replace(path: &std::path::Path, made: &serde_json::Value) -> Result<()> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(Error::io(path, e)),
    };
    let there: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
    if there.get("made_by") == Some(made) {
        return Ok(());
    }
    Err(Error::Parameter(format!(
        "{} holds the results of another experiment; choose another --results, or --force to replace them",
        path.display()
    )))
}

pub fn run(a: BiasArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let template = c.study.spec();
    let design = variants::checked_design(
        |r| bias::truth_design(r, &a.extended.files, &a.mined),
        &template,
    )?;
    bias::check_design(&design)?;
    fss::check_bootstrap(c.study.bootstrap)?;
    if a.scan_sequences > 0 {
        if let Some(l) = a.scan_boxes.iter().find(|l| !template.boxes.contains(l)) {
            return Err(Error::Parameter(format!(
                "--scan-boxes: box {l} is not one of --boxes {:?}",
                template.boxes
            )));
        }
        if !(a.scan_width > 0.0 && a.scan_width < 1.0) {
            return Err(Error::Parameter(format!(
                "--scan-width must lie in (0, 1), got {}",
                a.scan_width
            )));
        }
        if a.scan_sequences > template.sequences {
            return Err(Error::Parameter(format!(
                "--scan-sequences {} exceeds --sequences {}",
                a.scan_sequences, template.sequences
            )));
        }
    }
    output::check_dir(&c.results)?;
    output::check_dir(&c.studies)?;
    let path = |ext: &str| c.results.join(format!("{NAME}.{ext}"));
    let made = made_by(
        &serde_json::to_value(&template).expect("specs serialize"),
        &design,
    );
    if !c.force {
        check_replace(&path("json"), &made)?;
    }
    let progress = Reporter::new(c.quiet || c.json);
    let (outcomes, truth): (Vec<VariantBias>, _) =
        bias::measure(&template, &design, &c.studies, c.study.bootstrap, &progress)?;
    let command = super::command_line();
    let title = format!(
        "3D-RGC against the exact truth, gamma {}: paired bias of the critical density",
        c.study.gamma
    );
    let mut report = json!({ "command": command, "made_by": made, "variants": outcomes });
    let mut md = bias::markdown(&title, &command, &outcomes, &template.boxes);
    if a.scan_sequences > 0 {
        let scans = bias::scan(
            &template,
            &truth,
            &a.scan_boxes,
            a.scan_sequences,
            a.scan_width,
            &progress,
        )?;
        let summary = bias::scan_summary(&scans);
        md += &format!("\n{summary}\n");
        report["monotonicity"] = json!(summary);
        output::write_atomic(
            &c.results.join("truth-monotone.json"),
            serde_json::to_string_pretty(&json!({ "command": command, "scans": scans }))
                .expect("scans serialize")
                + "\n",
        )?;
        output::write_atomic(
            &c.results.join("truth-monotone.csv"),
            bias::scan_csv(&scans),
        )?;
    }
    output::write_atomic(
        &path("json"),
        serde_json::to_string_pretty(&report).expect("outcomes serialize") + "\n",
    )?;
    output::write_atomic(&path("md"), &md)?;
    output::write_atomic(&path("csv"), bias::csv(&outcomes))?;
    rgc::plot::bias_chart(&outcomes, &title, &path("svg"), &path("png"))?;
    if c.json {
        super::print_json(&report, out)
    } else {
        say!(out, "{md}");
        Ok(())
    }
}
