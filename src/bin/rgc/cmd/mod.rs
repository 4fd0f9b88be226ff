//! One file per subcommand, each with its arguments and a `run` that calls
//! the library and prints; here, what several of them share.

use std::path::{Path, PathBuf};

use serde::Serialize;

use rgc::engine::CompiledRule;
use rgc::threshold::variants::{self, Design, VariantOutcome};
use rgc::{Error, Result, rule_file};

use crate::args::VariantArgs;
use crate::progress::Reporter;

pub mod aspect_ratios;
pub mod audit;
pub mod bench;
pub mod check;
pub mod compare;
pub mod compress;
pub mod enumerate;
pub mod merge;
pub mod rules;
pub mod sample;
pub mod stability;
pub mod threshold;
pub mod tradeoff;

fn print_json(value: &impl Serialize, out: &mut String) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("reports serialize");
    say!(out, "{text}");
    Ok(())
}

/// Loads and verifies rule files, ready for the engine.
fn load(paths: &[PathBuf]) -> Result<Vec<CompiledRule>> {
    Ok(rule_file::load_rules(paths)?
        .iter()
        .map(CompiledRule::new)
        .collect())
}

/// Creates the directory a file goes into, if it names one.
fn create_parent(path: &Path) -> Result<()> {
    match path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e)),
        None => Ok(()),
    }
}

/// The command line that made a result, for the files that record it.
fn command_line() -> String {
    std::env::args()
        .enumerate()
        .map(|(k, a)| if k == 0 { "rgc".to_string() } else { a })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs the variants of `design` (`compare`, `tradeoff`), writes
/// `results/NAME.{json,md,csv}` and prints the Markdown table.
fn run_experiment(
    args: &VariantArgs,
    name: &str,
    title: &str,
    design: &Design,
    out: &mut String,
) -> Result<Vec<VariantOutcome>> {
    let template = args.study.spec();
    template.validate()?;
    let outcomes = variants::run_variants(
        &template,
        &design.variants,
        &args.studies,
        args.study.bootstrap,
        design.pairing,
        &Reporter::new(args.quiet),
    )?;
    let dir = &args.results;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let write = |ext: &str, text: String| -> Result<()> {
        let path = dir.join(format!("{name}.{ext}"));
        std::fs::write(&path, text).map_err(|e| Error::io(&path, e))
    };
    let command = command_line();
    write(
        "json",
        serde_json::to_string_pretty(&serde_json::json!({
            "command": command,
            "template": template,
            "variants": outcomes,
        }))
        .expect("outcomes serialize")
            + "\n",
    )?;
    let md = variants::markdown(title, &command, &outcomes);
    write("md", md.clone())?;
    write("csv", variants::csv(&outcomes))?;
    say!(out, "{md}");
    Ok(outcomes)
}
