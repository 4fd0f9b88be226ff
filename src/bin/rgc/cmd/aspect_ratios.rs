//! `rgc aspect-ratios`: finished studies' thresholds against 1/V_ex, with
//! the fits, as CSV and a chart.

use std::path::PathBuf;

use clap::Args;
use rgc::threshold::aspect;
use rgc::threshold::sequence::Kind;
use rgc::{Result, output, plot};

#[derive(Args)]
pub struct AspectArgs {
    /// Finished study directories (each with its summary.json), one per aspect ratio.
    #[arg(required = true)]
    studies: Vec<PathBuf>,
    /// Output path without extension: `.csv`, `.json` (the rows and both fits, with intervals), `.svg` and `.png` are written.
    #[arg(long, default_value = "results/threshold-vs-vex")]
    out: PathBuf,
}

pub fn run(a: AspectArgs, out: &mut String) -> Result<()> {
    output::check_file(&a.out)?;
    let r = aspect::read(&a.studies)?;
    for row in &r.rows {
        say!(
            out,
            "gamma {:>6}: threshold {:.4}, times V_ex {:.4}",
            row.gamma,
            row.threshold,
            row.threshold_times_vex
        );
    }
    let interval =
        |i: Option<(f64, f64)>| i.map_or(String::new(), |(lo, hi)| format!(" [{lo:.4}, {hi:.4}]"));
    say!(
        out,
        "fit: rho_c = {:.4}{} / V_ex (exponent fixed to 1){}",
        r.fit.fixed,
        interval(r.fit.fixed_interval),
        r.fit.free.map_or(String::new(), |p| format!(
            "; rho_c = {:.4} (1/V_ex)^m with m = {:.4}{}, R² = {:.4}",
            p.a,
            p.m,
            interval(p.m_interval),
            p.r2
        ))
    );
    let with = |ext: &str| a.out.with_extension(ext);
    aspect::write_csv(&with("csv"), &r.rows)?;
    aspect::write_json(&with("json"), &r)?;
    let title = format!(
        "{} threshold against the inverse excluded volume 1/V_ex",
        match r.kind {
            Kind::Contact => "Contact",
            Kind::Rigid => "Rigidity",
            Kind::Truth => "True rigidity",
        }
    );
    plot::threshold_vs_vex(&r.points(), &r.fit, &title, &with("svg"), &with("png"))?;
    say!(
        out,
        "Files: {}, {}, {}, {}",
        with("csv").display(),
        with("json").display(),
        with("svg").display(),
        with("png").display()
    );
    Ok(())
}
