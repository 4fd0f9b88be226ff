//! The chart of the motif horizon: 3D-RGC's paired bias against truth, as a
//! share of truth's critical density, against the largest motif of each
//! variant and against its number of rules, one colour per aspect ratio.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, PALETTE, error_bars, legend, render, span};
use crate::Result;
use crate::threshold::horizon::Variant;

/// Pixel size of the chart.
const SIZE: (u32, u32) = (1400, 600);

/// Draws `variants` as `svg` and `png`: left, the relative bias (95%
/// interval) against the largest motif's nodes, the rods-only series
/// joined; right, against the number of rules (logarithmic; the base set,
/// with none, at 1).
pub fn horizon_chart(variants: &[Variant], svg: &Path, png: &Path) -> Result<()> {
    render(&Horizon(variants), SIZE, svg, png)
}

struct Horizon<'a>(&'a [Variant]);

impl Chart for Horizon<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let root = root.titled(
            "The motif horizon: 3D-RGC's bias against the exact truth",
            ("sans-serif", 26),
        )?;
        let (left, right) = root.split_horizontally(SIZE.0 / 2);
        panel(&left, self.0, Axis::Size)?;
        panel(&right, self.0, Axis::Rules)?;
        root.present()
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Axis {
    Size,
    Rules,
}

impl Axis {
    fn x(self, v: &Variant) -> f64 {
        match self {
            Axis::Size => v.largest_nodes.max(crate::threshold::horizon::BASE_RODS) as f64,
            Axis::Rules => (v.rules.max(1) as f64).log10(),
        }
    }
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    vs: &[Variant],
    axis: Axis,
) -> Drawn<DB> {
    let percent = |x: Option<f64>, v: f64| 100.0 * x.unwrap_or(v);
    let top = vs
        .iter()
        .map(|v| percent(v.bias.relative.hi, v.bias.relative.value))
        .fold(1.0, f64::max)
        * 1.15;
    let (lo, hi) = span(vs.iter().map(|v| axis.x(v)), 0.08);
    let (caption, x_desc) = match axis {
        Axis::Size => (
            "against the largest motif",
            "nodes of the largest motif (base: 5 rods)",
        ),
        Axis::Rules => (
            "against the number of rules",
            "log10 of the rules loaded (base: 0)",
        ),
    };
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(lo..hi, 0.0..top)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc("bias, % of truth's critical density")
        .label_style(("sans-serif", 14))
        .draw()?;
    let mut gammas: Vec<f64> = vs.iter().map(|v| v.gamma).collect();
    gammas.sort_by(f64::total_cmp);
    gammas.dedup();
    for (gamma, colour) in gammas.iter().zip(PALETTE.iter().cycle()) {
        let c = *colour;
        let of: Vec<&Variant> = vs.iter().filter(|v| v.gamma == *gamma).collect();
        let bars = of.iter().map(|v| {
            let r = &v.bias.relative;
            (axis.x(v), percent(r.lo, r.value), percent(r.hi, r.value))
        });
        error_bars(&mut chart, bars, c.to_rgba(), 5)?;
        let mut series: Vec<(f64, f64)> = of
            .iter()
            .filter(|v| v.rods_only)
            .map(|v| (axis.x(v), 100.0 * v.bias.relative.value))
            .collect();
        series.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(series, c.stroke_width(2)))?;
        chart
            .draw_series(of.iter().map(|v| {
                let at = (axis.x(v), 100.0 * v.bias.relative.value);
                let style = if v.rods_only {
                    c.filled()
                } else {
                    c.stroke_width(2)
                };
                Circle::new(at, 5, style)
            }))?
            .label(format!("gamma {gamma} (filled: rods-only series, joined)"))
            .legend(move |(x, y)| Circle::new((x + 8, y), 5, c.filled()));
    }
    legend(&mut chart, SeriesLabelPosition::LowerLeft)
}
