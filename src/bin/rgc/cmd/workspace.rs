//! `rgc workspace`: a threshold study from a row (or signac) workspace.
//! `slice` runs the slice one directory's value names (row's `{directory}`
//! action); `merge` combines the slices of one study (a `{directories}`
//! action) and analyses it as `rgc merge` does.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use rgc::Result;
use rgc::threshold::fss;
use rgc::threshold::study::{self, MotifSet, RunOptions};
use rgc::threshold::workspace::{self, Pointers};

use crate::args::MemoryArgs;
use crate::progress::Reporter;

#[derive(Args)]
pub struct WorkspaceArgs {
    #[command(subcommand)]
    action: Action,
}

#[derive(Subcommand)]
enum Action {
    /// Run the slice of a study that a directory's value names (gamma, boxes, sequences, kind, rules, rule_files, runs, protocol, grid_points, criterion, seed, shard) into the directory; `slice.json` marks it done.
    Slice(SliceArgs),
    /// Merge the slices of one study under --studies (named by its parameters), analyse it, and write `merged.json` into each directory.
    Merge(MergeArgs),
}

/// Where the directories are: row passes names inside its workspace.
#[derive(Args)]
struct Place {
    /// The workspace the directories are in (row's `{workspace_path}`); default: the current directory.
    #[arg(long)]
    workspace: Option<PathBuf>,
}

impl Place {
    fn dir(&self, name: &Path) -> PathBuf {
        match &self.workspace {
            Some(w) => w.join(name),
            None => name.to_path_buf(),
        }
    }
}

#[derive(Args)]
struct SliceArgs {
    /// The workspace directory (row's `{directory}`).
    dir: PathBuf,
    #[command(flatten)]
    place: Place,
    /// The file holding the directory's value (`signac_statepoint.json` for signac).
    #[arg(long, default_value = workspace::VALUE_FILE)]
    value_file: String,
    /// Read a parameter from this JSON pointer of the value instead of `/NAME`: NAME=/POINTER, e.g. `gamma=/sp/aspect_ratio` (repeatable).
    #[arg(long = "pointer", value_name = "NAME=/POINTER")]
    pointers: Vec<String>,
    #[command(flatten)]
    memory: MemoryArgs,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args)]
struct MergeArgs {
    /// The workspace directories of one study (row's `{directories}`).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    #[command(flatten)]
    place: Place,
    /// Where the merged study goes, in a directory named by its parameters.
    #[arg(long, default_value = "studies")]
    studies: PathBuf,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    bootstrap: usize,
    /// Print the outcome as one JSON object (the summary, the files written) and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: WorkspaceArgs, out: &mut String) -> Result<()> {
    match a.action {
        Action::Slice(a) => slice(a, out),
        Action::Merge(a) => merge(a, out),
    }
}

fn slice(a: SliceArgs, out: &mut String) -> Result<()> {
    let dir = a.place.dir(&a.dir);
    let pointers = Pointers::parse(&a.pointers)?;
    let mut slice = workspace::read_slice(&dir, &a.value_file, &pointers)?;
    let name = format!(
        "slice {}/{} of {}",
        slice.shard.index,
        slice.shard.count,
        dir.display()
    );
    if workspace::is_done(&dir, &slice)? {
        say!(out, "The {name} is done ({}).", workspace::SLICE_FILE);
        return Ok(());
    }
    let rules = super::load_rules(&slice.rule_files)?;
    slice.spec.motifs = MotifSet::of(&rules, &slice.rule_files);
    let opts = RunOptions {
        out: dir.clone(),
        shard: slice.shard,
        extend: false,
        memory_limit: a.memory.memory_limit,
    };
    let compiled: Vec<_> = rules.iter().map(rgc::engine::CompiledRule::new).collect();
    let done = study::run(&slice.spec, &compiled, &opts, &Reporter::new(a.quiet))?;
    workspace::mark_done(&dir, &slice, done.ran + done.resumed)?;
    say!(
        out,
        "The {name}: {} sequences run in {:.1} s ({} found done); {} written.",
        done.ran,
        done.seconds,
        done.resumed,
        workspace::SLICE_FILE
    );
    Ok(())
}

fn merge(a: MergeArgs, out: &mut String) -> Result<()> {
    fss::check_bootstrap(a.bootstrap)?;
    let dirs: Vec<PathBuf> = a.dirs.iter().map(|d| a.place.dir(d)).collect();
    let (dest, spec, records) = workspace::merge(&dirs, &a.studies)?;
    if !a.json {
        say!(
            out,
            "Merged {} sequences from {} director{} into {}.",
            records.len(),
            dirs.len(),
            if dirs.len() == 1 { "y" } else { "ies" },
            dest.display()
        );
    }
    super::threshold::analyse(&dest, &spec, &records, a.bootstrap, None, a.json, out)?;
    workspace::mark_merged(&dirs, &dest, records.len())
}
