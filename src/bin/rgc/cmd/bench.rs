//! `rgc bench`: speed and memory on the reference systems, rank
//! throughput, the cost of truth, or of loading the extended rule sets.

use std::path::PathBuf;

use clap::Args;
use rgc::bench::{
    Foundation, Growth, REACH_DENSITY, TAIL_BOXES, TruthPlan, TruthReport, TruthRow, TruthSystem,
};
use rgc::{Error, Result, bench, output};
use serde::Serialize;

use crate::progress::Reporter;

#[derive(Args)]
pub struct BenchArgs {
    /// Repetitions per system (the median is reported).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
    repeat: u64,
    /// Only the systems up to this many rods.
    #[arg(long, default_value_t = 200_000)]
    max_rods: usize,
    /// Where the rule sets timed against the base engine are: `extended`
    /// (rods-6, rods-8 and mixed-4 .json) and `mined` (mined.json).
    #[arg(long, default_value = "motifs")]
    motifs: PathBuf,
    /// Time no rule sets.
    #[arg(long)]
    no_rules: bool,
    /// Instead: every rule set against the base engine on gamma 23 (L 10,
    /// rho 40) and gamma 98 (L 10, rho 190), one thread, interleaved:
    /// seconds, ratio to base, tasks, searches and merges, and each set's
    /// load time. The sets are --rule-set, else those of --motifs:
    /// extended (rods-6, rods-8, mixed-4), rods-10+mixed-4 (with rods-9 and
    /// rods-10, where both exist; rods-10+mixed-5 also with mixed-5) and
    /// mined.
    #[arg(long, conflicts_with_all = ["rank", "truth", "truth_aspects", "networkx", "no_rules", "rule_load"])]
    rule_sets: bool,
    /// A rule set of --rule-sets, `NAME=FILE[,FILE...]` (repeatable).
    #[arg(long, requires = "rule_sets")]
    rule_set: Vec<bench::RuleSetFiles>,
    /// Also set the whole `rgc sample` process against networkx's first RGC
    /// step (3-clique communities merged into bodies) on the same gamma 23,
    /// L = 10 system, interleaved; needs python3 with networkx.
    #[arg(long)]
    networkx: bool,
    /// The Python interpreter of --networkx.
    #[arg(long, default_value = "python3", requires = "networkx")]
    python: PathBuf,
    /// Also write the figures as JSON here.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Instead: exact and float rank throughput on random candidate motifs of this many rods (one thread).
    #[arg(long)]
    rank: Option<usize>,
    /// Print the figures as JSON instead of a table.
    #[arg(long, conflicts_with = "rank")]
    json: bool,
    /// Instead: the time to load the extended rule sets from --motifs (files read, every rule verified by exact rank on every thread, and compiled for the engine), median of --repeat.
    #[arg(long, conflicts_with_all = ["rank", "truth", "truth_aspects"])]
    rule_load: bool,
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
    /// Instead: truth on systems near the true threshold at gamma 23, 48 and 98, one thread each; their growth with the rods per gamma, and the cost per rod of gamma 98 (L 7) over gamma 23 (L 12) in the same run.
    #[arg(long, conflicts_with = "truth")]
    truth_aspects: bool,
    /// Instead: the elastic moduli against truth on gamma 23 systems near and above its threshold (box 3), both timed in one run.
    #[arg(long, conflicts_with_all = ["rank", "truth", "truth_aspects"])]
    moduli: bool,
    /// With --truth-aspects: add gamma 98, L 10 (165,000 rods; minutes and gigabytes).
    #[arg(long, requires = "truth_aspects")]
    truth_large: bool,
    /// With --truth-aspects: also run every system under memory limits (64 MiB, half and 1.5 times its peak), each in a process of its own, and report the peak against the limit: never more than 5% or 20 MB over it.
    #[arg(long, requires = "truth_aspects")]
    memory_limits: bool,
    /// Truth on one system, `gamma,density,box,seed`, as a JSON row: what `--truth` runs in a child process per system.
    #[arg(long, hide = true, conflicts_with_all = ["rank", "truth"])]
    truth_system: Option<String>,
    /// With --truth-system: run it as `rgc truth --memory-limit` does, bytes, and report the process's peak (what --memory-limits runs).
    #[arg(long, hide = true, requires = "truth_system")]
    memory_limit: Option<u64>,
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
        let system = spec.parse::<TruthSystem>()?;
        if let Some(limit) = a.memory_limit {
            return super::print_json(&system.under_limit(limit)?, out);
        }
        return super::print_json(&system.measure()?, out);
    }
    if a.rule_load {
        return rule_load(a, out);
    }
    if a.truth {
        return truth(a, out);
    }
    if a.truth_aspects {
        return truth_aspects(a, out);
    }
    if a.moduli {
        return moduli(a, out);
    }
    if a.rule_sets {
        return rule_sets(a, out);
    }
    bench::check_max_rods(a.max_rods)?;
    let sets = if a.no_rules {
        Vec::new()
    } else {
        bench::load_rule_sets(&a.motifs)?
    };
    if a.networkx {
        bench::networkx_version(&a.python)?;
    }
    let named: Vec<bench::RuleSetBench> = sets
        .iter()
        .map(|(name, rules)| bench::RuleSetBench {
            name: name.to_string(),
            rules,
        })
        .collect();
    let report = bench::run(a.repeat as usize, a.max_rods, &named);
    let networkx = if a.networkx {
        Some(bench::against_networkx(
            &rgc_exe()?,
            &a.python,
            a.repeat as usize,
        )?)
    } else {
        None
    };
    let all = Foundation { report, networkx };
    if written(&all, &a, out)? {
        return Ok(());
    }
    foundation_table(&all, out);
    Ok(())
}

fn foundation_table(all: &Foundation, out: &mut String) {
    let report = &all.report;
    say!(
        out,
        "{:>6} {:>6} {:>6} {:>8} {:>10} {:>10} {:>10} {:>11} {:>10} {:>9}",
        "gamma",
        "rho",
        "L",
        "rods",
        "contacts",
        "detect s",
        "compress s",
        "detect/rod",
        "ns/rod",
        "peak MiB"
    );
    for r in &report.systems {
        say!(
            out,
            "{:>6} {:>6} {:>6} {:>8} {:>10} {:>10.4} {:>10.4} {:>11.0} {:>10.0} {:>9.1}",
            r.gamma,
            r.density,
            r.box_len,
            r.n_rods,
            r.n_contacts,
            r.seconds_detect,
            r.seconds_compress,
            r.detect_ns_per_rod,
            r.ns_per_rod,
            r.peak_rss_mib
        );
    }
    if let Some(ratio) = report.detect_ratio_98_to_23 {
        say!(
            out,
            "detection per rod, gamma 98 over gamma 23 (L = 10): {ratio:.2}x"
        );
    }
    let (gamma, density, l) = report.rules_system;
    for r in &report.rules {
        say!(
            out,
            "{} ({} rules) at gamma {gamma}, rho {density}, L {l}: compression {:.3} s, {:.2}x the base engine",
            r.name,
            r.n_rules,
            r.seconds_compress,
            r.ratio_to_base
        );
    }
    if let Some(n) = &all.networkx {
        say!(
            out,
            "whole `rgc sample` process {:.3} s against networkx {} first RGC step {:.3} s: {:.1}x faster",
            n.rgc_sample_seconds,
            n.networkx_version,
            n.networkx_seconds,
            n.ratio
        );
    }
}

fn rule_load(a: BenchArgs, out: &mut String) -> Result<()> {
    let report = bench::run_rule_load(&a.motifs, a.repeat as usize)?;
    if written(&report, &a, out)? {
        return Ok(());
    }
    say!(
        out,
        "Loading rule sets from {} on {} threads, median of {}:",
        a.motifs.display(),
        report.threads,
        report.repeat
    );
    say!(
        out,
        "{:<20} {:>6} {:>8} {:>10} {:>8} {:>6}",
        "set",
        "rules",
        "load s",
        "compile s",
        "total s",
        "CPU s"
    );
    for r in &report.sets {
        say!(
            out,
            "{:<20} {:>6} {:>8.3} {:>10.3} {:>8.3} {:>6.3}",
            r.name,
            r.rules,
            r.seconds_load,
            r.seconds_compile,
            r.seconds,
            r.cpu_seconds
        );
    }
    Ok(())
}

fn rule_sets(a: BenchArgs, out: &mut String) -> Result<()> {
    let files = if a.rule_set.is_empty() {
        bench::default_rule_sets(&a.motifs)
    } else {
        a.rule_set.clone()
    };
    let sets = files
        .iter()
        .map(bench::load_set)
        .collect::<Result<Vec<_>>>()?;
    let report = bench::rules::run(a.repeat as usize, &sets);
    if written(&report, &a, out)? {
        return Ok(());
    }
    say!(
        out,
        "{:>5} {:>16} {:>5} {:>8} {:>6} {:>8} {:>6} {:>9} {:>9} {:>9} {:>7} {:>6}",
        "gamma",
        "rule set",
        "rules",
        "seconds",
        "ratio",
        "matching",
        "base",
        "rod tasks",
        "pairs",
        "searches",
        "merges",
        "rules"
    );
    for r in &report.rows {
        say!(
            out,
            "{:>5} {:>16} {:>5} {:>8.3} {:>6.2} {:>8.3} {:>6.2} {:>9.0} {:>9.0} {:>9.0} {:>7.0} {:>6.0}",
            r.gamma,
            r.name,
            r.n_rules,
            r.seconds,
            r.ratio_to_base,
            r.seconds_rules,
            r.base_work_ratio,
            r.rod_tasks,
            r.pair_tasks,
            r.attempts,
            r.merges,
            r.rule_merges
        );
    }
    for l in &report.loads {
        say!(
            out,
            "{}: {} rules ({} rods only) loaded and verified in {:.3} s, compiled in {:.3} s: {:.3} s",
            l.name,
            l.n_rules,
            l.n_rods_only,
            l.seconds_verify,
            l.seconds_compile,
            l.seconds_total
        );
    }
    say!(
        out,
        "medians of {} repetitions, one thread; ratio: the median of each repetition's time over the base engine's on the same graph;\n\
         matching: seconds spent on loaded rules; base: the rest over the base engine's time (the work the extra merges cause)",
        report.repeat
    );
    Ok(())
}

fn truth(a: BenchArgs, out: &mut String) -> Result<()> {
    let default = TruthPlan::default();
    let plan = TruthPlan {
        densities: a.truth_densities.clone().unwrap_or(default.densities),
        boxes: a.truth_boxes.clone().unwrap_or(default.boxes),
        seeds: a.truth_seeds.unwrap_or(default.seeds),
    };
    let exe = rgc_exe()?;
    let report = bench::run_truth(
        &plan,
        a.truth_max_seconds,
        a.truth_reach.map(|b| b as usize),
        |density, box_len, seed| {
            bench::truth_in_child(&exe, bench::TRUTH_GAMMA, density, box_len, seed)
        },
        &Reporter::new(a.json),
    )?;
    if written(&report, &a, out)? {
        return Ok(());
    }
    truth_table(&report, out);
    Ok(())
}

fn truth_aspects(a: BenchArgs, out: &mut String) -> Result<()> {
    let exe = rgc_exe()?;
    let mut report = bench::run_truth_aspects(
        a.truth_large,
        |gamma, density, box_len, seed| bench::truth_in_child(&exe, gamma, density, box_len, seed),
        &Reporter::new(a.json),
    )?;
    if a.memory_limits {
        report.limits = bench::run_memory_limits(
            &report.rows,
            |system, limit| system.under_limit_in_child(&exe, limit),
            &Reporter::new(a.json),
        )?;
    }
    if written(&report, &a, out)? {
        return Ok(());
    }
    say!(
        out,
        "gamma   rho   L    rods  core     front       CPU s  truth MiB  strain"
    );
    for r in &report.rows {
        say!(
            out,
            "{:>5} {:>5} {:>3} {:>7} {:>5} {:>11} {:>9.2} {:>10.1} {:>7}",
            r.gamma,
            r.density,
            r.box_len,
            r.n_rods,
            r.core_rods,
            r.largest_front
                .map_or("-".into(), |(rows, cols)| format!("{rows}x{cols}")),
            r.cpu_seconds.unwrap_or(r.seconds),
            r.truth_mib,
            r.strain_cost.map_or("-".into(), |c| format!(
                "{:+.1}%",
                100.0 * (c.ratio() - 1.0)
            ))
        );
    }
    let costs: Vec<_> = report.rows.iter().filter_map(|r| r.strain_cost).collect();
    if !costs.is_empty() {
        let (with, without) = costs
            .iter()
            .fold((0.0, 0.0), |(a, b), c| (a + c.with, b + c.without));
        say!(
            out,
            "strain columns (the strain rank): CPU {with:.2} s with, {without:.2} s without, {:+.1}% over all systems (each run again warm, in its child)",
            100.0 * (with / without - 1.0)
        );
    }
    for s in &report.scaling {
        say!(
            out,
            "gamma {}: CPU time ~ {}; truth memory ~ {}",
            s.gamma,
            law(s.time),
            law(s.memory)
        );
    }
    if let Some(ratio) = report.per_rod_ratio {
        let [(g1, l1), (g2, l2)] = bench::ASPECT_PAIR;
        say!(
            out,
            "CPU per rod, gamma {g1} L {l1} over gamma {g2} L {l2}: {ratio:.1}x"
        );
    }
    limits_table(&report.limits, out);
    Ok(())
}

/// The memory-limit rows: each peak against its limit, and the rule.
fn limits_table(rows: &[bench::LimitRow], out: &mut String) {
    if rows.is_empty() {
        return;
    }
    say!(out, "gamma   rho   L  limit MiB  peak MiB  within  outcome");
    for r in rows {
        say!(
            out,
            "{:>5} {:>5} {:>3} {:>10.1} {:>9.1} {:>7}  {}",
            r.gamma,
            r.density,
            r.box_len,
            r.limit_mib,
            r.peak_mib,
            if r.within { "yes" } else { "NO" },
            if r.refused.is_some() {
                "refused"
            } else {
                "finished"
            }
        );
    }
    let kept = rows.iter().filter(|r| r.within).count();
    say!(
        out,
        "peak within max(1.05 x limit, limit + 20 MB): {kept} of {}",
        rows.len()
    );
}

/// A fitted growth law as `N^a (R² b)`.
fn law(l: Option<Growth>) -> String {
    l.map_or("too few sizes to fit".into(), |l| {
        format!("N^{:.2} (R² {:.2})", l.exponent, l.r2)
    })
}

/// Writes the figures to --out when asked, and prints them as JSON with
/// --json: then nothing else is printed (true).
fn moduli(a: BenchArgs, out: &mut String) -> Result<()> {
    let rows = rgc::bench::moduli::SYSTEMS
        .iter()
        .map(|&(density, l, seed)| rgc::bench::moduli::measure(density, l, seed))
        .collect::<rgc::Result<Vec<_>>>()?;
    if written(&rows, &a, out)? {
        return Ok(());
    }
    for r in &rows {
        say!(
            out,
            "gamma 23, rho {}, L {}, seed {}: strain rank {}, G {:.3e} ({}); moduli {:.3} s, truth {:.3} s: {:.1}x (the relaxation alone {:.1}x; by LSMR {})",
            r.density,
            r.box_len,
            r.seed,
            r.strain_rank,
            r.shear,
            r.realization,
            r.seconds,
            r.truth_seconds,
            r.ratio,
            r.relaxation_ratio,
            match (r.lsmr_relaxation_ratio, r.lsmr_shear) {
                (Some(x), Some(g)) => format!("{x:.1}x, G {g:.3e}"),
                _ => "-".into(),
            }
        );
    }
    Ok(())
}

fn written(figures: &impl Serialize, a: &BenchArgs, out: &mut String) -> Result<bool> {
    if let Some(path) = &a.out {
        let text = serde_json::to_string_pretty(figures).expect("bench figures serialize");
        output::write_atomic(path, text + "\n")?;
    }
    if a.json {
        super::print_json(figures, out)?;
    }
    Ok(a.json)
}

/// This executable, which the benchmarks run in child processes.
fn rgc_exe() -> Result<PathBuf> {
    std::env::current_exe().map_err(|e| Error::io("rgc", e))
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
