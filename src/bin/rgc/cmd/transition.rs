//! `rgc transition`: the order of the rigidity transition from truth
//! studies (the jump of the largest true cluster at the critical rod, and
//! its share of the rods above the threshold).

use std::path::PathBuf;

use clap::Args;
use rgc::Result;
use rgc::plot;
use rgc::threshold::transition::{self, Transition};

#[derive(Args)]
pub struct TransitionArgs {
    /// Truth study directories (`rgc threshold --kind truth`), finished or in progress; studies of one aspect ratio with different boxes (a large-box study beside the small boxes) are read as one, and fixed-protocol truth studies (`--protocol fixed --grid-densities ...`) give the Binder cumulant at their densities.
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// The box of the P_inf curve [default: each study's largest box with records].
    #[arg(long = "box")]
    box_len: Option<f64>,
    /// Density bins of the P_inf curve.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u64).range(1..=100))]
    bins: u64,
    /// Write PREFIX.json, PREFIX.csv, PREFIX.histogram.csv, PREFIX.svg and PREFIX.png (and PREFIX.binder.csv where fixed-protocol truth studies give a Binder cumulant).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Replace those files if they exist.
    #[arg(long)]
    force: bool,
    /// Print the transitions as JSON and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: TransitionArgs, out: &mut String) -> Result<()> {
    let with = |prefix: &PathBuf, ext: &str| PathBuf::from(format!("{}.{ext}", prefix.display()));
    if let Some(prefix) = &a.out {
        super::refuse_existing(
            prefix,
            &["json", "csv", "histogram.csv", "binder.csv", "svg", "png"],
            a.force,
        )?;
    }
    let all: Vec<Transition> = transition::of_dirs(&a.dirs, a.box_len, a.bins as usize)?;
    let mut files = Vec::new();
    if let Some(prefix) = &a.out {
        files = transition::write(prefix, &all, &super::command_line())?;
        let (svg, png) = (with(prefix, "svg"), with(prefix, "png"));
        plot::transition_chart(&all, &svg, &png)?;
        files.extend([svg, png]);
    }
    if a.json {
        return super::print_json(&all, out);
    }
    for t in &all {
        say!(out, "{} (gamma {}):", t.study, t.gamma);
        say!(
            out,
            "{:>6} {:>9} {:>8} {:>18} {:>8} {:>8} {:>8} {:>8} {:>16} {:>28}",
            "box",
            "sequences",
            "jump",
            "95% (bootstrap)",
            "min",
            "max",
            "before",
            "at",
            "solid before/at",
            "critical density [95%]"
        );
        for j in &t.jumps {
            let known: usize = j.strain_at.iter().sum();
            say!(
                out,
                "{:>6} {:>9} {:>8.4} {:>18} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>16} {:>28}",
                j.box_len,
                j.sequences,
                j.mean,
                format!("[{:.4}, {:.4}]", j.interval.0, j.interval.1),
                j.min,
                j.max,
                j.before,
                j.at_critical,
                format!("{}/{} of {known}", j.strain_before[6], j.strain_at[6]),
                format!(
                    "{:.3} [{:.3}, {:.3}]",
                    j.critical_density, j.critical_interval.0, j.critical_interval.1
                )
            );
        }
        if let Some(d) = &t.drift {
            say!(
                out,
                "mean critical density over L = {:?}: slope {:.4} [{:.4}, {:.4}] per unit of L",
                d.boxes,
                d.slope,
                d.interval.0,
                d.interval.1
            );
        }
        for d in &t.decay {
            say!(
                out,
                "mean jump ~ L^-x over L = {:?}: x = {:.3} [{:.3}, {:.3}] (R^2 {:.3})",
                d.boxes,
                d.exponent,
                d.interval.0,
                d.interval.1,
                d.r2
            );
        }
        if !t.binder.is_empty() {
            say!(
                out,
                "Binder cumulant of the largest cluster's share (fixed densities):"
            );
            for b in &t.binder {
                say!(
                    out,
                    "  L = {:>4}, density {:>8.3}: U = {:.4} [{:.4}, {:.4}], mean share {:.4} ({} sequences)",
                    b.box_len,
                    b.density,
                    b.cumulant,
                    b.interval.0,
                    b.interval.1,
                    b.mean,
                    b.sequences
                );
            }
        }
        if let Some(first) = t.shares.first() {
            say!(
                out,
                "largest cluster's share at spanning steps, L = {}:",
                first.box_len
            );
            for s in &t.shares {
                say!(
                    out,
                    "  density {:>8.3}: {:.4} (sd {:.4}, {} steps)",
                    s.density,
                    s.mean,
                    s.sd,
                    s.steps
                );
            }
        }
    }
    for f in &files {
        say!(out, "wrote {}", f.display());
    }
    Ok(())
}
