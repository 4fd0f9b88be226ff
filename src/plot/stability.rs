//! The chart of the float-rank stability study.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, render};
use crate::Result;
use crate::math::float::RankRule;
use crate::rigidity::Ranker;
use crate::stability::{Axis, StabilityRow};

/// Pixel size of the stability chart.
const SIZE: (u32, u32) = (1400, 1000);

/// Draws the stability study as `svg` and `png`: one panel per geometric
/// axis (fractions undecided and wrong against `eps`, for rgc's decision,
/// the tolerance alone and one realization without its twin), and one for
/// the size axis (median singular-value gap against the number of rods).
pub fn stability_chart(rows: &[StabilityRow], svg: &Path, png: &Path) -> Result<()> {
    render(&Stability(rows), SIZE, svg, png)
}

struct Stability<'a>(&'a [StabilityRow]);

impl Chart for Stability<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        draw(root, self.0)
    }
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, rows: &[StabilityRow]) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(
        "Float rank against the exact verdict: rgc says undecided where SVD and QR err",
        ("sans-serif", 26),
    )?;
    let panels = root.split_evenly((2, 2));
    let geometric = [
        (
            Axis::Parallel,
            "nearly parallel rods (directions eps apart)",
        ),
        (Axis::Coincident, "nearly coincident contacts (eps apart)"),
        (
            Axis::Collinear,
            "nearly collinear contacts (eps off a line)",
        ),
    ];
    for (k, (area, (axis, title))) in panels.iter().zip(geometric).enumerate() {
        fractions(area, rows, axis, title, k == 0)?;
    }
    sizes(&panels[3], rows)?;
    root.present()
}

/// The quantities of a geometric panel: label, value, colour.
type Quantity = (&'static str, fn(&StabilityRow) -> f64, RGBColor);

const QUANTITIES: [Quantity; 4] = [
    ("rgc: undecided", |r| r.undecided, RGBColor(31, 119, 180)),
    ("rgc: wrong", |r| r.wrong, RGBColor(214, 39, 40)),
    (
        "tolerance only: wrong",
        |r| r.naive_wrong,
        RGBColor(255, 127, 14),
    ),
    (
        "one realization, no twin: wrong",
        |r| r.single_wrong,
        RGBColor(148, 103, 189),
    ),
];

fn method_label(m: Ranker) -> &'static str {
    match m {
        Ranker::Qr => "QR",
        _ => "SVD",
    }
}

/// Fractions against `-log10 eps` for one geometric axis.
fn fractions<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    rows: &[StabilityRow],
    axis: Axis,
    title: &str,
    legend: bool,
) -> Drawn<DB> {
    let of_axis: Vec<&StabilityRow> = rows.iter().filter(|r| r.axis == axis).collect();
    let x = |r: &StabilityRow| -r.eps.unwrap_or(1.0).log10();
    let (lo, hi) = of_axis
        .iter()
        .map(|r| x(r))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let (lo, hi) = if lo < hi { (lo, hi) } else { (1.0, 14.0) };
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(lo - 0.3..hi + 0.3, -0.02..1.02)?;
    chart
        .configure_mesh()
        .x_desc("eps (distance from the degenerate position)")
        .y_desc("fraction of trials")
        .x_labels(14)
        .x_label_formatter(&|v| format!("1e-{}", v.round()))
        .label_style(("sans-serif", 14))
        .draw()?;
    for method in [Ranker::Svd, Ranker::Qr] {
        let mut pts: Vec<&StabilityRow> = of_axis
            .iter()
            .copied()
            .filter(|r| r.method == method)
            .collect();
        pts.sort_by(|a, b| x(a).total_cmp(&x(b)));
        for (label, value, color) in QUANTITIES {
            let line: Vec<(f64, f64)> = pts.iter().map(|r| (x(r), value(r))).collect();
            let style = color.stroke_width(2);
            let name = format!("{label} ({})", method_label(method));
            let drawn = if method == Ranker::Svd {
                chart.draw_series(LineSeries::new(line, style))?
            } else {
                chart.draw_series(DashedLineSeries::new(line, 7, 5, style))?
            };
            if legend {
                drawn.label(name).legend(move |(x, y)| {
                    let dash = if method == Ranker::Svd { 20 } else { 8 };
                    PathElement::new(vec![(x, y), (x + dash, y)], color.stroke_width(2))
                });
            }
        }
    }
    if legend {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 14))
            .draw()?;
    }
    Ok(())
}

/// Median gap against the number of rods, with the least gap a decided rank has.
fn sizes<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, rows: &[StabilityRow]) -> Drawn<DB> {
    let of_axis: Vec<&StabilityRow> = rows.iter().filter(|r| r.axis == Axis::Size).collect();
    let all_correct = of_axis.iter().all(|r| r.correct == 1.0);
    let title = if all_correct {
        "growing rods-only ladders: median gap (all decided, all correct)"
    } else {
        "growing rods-only ladders: median gap"
    };
    let max_rods = of_axis.iter().filter_map(|r| r.rods).max().unwrap_or(60) as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..max_rods + 4.0, (1e2..1e16).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("rods")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_desc("median gap s_(r-1) / s_r")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 14))
        .draw()?;
    for method in [Ranker::Svd, Ranker::Qr] {
        let mut line: Vec<(f64, f64)> = of_axis
            .iter()
            .filter(|r| r.method == method && r.median_gap.is_finite())
            .filter_map(|r| Some((r.rods? as f64, r.median_gap)))
            .collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        let color = RGBColor(31, 119, 180).stroke_width(2);
        let drawn = if method == Ranker::Svd {
            chart.draw_series(LineSeries::new(line, color))?
        } else {
            chart.draw_series(DashedLineSeries::new(line, 7, 5, color))?
        };
        drawn
            .label(format!("median gap ({})", method_label(method)))
            .legend(move |(x, y)| {
                let dash = if method == Ranker::Svd { 20 } else { 8 };
                PathElement::new(vec![(x, y), (x + dash, y)], color)
            });
    }
    let grey = RankRule::SVD.grey;
    let red = RGBColor(214, 39, 40).stroke_width(2);
    chart
        .draw_series(DashedLineSeries::new(
            vec![(0.0, grey), (max_rods + 4.0, grey)],
            4,
            4,
            red,
        ))?
        .label("least gap of a decided rank")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 14))
        .draw()?;
    Ok(())
}
