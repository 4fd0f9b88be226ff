//! `rgc rules`: the base motifs as a verified rule file.

use std::path::PathBuf;

use clap::Args;
use rgc::{Result, engine, output, rule_file};

#[derive(Args)]
pub struct RulesArgs {
    /// Where the base motif rules go.
    #[arg(long, default_value = "motifs/base.json")]
    out: PathBuf,
    /// Replace `--out` if it exists.
    #[arg(long)]
    force: bool,
}

pub fn run(a: RulesArgs, out: &mut String) -> Result<()> {
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
