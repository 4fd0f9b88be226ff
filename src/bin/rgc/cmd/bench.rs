//! `rgc bench`: speed and memory on the reference systems, or rank throughput.

use std::path::PathBuf;

use clap::Args;
use rgc::{Error, Result, bench, output};

#[derive(Args)]
pub struct BenchArgs {
    /// Repetitions per system (the median is reported).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
    repeat: u64,
    /// Only the systems up to this many rods.
    #[arg(long, default_value_t = 200_000)]
    max_rods: usize,
    /// Also write the figures as JSON here.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Instead: exact and float rank throughput on random candidate motifs of this many rods (one thread).
    #[arg(long)]
    rank: Option<usize>,
}

pub fn run(a: BenchArgs, out: &mut String) -> Result<()> {
    if let Some(path) = &a.out {
        output::check_file(path)?;
    }
    if let Some(n) = a.rank {
        let t = rgc::stability::throughput(n, 200, 0.2)?;
        say!(
            out,
            "{n} rods, one thread: ranks/s exact {:.0}, SVD {:.0}, QR {:.0}; verdicts/s exact {:.0}, SVD {:.0}, QR {:.0}; exact/SVD rank speed {:.1}x",
            t.exact_per_s,
            t.svd_per_s,
            t.qr_per_s,
            t.check_exact_per_s,
            t.check_svd_per_s,
            t.check_qr_per_s,
            t.exact_per_s / t.svd_per_s
        );
        return Ok(());
    }
    bench::check_max_rods(a.max_rods)?;
    let rows = bench::run(a.repeat as usize, a.max_rods);
    say!(
        out,
        "{:>6} {:>6} {:>6} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9}",
        "gamma",
        "rho",
        "L",
        "rods",
        "contacts",
        "detect s",
        "compress s",
        "ns/rod",
        "peak MiB"
    );
    for r in &rows {
        say!(
            out,
            "{:>6} {:>6} {:>6} {:>8} {:>10} {:>10.4} {:>10.4} {:>10.0} {:>9.1}",
            r.gamma,
            r.density,
            r.box_len,
            r.n_rods,
            r.n_contacts,
            r.seconds_detect,
            r.seconds_compress,
            r.ns_per_rod,
            r.peak_rss_mib
        );
    }
    if let Some(path) = &a.out {
        let text = serde_json::to_string_pretty(&rows).expect("bench rows serialize");
        std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))?;
    }
    Ok(())
}
