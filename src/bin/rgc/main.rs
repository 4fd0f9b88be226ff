//! `rgc`: the command-line face of the library. Each subcommand parses its
//! arguments, calls one library entry point and prints the result.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use serde::Serialize;

use rgc::audit::{self, AuditOptions, AuditRow};
use rgc::body::Body;
use rgc::engine::{self, CompiledRule, Compression, Engine, RuleSet};
use rgc::enumerate::GraphFilter;
use rgc::graph::ContactGraph;
use rgc::graph::io as graphio;
use rgc::pattern::Pattern;
use rgc::rigidity::{Method, Verdict};
use rgc::rods::RodParams;
use rgc::rule_file::{self as motifs, RuleFile};
use rgc::sample::{SampleOptions, sample_with};
use rgc::spanning::Criterion;
use rgc::threshold::fss::Protocol;
use rgc::threshold::report::{self, Summary};
use rgc::threshold::sequence::Kind;
use rgc::threshold::study::{self, MotifSet, RunOptions, STUDY_FORMAT, Shard, StudySpec};
use rgc::threshold::variants::{self, Pairing, Variant, VariantOutcome};
use rgc::{Error, Result, bench, plot};

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
    Sample(SampleArgs),
    /// Compress a rods-only contact graph given as graph6 or as an edge list.
    Compress(CompressArgs),
    /// Audit the engine against every small rigid motif (exact rank) and write the missed ones as rule files.
    Audit(AuditArgs),
    /// Time contact detection and compression on the reference systems (single thread).
    Bench(BenchArgs),
    /// Decide whether a contact pattern is rigid (exact rank on every realization component, or floats).
    Check(CheckArgs),
    /// Non-isomorphic connected graphs as graph6 lines on stdout.
    Enumerate(EnumerateArgs),
    /// Write the base motifs as a verified rule file.
    Rules(RulesArgs),
    /// Push the float ranks to failure against the exact verdict; write the report.
    Stability(StabilityArgs),
    /// Percolation threshold by Monte Carlo and finite-size scaling (resumable; shardable).
    Threshold(ThresholdArgs),
    /// Combine the shards of a threshold study and analyse it.
    Merge(MergeArgs),
    /// Thresholds under the paper's base motifs, the sound base motifs and sound + extended motifs, on the same realizations.
    Compare(CompareArgs),
    /// Threshold and interval width against CPU time: runs per system, motif sets, realizations, nested against fixed.
    Tradeoff(TradeoffArgs),
    /// Chart the thresholds of finished studies at several aspect ratios against 1/V_ex.
    AspectRatios(AspectArgs),
}

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
struct CheckArgs {
    #[command(flatten)]
    input: PatternInput,
    /// `exact` (rank over F_p), `svd` or `qr` (floats, undecided when the gap is small).
    #[arg(long, value_enum, default_value_t = Method::Exact)]
    method: Method,
    /// Seed of the realizations.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print JSON instead of a summary.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct EnumerateArgs {
    /// Number of nodes.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=12))]
    nodes: u64,
    /// Smallest degree.
    #[arg(long, default_value_t = 0)]
    min_degree: usize,
    /// Maxwell's count for rods: at least ceil((5n - 6) / 3) edges.
    #[arg(long)]
    maxwell: bool,
    /// Fewest edges.
    #[arg(long)]
    min_edges: Option<usize>,
    /// Most edges.
    #[arg(long)]
    max_edges: Option<usize>,
    /// Print only the count.
    #[arg(long)]
    count: bool,
}

#[derive(Args)]
struct RulesArgs {
    /// Where the base motif rules go.
    #[arg(long, default_value = "motifs/base.json")]
    out: PathBuf,
}

#[derive(Args)]
struct StabilityArgs {
    /// Where `rank-stability.{csv,svg,png}` go.
    #[arg(long, default_value = "results")]
    out: PathBuf,
}

/// How to compress: shared by the subcommands that run the engine.
#[derive(Args)]
struct EngineArgs {
    /// Seed of the random motif order (and of the rods, for `sample`).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Independent compressions; a system is rigid-spanning if any finds a spanning body.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    runs: u64,
    /// Motif conditions: `paper` is verbatim; `sound` refuses what exact rank refutes (3D2A between planes, 3D4 closing a triangle on a plane, instances whose induced pattern is not rigid).
    #[arg(long, value_enum, default_value_t = RuleSet::Sound)]
    rules: RuleSet,
}

#[derive(Args)]
struct ThresholdArgs {
    /// Which spanning cluster: connected (`contact`) or rigid (`rigid`).
    #[arg(long, value_enum, default_value_t = Kind::Rigid)]
    kind: Kind,
    /// Aspect ratio l / (2r).
    #[arg(long, allow_hyphen_values = true, default_value_t = 23.0)]
    gamma: f64,
    /// Box sides, in rod lengths, comma-separated (at least 3 for the scaling fit).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "5,6,7,8,10"
    )]
    boxes: Vec<f64>,
    /// Realizations (random rod sequences) per box.
    #[arg(long, default_value_t = 200)]
    realizations: u64,
    /// Motif conditions: `paper` is verbatim; `sound` refuses what exact rank refutes (3D2A between planes, 3D4 closing a triangle on a plane, instances whose induced pattern is not rigid).
    #[arg(long, value_enum, default_value_t = RuleSet::Sound)]
    rules: RuleSet,
    /// Motif rule files (a file or a directory of `*.json`), used with the base motifs.
    #[arg(long)]
    motifs: Vec<PathBuf>,
    /// Independent compressions per system; it spans if any run finds a spanning body.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// Spanning definition: `wrap` (a cluster meets its own periodic image) or `faces`.
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    criterion: Criterion,
    /// `nested`: each sequence's exact critical number of rods; `fixed`: the paper's grid of densities.
    #[arg(long, value_enum, default_value_t = Protocol::Nested)]
    method: Protocol,
    /// Densities per box in the fixed protocol's grid (found by a pilot run).
    #[arg(long, default_value_t = 12)]
    grid_points: usize,
    /// Seed of the rods (realization seeds derive from it, the box and the index).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    bootstrap: usize,
    /// Run only slice i of n (`i/n`, from 0); combine the slices with `rgc merge`.
    #[arg(long)]
    shard: Option<String>,
    /// Study directory: checkpoints, tables and charts. Run the same command again to resume.
    #[arg(long)]
    out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

/// What the variants of `compare` and `tradeoff` share.
#[derive(Args)]
struct VariantArgs {
    /// Aspect ratio l / (2r).
    #[arg(long, allow_hyphen_values = true, default_value_t = 23.0)]
    gamma: f64,
    /// Box sides, in rod lengths, comma-separated (at least 3).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "4,5,6"
    )]
    boxes: Vec<f64>,
    /// Realizations per box.
    #[arg(long, default_value_t = 100)]
    realizations: u64,
    /// Spanning definition.
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    criterion: Criterion,
    /// Seed of the rods.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    bootstrap: usize,
    /// Where the studies go (one directory each; rerun to resume).
    #[arg(long, default_value = "results/studies")]
    studies: PathBuf,
    /// Where the comparison's JSON, Markdown, CSV and charts go.
    #[arg(long, default_value = "results")]
    results: PathBuf,
    /// No progress bars.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args)]
struct CompareArgs {
    #[command(flatten)]
    common: VariantArgs,
    /// Runs per system.
    #[arg(long, default_value_t = 1)]
    runs: usize,
    /// The extended motif rule files.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "motifs/rods-6.json,motifs/rods-8.json,motifs/mixed-4.json"
    )]
    extended: Vec<PathBuf>,
}

#[derive(Args)]
struct TradeoffArgs {
    #[command(flatten)]
    common: VariantArgs,
    /// Runs per system to compare (more than 10 analyse half the realizations).
    #[arg(long, value_delimiter = ',', default_value = "1,10,40")]
    runs_list: Vec<usize>,
    /// Directory of the audit's rule files (`rods-6.json`, `rods-8.json`, `mixed-4.json`).
    #[arg(long, default_value = "motifs")]
    motifs_dir: PathBuf,
}

#[derive(Args)]
struct AspectArgs {
    /// Finished study directories (each with its summary.json), one per aspect ratio.
    #[arg(required = true)]
    studies: Vec<PathBuf>,
    /// Output path without extension: `.csv`, `.svg` and `.png` are written.
    #[arg(long, default_value = "results/threshold-vs-vex")]
    out: PathBuf,
}

#[derive(Args)]
struct MergeArgs {
    /// Study directories holding the shards (one directory may hold them all).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Where the merged records and the analysis go (default: the first directory).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    bootstrap: usize,
}

#[derive(Args)]
struct SampleArgs {
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
    engine: EngineArgs,
    /// Spanning definition: `wrap` (a cluster meets its own periodic image) or `faces`.
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    criterion: Criterion,
    /// Write the contact graph as an edge list (`u v` per line) to this file.
    #[arg(long)]
    save_contacts: Option<PathBuf>,
    /// Write the bodies of the reported run (rods, class, whether each spans) as JSON to this file.
    #[arg(long)]
    save_bodies: Option<PathBuf>,
    /// Motif rule files (a file or a directory of `*.json`), used with the base motifs.
    #[arg(long)]
    motifs: Vec<PathBuf>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
#[group(id = "input", required = true, multiple = false)]
struct GraphInput {
    /// The contact graph as a graph6 string.
    #[arg(long, group = "input")]
    graph6: Option<String>,
    /// The contact graph as an edge list file (`u v` per line, `#` comments).
    #[arg(long, group = "input")]
    edges: Option<PathBuf>,
}

#[derive(Args)]
struct CompressArgs {
    #[command(flatten)]
    input: GraphInput,
    /// Motif rule files (a file or a directory of `*.json`), used with the base motifs.
    #[arg(long)]
    motifs: Vec<PathBuf>,
    #[command(flatten)]
    engine: EngineArgs,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct AuditArgs {
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

#[derive(Args)]
struct BenchArgs {
    /// Repetitions per system (the median is reported).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
    repeat: u64,
    /// Only the systems up to this many rods.
    #[arg(long, default_value_t = 200_000)]
    max_rods: usize,
    /// Also write the figures as JSON here.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Instead: exact and float rank throughput on random candidate motifs of this many rods (one thread).
    #[arg(long)]
    rank: Option<usize>,
}

/// Appends a line to a subcommand's output (writing to a `String` cannot fail).
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($out, $($arg)*);
    }};
}

fn main() -> ExitCode {
    let mut out = String::new();
    let result = run(Cli::parse(), &mut out);
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

fn run(cli: Cli, out: &mut String) -> Result<()> {
    match cli.command {
        Command::Sample(a) => run_sample(a, out),
        Command::Compress(a) => run_compress(a, out),
        Command::Audit(a) => run_audit(a, out),
        Command::Bench(a) => run_bench(a, out),
        Command::Check(a) => run_check(a, out),
        Command::Enumerate(a) => run_enumerate(a),
        Command::Rules(a) => run_rules(a, out),
        Command::Stability(a) => run_stability(a, out),
        Command::Threshold(a) => run_threshold(a, out),
        Command::Merge(a) => run_merge(a, out),
        Command::Compare(a) => run_compare(a, out),
        Command::Tradeoff(a) => run_tradeoff(a, out),
        Command::AspectRatios(a) => run_aspect_ratios(a, out),
    }
}

fn print_json(value: &impl Serialize, out: &mut String) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("reports serialize");
    say!(out, "{text}");
    Ok(())
}

fn run_sample(a: SampleArgs, out: &mut String) -> Result<()> {
    let opts = SampleOptions {
        params: RodParams::new(a.gamma, a.box_len, a.density)?,
        seed: a.engine.seed,
        runs: a.engine.runs as usize,
        rules: a.engine.rules,
        criterion: a.criterion,
    };
    let rules = load(&a.motifs)?;
    let s = sample_with(&opts, &rules);
    if let Some(path) = &a.save_contacts {
        let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
        let mut w = std::io::BufWriter::new(file);
        graphio::write_edge_list(&s.graph, &mut w)
            .and_then(|()| w.flush())
            .map_err(|e| Error::io(path, e))?;
    }
    if let Some(path) = &a.save_bodies {
        let text = serde_json::to_string_pretty(&s.reported_bodies(opts.criterion))
            .expect("bodies serialize");
        std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))?;
    }
    let r = &s.report;
    if a.json {
        return print_json(r, out);
    }
    say!(
        out,
        "{} rods, {} contacts: c0 = {:.4} (Philipse {:.4}), c1 = {:.4}, c2 = {:.4}, clustering = {:.4}",
        r.n_rods,
        r.n_contacts,
        r.c0,
        r.c0_expected,
        r.c1,
        r.c2,
        r.clustering
    );
    say!(
        out,
        "contact spanning ({:?}): {}; rigid spanning: {} ({} of {} runs, rules {:?})",
        r.criterion,
        r.contact_spanning,
        r.rigid_spanning,
        r.runs_spanning,
        r.runs,
        r.rules
    );
    say!(
        out,
        "largest body {} rods; {} bodies and {} nodes in run {}; {:.3} s",
        r.largest_body_rods,
        r.n_bodies,
        r.components,
        r.reported_run,
        r.seconds
    );
    Ok(())
}

/// The JSON printed by `rgc compress`.
#[derive(Serialize)]
struct CompressReport<'a> {
    nodes: usize,
    contacts: usize,
    rules: RuleSet,
    seed: u64,
    runs: u64,
    /// Nodes left in the reported run (the one with fewest).
    components: usize,
    /// Index of the reported run.
    reported_run: usize,
    bodies: &'a [Body],
    /// Nodes left in each run.
    components_per_run: Vec<usize>,
    motifs: engine::MotifCounts,
}

fn run_compress(a: CompressArgs, out: &mut String) -> Result<()> {
    let graph: ContactGraph = match (&a.input.graph6, &a.input.edges) {
        (Some(s), _) => graphio::parse_graph6(s)?,
        (None, Some(path)) => graphio::read_edge_list(path)?,
        (None, None) => unreachable!("clap requires one input"),
    };
    let rules = load(&a.motifs)?;
    let runs = Engine::with_rules(a.engine.rules, &rules).runs(
        &graph,
        a.engine.seed,
        a.engine.runs as usize,
    );
    let best = (0..runs.len())
        .min_by_key(|&k| runs[k].components)
        .expect("at least one run");
    let c: &Compression = &runs[best];
    let report = CompressReport {
        nodes: graph.n_nodes(),
        contacts: graph.n_edges(),
        rules: a.engine.rules,
        seed: a.engine.seed,
        runs: a.engine.runs,
        components: c.components,
        reported_run: best,
        bodies: &c.bodies,
        components_per_run: runs.iter().map(|r| r.components).collect(),
        motifs: c.motifs,
    };
    if a.json {
        return print_json(&report, out);
    }
    say!(
        out,
        "{} rods, {} contacts -> {} nodes (run {best} of {})",
        report.nodes,
        report.contacts,
        report.components,
        report.runs
    );
    for b in report.bodies {
        say!(out, "  {:?} body: {:?}", b.class, b.rods);
    }
    Ok(())
}

fn run_audit(a: AuditArgs, out: &mut String) -> Result<()> {
    let examples = rgc::engine::examples::check_all(16);
    if let Some(bad) = examples.iter().find(|r| !r.pass) {
        return Err(Error::Parameter(format!(
            "base motif example {:?} did not compress as expected",
            bad.name
        )));
    }
    let opts = AuditOptions {
        max_rods: a.max_rods as usize,
        max_components: a.max_components as usize,
        rules: a.rules,
        runs: a.runs,
        rod_sharing: a.rod_sharing,
        progress: !a.json,
    };
    let started = std::time::Instant::now();
    let result = audit::run(&opts)?;
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
            motifs::write_rules(&path, rules)?;
            written.push(path.display().to_string());
        }
    }
    if a.json {
        return print_json(
            &serde_json::json!({ "rods": result.rods, "mixed": result.mixed, "rule_files": written }),
            out,
        );
    }
    say!(
        out,
        "{} base motif examples compress as expected (sound and paper).\n",
        examples.len()
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
        let width = |k: usize| AuditRow::COLUMNS[k].len().max(7);
        let line = |cells: &[String]| -> String {
            cells
                .iter()
                .enumerate()
                .map(|(k, c)| format!("{c:>w$}", w = width(k)))
                .collect::<Vec<_>>()
                .join(" ")
        };
        say!(out, "{}", line(&AuditRow::COLUMNS.map(String::from)));
        for r in rows {
            say!(out, "{}", line(&r.cells()));
        }
        say!(out, "");
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

fn run_bench(a: BenchArgs, out: &mut String) -> Result<()> {
    if let Some(n) = a.rank {
        let t = rgc::stability::throughput(n, 200, 0.2)?;
        say!(
            out,
            "{n} rods, one thread: ranks/s exact {:.0}, SVD {:.0}, QR {:.0}; verdicts/s exact {:.0}, SVD {:.0}, QR {:.0}; exact/SVD rank speed {:.1}x",
            t.exact_per_s,
            t.svd_per_s,
            t.qr_per_s,
            t.check_exact_per_s,
            t.check_svd_per_s,
            t.check_qr_per_s,
            t.exact_per_s / t.svd_per_s
        );
        return Ok(());
    }
    let rows = bench::run(a.repeat as usize, a.max_rods);
    say!(
        out,
        "{:>6} {:>6} {:>6} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9}",
        "gamma",
        "rho",
        "L",
        "rods",
        "contacts",
        "detect s",
        "compress s",
        "ns/rod",
        "peak MiB"
    );
    for r in &rows {
        say!(
            out,
            "{:>6} {:>6} {:>6} {:>8} {:>10} {:>10.4} {:>10.4} {:>10.0} {:>9.1}",
            r.gamma,
            r.density,
            r.box_len,
            r.n_rods,
            r.n_contacts,
            r.seconds_detect,
            r.seconds_compress,
            r.ns_per_rod,
            r.peak_rss_mib
        );
    }
    if let Some(path) = &a.out {
        let text = serde_json::to_string_pretty(&rows).expect("bench rows serialize");
        std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))?;
    }
    Ok(())
}

/// Loads and verifies rule files, ready for the engine.
fn load(paths: &[PathBuf]) -> Result<Vec<CompiledRule>> {
    Ok(motifs::load_rules(paths)?
        .iter()
        .map(CompiledRule::new)
        .collect())
}

fn verdict(p: &Pattern, method: Method, seed: u64) -> Result<Verdict> {
    match method {
        Method::Exact => rgc::rigidity::check_exact(p, seed),
        _ => rgc::rigidity::check_float(p, method, seed),
    }
}

fn run_check(a: CheckArgs, out: &mut String) -> Result<()> {
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
        let v = verdict(p, a.method, a.seed)?;
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
            print_json(&verdicts[0], out)
        } else {
            print_json(&verdicts, out)
        };
    }
    Ok(())
}

fn run_enumerate(a: EnumerateArgs) -> Result<()> {
    let n = a.nodes as usize;
    let mut filter = if a.maxwell {
        GraphFilter::maxwell_rods(n)
    } else {
        GraphFilter::all()
    };
    filter = filter.with_min_degree(a.min_degree);
    if let Some(m) = a.min_edges {
        filter.min_edges = filter.min_edges.max(m);
    }
    if let Some(m) = a.max_edges {
        filter.max_edges = m;
    }
    if a.count {
        println!("{}", rgc::enumerate::count_connected(n, &filter)?);
        return Ok(());
    }
    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());
    match rgc::enumerate::write_connected_graph6(n, &filter, &mut w).and_then(|_| w.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Error::io("stdout", e)),
        _ => Ok(()),
    }
}

fn run_rules(a: RulesArgs, out: &mut String) -> Result<()> {
    let (rules, refuted) = engine::shapes::base_rules()?;
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    motifs::write_rules(&a.out, &rules)?;
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

fn run_stability(a: StabilityArgs, out: &mut String) -> Result<()> {
    let rows = rgc::stability::run(&rgc::stability::StudyConfig::full())?;
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(&a.out, e))?;
    rgc::stability::write_csv(&rows, &a.out.join("rank-stability.csv"))?;
    rgc::plot::stability_chart(
        &rows,
        &a.out.join("rank-stability.svg"),
        &a.out.join("rank-stability.png"),
    )?;
    say!(
        out,
        "{} rows written to {}/rank-stability.{{csv,svg,png}}",
        rows.len(),
        a.out.display()
    );
    Ok(())
}

fn run_threshold(a: ThresholdArgs, out: &mut String) -> Result<()> {
    let rules = motifs::load_rules(&a.motifs)?;
    let compiled: Vec<CompiledRule> = rules.iter().map(CompiledRule::new).collect();
    let spec = StudySpec {
        format: STUDY_FORMAT.into(),
        kind: a.kind,
        gamma: a.gamma,
        boxes: a.boxes,
        realizations: a.realizations,
        rules: a.rules,
        motifs: MotifSet::of(&rules, &a.motifs),
        runs: a.runs as usize,
        criterion: a.criterion,
        method: a.method,
        grid_points: a.grid_points,
        seed: a.seed,
    };
    let shard = a
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()?
        .unwrap_or(Shard::WHOLE);
    let opts = RunOptions {
        out: a.out.clone(),
        shard,
        progress: !a.quiet,
    };
    let done = study::run(&spec, &compiled, &opts)?;
    say!(
        out,
        "{} realizations run in {:.1} s ({} found done).",
        done.ran,
        done.seconds,
        done.resumed
    );
    if !done.complete {
        say!(
            out,
            "Shard {}/{} is done; when every shard is, run `rgc merge {}`.",
            shard.index,
            shard.count,
            a.out.display()
        );
        return Ok(());
    }
    let records = study::in_study_order(&spec, study::read_records(&a.out, &spec)?);
    analyse_study(&a.out, &spec, &records, a.bootstrap, out)
}

fn run_merge(a: MergeArgs, out: &mut String) -> Result<()> {
    let dest = a.out.clone().unwrap_or_else(|| a.dirs[0].clone());
    let (spec, records) = study::merge(&a.dirs, &dest)?;
    say!(
        out,
        "Merged {} realizations from {} director{}.",
        records.len(),
        a.dirs.len(),
        if a.dirs.len() == 1 { "y" } else { "ies" }
    );
    analyse_study(&dest, &spec, &records, a.bootstrap, out)
}

fn analyse_study(
    dir: &std::path::Path,
    spec: &StudySpec,
    records: &[rgc::threshold::sequence::Record],
    bootstrap: usize,
    out: &mut String,
) -> Result<()> {
    let mut written = report::write_study(dir, spec, records, bootstrap)?;
    let charts = plot::study_charts(spec, &written, dir)?;
    written.files.extend(charts);
    let (s, files) = (written.summary, written.files);
    print_summary(&s, out);
    say!(
        out,
        "Files: {}",
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}

fn print_summary(s: &Summary, out: &mut String) {
    let f = &s.fss;
    let interval = |e: &rgc::threshold::fss::Estimate| match (e.lo, e.hi) {
        (Some(lo), Some(hi)) => format!("[{lo:.4}, {hi:.4}]"),
        _ => "(no interval)".into(),
    };
    say!(
        out,
        "{:>6} {:>6} {:>10} {:>10} {:>10}",
        "box",
        "n",
        "mu",
        "s",
        "delta_rho"
    );
    for b in &f.boxes {
        say!(
            out,
            "{:>6} {:>6} {:>10.4} {:>10.4} {:>10.4}",
            b.box_len,
            b.realizations,
            b.mu,
            b.s,
            b.delta_rho
        );
    }
    say!(
        out,
        "threshold rho_c = {:.4} {} ({:.0}% interval, {} resamples); rho_c V_ex = {:.4}",
        f.threshold.value,
        interval(&f.threshold),
        100.0 * f.confidence,
        f.bootstrap,
        s.threshold_times_vex
    );
    say!(out, "nu = {:.4} {}", f.nu.value, interval(&f.nu));
    if let Some(c) = &f.contact_numbers {
        for (name, fit) in [
            ("c0", &c.pooled.c0),
            ("c1", &c.pooled.c1),
            ("c2", &c.pooled.c2),
        ] {
            say!(
                out,
                "{name} at threshold = {:.4} {}",
                fit.at_threshold.value,
                interval(&fit.at_threshold)
            );
        }
    }
    let o = &s.order;
    if let Some(rate) = o.single_run_miss_rate {
        say!(
            out,
            "single runs miss {:.1}% of the spanning bodies that {} runs find",
            100.0 * rate,
            s.study.runs
        );
    }
    if o.fresh_checks > 0 {
        say!(
            out,
            "fresh compression at the critical number misses the spanning body in {} of {} realizations (found only with carried bodies)",
            o.fresh_misses,
            o.fresh_checks
        );
    }
    if o.nonmonotone_steps > 0 {
        say!(
            out,
            "non-monotone spanning: {} steps in {} realizations",
            o.nonmonotone_steps,
            o.nonmonotone_realizations
        );
    }
    for w in &f.warnings {
        say!(out, "warning: {w}");
    }
}

impl VariantArgs {
    fn template(&self) -> StudySpec {
        StudySpec {
            format: STUDY_FORMAT.into(),
            kind: Kind::Rigid,
            gamma: self.gamma,
            boxes: self.boxes.clone(),
            realizations: self.realizations,
            rules: RuleSet::Sound,
            motifs: MotifSet::default(),
            runs: 1,
            criterion: self.criterion,
            method: Protocol::Nested,
            grid_points: 12,
            seed: self.seed,
        }
    }

    /// Runs the variants and writes `results/NAME.{json,md,csv}`.
    fn run(
        &self,
        name: &str,
        title: &str,
        command: &str,
        variants: &[Variant],
        pairing: Pairing,
        out: &mut String,
    ) -> Result<Vec<VariantOutcome>> {
        let template = self.template();
        template.validate()?;
        let outcomes = variants::run_variants(
            &template,
            variants,
            &self.studies,
            self.bootstrap,
            pairing,
            !self.quiet,
        )?;
        let dir = &self.results;
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let write = |ext: &str, text: String| -> Result<()> {
            let path = dir.join(format!("{name}.{ext}"));
            std::fs::write(&path, text).map_err(|e| Error::io(&path, e))
        };
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
        let md = variants::markdown(title, command, &outcomes);
        write("md", md.clone())?;
        write("csv", variants::csv(&outcomes))?;
        say!(out, "{md}");
        Ok(outcomes)
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

fn run_compare(a: CompareArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let variant = |label: &str, rules: RuleSet, motifs: &[PathBuf]| Variant {
        label: label.into(),
        family: "rules".into(),
        rules,
        motifs: motifs.to_vec(),
        runs: a.runs,
        method: Protocol::Nested,
        realizations: c.realizations,
    };
    let variants = [
        variant("paper base", RuleSet::Paper, &[]),
        variant("sound base", RuleSet::Sound, &[]),
        variant("sound + extended", RuleSet::Sound, &a.extended),
    ];
    let title = format!(
        "Rigidity threshold, gamma {}: paper base against sound base against sound + extended motifs",
        c.gamma
    );
    let outcomes = c.run(
        "compare-base-extended",
        &title,
        &command_line(),
        &variants,
        Pairing::Previous,
        out,
    )?;
    rgc::plot::compare_chart(
        &outcomes,
        &title,
        &c.results.join("compare-base-extended.svg"),
        &c.results.join("compare-base-extended.png"),
    )
}

fn run_tradeoff(a: TradeoffArgs, out: &mut String) -> Result<()> {
    let c = &a.common;
    let r = c.realizations;
    let base = Variant {
        label: String::new(),
        family: String::new(),
        rules: RuleSet::Sound,
        motifs: Vec::new(),
        runs: 1,
        method: Protocol::Nested,
        realizations: r,
    };
    let mut variants = Vec::new();
    for &k in &a.runs_list {
        variants.push(Variant {
            label: format!("K={k}"),
            family: "runs".into(),
            runs: k,
            realizations: if k > 10 { r / 2 } else { r },
            ..base.clone()
        });
    }
    let m = |f: &str| a.motifs_dir.join(f);
    for (label, files) in [
        ("+rods<=6 (=<=7)", vec![m("rods-6.json")]),
        ("+rods<=8", vec![m("rods-6.json"), m("rods-8.json")]),
        (
            "+rods<=8 +mixed<=4",
            vec![m("rods-6.json"), m("rods-8.json"), m("mixed-4.json")],
        ),
    ] {
        variants.push(Variant {
            label: label.into(),
            family: "motifs".into(),
            motifs: files,
            ..base.clone()
        });
    }
    for n in [r / 4, r / 2] {
        variants.push(Variant {
            label: format!("R={n}"),
            family: "realizations".into(),
            realizations: n,
            ..base.clone()
        });
    }
    for k in [1, 10] {
        variants.push(Variant {
            label: format!("fixed K={k}"),
            family: "method".into(),
            runs: k,
            method: Protocol::Fixed,
            ..base.clone()
        });
    }
    let title = format!(
        "Speed against accuracy, rigidity threshold, gamma {}",
        c.gamma
    );
    let outcomes = c.run(
        "speed-accuracy",
        &title,
        &command_line(),
        &variants,
        Pairing::First,
        out,
    )?;
    rgc::plot::speed_accuracy_chart(
        &outcomes,
        &title,
        &c.results.join("speed-accuracy.svg"),
        &c.results.join("speed-accuracy.png"),
    )
}

fn run_aspect_ratios(a: AspectArgs, out: &mut String) -> Result<()> {
    let mut points = Vec::new();
    let mut csv = String::from(
        "gamma,inv_vex,threshold,threshold_lo,threshold_hi,threshold_times_vex,nu,study\n",
    );
    let mut kind = None;
    for dir in &a.studies {
        let path = dir.join("summary.json");
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let s: Summary = serde_json::from_str(&text).map_err(|e| Error::Study {
            path: path.clone(),
            reason: format!("not a study summary: {e}"),
        })?;
        if kind.is_some_and(|k| k != s.study.kind) {
            return Err(Error::Parameter(format!(
                "{} is a {:?} study; the others are {:?}",
                dir.display(),
                s.study.kind,
                kind.unwrap_or_default()
            )));
        }
        kind = Some(s.study.kind);
        let t = s.fss.threshold;
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.6}"));
        csv += &format!(
            "{},{:.6},{:.6},{},{},{:.6},{:.6},{}\n",
            s.study.gamma,
            1.0 / s.excluded_volume,
            t.value,
            opt(t.lo),
            opt(t.hi),
            s.threshold_times_vex,
            s.fss.nu.value,
            dir.display()
        );
        say!(
            out,
            "gamma {:>6}: threshold {:.4}, times V_ex {:.4}",
            s.study.gamma,
            t.value,
            s.threshold_times_vex
        );
        points.push((s.study.gamma, 1.0 / s.excluded_volume, t));
    }
    let with = |ext: &str| a.out.with_extension(ext);
    if let Some(parent) = a.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
    }
    std::fs::write(with("csv"), csv).map_err(|e| Error::io(with("csv"), e))?;
    let title = format!(
        "{} threshold against the inverse excluded volume 1/V_ex",
        match kind {
            Some(Kind::Contact) => "Contact",
            _ => "Rigidity",
        }
    );
    rgc::plot::threshold_vs_vex(&points, &title, &with("svg"), &with("png"))?;
    say!(
        out,
        "Files: {}, {}, {}",
        with("csv").display(),
        with("svg").display(),
        with("png").display()
    );
    Ok(())
}
