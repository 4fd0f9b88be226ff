//! `rgc compare`: paper base, sound base and sound + extended motifs on the
//! same sequences.

use clap::Args;
use rgc::Result;
use rgc::threshold::variants;

use crate::args::{ExtendedArgs, VariantArgs};

#[derive(Args)]
pub struct CompareArgs {
    #[command(flatten)]
    common: VariantArgs,
    /// Runs per system.
    #[arg(long, default_value_t = 1)]
    runs: usize,
    #[command(flatten)]
    extended: ExtendedArgs,
}

pub fn run(a: CompareArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let title = format!(
        "Rigidity threshold, gamma {}: paper base against sound base against sound + extended motifs",
        c.study.gamma
    );
    let name = "compare-base-extended";
    let make = |r| variants::compare_design(a.runs, r, &a.extended.files);
    let outcomes = super::run_experiment(c, name, &title, make, out)?;
    rgc::plot::compare_chart(
        &outcomes,
        &title,
        &c.results.join(format!("{name}.svg")),
        &c.results.join(format!("{name}.png")),
    )
}
