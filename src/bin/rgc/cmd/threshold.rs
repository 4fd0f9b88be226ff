//! `rgc threshold`: a resumable, shardable study of the percolation
//! threshold, and its analysis (shared with `rgc merge`).

use std::path::{Path, PathBuf};

use clap::Args;
use rgc::threshold::fss::{Estimate, Protocol};
use rgc::threshold::report::{self, Summary};
use rgc::threshold::sequence::{Kind, Record};
use rgc::threshold::study::{self, MotifSet, RunOptions, Shard, StudySpec};
use rgc::{Result, plot, rule_file};

use crate::args::{RuleArgs, StudyArgs};
use crate::progress::Reporter;

#[derive(Args)]
pub struct ThresholdArgs {
    /// Which spanning cluster: connected (`contact`) or rigid (`rigid`).
    #[arg(long, value_enum, default_value_t = Kind::Rigid)]
    kind: Kind,
    #[command(flatten)]
    study: StudyArgs,
    #[command(flatten)]
    rules: RuleArgs,
    /// Independent compressions per system; it spans if any run finds a spanning body.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// `nested`: each sequence's exact critical number of rods; `fixed`: the paper's grid of densities.
    #[arg(long, alias = "method", value_enum, default_value_t = Protocol::Nested)]
    protocol: Protocol,
    /// Densities per box in the fixed protocol's grid (found by a pilot run).
    #[arg(long, default_value_t = 12)]
    grid_points: usize,
    /// Run only slice i of n (`i/n`, from 0); combine the slices with `rgc merge`.
    #[arg(long)]
    shard: Option<String>,
    /// Study directory: checkpoints, tables and charts. Run the same command again to resume.
    #[arg(long)]
    out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

pub fn run(a: ThresholdArgs, out: &mut String) -> Result<()> {
    let rules = rule_file::load_rules(&a.rules.rule_files)?;
    let spec = StudySpec {
        kind: a.kind,
        rules: a.rules.rules,
        motifs: MotifSet::of(&rules, &a.rules.rule_files),
        runs: a.runs as usize,
        method: a.protocol,
        grid_points: a.grid_points,
        ..a.study.spec()
    };
    let shard = a
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()?
        .unwrap_or(Shard::WHOLE);
    let opts = RunOptions {
        out: a.out.clone(),
        shard,
    };
    let compiled: Vec<_> = rules.iter().map(rgc::engine::CompiledRule::new).collect();
    let done = study::run(&spec, &compiled, &opts, &Reporter::new(a.quiet))?;
    say!(
        out,
        "{} realizations run in {:.1} s ({} found done).",
        done.ran,
        done.seconds,
        done.resumed
    );
    if !done.complete {
        say!(
            out,
            "Shard {}/{} is done; when every shard is, run `rgc merge {}`.",
            shard.index,
            shard.count,
            a.out.display()
        );
        return Ok(());
    }
    let records = study::in_study_order(&spec, study::read_records(&a.out, &spec)?);
    analyse(&a.out, &spec, &records, a.study.bootstrap, out)
}

/// Writes a finished study's tables and charts into `dir` and prints its summary.
pub fn analyse(
    dir: &Path,
    spec: &StudySpec,
    records: &[Record],
    bootstrap: usize,
    out: &mut String,
) -> Result<()> {
    let mut written = report::write_study(dir, spec, records, bootstrap)?;
    let charts = plot::study_charts(spec, &written, dir)?;
    written.files.extend(charts);
    let (s, files) = (written.summary, written.files);
    print_summary(&s, out);
    say!(
        out,
        "Files: {}",
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}

fn print_summary(s: &Summary, out: &mut String) {
    let f = &s.fss;
    let interval = |e: &Estimate| match (e.lo, e.hi) {
        (Some(lo), Some(hi)) => format!("[{lo:.4}, {hi:.4}]"),
        _ => "(no interval)".into(),
    };
    say!(
        out,
        "{:>6} {:>6} {:>10} {:>10} {:>10}",
        "box",
        "n",
        "mu",
        "s",
        "delta_rho"
    );
    for b in &f.boxes {
        say!(
            out,
            "{:>6} {:>6} {:>10.4} {:>10.4} {:>10.4}",
            b.box_len,
            b.realizations,
            b.mu,
            b.s,
            b.delta_rho
        );
    }
    say!(
        out,
        "threshold rho_c = {:.4} {} ({:.0}% interval, {} resamples); rho_c V_ex = {:.4}",
        f.threshold.value,
        interval(&f.threshold),
        100.0 * f.confidence,
        f.bootstrap,
        s.threshold_times_vex
    );
    say!(out, "nu = {:.4} {}", f.nu.value, interval(&f.nu));
    if let Some(c) = &f.contact_numbers {
        for (name, fit) in [
            ("c0", &c.pooled.c0),
            ("c1", &c.pooled.c1),
            ("c2", &c.pooled.c2),
        ] {
            say!(
                out,
                "{name} at threshold = {:.4} {}",
                fit.at_threshold.value,
                interval(&fit.at_threshold)
            );
        }
    }
    let o = &s.order;
    if let Some(rate) = o.single_run_miss_rate {
        say!(
            out,
            "single runs miss {:.1}% of the spanning bodies that {} runs find",
            100.0 * rate,
            s.study.runs
        );
    }
    if o.fresh_checks > 0 {
        say!(
            out,
            "fresh compression at the critical number misses the spanning body in {} of {} realizations (found only with carried bodies)",
            o.fresh_misses,
            o.fresh_checks
        );
    }
    if o.nonmonotone_steps > 0 {
        say!(
            out,
            "non-monotone spanning: {} steps in {} realizations",
            o.nonmonotone_steps,
            o.nonmonotone_realizations
        );
    }
    for w in &f.warnings {
        say!(out, "warning: {w}");
    }
}
