//! `rgc locality`: how far the rigidity 3D-RGC misses at the true
//! threshold reaches, measured on the sequences of truth studies.

use std::path::PathBuf;

use clap::Args;
use rgc::engine::CompiledRule;
use rgc::mine::Search;
use rgc::rule_file;
use rgc::threshold::locality::{self, LocalitySpec};
use rgc::threshold::study::MotifSet;
use rgc::{Result, output};

use crate::args::MeasuredArgs;
use crate::progress::Reporter;

#[derive(Args)]
pub struct LocalityArgs {
    #[command(flatten)]
    measured: MeasuredArgs,
    /// Motif rule files the compression adds to the base motifs.
    #[arg(long)]
    rule_files: Vec<PathBuf>,
    /// Seed pairs per started ten whole nodes of the spanning cluster.
    #[arg(long, default_value_t = 1)]
    pairs: usize,
    /// Quotient layers grown around a seed pair at most.
    #[arg(long, default_value_t = 6)]
    max_radius: usize,
    /// Rods in a ball truth is asked about, at most.
    #[arg(long, default_value_t = 3000)]
    max_ball_rods: usize,
    /// Also write the summary as PREFIX.json and PREFIX.csv.
    #[arg(long)]
    summary: Option<PathBuf>,
}

pub fn run(a: LocalityArgs, out: &mut String) -> Result<()> {
    if let Some(prefix) = &a.summary {
        output::check_file(prefix)?;
    }
    let m = &a.measured;
    let rules = rule_file::load_rules(&a.rule_files)?;
    let spec = LocalitySpec {
        studies: m.studies(),
        boxes: m.boxes.clone(),
        sequences: m.sequences,
        motifs: MotifSet::of(&rules, &a.rule_files),
        search: Search {
            pairs: a.pairs,
            max_radius: a.max_radius,
            max_ball_rods: a.max_ball_rods,
        },
    };
    let compiled: Vec<CompiledRule> = rules.iter().map(CompiledRule::new).collect();
    let summaries = locality::run(&m.dirs, &spec, &compiled, &m.out, &Reporter::new(m.quiet))?;
    say!(
        out,
        "{:>6} {:>5} {:>4} {:>8} {:>8} {:>8} {:>6} {:>6} {:>7} {:>5} {:>8} {:>8} {:>7}",
        "gamma",
        "box",
        "seqs",
        "cluster",
        "covered",
        "largest",
        "nodes",
        "pairs",
        "found",
        "sets",
        "med.node",
        "max.node",
        ">10"
    );
    for s in &summaries {
        say!(
            out,
            "{:>6} {:>5} {:>4} {:>8.0} {:>7.1}% {:>7.1}% {:>6.0} {:>6} {:>6.1}% {:>5} {:>8.1} {:>8} {:>7}",
            s.gamma,
            s.box_len,
            s.sequences,
            s.cluster_rods,
            100.0 * s.covered_share,
            100.0 * s.largest_body_share,
            s.cluster_nodes,
            s.pairs,
            100.0 * s.found_share,
            s.sets,
            s.median_nodes,
            s.max_nodes,
            s.beyond_ten_nodes
        );
    }
    if let Some(prefix) = &a.summary {
        for f in locality::write(prefix, &summaries, &super::command_line())? {
            say!(out, "wrote {}", f.display());
        }
    }
    Ok(())
}
