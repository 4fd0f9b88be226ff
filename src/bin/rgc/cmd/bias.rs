//! `rgc bias`: every 3D-RGC variant against the exact truth on the same
//! sequences; writes `truth-vs-rgc.{json,md,csv,svg,png}`.

use std::path::PathBuf;

use clap::Args;

use rgc::stamp::{self, Nothing, Stamp};
use rgc::threshold::bias::{self, VariantBias};
use rgc::threshold::experiment::{BiasReport, MadeBy, MonotoneReport};
use rgc::threshold::fss;
use rgc::threshold::variants;
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
    let command = super::command_line();
    let made = Stamp::new(None, &command, MadeBy::of(&template, &design));
    made.check_replace(&path("json"), "experiment", c.force)?;
    let progress = Reporter::new(c.quiet || c.json);
    let (outcomes, truth): (Vec<VariantBias>, _) = bias::measure(
        &template,
        &design,
        &c.studies,
        c.memory.memory_limit,
        c.study.bootstrap,
        &progress,
    )?;
    let title = format!(
        "3D-RGC against the exact truth, gamma {}: paired bias of the critical density",
        c.study.gamma
    );
    let mut md = bias::markdown(&title, &command, &outcomes, &template.boxes);
    let mut report = BiasReport {
        stamp: made,
        monotonicity: None,
        variants: outcomes,
    };
    if a.scan_sequences > 0 {
        let scans = bias::scan(
            &template,
            &truth,
            &a.scan_boxes,
            a.scan_sequences,
            a.scan_width,
            c.memory.memory_limit,
            &progress,
        )?;
        let summary = bias::scan_summary(&scans);
        md += &format!("\n{summary}\n");
        report.monotonicity = Some(summary);
        let monotone = MonotoneReport {
            stamp: Stamp::new(None, &command, Nothing {}),
            scans,
        };
        output::write_atomic(
            &c.results.join("truth-monotone.json"),
            stamp::json_sorted(&monotone),
        )?;
        output::write_atomic(
            &c.results.join("truth-monotone.csv"),
            bias::scan_csv(&monotone.scans),
        )?;
    }
    let json = stamp::json_sorted(&report);
    output::write_atomic(&path("json"), &json)?;
    output::write_atomic(&path("md"), &md)?;
    output::write_atomic(&path("csv"), bias::csv(&report.variants))?;
    rgc::plot::bias_chart(&report.variants, &title, &path("svg"), &path("png"))?;
    if c.json {
        say!(out, "{}", json.trim_end());
        Ok(())
    } else {
        say!(out, "{md}");
        Ok(())
    }
}
