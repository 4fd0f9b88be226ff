//! The forced-plane scan: how much of the well-held network the largest
//! forced plane holds, against the mean contact number `rho V_ex` so that
//! every aspect ratio shares one axis, with the committed rigidity
//! thresholds marked on it.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, colour, error_bars, legend, render, span};
use crate::threshold::planes::GammaScan;
use crate::{Error, Result};

const SIZE: (u32, u32) = (1200, 850);

/// Draws `scans` as `svg` and `png`: per gamma, the mean fraction of heavy
/// rods in the largest forced class (solid, with standard errors), the
/// share of unrealizable systems (dashed), and the committed rigidity
/// threshold (a vertical dashed line) where one was found.
pub fn forced_planes_chart(scans: &[GammaScan], svg: &Path, png: &Path) -> Result<()> {
    if scans.iter().all(|s| s.points.is_empty()) {
        return Err(Error::Parameter("no forced-plane scan to plot".into()));
    }
    render(&Planes { scans }, SIZE, svg, png)
}

struct Planes<'a> {
    scans: &'a [GammaScan],
}

impl Chart for Planes<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let rigid = |s: &GammaScan| s.references.rigidity.as_ref().map(|t| t.contact_number);
        let (x0, x1) = span(
            self.scans
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.contact_number).chain(rigid(s))),
            0.03,
        );
        // Room above the data for the legend, so that it hides no curve or marker.
        let high = self
            .scans
            .iter()
            .flat_map(|s| &s.points)
            .map(|p| p.mean_fraction + p.se_fraction)
            .fold(1.0, f64::max)
            + 0.02;
        let top = high + 0.45;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Forced planes of the line model: largest class against the mean contact number",
                ("sans-serif", 26),
            )
            .margin(16)
            .x_label_area_size(55)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, -0.02..top)?;
        chart
            .configure_mesh()
            .x_desc(
                "mean contact number ρ V_ex (ρ in rods per unit volume, V_ex the excluded volume)",
            )
            .y_desc("fraction / share")
            // The band above 1 holds the legend, not values.
            .y_label_formatter(&|v| {
                if *v <= 1.0 + 1e-9 {
                    format!("{v:.1}")
                } else {
                    String::new()
                }
            })
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        let grey = BLACK.mix(0.35).stroke_width(1);
        chart.draw_series(DashedLineSeries::new(
            vec![(x0, 0.5), (x1, 0.5)],
            3,
            5,
            grey,
        ))?;
        for (i, s) in self.scans.iter().enumerate() {
            let c = colour(i);
            let solid = c.stroke_width(3);
            let n_rods = |k: usize| s.points.get(k).map_or(0.0, |p| p.mean_rods);
            let bars = s.points.iter().map(|p| {
                (
                    p.contact_number,
                    p.mean_fraction - p.se_fraction,
                    p.mean_fraction + p.se_fraction,
                )
            });
            error_bars(&mut chart, bars, c.mix(0.6), 3)?;
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().map(|p| (p.contact_number, p.mean_fraction)),
                    solid,
                ))?
                .label(format!(
                    "γ = {}, L = {} ({:.0} to {:.0} rods, {} seeds): heavy rods in the largest class",
                    s.spec.gamma,
                    s.spec.box_len,
                    n_rods(0),
                    n_rods(s.points.len().saturating_sub(1)),
                    s.spec.seeds
                ))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], solid));
            chart.draw_series(
                s.points
                    .iter()
                    .map(|p| Circle::new((p.contact_number, p.mean_fraction), 4, c.filled())),
            )?;
            let dashed = c.stroke_width(2);
            chart
                .draw_series(DashedLineSeries::new(
                    s.points
                        .iter()
                        .map(|p| (p.contact_number, p.unrealizable_share)),
                    10,
                    6,
                    dashed,
                ))?
                .label(format!(
                    "γ = {}: share of systems forced flat",
                    s.spec.gamma
                ))
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (8, 0)], dashed)
                        + PathElement::new(vec![(13, 0), (20, 0)], dashed)
                });
            if let Some(t) = &s.references.rigidity {
                let x = t.contact_number;
                let thin = c.mix(0.8).stroke_width(2);
                chart
                    .draw_series(DashedLineSeries::new(
                        vec![(x, -0.02), (x, high)],
                        3,
                        4,
                        thin,
                    ))?
                    .label(format!(
                        "γ = {}: rigidity threshold ρc V_ex = {x:.3} (ρc = {:.2})",
                        s.spec.gamma, t.density
                    ))
                    .legend(move |(px, py)| {
                        PathElement::new(vec![(px + 10, py - 7), (px + 10, py + 7)], thin)
                    });
            }
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present()
    }
}
