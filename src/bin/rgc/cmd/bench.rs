//! `rgc bench`: speed and memory on the reference systems, rank
//! throughput, or the cost of truth.

use std::path::PathBuf;
use std::process::Command;

use clap::Args;
use rgc::bench::{PowerLaw, REACH_DENSITY, TAIL_BOXES, TruthPlan, TruthReport, TruthRow};
use rgc::{Error, Result, bench, output};

use crate::progress::Reporter;

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
    /// Print the figures as JSON instead of a table.
    #[arg(long, conflicts_with = "rank")]
    json: bool,
    /// Instead: time and peak memory of truth on gamma 23 systems near its threshold, one thread; fits their growth with the rods.
    #[arg(long, conflicts_with = "rank")]
    truth: bool,
    /// Box sides of the truth benchmark [default: 3,4,5,6,7].
    #[arg(long, value_delimiter = ',', requires = "truth")]
    truth_boxes: Option<Vec<usize>>,
    /// Densities of the truth benchmark [default: 34,38].
    #[arg(long, value_delimiter = ',', requires = "truth")]
    truth_densities: Option<Vec<f64>>,
    /// Seeds 1..=N of each truth benchmark system [default: 3].
    #[arg(long, requires = "truth", value_parser = clap::value_parser!(u64).range(1..=1000))]
    truth_seeds: Option<u64>,
    /// The time limit of the reach: the largest box truth decides within it at density 38, predicted from the growth on the largest boxes (measured with --truth-reach).
    #[arg(long, default_value_t = 600.0, requires = "truth")]
    truth_max_seconds: f64,
    /// Also measure the reach: box sides 3, 4, ... up to this one at density 38 (seed 1) until one system takes longer than --truth-max-seconds.
    #[arg(long, requires = "truth", value_parser = clap::value_parser!(u64).range(3..=100))]
    truth_reach: Option<u64>,
    /// Truth on one system, `density,box,seed`, as a JSON row: what `--truth` runs in a child process per system.
    #[arg(long, hide = true, conflicts_with_all = ["rank", "truth"])]
    truth_system: Option<String>,
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
    if let Some(spec) = &a.truth_system {
        let row = one_system(spec)?;
        return super::print_json(&row, out);
    }
    if a.truth {
        return truth(a, out);
    }
    bench::check_max_rods(a.max_rods)?;
    let rows = bench::run(a.repeat as usize, a.max_rods);
    if let Some(path) = &a.out {
        let text = serde_json::to_string_pretty(&rows).expect("bench rows serialize");
        std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))?;
    }
    if a.json {
        return super::print_json(&rows, out);
    }
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
    Ok(())
}

fn truth(a: BenchArgs, out: &mut String) -> Result<()> {
    let default = TruthPlan::default();
    let plan = TruthPlan {
        densities: a.truth_densities.unwrap_or(default.densities),
        boxes: a.truth_boxes.unwrap_or(default.boxes),
        seeds: a.truth_seeds.unwrap_or(default.seeds),
    };
    let report = bench::run_truth(
        &plan,
        a.truth_max_seconds,
        a.truth_reach.map(|b| b as usize),
        in_child,
        &Reporter::new(a.json),
    )?;
    if let Some(path) = &a.out {
        let text = serde_json::to_string_pretty(&report).expect("truth report serializes");
        output::write_atomic(path, text + "\n")?;
    }
    if a.json {
        return super::print_json(&report, out);
    }
    truth_table(&report, out);
    Ok(())
}

/// Truth on `density,box,seed` in this process.
fn one_system(spec: &str) -> Result<TruthRow> {
    let bad = || {
        Error::Parameter(format!(
            "--truth-system wants density,box,seed, got {spec:?}"
        ))
    };
    let [density, l, seed] = spec.split(',').collect::<Vec<_>>()[..] else {
        return Err(bad());
    };
    bench::measure_truth(
        density.trim().parse().map_err(|_| bad())?,
        l.trim().parse().map_err(|_| bad())?,
        seed.trim().parse().map_err(|_| bad())?,
    )
}

/// Truth on one system in a child process of its own, so that its peak
/// memory is its own: in one long process, pages the allocator kept from
/// earlier systems would hide what later ones need. (The standard library
/// cannot read a child's peak memory, so the child reports it.)
fn in_child(density: f64, l: usize, seed: u64) -> Result<TruthRow> {
    let exe = std::env::current_exe().map_err(|e| Error::io("rgc", e))?;
    let spec = format!("{density},{l},{seed}");
    let child = Command::new(&exe)
        .args(["bench", "--truth-system", &spec])
        .output()
        .map_err(|e| Error::io(&exe, e))?;
    let failed = |why: String| Error::io(&exe, std::io::Error::other(why));
    if !child.status.success() {
        return Err(failed(format!(
            "truth on system {spec} failed: {}",
            String::from_utf8_lossy(&child.stderr).trim()
        )));
    }
    serde_json::from_slice(&child.stdout)
        .map_err(|e| failed(format!("truth on system {spec}: unreadable row: {e}")))
}

fn truth_table(r: &TruthReport, out: &mut String) {
    say!(
        out,
        "{:>4} {:>3} {:>4} {:>6} {:>6} {:>6} {:>7} {:>9} {:>11} {:>9} {:>8} {:>8} {:>9}",
        "rho",
        "L",
        "seed",
        "rods",
        "core",
        "parts",
        "columns",
        "rank",
        "front",
        "seconds",
        "CPU s",
        "peak MiB",
        "truth MiB"
    );
    for row in &r.rows {
        truth_line(row, out);
    }
    if let Some(reach) = &r.reach {
        say!(
            out,
            "reach: density {REACH_DENSITY}, seed 1, box 3 up to {} or the first over {} s",
            reach.max_box,
            reach.max_seconds
        );
        for row in &reach.rows {
            truth_line(row, out);
        }
    }
    say!(
        out,
        "seconds: wall time (fitted below); CPU s: of the thread, less where other processes shared the cores;\n\
         peak MiB: the process while truth ran (one per system); truth MiB: what truth added to it"
    );
    let reset = r
        .rows
        .iter()
        .chain(r.reach.iter().flat_map(|x| &x.rows))
        .all(|row| row.peak_reset);
    if !reset {
        say!(
            out,
            "(the peak could not be reset before truth: the figures include generation and contact detection)"
        );
    }
    let law = |l: Option<PowerLaw>| {
        l.map_or("too few sizes to fit".into(), |l| {
            format!("N^{:.2} (R² {:.2})", l.exponent, l.r2)
        })
    };
    for s in &r.scaling {
        say!(
            out,
            "density {}: time ~ {}, on the largest {TAIL_BOXES} boxes ~ {}; truth memory ~ {}",
            s.density,
            law(s.time),
            law(s.time_tail),
            law(s.memory)
        );
    }
    let limit = r.max_seconds;
    let measured = r.rows.iter().map(|row| row.box_len).max().unwrap_or(0);
    match r.predicted_largest_box {
        Some(l) => say!(
            out,
            "largest box within {limit} s at density {REACH_DENSITY}: L = {l}, predicted (not measured): \
             the time law of the largest {TAIL_BOXES} boxes extrapolated beyond L = {measured}"
        ),
        None => say!(
            out,
            "largest box within {limit} s at density {REACH_DENSITY}: no prediction (no fit at that density, or no box fits)"
        ),
    }
    if let Some(reach) = &r.reach {
        let largest = reach
            .largest_box
            .map_or("none".into(), |l| format!("L = {l}"));
        let why = if reach.stopped_by_time {
            "the next box took longer"
        } else {
            "the cap stopped the search"
        };
        say!(
            out,
            "measured: {largest} finished within {limit} s ({why}; box cap {})",
            reach.max_box
        );
    }
}

fn truth_line(row: &TruthRow, out: &mut String) {
    say!(
        out,
        "{:>4} {:>3} {:>4} {:>6} {:>6} {:>6} {:>7} {:>9} {:>11} {:>9.3} {:>8} {:>8.1} {:>9.1}",
        row.density,
        row.box_len,
        row.seed,
        row.n_rods,
        row.core_rods,
        row.parts,
        row.columns,
        row.rank.map_or("undecided".into(), |k| k.to_string()),
        row.largest_front
            .map_or("-".into(), |(rows, cols)| format!("{rows}x{cols}")),
        row.seconds,
        row.cpu_seconds.map_or("-".into(), |c| format!("{c:.2}")),
        row.peak_mib,
        row.truth_mib
    );
}
