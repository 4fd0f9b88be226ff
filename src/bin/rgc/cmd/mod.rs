//! One file per subcommand, each with its arguments and a `run` that calls
//! the library and prints; here, what several of them share.

use std::path::PathBuf;

use rayon::prelude::*;
use serde::Serialize;

use rgc::engine::CompiledRule;
use rgc::stamp::{self, Stamp};
use rgc::threshold::experiment::Experiment;
use rgc::threshold::fss;
use rgc::threshold::variants::{self, Design, VariantOutcome};
use rgc::{Result, output, rule_file};

use crate::args::VariantArgs;
use crate::progress::Reporter;

pub mod aspect_ratios;
pub mod audit;
pub mod bench;
pub mod bias;
pub mod check;
pub mod compare;
pub mod compress;
pub mod enumerate;
pub mod horizon;
pub mod locality;
pub mod merge;
pub mod mine;
pub mod moduli;
pub mod paired;
pub mod planes;
pub mod render;
pub mod rules;
pub mod sample;
pub mod stability;
pub mod stiffening;
pub mod threshold;
pub mod tradeoff;
pub mod transition;
pub mod truth;
pub mod twins;
pub mod workspace;

/// The output files given, as (flag, path), checked before the work: each
/// writable, and no two the same file ([`output::check_outputs`]).
fn check_outputs(outputs: &[(&str, &Option<PathBuf>)]) -> Result<()> {
    let given: Vec<(&str, &std::path::Path)> = outputs
        .iter()
        .filter_map(|(flag, p)| Some((*flag, p.as_deref()?)))
        .collect();
    output::check_outputs(&given)
}

/// An `--out` prefix must end in a file name: `DIR/` would write the
/// hidden files `DIR/.png` and `DIR/.svg`.
fn check_prefix(prefix: &std::path::Path) -> Result<()> {
    let text = prefix.to_string_lossy();
    if text.ends_with('/') || prefix.file_name().is_none() || prefix.is_dir() {
        return Err(rgc::Error::Parameter(format!(
            "--out {text} is a directory: give a file name prefix, such as {}",
            prefix.join("name").display()
        )));
    }
    Ok(())
}

/// Refuses to replace `PREFIX.ext` for any of `exts` unless `force`: an
/// exploratory run never silently replaces committed results. Each file
/// must be writable (its folder is made now, as for every output).
fn refuse_existing(prefix: &std::path::Path, exts: &[&str], force: bool) -> Result<()> {
    check_prefix(prefix)?;
    let paths: Vec<std::path::PathBuf> = exts
        .iter()
        .map(|ext| format!("{}.{ext}", prefix.display()).into())
        .collect();
    refuse_files(&paths, force)?;
    paths.iter().try_for_each(|p| output::check_file(p))
}

/// Refuses to replace any of `paths` that exists, unless `force`.
fn refuse_files(paths: &[std::path::PathBuf], force: bool) -> Result<()> {
    match paths.iter().find(|p| !force && p.exists()) {
        Some(path) => Err(rgc::Error::Parameter(format!(
            "{} exists; choose another --out, or --force to replace it",
            path.display()
        ))),
        None => Ok(()),
    }
}

fn print_json(value: &impl Serialize, out: &mut String) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("reports serialize");
    say!(out, "{text}");
    Ok(())
}

/// Loads and verifies rule files, ready for the engine (each rule compiled
/// on its own: in parallel).
fn load(paths: &[PathBuf]) -> Result<Vec<CompiledRule>> {
    Ok(load_rules(paths)?
        .par_iter()
        .map(CompiledRule::new)
        .collect())
}

/// Loads and verifies rule files; a file given twice or a rule repeated is
/// dropped with one warning line each on stderr.
fn load_rules(paths: &[PathBuf]) -> Result<Vec<rule_file::Rule>> {
    let loaded = rule_file::load(paths)?;
    for d in &loaded.dropped {
        eprintln!("rgc: warning: {d}");
    }
    Ok(loaded.rules)
}

/// The command line that made a result, for the files that record it.
fn command_line() -> String {
    std::env::args()
        .enumerate()
        .map(|(k, a)| if k == 0 { "rgc".to_string() } else { a })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs the variants of the design `make` gives for `--sequences`
/// (`compare`, `tradeoff`), writes `results/NAME.{json,md,csv}` and prints
/// the Markdown table (or the JSON). Everything that can be refused is
/// refused before the first sequence runs.
fn run_experiment(
    args: &VariantArgs,
    name: &str,
    title: &str,
    make: impl Fn(u64) -> Design,
    out: &mut String,
) -> Result<Vec<VariantOutcome>> {
    let template = args.study.spec();
    let design = variants::checked_design(make, &template)?;
    template.validate_for_analysis()?;
    fss::check_bootstrap(args.study.bootstrap)?;
    let dir = &args.results;
    output::check_dir(dir)?;
    output::check_dir(&args.studies)?;
    let path = |ext: &str| dir.join(format!("{name}.{ext}"));
    let command = command_line();
    Stamp::new(None, &command, Experiment::of(&template, &design)).check_replace(
        &path("json"),
        "experiment",
        args.force,
    )?;
    let outcomes = variants::run_variants(
        &template,
        &design.variants,
        &args.studies,
        args.memory.memory_limit,
        args.study.bootstrap,
        design.pairing,
        &Reporter::new(args.quiet || args.json),
    )?;
    let md = variants::markdown(title, &command, &outcomes);
    let report = Stamp::new(
        None,
        &command,
        Experiment {
            template,
            variants: outcomes,
        },
    );
    let json = stamp::json_sorted(&report);
    output::write_atomic(&path("json"), &json)?;
    output::write_atomic(&path("md"), &md)?;
    output::write_atomic(&path("csv"), variants::csv(&report.made.variants))?;
    if args.json {
        say!(out, "{}", json.trim_end());
    } else {
        say!(out, "{md}");
    }
    Ok(report.made.variants)
}
