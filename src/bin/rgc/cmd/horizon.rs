//! `rgc horizon`: 3D-RGC's bias against truth as its motif set grows.

use std::path::PathBuf;

use clap::Args;
use rgc::threshold::horizon;
use rgc::{Result, output, plot};

#[derive(Args)]
pub struct HorizonArgs {
    /// Truth studies (`rgc threshold --kind truth`), one per aspect ratio.
    #[arg(long, value_delimiter = ',', required = true)]
    truth: Vec<PathBuf>,
    /// Finished studies of the same sequences with some motif set each (`rgc threshold --rule-files ...`).
    #[arg(long, value_delimiter = ',', required = true)]
    variants: Vec<PathBuf>,
    /// Writes PREFIX.json, PREFIX.csv, PREFIX.svg and PREFIX.png.
    #[arg(long)]
    out: PathBuf,
}

pub fn run(a: HorizonArgs, out: &mut String) -> Result<()> {
    output::check_file(&a.out)?;
    let variants = horizon::measure(&a.truth, &a.variants)?;
    let trends = horizon::trends(&variants);
    say!(
        out,
        "{:>6}  {:<40} {:>6} {:>5} {:>5} {:>9} {:>20} {:>7} {:>9} {:>9}",
        "gamma",
        "variant",
        "rules",
        "nodes",
        "rods",
        "sequences",
        "bias [95%]",
        "share",
        "cpu/seq",
        "truth/seq"
    );
    for v in &variants {
        let m = &v.bias.mean;
        say!(
            out,
            "{:>6}  {:<40} {:>6} {:>5} {:>5} {:>9} {:>20} {:>6.2}% {:>8.2}s {:>8.2}s",
            v.gamma,
            v.label,
            v.rules,
            v.largest_nodes,
            v.largest_rods,
            v.bias.sequences,
            format!(
                "{:+.2} [{:+.2}, {:+.2}]",
                m.value,
                m.lo.unwrap_or(f64::NAN),
                m.hi.unwrap_or(f64::NAN)
            ),
            100.0 * v.bias.relative.value,
            v.cpu_per_sequence,
            v.truth_cpu_per_sequence
        );
    }
    for t in &trends {
        let series: Vec<String> = t
            .points
            .iter()
            .map(|(n, b)| format!("{n} rods {:.2}%", 100.0 * b))
            .collect();
        let halving = match (t.halving_size_linear, t.halving_rods_exponential) {
            (Some(size), Some(every)) => format!(
                "half the base bias at a largest motif of {size:.0} rods if it falls linearly, or every {every:.0} added rods if it decays exponentially"
            ),
            _ => "it does not fall, so no motif size halves it".into(),
        };
        say!(
            out,
            "gamma {}: rods-only bias by largest motif {}; it changes by {:+.4} of truth per added motif rod: {halving}",
            t.gamma,
            series.join(", "),
            -t.slope,
        );
    }
    let mut written = horizon::write(&a.out, &variants, &trends, &super::command_line())?;
    let (svg, png) = (
        output::with_extension(&a.out, "svg"),
        output::with_extension(&a.out, "png"),
    );
    plot::horizon_chart(&variants, &svg, &png)?;
    written.extend([svg, png]);
    for f in written {
        say!(out, "wrote {}", f.display());
    }
    Ok(())
}
