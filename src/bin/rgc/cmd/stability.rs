//! `rgc stability`: where float ranks fail against the exact verdict.

use std::path::PathBuf;

use clap::Args;
use rgc::{Error, Result, output};

#[derive(Args)]
pub struct StabilityArgs {
    /// Where `rank-stability.{csv,svg,png}` go.
    #[arg(long, default_value = "results")]
    out: PathBuf,
}

pub fn run(a: StabilityArgs, out: &mut String) -> Result<()> {
    output::check_dir(&a.out)?;
    let rows = rgc::stability::run(&rgc::stability::StudyConfig::full())?;
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(&a.out, e))?;
    rgc::stability::write_csv(&rows, &a.out.join("rank-stability.csv"))?;
    rgc::plot::stability_chart(
        &rows,
        &a.out.join("rank-stability.svg"),
        &a.out.join("rank-stability.png"),
    )?;
    say!(
        out,
        "{} rows written to {}/rank-stability.{{csv,svg,png}}",
        rows.len(),
        a.out.display()
    );
    Ok(())
}
