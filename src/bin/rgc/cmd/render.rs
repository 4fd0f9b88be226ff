//! `rgc render`: one rod system drawn as PNG and SVG, coloured by body (or,
//! with `--truth`, by true rigid cluster).

use std::path::PathBuf;

use clap::Args;
use rgc::plot::rods::{Groups, View, rods_picture};
use rgc::sample::{Rods, sample_with};
use rgc::{Result, output};

use crate::args::{MemoryArgs, SystemArgs};

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    system: SystemArgs,
    #[command(flatten)]
    memory: MemoryArgs,
    /// Turn of the view about the box's z axis, in degrees.
    #[arg(long, default_value_t = View::default().azimuth, allow_hyphen_values = true)]
    azimuth: f64,
    /// How far the view looks down, in degrees (-90 to 90).
    #[arg(long, default_value_t = View::default().elevation, allow_hyphen_values = true)]
    elevation: f64,
    /// Write PREFIX.png and PREFIX.svg.
    #[arg(long)]
    out: PathBuf,
}

pub fn run(a: RenderArgs, out: &mut String) -> Result<()> {
    let opts = a.system.options()?;
    opts.check_memory(a.memory.memory_limit)?;
    let view = View {
        azimuth: a.azimuth,
        elevation: a.elevation,
    };
    super::check_prefix(&a.out)?;
    let (png, svg) = (
        PathBuf::from(format!("{}.png", a.out.display())),
        PathBuf::from(format!("{}.svg", a.out.display())),
    );
    for path in [&png, &svg] {
        output::check_file(path)?;
    }
    let rules = super::load(&a.system.engine.rules.rule_files)?;
    let s = sample_with(&opts, &rules)?;
    let r = &s.report;
    let method = if opts.truth {
        "exact truth".to_string()
    } else {
        format!("rules {}", opts.rules)
    };
    let n = s.system.len();
    let domain = s.system.domain.describe();
    let title = match (&opts.rods, r.gamma) {
        // Rods from a file: the file names them; no seed or density drew them.
        (Rods::Read { path, .. }, _) => format!(
            "{}: {n} rods, box {domain}, {method}",
            path.file_name().unwrap_or_default().to_string_lossy()
        ),
        (Rods::Generated(e), gamma) => {
            let rods = gamma.map_or_else(
                || {
                    format!(
                        "mean length {:.3}, mean radius {:.4}",
                        r.mean_length, r.mean_radius
                    )
                },
                |g| format!("gamma {g}"),
            );
            format!(
                "{rods}, box {domain}, density {} ({n} rods), seed {}, {method}",
                e.density, opts.seed
            )
        }
    };
    let bodies = s.reported_bodies(opts.criterion);
    let groups = match &s.truth {
        Some(t) => Groups::true_clusters(t, opts.criterion),
        None => Groups::bodies(&bodies),
    };
    rods_picture(&s.system, &groups, view, &title, &svg, &png)?;
    say!(out, "Files: {}, {}", png.display(), svg.display());
    Ok(())
}
