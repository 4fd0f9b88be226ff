//! `rgc tradeoff`: threshold and interval width against CPU time.

use std::path::PathBuf;

use clap::Args;
use rgc::Result;
use rgc::output;
use rgc::threshold::{tradeoff, variants};

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
    /// Instead: set the finished experiments of these aspect ratios (in
    /// `--results`) side by side, the bias in percent of each one's truth
    /// threshold: `speed-accuracy-gammas.{md,csv,svg,png}`.
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    combine: Vec<f64>,
}

pub fn run(a: TradeoffArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let title = format!(
        "Speed against accuracy, rigidity threshold, gamma {}",
        c.study.gamma
    );
    if !a.combine.is_empty() {
        return combine(&a, out);
    }
    let name = tradeoff::name(c.study.gamma);
    let make = |r| variants::tradeoff_design(&a.runs_list, r, &a.rules_dir);
    let outcomes = super::run_experiment(c, &name, &title, make, out)?;
    rgc::plot::speed_accuracy_chart(
        &outcomes,
        &title,
        &c.results.join(format!("{name}.svg")),
        &c.results.join(format!("{name}.png")),
    )
}

/// `--combine`: the experiments of several aspect ratios side by side.
fn combine(a: &TradeoffArgs, out: &mut String) -> Result<()> {
    let dir = &a.common.results;
    let panels = tradeoff::read(dir, &a.combine)?;
    let command = super::command_line();
    let md = tradeoff::markdown(&panels, &command);
    let [md_path, csv_path, svg, png] = tradeoff::paths(dir);
    output::write_atomic(&md_path, &md)?;
    output::write_csv(&csv_path, tradeoff::rows(&panels))?;
    let gammas: Vec<String> = a.combine.iter().map(|g| g.to_string()).collect();
    let title = format!(
        "Speed against accuracy, rigidity threshold, gamma {}",
        gammas.join(", ")
    );
    rgc::plot::speed_accuracy_gammas(&panels, &title, &svg, &png)?;
    say!(out, "{md}");
    Ok(())
}
