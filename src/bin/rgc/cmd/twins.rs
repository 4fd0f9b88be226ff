//! `rgc twins`: how often truth's exact realizations disagree, measured on
//! the evaluations of truth studies ranked again.

use std::path::PathBuf;

use clap::Args;
use rgc::Result;
use rgc::threshold::twins::{self, TwinsSpec};

use crate::progress::Reporter;

#[derive(Args)]
pub struct TwinsArgs {
    /// Truth study directories (`rgc threshold --kind truth`), finished or in progress.
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Boxes to rank again [default: every box of each study].
    #[arg(long, value_delimiter = ',')]
    boxes: Vec<f64>,
    /// The first this many sequences of each box.
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    sequences: u64,
    /// Realizations ranked whole per evaluation (the third is the lone one).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(2..=3))]
    realizations: u64,
    /// The measurement's directory: its spec and one line of ranks per sequence (rerun to resume).
    #[arg(long)]
    out: PathBuf,
    /// Also write the tally as PREFIX.json and PREFIX.csv.
    #[arg(long)]
    tally: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

pub fn run(a: TwinsArgs, out: &mut String) -> Result<()> {
    let spec = TwinsSpec {
        studies: a.dirs.iter().map(|d| d.display().to_string()).collect(),
        boxes: a.boxes.clone(),
        sequences: a.sequences,
        realizations: a.realizations as usize,
    };
    let tallies = twins::run(
        &a.dirs,
        &spec,
        &a.out,
        a.tally.as_deref(),
        &Reporter::new(a.quiet),
    )?;
    say!(
        out,
        "{:>6} {:>5} {:>9} {:>11} {:>12} {:>12} {:>10}",
        "gamma",
        "box",
        "sequences",
        "evaluations",
        "twins differ",
        "lone differs",
        "any below"
    );
    for t in &tallies {
        say!(
            out,
            "{:>6} {:>5} {:>9} {:>11} {:>12} {:>12} {:>10}",
            t.gamma,
            t.box_len,
            t.sequences,
            t.evaluations,
            t.twins_differ,
            t.lone_differs,
            t.any_below
        );
    }
    if let Some(prefix) = &a.tally {
        for f in twins::write(prefix, &tallies, &super::command_line())? {
            say!(out, "wrote {}", f.display());
        }
    }
    Ok(())
}
