//! The chart of the order of the rigidity transition: the jump of the
//! largest true cluster at the critical number against the box (log-log,
//! with its power-law fits), the jump's histogram in the smallest and
//! largest box, the cluster's share of the rods above the threshold, and
//! the Binder cumulant of that share at fixed densities.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, error_bars, log_ticks, render};
use crate::Result;
use crate::threshold::transition::Transition;
use crate::threshold::transition::{HISTOGRAM_BIN, Jump};

/// Pixel size of the chart.
const SIZE: (u32, u32) = (1600, 1150);

/// Boxes with fewer sequences have no histogram drawn.
const HISTOGRAM_SEQUENCES: usize = 20;

/// One colour per study.
const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// Draws `all` as `svg` and `png`: left, the mean jump of the largest true
/// cluster's share of the rods at the critical number per box (95%
/// bootstrap intervals; log-log, with the fitted power laws); middle, the
/// share of sequences by jump in each aspect ratio's smallest and largest
/// box; below, the cluster's share at spanning steps against density
/// (`P_inf` above the threshold) in one box per aspect ratio, and the
/// Binder cumulant of that share at fixed densities per box, where
/// fixed-protocol studies give it.
pub fn transition_chart(all: &[Transition], svg: &Path, png: &Path) -> Result<()> {
    render(&Chart2(all), SIZE, svg, png)
}

struct Chart2<'a>(&'a [Transition]);

impl Chart for Chart2<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let root = root.titled(
            "Order of the rigidity transition (exact truth)",
            ("sans-serif", 26),
        )?;
        let panels = root.split_evenly((2, 2));
        jumps(&panels[0], self.0)?;
        histograms(&panels[1], self.0)?;
        shares(&panels[2], self.0)?;
        binder(&panels[3], self.0)?;
        root.present()
    }
}

fn jumps<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, all: &[Transition]) -> Drawn<DB> {
    let js = all.iter().flat_map(|t| &t.jumps);
    let l0 = js.clone().map(|j| j.box_len).fold(f64::INFINITY, f64::min) * 0.9;
    let l1 = js.clone().map(|j| j.box_len).fold(1.0, f64::max) * 1.1;
    let y0 = js
        .clone()
        .map(|j| j.interval.0)
        .fold(1.0, f64::min)
        .max(1e-4)
        * 0.8;
    let y1 = js.map(|j| j.interval.1).fold(0.01, f64::max) * 1.25;
    let l0 = l0.min(l1 / 2.0);
    let mut chart = ChartBuilder::on(area)
        .caption("jump at the critical rod", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (l0..l1).log_scale().with_key_points(log_ticks(l0, l1)),
            (y0..y1).log_scale().with_key_points(log_ticks(y0, y1)),
        )?;
    chart
        .configure_mesh()
        .x_desc("box side L")
        .y_desc("share of rods added to the largest cluster")
        .label_style(("sans-serif", 14))
        .draw()?;
    for (t, colour) in all.iter().zip(COLOURS.iter().cycle()) {
        let c = *colour;
        let bars = t
            .jumps
            .iter()
            .map(|j| (j.box_len, j.interval.0, j.interval.1));
        error_bars(&mut chart, bars, c.to_rgba(), 6)?;
        chart
            .draw_series(
                t.jumps
                    .iter()
                    .map(|j| Circle::new((j.box_len, j.mean), 4, c.filled())),
            )?
            .label(format!("gamma {}", t.gamma))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
        // Each fit through the geometric mean of its boxes' means.
        for (k, d) in t.decay.iter().enumerate() {
            let fitted: Vec<(f64, f64)> = t
                .jumps
                .iter()
                .filter(|j| d.boxes.contains(&j.box_len))
                .map(|j| (j.box_len.ln(), j.mean.ln()))
                .collect();
            let n = fitted.len() as f64;
            let (lx, ly) = fitted
                .iter()
                .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
            let at = |l: f64| (ly - d.exponent * (l.ln() - lx)).exp();
            let (from, to) = (d.boxes[0], *d.boxes.last().expect("boxes"));
            let style = if k == 0 {
                c.stroke_width(1)
            } else {
                c.mix(0.6).stroke_width(3)
            };
            chart
                .draw_series(LineSeries::new([(from, at(from)), (to, at(to))], style))?
                .label(format!(
                    "gamma {}, L {from}-{to}: L^{:.2}",
                    t.gamma, -d.exponent
                ))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
    }
    super::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)
}

fn histograms<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, all: &[Transition]) -> Drawn<DB> {
    // Each aspect ratio's smallest and largest box of enough sequences for
    // a histogram, as shares of sequences.
    let shown: Vec<(usize, &Jump, bool)> = all
        .iter()
        .enumerate()
        .flat_map(|(i, t)| {
            let enough: Vec<&Jump> = t
                .jumps
                .iter()
                .filter(|j| j.sequences >= HISTOGRAM_SEQUENCES)
                .collect();
            let last = enough.len().saturating_sub(1);
            enough
                .into_iter()
                .enumerate()
                .filter(move |(k, _)| *k == 0 || *k == last)
                .map(move |(k, j)| (i, j, k == last))
        })
        .collect();
    let x1 = shown
        .iter()
        .map(|s| s.1.histogram.len() as f64 * HISTOGRAM_BIN)
        .fold(0.05, f64::max);
    let share = |j: &Jump, b: usize| j.histogram[b] as f64 / j.sequences.max(1) as f64;
    let y1 = shown
        .iter()
        .flat_map(|s| (0..s.1.histogram.len()).map(|b| share(s.1, b)))
        .fold(0.05, f64::max)
        * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption("jumps of the sequences", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..x1, 0.0..y1)?;
    chart
        .configure_mesh()
        .x_desc("share of rods added at the critical rod")
        .y_desc(format!("share of sequences per {HISTOGRAM_BIN} bin"))
        .label_style(("sans-serif", 14))
        .draw()?;
    for (i, j, largest) in shown {
        let c = COLOURS[i % COLOURS.len()];
        let style = if largest {
            c.stroke_width(3)
        } else {
            c.mix(0.5).stroke_width(1)
        };
        let steps = (0..j.histogram.len()).flat_map(|b| {
            let y = share(j, b);
            [
                (b as f64 * HISTOGRAM_BIN, y),
                ((b + 1) as f64 * HISTOGRAM_BIN, y),
            ]
        });
        chart
            .draw_series(LineSeries::new(steps, style))?
            .label(format!(
                "gamma {}, L = {} ({} sequences)",
                all[i].gamma, j.box_len, j.sequences
            ))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    super::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)
}

fn shares<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, all: &[Transition]) -> Drawn<DB> {
    let ss = all.iter().flat_map(|t| &t.shares);
    let lo = ss.clone().map(|s| s.density).fold(f64::INFINITY, f64::min);
    let hi = ss.map(|s| s.density).fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo < hi { (lo, hi) } else { (0.0, 1.0) };
    let pad = 0.05 * (hi - lo);
    let mut chart = ChartBuilder::on(area)
        .caption(
            "largest cluster above the threshold (P_inf)",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(lo - pad..hi + pad, 0.0..1.0)?;
    chart
        .configure_mesh()
        .x_desc("density (rods per unit volume)")
        .y_desc("share of rods in the largest true cluster")
        .label_style(("sans-serif", 14))
        .draw()?;
    for (t, colour) in all.iter().zip(COLOURS.iter().cycle()) {
        let c = *colour;
        let l = t.shares.first().map_or(0.0, |s| s.box_len);
        chart
            .draw_series(LineSeries::new(
                t.shares.iter().map(|s| (s.density, s.mean)),
                c.stroke_width(2),
            ))?
            .label(format!("gamma {}, L = {l}", t.gamma))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart.draw_series(
            t.shares
                .iter()
                .map(|s| Circle::new((s.density, s.mean), 3, c.filled())),
        )?;
    }
    super::chart::legend(&mut chart, SeriesLabelPosition::LowerRight)
}

fn binder<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, all: &[Transition]) -> Drawn<DB> {
    let cells = all.iter().flat_map(|t| &t.binder);
    let lo = cells
        .clone()
        .map(|b| b.density)
        .fold(f64::INFINITY, f64::min);
    let hi = cells
        .clone()
        .map(|b| b.density)
        .fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo < hi { (lo, hi) } else { (0.0, 1.0) };
    let pad = 0.05 * (hi - lo);
    let bottom = cells.map(|b| b.interval.0).fold(0.0, f64::min) - 0.05;
    let mut chart = ChartBuilder::on(area)
        .caption(
            "Binder cumulant of the largest cluster's share",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(lo - pad..hi + pad, bottom..0.75)?;
    chart
        .configure_mesh()
        .x_desc("density (rods per unit volume)")
        .y_desc("U = 1 - <P^4> / 3 <P^2>^2")
        .label_style(("sans-serif", 14))
        .draw()?;
    for t in all {
        let mut lens: Vec<f64> = t.binder.iter().map(|b| b.box_len).collect();
        lens.dedup();
        for (k, &l) in lens.iter().enumerate() {
            let c = COLOURS[k % COLOURS.len()];
            let here: Vec<_> = t.binder.iter().filter(|b| b.box_len == l).collect();
            let bars = here.iter().map(|b| (b.density, b.interval.0, b.interval.1));
            error_bars(&mut chart, bars, c.mix(0.6), 4)?;
            chart
                .draw_series(LineSeries::new(
                    here.iter().map(|b| (b.density, b.cumulant)),
                    c.stroke_width(2),
                ))?
                .label(format!("gamma {}, L = {l}", t.gamma))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
        }
    }
    super::chart::legend(&mut chart, SeriesLabelPosition::LowerRight)
}
