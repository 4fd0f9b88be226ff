//! `rgc compare`: paper base, sound base and sound + extended motifs on the
//! same sequences.

use std::path::PathBuf;

use clap::Args;
use rgc::Result;
use rgc::threshold::variants;

use crate::args::VariantArgs;

#[derive(Args)]
pub struct CompareArgs {
    #[command(flatten)]
    common: VariantArgs,
    /// Runs per system.
    #[arg(long, default_value_t = 1)]
    runs: usize,
    /// The extended motif rule files.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "motifs/rods-6.json,motifs/rods-8.json,motifs/mixed-4.json"
    )]
    extended: Vec<PathBuf>,
}

pub fn run(a: CompareArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let title = format!(
        "Rigidity threshold, gamma {}: paper base against sound base against sound + extended motifs",
        c.study.gamma
    );
    let name = "compare-base-extended";
    let make = |r| variants::compare_design(a.runs, r, &a.extended);
    let outcomes = super::run_experiment(c, name, &title, make, out)?;
    rgc::plot::compare_chart(
        &outcomes,
        &title,
        &c.results.join(format!("{name}.svg")),
        &c.results.join(format!("{name}.png")),
    )
}
