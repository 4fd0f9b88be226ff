//! `rgc rules`: the base motifs as a verified rule file; or, with
//! `--check`, the rules of given rule files that smaller ones make redundant.

use std::path::PathBuf;

use clap::Args;
use rgc::engine::RuleSet;
use rgc::{Result, audit, engine, output, rule_file};

use crate::progress::Reporter;

#[derive(Args)]
pub struct RulesArgs {
    /// Where the base motif rules go.
    #[arg(long, default_value = "motifs/base.json")]
    out: PathBuf,
    /// Replace `--out` if it exists.
    #[arg(long)]
    force: bool,
    /// Instead: load these rule files (or directories of them) and report
    /// every rule the engine compresses to one node with the smaller rules
    /// among them (fewer nodes, or as many and fewer contacts) in some
    /// motif order: a redundant rule.
    #[arg(long, num_args = 1.., value_name = "FILE", conflicts_with_all = ["out", "force"])]
    check: Vec<PathBuf>,
    /// With --check: the engine's rule set.
    #[arg(long, value_enum, default_value_t = RuleSet::Sound, requires = "check")]
    rules: RuleSet,
    /// With --check: motif orders tried per rule (redundant if any of them compresses it).
    #[arg(long, default_value_t = 8, requires = "check", value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// With --check: print the redundant rules as JSON.
    #[arg(long, requires = "check")]
    json: bool,
}

pub fn run(a: RulesArgs, out: &mut String) -> Result<()> {
    if !a.check.is_empty() {
        return check(&a, out);
    }
    super::refuse_files(std::slice::from_ref(&a.out), a.force)?;
    output::check_file(&a.out)?;
    let (rules, refuted) = engine::shapes::base_rules()?;
    rule_file::write_rules(&a.out, &rules)?;
    say!(
        out,
        "{} base motif rules written to {}; {} variants the published conditions accept are refuted by exact rank:",
        rules.len(),
        a.out.display(),
        refuted.len()
    );
    for r in &refuted {
        say!(
            out,
            "  {} {} (DOF {:?}): {}",
            r.motif,
            r.class,
            r.dof,
            serde_json::to_string(&r.pattern).expect("patterns serialize")
        );
    }
    Ok(())
}

/// `--check`: the redundant rules of the files, one line each.
fn check(a: &RulesArgs, out: &mut String) -> Result<()> {
    let rules = super::load_rules(&a.check)?;
    let found = audit::redundant(&rules, a.rules, a.runs, &Reporter::new(a.json))?;
    if a.json {
        return super::print_json(&found, out);
    }
    let files = a
        .check
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ");
    say!(
        out,
        "{} rules of {files}, rules {}, {} motif orders: {} redundant{}",
        rules.len(),
        a.rules,
        a.runs,
        found.len(),
        if found.is_empty() { "." } else { ":" }
    );
    for r in &found {
        let motifs: Vec<String> = r
            .sequence
            .iter()
            .map(|m| serde_json::to_value(m).expect("motifs serialize"))
            .map(|v| v.as_str().unwrap_or_default().to_string())
            .collect();
        say!(
            out,
            "  {} ({} nodes, {} contacts): one node in motif order {} by {}",
            r.id,
            r.nodes,
            r.contacts,
            r.run,
            motifs.join(", ")
        );
    }
    Ok(())
}
