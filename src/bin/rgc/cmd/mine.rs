//! `rgc mine`: the rigidity 3D-RGC misses in generated systems, as minimal
//! patterns counted per density; the rigid missed ones as a rule file.

use std::path::PathBuf;

use clap::Args;
use rgc::mine::{self, Parameters, Report, Search};
use rgc::{Result, output, rule_file};

use crate::progress::Reporter;

#[derive(Args)]
pub struct MineArgs {
    /// Aspect ratio l / (2r).
    #[arg(long, allow_hyphen_values = true, default_value_t = 23.0)]
    gamma: f64,
    /// Side of the periodic box, in rod lengths.
    #[arg(long = "box", allow_hyphen_values = true, default_value_t = 4.0)]
    box_len: f64,
    /// Rods per unit volume, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "30,34,38,42"
    )]
    densities: Vec<f64>,
    /// Systems per density: seeds SEED, SEED+1, ... (the same seeds at every density).
    #[arg(long, default_value_t = 10)]
    systems: u64,
    /// Seed of the first system.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Seed pairs tried per missed cluster, per started ten whole nodes of it (a seeded shuffle picks them).
    #[arg(long, default_value_t = Search::default().pairs)]
    pairs: usize,
    /// Quotient layers grown around a seed pair before it counts as not local.
    #[arg(long, default_value_t = Search::default().max_radius)]
    max_radius: usize,
    /// Rods in a ball before it counts as not local.
    #[arg(long, default_value_t = Search::default().max_ball_rods)]
    max_ball_rods: usize,
    /// Motif orders in which the sound engine may compress a pattern.
    #[arg(long, default_value_t = 32)]
    runs: u64,
    /// Rules written at most, the most frequent first.
    #[arg(long, default_value_t = 20)]
    top: usize,
    /// Extended rule files also tried on every pattern (comma-separated; none with an empty value).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "motifs/rods-6.json,motifs/rods-8.json,motifs/mixed-4.json"
    )]
    extended: Vec<String>,
    /// The rule file of the rigid patterns the engine misses.
    #[arg(long, default_value = "motifs/mined.json")]
    out: PathBuf,
    /// Where `mined-motifs.{json,csv,md}` go.
    #[arg(long, default_value = "results")]
    results: PathBuf,
    /// Replace a rule file or results that a run with other parameters made.
    #[arg(long)]
    force: bool,
    /// No progress bars.
    #[arg(long)]
    quiet: bool,
    /// Print the report (as written to `mined-motifs.json`) and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: MineArgs, out: &mut String) -> Result<()> {
    let extended: Vec<PathBuf> = a
        .extended
        .iter()
        .filter(|p| !p.is_empty())
        .map(PathBuf::from)
        .collect();
    let params = Parameters {
        gamma: a.gamma,
        box_len: a.box_len,
        densities: a.densities,
        systems: a.systems,
        seed: a.seed,
        search: Search {
            pairs: a.pairs,
            max_radius: a.max_radius,
            max_ball_rods: a.max_ball_rods,
        },
        runs: a.runs,
        top: a.top,
        extended: extended.iter().map(|p| p.display().to_string()).collect(),
    };
    // Everything that can be refused is refused before the first system.
    params.validate()?;
    output::check_dir(&a.results)?;
    let report = |ext: &str| a.results.join(format!("mined-motifs.{ext}"));
    let (json, csv, md) = (report("json"), report("csv"), report("md"));
    output::check_outputs(&[
        ("--out", &a.out),
        ("--results", &json),
        ("--results", &csv),
        ("--results", &md),
    ])?;
    let command = super::command_line();
    mine::check_replace(
        &a.results.join("mined-motifs.json"),
        &a.out,
        &mine::stamp(&command, &params),
        a.force,
    )?;
    let known = if extended.is_empty() {
        Vec::new()
    } else {
        super::load(&extended)?
    };
    let report = mine::run(&params, &known, &command, &Reporter::new(a.quiet || a.json))?;
    let rules = mine::rules(&report)?;
    rule_file::write_rules(&a.out, &rules)?;
    mine::write(&report, &a.results)?;
    if a.json {
        return super::print_json(&report, out);
    }
    summary(&report, out);
    say!(
        out,
        "{} rules written to {}; tables in {}/mined-motifs.{{json,csv,md}}; {:.0} s.",
        rules.len(),
        a.out.display(),
        a.results.display(),
        report.seconds
    );
    Ok(())
}

fn summary(r: &Report, out: &mut String) {
    for d in &r.densities {
        say!(
            out,
            "density {}: {} systems (truth spans {}, sound {}); {} missed clusters; {} seed pairs -> {} minimal sets ({} not local, {} too large, {} not whole); {} patterns, {} rule candidates",
            d.density,
            d.systems,
            d.truth_spans,
            d.sound_spans,
            d.missed_clusters,
            d.pairs,
            d.sets,
            d.not_local,
            d.too_large,
            d.not_whole,
            d.patterns,
            d.candidates
        );
    }
    let candidates = r.motifs.iter().filter(|m| m.candidate).count();
    say!(
        out,
        "{} distinct patterns, {} rigid on every component and missed by sound. Most frequent:",
        r.motifs.len(),
        candidates
    );
    for m in r.motifs.iter().take(10) {
        say!(
            out,
            "  {:>3}. {:>4} occurrences in {:>3} systems: {} nodes ({} rods, {} planar, {} spatial), {} contacts, {}{}{}",
            m.rank,
            m.occurrences,
            m.systems,
            m.nodes,
            m.rod_nodes,
            m.planar,
            m.spatial,
            m.contacts,
            m.class,
            if m.sound_compresses {
                ", sound compresses it"
            } else {
                ""
            },
            m.rule
                .as_ref()
                .map_or(String::new(), |id| format!(" -> {id}"))
        );
    }
}
