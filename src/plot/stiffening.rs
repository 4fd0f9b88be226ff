//! The stiffening curve: the shear and bulk moduli against the density,
//! beside the largest true cluster's share of the rods, one colour per box,
//! with the thresholds of given studies marked (truth's, 3D-RGC's: where an
//! experiment would see stiffening if each were right).

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, RHO, colour, error_bars, legend, log_ticks, render, span};
use crate::Result;
use crate::threshold::stiffening::{GridPoint, Mean, StiffeningSummary};

/// Pixel size of the chart.
const SIZE: (u32, u32) = (2100, 600);

/// Draws the density grids of `summaries` as `svg` and `png`: left, G
/// (filled) and K (open) in `k / L_rod` with 95% intervals; middle, the
/// same on a log axis, where the rise just above the threshold shows (a
/// power law with a large exponent looks flat on the linear one until far
/// above it); right, the largest true cluster's share of the rods; `marks`
/// (label, density) as vertical lines on all three.
pub fn stiffening_chart(
    summaries: &[StiffeningSummary],
    marks: &[(String, f64)],
    svg: &Path,
    png: &Path,
) -> Result<()> {
    render(&Stiffening { summaries, marks }, SIZE, svg, png)
}

struct Stiffening<'a> {
    summaries: &'a [StiffeningSummary],
    marks: &'a [(String, f64)],
}

impl Chart for Stiffening<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let root = root.titled(
            "Stiffening: the moduli and the largest true cluster against the density",
            ("sans-serif", 26),
        )?;
        let third = SIZE.0 / 3;
        let (linear, rest) = root.split_horizontally(third);
        let (log, cluster) = rest.split_horizontally(third);
        self.panel(&linear, Panel::Moduli)?;
        self.log_panel(&log)?;
        self.panel(&cluster, Panel::Cluster)?;
        root.present()
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Panel {
    Moduli,
    Cluster,
}

impl Panel {
    /// The series of a grid point: G and K, or the cluster's share.
    fn values(self, p: &GridPoint) -> Vec<Option<(f64, f64, f64)>> {
        match self {
            Panel::Moduli => vec![interval(p.shear), interval(p.bulk)],
            Panel::Cluster => vec![interval(p.largest_share)],
        }
    }
}

/// A mean and its interval as (value, low, high).
fn interval(m: Option<Mean>) -> Option<(f64, f64, f64)> {
    m.map(|m| {
        let h = m.half_width.unwrap_or(0.0);
        (m.mean, m.mean - h, m.mean + h)
    })
}

impl Stiffening<'_> {
    fn points(&self) -> impl Iterator<Item = &GridPoint> {
        self.summaries.iter().flat_map(|s| &s.grid)
    }

    /// The densities' axis, the marks included.
    fn densities(&self) -> (f64, f64) {
        span(
            self.points()
                .map(|p| p.density)
                .chain(self.marks.iter().map(|m| m.1)),
            0.05,
        )
    }

    fn panel<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, panel: Panel) -> Drawn<DB> {
        let top = self
            .points()
            .flat_map(|p| panel.values(p))
            .flatten()
            .map(|v| v.2)
            .fold(f64::MIN_POSITIVE, f64::max)
            * 1.1;
        let (lo, hi) = self.densities();
        let (caption, y_desc) = match panel {
            Panel::Moduli => (
                "G (filled) and K (open), Voigt averages",
                "modulus, k / L_rod",
            ),
            Panel::Cluster => ("the largest true rigid cluster", "share of the rods"),
        };
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(lo..hi, 0.0..top)?;
        chart
            .configure_mesh()
            .x_desc(format!("density, {RHO}"))
            .y_desc(y_desc)
            .label_style(("sans-serif", 14))
            .draw()?;
        self.series(&mut chart, panel, 0.0, top)
    }

    /// G and K on a log axis: the positive means only (below the threshold
    /// the moduli are exactly zero), each interval cut at the axis.
    fn log_panel<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        let positive: Vec<(f64, f64, f64)> = self
            .points()
            .flat_map(|p| Panel::Moduli.values(p))
            .flatten()
            .filter(|v| v.0 > 0.0)
            .collect();
        let y0 = positive.iter().map(|v| v.0).fold(1.0, f64::min) * 0.3;
        let y1 = positive.iter().map(|v| v.2).fold(y0 * 10.0, f64::max) * 2.0;
        let (lo, hi) = self.densities();
        let mut chart = ChartBuilder::on(area)
            .caption("the same on a log axis", ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                lo..hi,
                (y0..y1).log_scale().with_key_points(log_ticks(y0, y1)),
            )?;
        chart
            .configure_mesh()
            .x_desc(format!("density, {RHO}"))
            .y_desc("modulus, k / L_rod")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()?;
        self.series(&mut chart, Panel::Moduli, y0, y1)
    }

    /// The marks, then each summary's series with their intervals, on an
    /// axis from `bottom` to `top` (values below it left out, intervals cut).
    fn series<'a, DB, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, Y>>,
        panel: Panel,
        bottom: f64,
        top: f64,
    ) -> Drawn<DB>
    where
        DB: DrawingBackend + 'a,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        for (mark, grey) in self.marks.iter().zip([0u8, 110, 170].iter().cycle()) {
            let c = RGBColor(*grey, *grey, *grey);
            chart
                .draw_series([PathElement::new(
                    vec![(mark.1, bottom), (mark.1, top)],
                    c.stroke_width(2),
                )])?
                .label(format!("{} ({:.2})", mark.0, mark.1))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                });
        }
        for (i, s) in self.summaries.iter().enumerate() {
            let c = colour(i);
            let series = if panel == Panel::Moduli { 2 } else { 1 };
            for k in 0..series {
                let filled = k == 0;
                let pts: Vec<(f64, (f64, f64, f64))> = s
                    .grid
                    .iter()
                    .filter_map(|p| Some((p.density, panel.values(p)[k]?)))
                    .filter(|(_, v)| v.0 >= bottom)
                    .collect();
                error_bars(
                    chart,
                    pts.iter().map(|(x, v)| (*x, v.1.max(bottom), v.2)),
                    c.to_rgba(),
                    4,
                )?;
                chart.draw_series(LineSeries::new(
                    pts.iter().map(|(x, v)| (*x, v.0)),
                    c.stroke_width(if filled { 2 } else { 1 }),
                ))?;
                let style = if filled {
                    c.filled()
                } else {
                    c.stroke_width(2)
                };
                let series =
                    chart.draw_series(pts.iter().map(|(x, v)| Circle::new((*x, v.0), 5, style)))?;
                if k == 0 {
                    series
                        .label(format!("gamma {}, box {}", s.gamma, s.box_len))
                        .legend(move |(x, y)| Circle::new((x + 8, y), 5, c.filled()));
                }
            }
        }
        legend(chart, SeriesLabelPosition::UpperLeft)
    }
}
