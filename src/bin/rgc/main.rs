//! `rgc`: the command-line face of the library. Each subcommand (one file in
//! `cmd/`) parses its arguments, calls the library and prints the result;
//! the numbers it prints or writes all come from library functions.

use std::io::Write;
use std::process::ExitCode;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{CommandFactory, Parser, Subcommand};

/// Appends a line to a subcommand's output (writing to a `String` cannot fail).
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($out, $($arg)*);
    }};
}

mod args;
mod cmd;
mod progress;

#[derive(Parser)]
#[command(
    name = "rgc",
    version,
    about = "Rigidity percolation in random 3-D rod systems"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate one rod system, find its contacts and rigid bodies.
    Sample(cmd::sample::SampleArgs),
    /// Draw one rod system (PNG and SVG): an orthographic view, rods coloured by body, the spanning or largest one highlighted.
    Render(cmd::render::RenderArgs),
    /// Compress a rods-only contact graph given as graph6 or as an edge list.
    Compress(cmd::compress::CompressArgs),
    /// Audit the engine against every small rigid motif (exact rank) and write the missed ones as rule files.
    Audit(cmd::audit::AuditArgs),
    /// Time contact detection and compression on the reference systems (single thread); --truth: time and memory of exact truth against system size.
    Bench(cmd::bench::BenchArgs),
    /// Decide whether a contact pattern is rigid (exact rank on every realization component, or floats).
    Check(cmd::check::CheckArgs),
    /// Non-isomorphic connected graphs as graph6 lines on stdout.
    Enumerate(cmd::enumerate::EnumerateArgs),
    /// Write the base motifs as a verified rule file, or (--check) report the rules of rule files that smaller ones make redundant.
    Rules(cmd::rules::RulesArgs),
    /// Push the float ranks to failure against the exact verdict; write the report.
    Stability(cmd::stability::StabilityArgs),
    /// Percolation threshold by Monte Carlo and finite-size scaling (resumable; shardable).
    Threshold(cmd::threshold::ThresholdArgs),
    /// Combine the shards of a threshold study and analyse it.
    Merge(cmd::merge::MergeArgs),
    /// A threshold study from a row or signac workspace: one directory's slice, or the merge of one study's directories.
    Workspace(cmd::workspace::WorkspaceArgs),
    /// Finished studies of the same sequences compared sequence by sequence: mean shift of the critical density per box.
    Paired(cmd::paired::PairedArgs),
    /// The order of the rigidity transition from truth studies: the jump of the largest true cluster at the critical rod per box, and its share of the rods above the threshold.
    Transition(cmd::transition::TransitionArgs),
    /// How often truth's exact realizations disagree: the evaluations of truth studies ranked again, every realization whole, each in a prime of its own.
    Twins(cmd::twins::TwinsArgs),
    /// How far the rigidity 3D-RGC misses at the true threshold reaches: on truth studies' sequences, the spanning true cluster against a compression's bodies, and the minimal rigid sets joining two of its nodes (their sizes are the motif size it would take).
    Locality(cmd::locality::LocalityArgs),
    /// The elastic moduli one rod below and at each sequence's critical number in truth studies: does the shear modulus jump where the largest true cluster does?
    Stiffening(cmd::stiffening::StiffeningArgs),
    /// The motif horizon: 3D-RGC's paired bias against truth for studies with growing motif sets, against the largest motif and the number of rules, with CPU per sequence; where the rods-only series would halve the bias.
    Horizon(cmd::horizon::HorizonArgs),
    /// Thresholds under the paper's base motifs, the sound base motifs and sound + extended motifs, on the same sequences.
    Compare(cmd::compare::CompareArgs),
    /// Threshold and interval width against CPU time: runs per system, motif sets, sequences per box, nested against fixed.
    Tradeoff(cmd::tradeoff::TradeoffArgs),
    /// Every engine variant against the exact truth on the same sequences: paired bias per box, false spans, CPU time.
    Bias(cmd::bias::BiasArgs),
    /// The exact rigidity of a whole contact graph or generated rod system: DOF, rigid clusters, spanning.
    ///
    /// What is certain and what is not. The rank is taken at random exact realizations, each over a prime field F_q with q drawn at random below 2^24. A realization can only lose rank, never gain it, so the rank found never exceeds the generic rank: a system found rigid (DOF 0) is rigid for certain. A flexibility (DOF above 0), a rigid cluster and a spanning verdict rest on realizations that did not hit a special position: a second realization (twin) checks every answer and the larger rank wins; `realizations agree` (`twins_agree` in JSON) says whether they differed. A rigid cluster is not certain even where the rank is the generic one: a special position can lock a mechanism, as a four-bar at its dead centre. No proven bound makes that chance small for whole systems (the Schwartz-Zippel bound, degree over q, exceeds 1 there); `rgc twins` measures it on the evaluations of truth studies: at gamma 23, 48 and 98 the twins differed once in 11,952 evaluations, and 3 of 35,856 realizations lost one rank (results/truth-twins/).
    #[command(verbatim_doc_comment)]
    Truth(cmd::truth::TruthArgs),
    /// The elastic tensor of a rod system in a cubic periodic box: a spring k at every contact, rigid rods, the non-affine relaxation; C, Voigt G and K, the Born tensor, the non-affinity, kept at truth's exact strain rank.
    Moduli(cmd::moduli::ModuliArgs),
    /// Chart the thresholds of finished studies at several aspect ratios against 1/V_ex.
    AspectRatios(cmd::aspect_ratios::AspectArgs),
    /// Where forced planes percolate (and force the line model flat), per aspect ratio, against the committed thresholds.
    Planes(cmd::planes::PlanesArgs),
    /// The rigidity 3D-RGC misses in generated systems (found by truth), as minimal patterns counted per density; the rigid ones as a rule file.
    Mine(cmd::mine::MineArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage(&e),
    };
    let mut out = String::new();
    let result = run(cli, &mut out);
    // A reader that closed the pipe early (`rgc audit | head`) is not an error.
    match std::io::stdout().write_all(out.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("rgc: error: writing the output: {e}");
            return ExitCode::from(2);
        }
        _ => {}
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("rgc: error: {e}");
            ExitCode::from(2)
        }
    }
}

/// A usage error in two lines, the error and where to read more, exit code
/// 2 (clap's own runs to five or six); help and version as clap prints them.
fn usage(e: &clap::Error) -> ExitCode {
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::from(e.exit_code() as u8);
    }
    let strings = |kind| match e.get(kind) {
        Some(ContextValue::Strings(v)) => v.join(", "),
        Some(ContextValue::String(v)) => v.clone(),
        _ => String::new(),
    };
    let rendered = e.render().to_string();
    let first = rendered.lines().next().unwrap_or_default();
    let mut message = match e.kind() {
        ErrorKind::MissingRequiredArgument => format!(
            "missing the required argument {}",
            strings(ContextKind::InvalidArg)
        ),
        _ => first.strip_prefix("error: ").unwrap_or(first).to_string(),
    };
    // What clap would say on its further lines, kept on the first.
    let suggested = [
        ContextKind::SuggestedArg,
        ContextKind::SuggestedSubcommand,
        ContextKind::SuggestedValue,
    ]
    .map(strings)
    .join("");
    if !suggested.is_empty() {
        message += &format!(" (did you mean '{suggested}'?)");
    }
    let valid = strings(ContextKind::ValidValue);
    if !valid.is_empty() {
        message += &format!(" (possible values: {valid})");
    }
    // The subcommand the arguments name, for the help to read.
    let cmd = Cli::command();
    let sub = std::env::args()
        .skip(1)
        .find(|a| cmd.find_subcommand(a).is_some())
        .map_or(String::new(), |s| format!(" {s}"));
    eprintln!("rgc: error: {message}\nsee 'rgc{sub} --help'");
    ExitCode::from(2)
}

fn run(cli: Cli, out: &mut String) -> rgc::Result<()> {
    match cli.command {
        Command::Sample(a) => cmd::sample::run(a, out),
        Command::Render(a) => cmd::render::run(a, out),
        Command::Compress(a) => cmd::compress::run(a, out),
        Command::Audit(a) => cmd::audit::run(a, out),
        Command::Bench(a) => cmd::bench::run(a, out),
        Command::Check(a) => cmd::check::run(a, out),
        Command::Enumerate(a) => cmd::enumerate::run(a),
        Command::Rules(a) => cmd::rules::run(a, out),
        Command::Stability(a) => cmd::stability::run(a, out),
        Command::Threshold(a) => cmd::threshold::run(a, out),
        Command::Merge(a) => cmd::merge::run(a, out),
        Command::Workspace(a) => cmd::workspace::run(a, out),
        Command::Paired(a) => cmd::paired::run(a, out),
        Command::Transition(a) => cmd::transition::run(a, out),
        Command::Twins(a) => cmd::twins::run(a, out),
        Command::Locality(a) => cmd::locality::run(a, out),
        Command::Stiffening(a) => cmd::stiffening::run(a, out),
        Command::Horizon(a) => cmd::horizon::run(a, out),
        Command::Compare(a) => cmd::compare::run(a, out),
        Command::Tradeoff(a) => cmd::tradeoff::run(a, out),
        Command::AspectRatios(a) => cmd::aspect_ratios::run(a, out),
        Command::Truth(a) => cmd::truth::run(a, out),
        Command::Moduli(a) => cmd::moduli::run(a, out),
        Command::Bias(a) => cmd::bias::run(a, out),
        Command::Planes(a) => cmd::planes::run(a, out),
        Command::Mine(a) => cmd::mine::run(a, out),
    }
}
