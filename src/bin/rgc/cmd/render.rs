//! `rgc render`: one rod system drawn as PNG and SVG, coloured by body.

use std::path::PathBuf;

use clap::Args;
use rgc::plot::rods::{View, rods_picture};
use rgc::sample::sample_with;
use rgc::{Result, output};

use crate::args::SystemArgs;

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    system: SystemArgs,
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
    let view = View {
        azimuth: a.azimuth,
        elevation: a.elevation,
    };
    let (png, svg) = (
        PathBuf::from(format!("{}.png", a.out.display())),
        PathBuf::from(format!("{}.svg", a.out.display())),
    );
    for path in [&png, &svg] {
        output::check_file(path)?;
    }
    let rules = super::load(&a.system.engine.rules.rule_files)?;
    let s = sample_with(&opts, &rules);
    let title = format!(
        "gamma {}, box {}, density {} ({} rods), seed {}, rules {}",
        opts.params.gamma,
        opts.params.box_len,
        opts.params.density,
        s.system.len(),
        opts.seed,
        format!("{:?}", opts.rules).to_lowercase()
    );
    rods_picture(
        &s.system,
        &s.reported_bodies(opts.criterion),
        view,
        &title,
        &svg,
        &png,
    )?;
    say!(out, "Files: {}, {}", png.display(), svg.display());
    Ok(())
}
