//! `rgc aspect-ratios`: finished studies' thresholds against 1/V_ex, with
//! the fits and the contact numbers at each threshold, as CSV, Markdown and
//! a chart.

use std::path::PathBuf;

use clap::Args;
use rgc::threshold::aspect::{self, AspectRatios};
use rgc::threshold::sequence::Kind;
use rgc::{Result, output, plot};

#[derive(Args)]
pub struct AspectArgs {
    /// Finished study directories (each with its summary.json), one per aspect ratio.
    #[arg(required = true)]
    studies: Vec<PathBuf>,
    /// Finished studies of another kind to draw beside them (for example
    /// 3D-RGC's beside the truth's), with their own fits.
    #[arg(long, num_args = 1.., value_delimiter = ',')]
    beside: Vec<PathBuf>,
    /// Output path without extension: `.csv`, `.json` (the rows and both fits, with intervals), `.svg` and `.png` are written, and `-contacts.csv` and `-contacts.md` (c0, c1, c2 at each threshold against Maxwell's 10/3).
    #[arg(long, default_value = "results/threshold-vs-vex")]
    out: PathBuf,
    /// Replace those files if they exist.
    #[arg(long)]
    force: bool,
}

fn name(kind: Kind) -> &'static str {
    match kind {
        Kind::Contact => "contact",
        Kind::Rigid => "3D-RGC",
        Kind::Truth => "truth",
    }
}

pub fn run(a: AspectArgs, out: &mut String) -> Result<()> {
    output::check_file(&a.out)?;
    let with = |ext: &str| PathBuf::from(format!("{}.{ext}", a.out.display()));
    let contacts = |ext: &str| PathBuf::from(format!("{}-contacts.{ext}", a.out.display()));
    let files = [
        with("csv"),
        with("json"),
        with("svg"),
        with("png"),
        contacts("csv"),
        contacts("md"),
    ];
    super::refuse_files(&files, a.force)?;
    let mut all = vec![aspect::read(&a.studies)?];
    if !a.beside.is_empty() {
        all.push(aspect::read(&a.beside)?);
    }
    let interval =
        |i: Option<(f64, f64)>| i.map_or(String::new(), |(lo, hi)| format!(" [{lo:.4}, {hi:.4}]"));
    for r in &all {
        for row in &r.rows {
            say!(
                out,
                "{} gamma {:>6}: threshold {:.4}, times V_ex {:.4}",
                name(r.kind),
                row.gamma,
                row.threshold,
                row.threshold_times_vex
            );
        }
        say!(
            out,
            "{} fit: rho_c = {:.4}{} / V_ex (exponent fixed to 1){}",
            name(r.kind),
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
        for c in r.contacts.iter().filter(|c| c.box_len.is_none()) {
            say!(
                out,
                "{} gamma {:>6}: at the threshold c0 {:.4}, c1 {:.4}, c2 {:.4} ({:+.4} from Maxwell's 10/3)",
                name(r.kind),
                c.gamma,
                c.c0,
                c.c1,
                c.c2,
                c.c2_minus_maxwell
            );
        }
    }
    aspect::write_csv(
        &with("csv"),
        &all.iter().flat_map(|r| r.rows.clone()).collect::<Vec<_>>(),
    )?;
    aspect::write_json(&with("json"), &all)?;
    aspect::write_contacts(&contacts("csv"), &contacts("md"), &all)?;
    let title = match all.as_slice() {
        [r] => format!(
            "{} threshold against the inverse excluded volume 1/V_ex",
            match r.kind {
                Kind::Contact => "Contact",
                Kind::Rigid => "Rigidity",
                Kind::Truth => "True rigidity",
            }
        ),
        _ => "Thresholds against the inverse excluded volume 1/V_ex".to_string(),
    };
    let points: Vec<_> = all.iter().map(AspectRatios::points).collect();
    let series: Vec<plot::VexSeries> = all
        .iter()
        .zip(&points)
        .map(|(r, p)| plot::VexSeries {
            label: name(r.kind),
            points: p,
            fit: &r.fit,
        })
        .collect();
    plot::threshold_vs_vex(&series, &title, &with("svg"), &with("png"))?;
    let shown: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    say!(out, "Files: {}", shown.join(", "));
    Ok(())
}
