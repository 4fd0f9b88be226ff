//! The chart of the order of the rigidity transition: the jump of the
//! largest true cluster at the critical number against the box, and its
//! share of the rods above the threshold.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, error_bars, render};
use crate::Result;
use crate::threshold::transition::Transition;

/// Pixel size of the chart.
const SIZE: (u32, u32) = (1400, 600);

/// One colour per study.
const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// Draws `all` as `svg` and `png`: left, the mean jump of the largest true
/// cluster's share of the rods at the critical number per box (95%
/// intervals); right, that share at spanning steps against density (`P_inf`
/// above the threshold) in one box per study.
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
        let (left, right) = root.split_horizontally(SIZE.0 / 2);
        jumps(&left, self.0)?;
        shares(&right, self.0)?;
        root.present()
    }
}

fn jumps<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, all: &[Transition]) -> Drawn<DB> {
    let js = all.iter().flat_map(|t| &t.jumps);
    let max_l = js.clone().map(|j| j.box_len).fold(1.0, f64::max);
    let top = js.map(|j| j.mean + j.half_width).fold(0.05, f64::max) * 1.2;
    let mut chart = ChartBuilder::on(area)
        .caption("jump at the critical rod", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..max_l + 1.0, 0.0..top)?;
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
            .map(|j| (j.box_len, j.mean - j.half_width, j.mean + j.half_width));
        error_bars(&mut chart, bars, c.to_rgba(), 6)?;
        chart
            .draw_series(
                t.jumps
                    .iter()
                    .map(|j| Circle::new((j.box_len, j.mean), 4, c.filled())),
            )?
            .label(format!("gamma {}", t.gamma))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
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
