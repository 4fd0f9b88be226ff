//! `rgc planes`: where forced planes percolate, per aspect ratio, against
//! the committed thresholds.

use std::path::PathBuf;

use clap::Args;
use rgc::threshold::planes::{self, Crossing, Parameters, Report};
use rgc::{Result, output, plot};

use crate::progress::Reporter;

#[derive(Args)]
pub struct PlanesArgs {
    /// Aspect ratios l / (2r), comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "23,48,98"
    )]
    gamma: Vec<f64>,
    /// Box side in rod lengths: one for every gamma, or one per gamma (comma-separated).
    #[arg(
        long = "box",
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "3.2"
    )]
    box_len: Vec<f64>,
    /// Seeds 1..=SEEDS at each density (one seed's systems are nested).
    #[arg(long, default_value_t = 4)]
    seeds: u64,
    /// Mean contact numbers rho V_ex to scan, comma-separated (default 2 to 6 in steps of 0.25).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    contact_numbers: Option<Vec<f64>>,
    /// Where `forced-planes.{json,csv,svg,png}` go.
    #[arg(long, default_value = "results")]
    results: PathBuf,
    /// Where the committed threshold studies (`g{gamma}-contact`, `g{gamma}-rigid-sound`) are read, to mark them.
    #[arg(long, default_value = "results")]
    thresholds: PathBuf,
    /// Replace `forced-planes.json` even when a scan with other parameters made it.
    #[arg(long)]
    force: bool,
    /// No progress bars.
    #[arg(long)]
    quiet: bool,
    /// Print the report (as written to `forced-planes.json`) and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: PlanesArgs, out: &mut String) -> Result<()> {
    let params = Parameters::new(
        a.gamma,
        &a.box_len,
        a.seeds,
        a.contact_numbers
            .unwrap_or_else(planes::default_contact_numbers),
    )?;
    output::check_dir(&a.results)?;
    let path = |ext: &str| a.results.join(format!("forced-planes.{ext}"));
    let command = super::command_line();
    planes::stamp(&command, &params).check_replace(&path("json"), "scan", a.force)?;
    let report = planes::run(
        &params,
        &a.thresholds,
        &command,
        &Reporter::new(a.quiet || a.json),
    )?;
    planes::write(&report, &a.results)?;
    plot::forced_planes_chart(&report.scans, &path("svg"), &path("png"))?;
    if a.json {
        return super::print_json(&report, out);
    }
    summary(&report, out);
    say!(
        out,
        "Files: {}, {}, {}, {}",
        path("json").display(),
        path("csv").display(),
        path("svg").display(),
        path("png").display()
    );
    Ok(())
}

fn summary(r: &Report, out: &mut String) {
    let show = |c: &Crossing| match c {
        Crossing::Within {
            density,
            contact_number,
        } => format!("{density:.2} (rho V_ex {contact_number:.3})"),
        Crossing::AtFirst => "at or below the first density".into(),
        Crossing::NotReached => "not reached".into(),
    };
    for s in &r.scans {
        say!(
            out,
            "gamma {} (box {}, {} seeds, {:.0} s):",
            s.spec.gamma,
            s.spec.box_len,
            s.spec.seeds,
            s.seconds
        );
        say!(
            out,
            "  largest forced class above half the heavy rods: {}",
            show(&s.percolation)
        );
        say!(
            out,
            "  half the systems unrealizable (forced flat):    {}",
            show(&s.flat)
        );
        for (name, t) in [
            ("rigidity", &s.references.rigidity),
            ("contact", &s.references.contact),
        ] {
            if let Some(t) = t {
                say!(
                    out,
                    "  committed {name} threshold: {:.2} (rho V_ex {:.3})",
                    t.density,
                    t.contact_number
                );
            }
        }
    }
}
