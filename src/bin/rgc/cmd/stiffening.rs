//! `rgc stiffening`: the elastic moduli one rod below and at the critical
//! number of each sequence of truth studies.

use std::path::PathBuf;

use clap::Args;
use rgc::moduli::Solver;
use rgc::threshold::stiffening::{self, Mean, StiffeningSpec};
use rgc::{Result, output, plot, threshold};

use crate::args::{LsmrArgs, MeasuredArgs, MemoryArgs};
use crate::progress::Reporter;

#[derive(Args)]
pub struct StiffeningArgs {
    #[command(flatten)]
    measured: MeasuredArgs,
    #[command(flatten)]
    memory: MemoryArgs,
    /// Spring stiffness k of a contact.
    #[arg(long, default_value_t = 1.0)]
    k: f64,
    /// Also measure each sequence at these densities (rods per unit volume, increasing): the stiffening curve.
    #[arg(long, value_delimiter = ',')]
    densities: Vec<f64>,
    /// How the springs' least squares is solved: qr or lsmr (as `rgc moduli --solver`; a measurement never lets the memory free at the time choose).
    #[arg(long, value_enum, default_value_t = Solver::Qr)]
    solver: Solver,
    #[command(flatten)]
    lsmr: LsmrArgs,
    /// Add the densities of --densities that continue the directory's grid (its densities, then more) to its finished sequences, measuring only the new sides (with this run's --solver; each side records its own); or, with a larger --lsmr-iterations than the directory's, measure again the sides LSMR left unsettled.
    #[arg(long)]
    extend: bool,
    /// Also write the summary as PREFIX.json, and with --densities the chart as PREFIX.svg and PREFIX.png.
    #[arg(long)]
    summary: Option<PathBuf>,
    /// Finished studies whose thresholds the chart marks (for example the truth study's and 3D-RGC's on the same sequences), each labelled by its directory's name.
    #[arg(long, value_delimiter = ',', requires = "summary")]
    marks: Vec<PathBuf>,
    /// Other measurements (`rgc stiffening` directories of other boxes, with the same k; each box keeps the densities it was measured at) whose sequences join the summary: the shear modulus at the critical rod against the box.
    #[arg(long, value_delimiter = ',')]
    with: Vec<PathBuf>,
}

pub fn run(a: StiffeningArgs, out: &mut String) -> Result<()> {
    if let Some(prefix) = &a.summary {
        output::check_file(prefix)?;
    }
    let m = &a.measured;
    let spec = StiffeningSpec {
        studies: m.studies(),
        boxes: m.boxes.clone(),
        sequences: m.sequences,
        stiffness: a.k,
        densities: a.densities.clone(),
        solver: a.solver,
        lsmr_iterations: a.lsmr.iterations(),
    };
    let summary = stiffening::run(
        &m.dirs,
        &spec,
        &m.out,
        a.extend,
        &a.with,
        a.memory.memory_limit,
        &Reporter::new(m.quiet),
    )?;
    let summaries = &summary.boxes;
    let mean = |m: Option<Mean>| {
        m.map_or("-".to_string(), |m| {
            let half = m.half_width.map_or("-".to_string(), |h| format!("{h:.1e}"));
            format!("{:.3e} +- {half}", m.mean)
        })
    };
    say!(
        out,
        "{:>6} {:>5} {:>4} {:>6} {:>10} {:>10} {:>6} {:>6} {:>22} {:>22} {:>22} {:>10} {:>8} {:>6} {:>9}",
        "gamma",
        "box",
        "seqs",
        "failed",
        "rank below",
        "rank at",
        "0->r>0",
        "solid",
        "G below",
        "G at",
        "G jump",
        "comparable",
        "one geom",
        "G fell",
        "unsettled"
    );
    for s in summaries {
        let rank = |m: Option<Mean>| m.map_or("-".to_string(), |m| format!("{:.2}", m.mean));
        say!(
            out,
            "{:>6} {:>5} {:>4} {:>6} {:>10} {:>10} {:>6} {:>6} {:>22} {:>22} {:>22} {:>10} {:>8} {:>6} {:>9}",
            s.gamma,
            s.box_len,
            s.sequences,
            s.failed,
            rank(s.strain_rank_before),
            rank(s.strain_rank_at),
            s.rank_rises_from_zero,
            s.solid_at,
            mean(s.shear_before),
            mean(s.shear_at),
            mean(s.shear_jump),
            s.both_comparable,
            s.one_geometry,
            s.shear_fell,
            s.unsettled
        );
    }
    for s in summaries {
        for p in &s.grid {
            say!(
                out,
                "gamma {} box {} rho {}: {} measured ({} failed, {} comparable: exact zeros or nearest the rods, {} unsettled), solid {}, G {}, K {}, largest cluster {}",
                s.gamma,
                s.box_len,
                p.density,
                p.measured,
                p.failed,
                p.comparable,
                p.unsettled,
                p.solid,
                mean(p.shear),
                mean(p.bulk),
                mean(p.largest_share)
            );
        }
    }
    for s in summaries {
        let fits = [
            ("the studies' threshold", s.exponent),
            ("each sequence's own critical density", s.exponent_own),
        ];
        for (against, e) in fits {
            let Some(e) = e else { continue };
            let interval = e
                .interval
                .map_or("-".to_string(), |(lo, hi)| format!("[{lo:.2}, {hi:.2}]"));
            let at = e.threshold.map_or(String::new(), |t| format!(" {t:.2}"));
            say!(
                out,
                "gamma {} box {}: G ~ (rho - rho_c)^f with f = {:.2} {interval} against {against}{at} ({} points, rho - rho_c from {:.2} to {:.2})",
                s.gamma,
                s.box_len,
                e.f,
                e.points,
                e.from,
                e.to
            );
        }
    }
    for d in &summary.decay {
        let boxes: Vec<String> = d
            .boxes
            .iter()
            .map(|(l, n, g, geo)| match geo {
                Some(geo) => format!("L = {l}: mean {g:.3e}, geometric {geo:.3e} ({n})"),
                None => format!("L = {l}: mean {g:.3e} ({n})"),
            })
            .collect();
        say!(
            out,
            "gamma {}: G at the critical rod by box {}",
            d.gamma,
            boxes.join(", ")
        );
        for (mean, fits) in [("mean", &d.decay), ("geometric mean", &d.geometric)] {
            for f in fits {
                say!(
                    out,
                    "gamma {}: {mean} G at the critical rod ~ L^-{:.2} [{:.2}, {:.2}] over L = {:?} (R2 {:.3})",
                    d.gamma,
                    f.exponent,
                    f.interval.0,
                    f.interval.1,
                    f.boxes,
                    f.r2
                );
            }
        }
    }
    if let Some(prefix) = &a.summary {
        let mut written = vec![stiffening::write(prefix, &summary, &super::command_line())?];
        if !a.densities.is_empty() {
            let marks = a
                .marks
                .iter()
                .map(|dir| {
                    let label = dir.file_name().map_or_else(
                        || dir.display().to_string(),
                        |n| n.to_string_lossy().into_owned(),
                    );
                    Ok((
                        label,
                        threshold::report::read_summary(dir)?.fss.threshold.value,
                    ))
                })
                .collect::<Result<Vec<_>>>()?;
            let (svg, png) = (
                output::with_extension(prefix, "svg"),
                output::with_extension(prefix, "png"),
            );
            plot::stiffening_chart(summaries, &marks, &svg, &png)?;
            written.extend([svg, png]);
        }
        for f in written {
            say!(out, "wrote {}", f.display());
        }
    }
    Ok(())
}
