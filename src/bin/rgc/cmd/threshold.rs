//! `rgc threshold`: a resumable, shardable study of the percolation
//! threshold, and its analysis (shared with `rgc merge`).

use std::path::{Path, PathBuf};

use clap::Args;
use serde::Serialize;

use rgc::threshold::fss::{self, Estimate, Protocol};
use rgc::threshold::report::{self, Concluded, PerBoxReport, Summary, file_list};
use rgc::threshold::sequence::{Kind, Record};
use rgc::threshold::study::{self, MotifSet, RunOptions, Shard, StudySpec};
use rgc::{Result, plot};

use crate::args::{MemoryArgs, RuleArgs, StudyArgs};
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
    #[command(flatten)]
    memory: MemoryArgs,
    /// Independent compressions per system; it spans if any run finds a spanning body.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// `nested`: each sequence's exact critical number of rods; `fixed`: the paper's grid of densities.
    #[arg(long, alias = "method", value_enum, default_value_t = Protocol::Nested)]
    protocol: Protocol,
    /// Densities per box in the fixed protocol's grid (found by a pilot run).
    #[arg(long, default_value_t = 12)]
    grid_points: usize,
    /// The fixed protocol's densities (rods per unit volume), the same in every box, instead of a pilot's grid: for quantities compared across boxes at one density, such as the Binder cumulant of `rgc transition`.
    #[arg(long, value_delimiter = ',', requires = "protocol")]
    grid_densities: Option<Vec<f64>>,
    /// Run only slice i of n (`i/n`, from 0); combine the slices with `rgc merge`.
    #[arg(long)]
    shard: Option<String>,
    /// Grow the study in --out, made with fewer sequences per box, to --sequences; its records are kept.
    #[arg(long)]
    extend: bool,
    /// Study directory: checkpoints, tables and charts. Run the same command again to resume.
    #[arg(long)]
    out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Print the outcome as one JSON object (the summary, the files written) and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: ThresholdArgs, out: &mut String) -> Result<()> {
    fss::check_bootstrap(a.study.bootstrap)?;
    let mut spec = StudySpec {
        kind: a.kind,
        rules: a.rules.rules,
        runs: a.runs as usize,
        method: a.protocol,
        grid_points: a.grid_points,
        grid_densities: a.grid_densities,
        ..a.study.spec()
    };
    // A study the analysis could not use fails before its rules are verified or its sequences run.
    spec.validate_for_analysis()?;
    let rules = super::load_rules(&a.rules.rule_files)?;
    spec.motifs = MotifSet::of(&rules, &a.rules.rule_files);
    let shard = a
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()?
        .unwrap_or(Shard::WHOLE);
    let opts = RunOptions {
        out: a.out.clone(),
        shard,
        extend: a.extend,
        memory_limit: a.memory.memory_limit,
    };
    let compiled: Vec<_> = rules.iter().map(rgc::engine::CompiledRule::new).collect();
    let done = study::run(&spec, &compiled, &opts, &Reporter::new(a.quiet || a.json))?;
    let ran = Ran {
        ran: done.ran,
        resumed: done.resumed,
        seconds: done.seconds,
    };
    if !done.complete && a.json {
        return super::print_json(&serde_json::json!({ "run": ran, "complete": false }), out);
    }
    if !a.json {
        say!(
            out,
            "{} sequences run in {:.1} s ({} found done).",
            done.ran,
            done.seconds,
            done.resumed
        );
    }
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
    analyse(
        &a.out,
        &spec,
        &records,
        a.study.bootstrap,
        Some(ran).filter(|_| a.json),
        a.json,
        out,
    )
}

/// What `rgc threshold --json` says of the sequences it ran.
#[derive(Clone, Copy, Serialize)]
pub struct Ran {
    pub ran: usize,
    pub resumed: usize,
    pub seconds: f64,
}

/// Writes a finished study's tables and charts into `dir` and prints its
/// summary (as JSON with `json`, with `ran` when a run came first); where
/// the scaling analysis fails, the per-box results and the failure that
/// [`report::conclude`] gives.
pub fn analyse(
    dir: &Path,
    spec: &StudySpec,
    records: &[Record],
    bootstrap: usize,
    ran: Option<Ran>,
    json: bool,
    out: &mut String,
) -> Result<()> {
    let mut written = match report::conclude(dir, spec, records, bootstrap)? {
        Concluded::Full(w) => *w,
        Concluded::PerBox(per_box) => {
            if json {
                super::print_json(
                    &serde_json::json!({ "run": ran, "complete": true, "summary": null, "per_box": per_box }),
                    out,
                )?;
            } else {
                print_per_box(&per_box, out);
                say!(out, "warning: {}", per_box.warning());
                say!(out, "Files: {}", file_list(&per_box.files));
            }
            return Err(per_box.failure());
        }
    };
    let charts = plot::study_charts(spec, &written, dir)?;
    written.files.extend(charts);
    let (s, files) = (written.summary, written.files);
    if json {
        return super::print_json(
            &serde_json::json!({ "run": ran, "complete": true, "summary": s, "files": files }),
            out,
        );
    }
    print_summary(&s, out);
    say!(out, "Files: {}", file_list(&files));
    Ok(())
}

/// The header of the per-box table both summaries print.
fn box_header(out: &mut String) {
    say!(
        out,
        "{:>6} {:>6} {:>10} {:>10} {:>10}",
        "box",
        "n",
        "mu",
        "s",
        "delta_rho"
    );
}

fn print_per_box(r: &PerBoxReport, out: &mut String) {
    box_header(out);
    for b in &r.boxes {
        match (&b.fit, &b.error) {
            (Some(f), _) => say!(
                out,
                "{:>6} {:>6} {:>10.4} {:>10.4} {:>10.4}",
                b.box_len,
                b.sequences,
                f.mu,
                f.s,
                f.delta_rho()
            ),
            (None, e) => say!(
                out,
                "{:>6} {:>6} no fit: {}",
                b.box_len,
                b.observations,
                e.as_deref().unwrap_or("")
            ),
        }
    }
}

fn print_summary(s: &Summary, out: &mut String) {
    let f = &s.fss;
    let interval = |e: &Estimate| match (e.lo, e.hi) {
        (Some(lo), Some(hi)) => format!("[{lo:.4}, {hi:.4}]"),
        _ => "(no interval)".into(),
    };
    box_header(out);
    for b in &f.boxes {
        say!(
            out,
            "{:>6} {:>6} {:>10.4} {:>10.4} {:>10.4}",
            b.box_len,
            b.sequences,
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
            "fresh compression at the critical number misses the spanning body in {} of {} sequences (found only with carried bodies)",
            o.fresh_misses,
            o.fresh_checks
        );
    }
    if o.undecided > 0 {
        say!(
            out,
            "truth undecided (no realization of the model) in {} sequences, left out of the analysis",
            o.undecided
        );
    }
    if o.nonmonotone_steps > 0 {
        say!(
            out,
            "non-monotone spanning: {} steps in {} sequences",
            o.nonmonotone_steps,
            o.nonmonotone_sequences
        );
    }
    for w in &f.warnings {
        say!(out, "warning: {w}");
    }
}
