//! `rgc merge`: the shards of a threshold study combined and analysed.

use std::path::PathBuf;

use clap::Args;
use rgc::threshold::{fss, study};
use rgc::{Error, Result, output};

#[derive(Args)]
pub struct MergeArgs {
    /// Study directories holding the shards (one directory may hold them all).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Where the merged records and the analysis go (default: the first directory).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    bootstrap: usize,
    /// Print the outcome as one JSON object (the summary, the files written) and nothing else.
    #[arg(long)]
    json: bool,
}

pub fn run(a: MergeArgs, out: &mut String) -> Result<()> {
    fss::check_bootstrap(a.bootstrap)?;
    let dest = a.out.clone().unwrap_or_else(|| a.dirs[0].clone());
    // Refused before the shards are read; the first directory, the default,
    // may be read-only when it was merged before.
    if let Some(dir) = &a.out {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::Parameter(format!(
                "--out {} is a file, not a directory: the merged study is a directory",
                dir.display()
            )));
        }
        output::check_dir(dir)?;
    }
    let (spec, records) = study::merge(&a.dirs, &dest)?;
    if !a.json {
        say!(
            out,
            "Merged {} sequences from {} director{}.",
            records.len(),
            a.dirs.len(),
            if a.dirs.len() == 1 { "y" } else { "ies" }
        );
    }
    super::threshold::analyse(&dest, &spec, &records, a.bootstrap, None, a.json, out)
}
