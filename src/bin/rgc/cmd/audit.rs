//! `rgc audit`: which small rigid motifs the engine misses; their tables and rule files.

use std::path::PathBuf;

use clap::Args;
use rgc::audit::{self, AuditOptions};
use rgc::engine::RuleSet;
use rgc::{Error, Result, rule_file};

use crate::progress::Reporter;

#[derive(Args)]
pub struct AuditArgs {
    /// Rods-only motifs with up to this many rods.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u64).range(2..=10))]
    max_rods: u64,
    /// Mixed motifs (rods, planar and spatial bodies) with up to this many components.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u64).range(0..=5))]
    max_components: u64,
    /// The engine's rule set.
    #[arg(long, value_enum, default_value_t = RuleSet::Sound)]
    rules: RuleSet,
    /// Motif orders tried per pattern.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// Also audit every way a body's contacts can share its rods (mixed motifs).
    #[arg(long)]
    rod_sharing: bool,
    /// Where the tables go (`audit-rods.csv`, `audit-mixed.csv`).
    #[arg(long, default_value = "results")]
    results: PathBuf,
    /// Where the rule files of the missed motifs go.
    #[arg(long, default_value = "motifs")]
    motifs: PathBuf,
    /// Print the tables as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: AuditArgs, out: &mut String) -> Result<()> {
    let examples = audit::self_check()?;
    let opts = AuditOptions {
        max_rods: a.max_rods as usize,
        max_components: a.max_components as usize,
        rules: a.rules,
        runs: a.runs,
        rod_sharing: a.rod_sharing,
    };
    let started = std::time::Instant::now();
    let result = audit::run(&opts, &Reporter::new(a.json))?;
    for dir in [&a.results, &a.motifs] {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    // A part that did not run (size 0) keeps its previous table.
    let mut tables = Vec::new();
    for (name, rows) in [
        ("audit-rods.csv", &result.rods),
        ("audit-mixed.csv", &result.mixed),
    ] {
        if !rows.is_empty() {
            let path = a.results.join(name);
            audit::write_csv(&path, rows)?;
            tables.push(path.display().to_string());
        }
    }
    let mut written = Vec::new();
    for (kind, sets) in [("rods", &result.rod_rules), ("mixed", &result.mixed_rules)] {
        for (size, rules) in sets.iter().filter(|(_, r)| !r.is_empty()) {
            let path = a.motifs.join(format!("{kind}-{size}.json"));
            rule_file::write_rules(&path, rules)?;
            written.push(path.display().to_string());
        }
    }
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
        say!(
            out,
            "{title}, rules {:?}, {} motif orders:",
            a.rules,
            a.runs
        );
        say!(out, "{}", audit::table(rows));
    }
    say!(
        out,
        "Tables: {}. Rule files: {}. {:.1} s.",
        tables.join(", "),
        if written.is_empty() {
            "none (nothing missed)".to_string()
        } else {
            written.join(", ")
        },
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
