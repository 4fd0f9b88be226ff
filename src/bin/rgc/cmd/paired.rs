//! `rgc paired`: finished studies of the same sequences compared sequence
//! by sequence (other minus reference critical density).

use std::path::PathBuf;

use clap::Args;
use rgc::plot;
use rgc::threshold::paired::{self, Difference};
use rgc::{Error, Result};

#[derive(Args)]
pub struct PairedArgs {
    /// Study directories in pairs: REFERENCE OTHER [REFERENCE OTHER ...].
    #[arg(required = true, num_args = 2..)]
    dirs: Vec<PathBuf>,
    /// Write PREFIX.json, PREFIX.csv, PREFIX.md, PREFIX.svg and PREFIX.png.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Replace those files if they exist.
    #[arg(long)]
    force: bool,
    /// Print the pairings as JSON and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: PairedArgs, out: &mut String) -> Result<()> {
    if !a.dirs.len().is_multiple_of(2) {
        return Err(Error::Parameter(format!(
            "paired takes study directories in pairs (REFERENCE OTHER ...); {} given",
            a.dirs.len()
        )));
    }
    if let Some(prefix) = &a.out {
        super::refuse_existing(prefix, &["json", "csv", "md", "svg", "png"], a.force)?;
    }
    let pairings = a
        .dirs
        .chunks(2)
        .map(|p| paired::of_dirs(&p[0], &p[1]))
        .collect::<Result<Vec<_>>>()?;
    let mut files = Vec::new();
    if let Some(prefix) = &a.out {
        files = paired::write(prefix, &pairings, &super::command_line())?;
        let with = |ext: &str| PathBuf::from(format!("{}.{ext}", prefix.display()));
        let (svg, png) = (with("svg"), with("png"));
        plot::paired_chart(&pairings, &svg, &png)?;
        files.extend([svg, png]);
    }
    if a.json {
        return super::print_json(&pairings, out);
    }
    let interval = |d: &Difference, vex: bool| {
        let e = if vex { d.mean_vex } else { d.mean };
        match (e.lo, e.hi) {
            (Some(lo), Some(hi)) => format!("{:+.4} [{lo:+.4}, {hi:+.4}]", e.value),
            _ => format!("{:+.4}", e.value),
        }
    };
    for p in &pairings {
        let c = &p.comparison;
        say!(
            out,
            "{} minus {} (gamma {}):",
            p.other,
            p.reference,
            c.gamma
        );
        say!(
            out,
            "{:>6} {:>9} {:>30} {:>30} {:>8} {:>6} {:>6}",
            "box",
            "sequences",
            "rho (95%)",
            "rho V_ex (95%)",
            "share",
            "below",
            "above"
        );
        for d in c.boxes.iter().chain([&c.all]) {
            let b = d.box_len.map_or("all".into(), |l| l.to_string());
            say!(
                out,
                "{b:>6} {:>9} {:>30} {:>30} {:>7.1}% {:>6} {:>6}",
                d.sequences,
                interval(d, false),
                interval(d, true),
                100.0 * d.relative.value,
                d.below,
                d.above
            );
        }
    }
    if !files.is_empty() {
        let shown: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
        say!(out, "Files: {}", shown.join(", "));
    }
    Ok(())
}
