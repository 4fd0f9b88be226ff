//! Argument groups that several subcommands share, flattened into each, so
//! a flag means the same thing and has the same default everywhere.

use std::path::PathBuf;

use clap::Args;
use rgc::engine::RuleSet;
use rgc::rods::RodParams;
use rgc::sample::SampleOptions;
use rgc::spanning::Criterion;
use rgc::threshold::study::StudySpec;

/// Which motifs the engine applies: every subcommand that compresses.
#[derive(Args)]
pub struct RuleArgs {
    /// Motif conditions: `paper` is verbatim; `sound` refuses what exact rank refutes (3D2A between planes, 3D4 closing a triangle on a plane, instances whose induced pattern is not rigid).
    #[arg(long, value_enum, default_value_t = RuleSet::Sound)]
    pub rules: RuleSet,
    /// Motif rule files (a file or a directory of `*.json`), used with the base motifs.
    #[arg(long, alias = "motifs")]
    pub rule_files: Vec<PathBuf>,
}

/// How to compress one system: `sample` and `compress`.
#[derive(Args)]
pub struct EngineArgs {
    /// Seed of the random motif order (and of the rods, for `sample`).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Independent compressions; a system is rigid-spanning if any finds a spanning body.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub runs: u64,
    #[command(flatten)]
    pub rules: RuleArgs,
}

/// One generated rod system and how to compress it (`sample`, `render`).
#[derive(Args)]
pub struct SystemArgs {
    /// Aspect ratio l / (2r).
    #[arg(long, allow_hyphen_values = true)]
    gamma: f64,
    /// Side of the periodic box, in rod lengths.
    #[arg(long = "box", allow_hyphen_values = true)]
    box_len: f64,
    /// Number density N / L^3.
    #[arg(long, allow_hyphen_values = true)]
    density: f64,
    #[command(flatten)]
    pub engine: EngineArgs,
    /// Spanning definition: `wrap` (a cluster meets its own periodic image) or `faces`.
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    pub criterion: Criterion,
}

impl SystemArgs {
    /// The sample these arguments ask for, checked.
    pub fn options(&self) -> rgc::Result<SampleOptions> {
        Ok(SampleOptions {
            params: RodParams::new(self.gamma, self.box_len, self.density)?,
            seed: self.engine.seed,
            runs: self.engine.runs as usize,
            rules: self.engine.rules.rules,
            criterion: self.criterion,
        })
    }
}

/// What a threshold study is measured on: `threshold`, and the variants of
/// `compare` and `tradeoff`.
#[derive(Args)]
pub struct StudyArgs {
    /// Aspect ratio l / (2r).
    #[arg(long, allow_hyphen_values = true, default_value_t = 23.0)]
    pub gamma: f64,
    /// Box sides, in rod lengths, comma-separated (at least 3 for the scaling fit).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "5,6,7,8,10"
    )]
    pub boxes: Vec<f64>,
    /// Monte Carlo sequences (seeded random orders of rods) per box.
    // `--realizations` is the old spelling, kept as a hidden alias for existing scripts.
    #[arg(long, alias = "realizations", default_value_t = 200)]
    pub sequences: u64,
    /// Spanning definition: `wrap` (a cluster meets its own periodic image) or `faces`.
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    pub criterion: Criterion,
    /// Seed of the rods (sequence seeds derive from it, the box and the index).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    pub bootstrap: usize,
}

impl StudyArgs {
    /// The study these arguments describe, with [`StudySpec::new`]'s defaults for the rest.
    pub fn spec(&self) -> StudySpec {
        StudySpec::new(
            self.gamma,
            self.boxes.clone(),
            self.sequences,
            self.criterion,
            self.seed,
        )
    }
}

/// What the variants of `compare` and `tradeoff` share; their studies are
/// smaller by default than `threshold`'s, since they run several.
#[derive(Args)]
#[command(
    mut_arg("boxes", |a| a.default_value("4,5,6")),
    mut_arg("sequences", |a| a.default_value("100")),
)]
pub struct VariantArgs {
    #[command(flatten)]
    pub study: StudyArgs,
    /// Where the studies go: one directory each, named by every parameter of its study; rerun to resume.
    #[arg(long, default_value = "results/studies")]
    pub studies: PathBuf,
    /// Where the comparison's JSON, Markdown, CSV and charts go.
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
    /// Print the experiment as one JSON object (as written to `--results`) and nothing else.
    #[arg(long)]
    pub json: bool,
    /// Replace the experiment's files in `--results` even when another experiment (other gamma, boxes, sequences, variants ...) made them.
    #[arg(long)]
    pub force: bool,
}

/// The extended motif sets that `compare` and `bias` measure.
#[derive(Args)]
pub struct ExtendedArgs {
    /// The extended motif rule files.
    #[arg(
        long = "extended",
        value_delimiter = ',',
        default_value = "motifs/rods-6.json,motifs/rods-8.json,motifs/mixed-4.json"
    )]
    pub files: Vec<PathBuf>,
}
