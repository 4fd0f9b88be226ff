//! `rgc sample`: one rod system, its contacts and rigid bodies.

use std::path::PathBuf;

use clap::Args;
use rgc::graph::{graphml, io as graphio};
use rgc::sample::sample_with;
use rgc::{Result, output};

use crate::args::{MemoryArgs, SystemArgs};

#[derive(Args)]
pub struct SampleArgs {
    #[command(flatten)]
    system: SystemArgs,
    #[command(flatten)]
    memory: MemoryArgs,
    /// Write the rods to this file: CSV (x,y,z,dx,dy,dz,length,radius, with id first for rods read with ids), or JSON or a LAMMPS dump by the extension, centres in [0, L) and the box at the origin; `--rods` reads it back to the same system.
    #[arg(long)]
    save_rods: Option<PathBuf>,
    /// Write the contact graph as an edge list (`u v` per line) to this file.
    #[arg(long)]
    save_contacts: Option<PathBuf>,
    /// Write the rods and contacts as GraphML (rod centres, axes, lengths and radii; each contact's point, axis parameters and periodic image) to this file.
    #[arg(long)]
    save_graphml: Option<PathBuf>,
    /// Write the rods as VTK PolyData (.vtp, binary: line cells with their radius, the box outline as a second piece and the box as field data; per rod the body of the reported run, -1 if free, whether it spans, the degree, and with --truth the true rigid cluster and whether it spans) to this file.
    #[arg(long)]
    save_vtk: Option<PathBuf>,
    /// Write the bodies of the reported run (rods, class, whether each spans) as JSON to this file.
    #[arg(long)]
    save_bodies: Option<PathBuf>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
}

pub fn run(a: SampleArgs, out: &mut String) -> Result<()> {
    let opts = a.system.options()?;
    opts.check_memory(a.memory.memory_limit)?;
    // An output that cannot be written fails before the sample is drawn.
    if let Some(path) = &a.save_rods {
        rgc::rods::file::Format::of_path(path)?;
    }
    if let Some(path) = &a.save_vtk {
        rgc::vtk::check_extension(path)?;
    }
    super::check_outputs(&[
        ("--save-rods", &a.save_rods),
        ("--save-contacts", &a.save_contacts),
        ("--save-bodies", &a.save_bodies),
        ("--save-graphml", &a.save_graphml),
        ("--save-vtk", &a.save_vtk),
    ])?;
    let rules = super::load(&a.system.engine.rules.rule_files)?;
    let s = sample_with(&opts, &rules)?;
    if let Some(path) = &a.save_rods {
        rgc::rods::file::save(&s.system, s.ids.as_deref(), path)?;
    }
    if let Some(path) = &a.save_contacts {
        graphio::save_edge_list(&s.graph, path)?;
    }
    if let Some(path) = &a.save_graphml {
        graphml::save_graphml(&s.system, &s.contacts, path)?;
    }
    if let Some(path) = &a.save_vtk {
        rgc::vtk::save_sample(&s, opts.criterion, path)?;
    }
    if let Some(path) = &a.save_bodies {
        let text = serde_json::to_string_pretty(&s.reported_bodies(opts.criterion))
            .expect("bodies serialize");
        output::write_atomic(path, text + "\n")?;
    }
    let r = &s.report;
    if a.json {
        return super::print_json(r, out);
    }
    for line in rgc::rods::file::placement(r.cut, r.wrapped) {
        say!(out, "{line}");
    }
    let expected = r
        .c0_expected
        .map_or(String::new(), |e| format!(" (expected {e:.4})"));
    say!(
        out,
        "{} rods, {} contacts: c0 = {:.4}{expected}, c1 = {:.4}, c2 = {:.4}, clustering = {:.4}",
        r.n_rods,
        r.n_contacts,
        r.c0,
        r.c1,
        r.c2,
        r.clustering
    );
    say!(
        out,
        "contact spanning ({}): {}; rigid spanning: {} ({} of {} runs, rules {})",
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
    if let Some(t) = &r.truth {
        let spanning = t.spanning.map_or("undecided".into(), |s| s.to_string());
        say!(
            out,
            "truth ({}): rigid spanning {spanning}; {} true rigid clusters, largest {} rods; {:.3} s",
            t.method,
            t.clusters,
            t.largest_cluster_rods,
            t.seconds
        );
    }
    Ok(())
}
