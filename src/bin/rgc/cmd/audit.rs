//! `rgc audit`: which small rigid motifs the engine misses; their tables and rule files.

use std::path::PathBuf;

use clap::Args;
use rgc::audit::{self, AuditOptions};
use rgc::engine::RuleSet;
use rgc::progress::Progress;
use rgc::{Result, output};

use crate::progress::Reporter;

#[derive(Args)]
pub struct AuditArgs {
    /// Rods-only motifs with up to this many rods [default: 8; 10 with --extended].
    #[arg(long, value_parser = clap::value_parser!(u64).range(2..=10))]
    max_rods: Option<u64>,
    /// Mixed motifs (rods, planar and spatial bodies) with up to this many components [default: 4; 5 with --extended].
    #[arg(long, value_parser = clap::value_parser!(u64).range(0..=5))]
    max_components: Option<u64>,
    /// The extended audit: rods up to 10, mixed motifs up to 5 components;
    /// its tables in results/audit-extended/, and only the rule files of the
    /// sizes above the default audit's (rods-9.json, rods-10.json,
    /// mixed-5.json), so the default audit's files stay as they are.
    #[arg(long)]
    extended: bool,
    /// The engine's rule set.
    #[arg(long, value_enum, default_value_t = RuleSet::Sound)]
    rules: RuleSet,
    /// Motif orders tried per pattern.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// Also audit every way a body's contacts can share its rods (mixed motifs).
    #[arg(long)]
    rod_sharing: bool,
    /// Where the tables go (`audit-rods.csv`, `audit-mixed.csv`) [default: results; results/audit-extended with --extended].
    #[arg(long)]
    results: Option<PathBuf>,
    /// Where the rule files of the missed motifs go.
    #[arg(long, alias = "motifs", default_value = "motifs")]
    rules_dir: PathBuf,
    /// Print the tables as JSON.
    #[arg(long)]
    json: bool,
    /// Replace tables and rule files that an audit with other parameters wrote.
    #[arg(long)]
    force: bool,
}

pub fn run(a: AuditArgs, out: &mut String) -> Result<()> {
    let preset = if a.extended {
        AuditOptions::extended()
    } else {
        AuditOptions::default()
    };
    let opts = AuditOptions {
        max_rods: a.max_rods.map_or(preset.max_rods, |n| n as usize),
        max_components: a
            .max_components
            .map_or(preset.max_components, |n| n as usize),
        rules: a.rules,
        runs: a.runs,
        rod_sharing: a.rod_sharing,
        ..preset
    };
    let results = a.results.unwrap_or_else(|| {
        PathBuf::from(if a.extended {
            "results/audit-extended"
        } else {
            "results"
        })
    });
    // Refused before the work: outputs that cannot be written, or that
    // another audit made (the committed tables and rules `compare` reads).
    output::check_dir(&results)?;
    output::check_dir(&a.rules_dir)?;
    if !a.force {
        audit::check_outputs(&opts, &results, &a.rules_dir)?;
    }
    let examples = audit::self_check()?;
    let started = std::time::Instant::now();
    let reporter = Reporter::new(a.json);
    let result = audit::run(&opts, &reporter)?;
    let files = audit::write_outputs(&result, &opts, &results, &a.rules_dir)?;
    let shown = |paths: &[std::path::PathBuf]| {
        paths
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let written: Vec<String> = files
        .rule_files
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    if a.json {
        return super::print_json(
            &serde_json::json!({ "rods": result.rods, "mixed": result.mixed, "rule_files": written }),
            out,
        );
    }
    say!(
        out,
        "{examples} base motif examples compress as expected (sound and paper).\n"
    );
    for (title, rows) in [
        ("Rods-only motifs (size = rods)", &result.rods),
        ("Mixed motifs (size = components)", &result.mixed),
    ] {
        if rows.is_empty() {
            continue;
        }
        say!(out, "{title}, rules {}, {} motif orders:", a.rules, a.runs);
        say!(out, "{}", audit::table(rows));
    }
    say!(
        out,
        "Tables: {}. Rule files: {}.",
        shown(&files.tables),
        if written.is_empty() && opts.extended {
            "none (none missed above the default audit's sizes)".to_string()
        } else if written.is_empty() {
            "none (nothing missed)".to_string()
        } else {
            written.join(", ")
        }
    );
    say!(
        out,
        "Falsely compressed patterns, with the motifs that compressed each: {}.",
        shown(&files.beside)
    );
    // Timings on stderr: what stdout and the tables hold repeats exactly.
    let seconds = |rows: &[audit::AuditRow]| {
        rows.iter()
            .map(|r| format!("{} {:.3}", r.size, r.seconds))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let parts: Vec<String> = [("rods", &result.rods), ("mixed", &result.mixed)]
        .into_iter()
        .filter(|(_, rows)| !rows.is_empty())
        .map(|(kind, rows)| format!("{kind} {}", seconds(rows)))
        .collect();
    reporter.note(&format!(
        "Seconds by size: {}; {:.1} s in all.",
        parts.join("; "),
        started.elapsed().as_secs_f64()
    ));
    Ok(())
}
