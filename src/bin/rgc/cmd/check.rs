//! `rgc check`: whether a contact pattern is rigid, by exact rank or floats.

use std::path::PathBuf;

use clap::Args;
use rgc::graph::io as graphio;
use rgc::pattern::Pattern;
use rgc::rigidity::{Ranker, Verdict};
use rgc::rule_file::RuleFile;
use rgc::{Error, Result};

#[derive(Args)]
#[group(id = "pattern", required = true, multiple = false)]
struct PatternInput {
    /// A rods-only contact graph as graph6.
    #[arg(long, group = "pattern")]
    graph6: Option<String>,
    /// A pattern (JSON `Pattern`) or a rule file (every rule is checked).
    #[arg(long, group = "pattern")]
    motif: Option<PathBuf>,
}

#[derive(Args)]
pub struct CheckArgs {
    #[command(flatten)]
    input: PatternInput,
    /// `exact` (rank over F_p), `svd` or `qr` (floats, undecided when the gap is small).
    #[arg(long, alias = "method", value_enum, default_value_t = Ranker::Exact)]
    rank_method: Ranker,
    /// Seed of the realizations.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print JSON instead of a summary.
    #[arg(long)]
    json: bool,
}

fn verdict(p: &Pattern, method: Ranker, seed: u64) -> Result<Verdict> {
    match method {
        Ranker::Exact => rgc::rigidity::check_exact(p, seed),
        _ => rgc::rigidity::check_float(p, method, seed),
    }
}

pub fn run(a: CheckArgs, out: &mut String) -> Result<()> {
    let patterns: Vec<(String, Pattern)> = match (&a.input.graph6, &a.input.motif) {
        (Some(s), _) => vec![(s.clone(), Pattern::from_graph(&graphio::parse_graph6(s)?)?)],
        (None, Some(path)) => {
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            let bad = |e: serde_json::Error| {
                Error::Parameter(format!(
                    "{}: neither a pattern nor a rule file: {e}",
                    path.display()
                ))
            };
            match serde_json::from_str::<RuleFile>(&text) {
                Ok(file) => file.rules.into_iter().map(|r| (r.id, r.pattern)).collect(),
                Err(_) => vec![(
                    path.display().to_string(),
                    serde_json::from_str::<Pattern>(&text).map_err(bad)?,
                )],
            }
        }
        (None, None) => unreachable!("clap requires one input"),
    };
    let mut verdicts = Vec::new();
    for (name, p) in &patterns {
        let v = verdict(p, a.rank_method, a.seed)?;
        if !a.json {
            say!(
                out,
                "{name}: {} (DOF {}, rank {}, {:?})",
                v.class,
                v.dof.map_or("?".into(), |d| d.to_string()),
                v.rank,
                v.method
            );
            for c in &v.components {
                say!(
                    out,
                    "  {:<34} dimension {:>3}{} DOF {}",
                    c.built,
                    c.dimension,
                    if c.component {
                        "            "
                    } else {
                        " (special)  "
                    },
                    c.dof
                );
            }
            if let Some(note) = &v.note {
                say!(out, "  note: {note}");
            }
        }
        verdicts.push(v);
    }
    if a.json {
        return if verdicts.len() == 1 {
            super::print_json(&verdicts[0], out)
        } else {
            super::print_json(&verdicts, out)
        };
    }
    Ok(())
}
