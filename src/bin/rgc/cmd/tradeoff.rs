//! `rgc tradeoff`: threshold and interval width against CPU time.

use std::path::PathBuf;

use clap::Args;
use rgc::Result;
use rgc::threshold::variants;

use crate::args::VariantArgs;

#[derive(Args)]
pub struct TradeoffArgs {
    #[command(flatten)]
    common: VariantArgs,
    /// Runs per system to compare (more than 10 analyse half the sequences).
    #[arg(long, value_delimiter = ',', default_value = "1,10,40")]
    runs_list: Vec<usize>,
    /// Directory of the audit's rule files (`rods-6.json`, `rods-8.json`, `mixed-4.json`).
    #[arg(long, alias = "motifs-dir", default_value = "motifs")]
    rules_dir: PathBuf,
}

pub fn run(a: TradeoffArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let title = format!(
        "Speed against accuracy, rigidity threshold, gamma {}",
        c.study.gamma
    );
    let name = "speed-accuracy";
    let make = |r| variants::tradeoff_design(&a.runs_list, r, &a.rules_dir);
    let outcomes = super::run_experiment(c, name, &title, make, out)?;
    rgc::plot::speed_accuracy_chart(
        &outcomes,
        &title,
        &c.results.join(format!("{name}.svg")),
        &c.results.join(format!("{name}.png")),
    )
}
