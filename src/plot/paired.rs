//! The chart of paired shifts (`rgc paired`): each study's critical density
//! against its reference's on the same sequences, per box, as a share of
//! the reference, so that shifts at different aspect ratios compare.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, colour, error_bars, legend, render, span, tick};
use crate::threshold::paired::Pairing;
use crate::{Error, Result};

const SIZE: (u32, u32) = (1100, 700);

/// Draws the shift of every pairing per box (95% intervals) in percent of
/// the reference's mean critical density, with a line at zero.
pub fn paired_chart(pairings: &[Pairing], svg: &Path, png: &Path) -> Result<()> {
    let values = pairings
        .iter()
        .flat_map(|p| p.comparison.boxes.iter())
        .flat_map(|d| [Some(d.relative.value), d.relative.lo, d.relative.hi])
        .flatten();
    if values.clone().any(|x| !x.is_finite()) {
        return Err(Error::Analysis(
            "a paired shift or its interval is not finite".into(),
        ));
    }
    render(&Paired(pairings), SIZE, svg, png)
}

struct Paired<'a>(&'a [Pairing]);

impl Chart for Paired<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let boxes = || self.0.iter().flat_map(|p| p.comparison.boxes.iter());
        let (lo_l, hi_l) = span(boxes().filter_map(|d| d.box_len), 0.0);
        let (ylo, yhi) = span(
            boxes()
                .flat_map(|d| [d.relative.lo, d.relative.hi, Some(d.relative.value)])
                .flatten()
                .map(|v| 100.0 * v)
                .chain([0.0]),
            0.08,
        );
        let n = self.0.len() as f64;
        // Pairing i sits at an offset inside [-0.2, 0.2] of its box.
        let x = |l: f64, i: usize| l + 0.4 * ((i as f64 + 0.5) / n - 0.5);
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Paired shift of the critical density, per box",
                ("sans-serif", 22),
            )
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(lo_l - 0.5..hi_l + 0.5, ylo..yhi)?;
        chart
            .configure_mesh()
            .x_desc("box side L (rod lengths)")
            .y_desc("shift, % of the reference's critical density")
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        chart.draw_series([PathElement::new(
            vec![(lo_l - 0.5, 0.0), (hi_l + 0.5, 0.0)],
            BLACK.mix(0.6).stroke_width(1),
        )])?;
        for (i, p) in self.0.iter().enumerate() {
            let c = colour(i);
            let per_box = || {
                p.comparison
                    .boxes
                    .iter()
                    .filter_map(move |d| Some((x(d.box_len?, i), d)))
            };
            error_bars(
                &mut chart,
                per_box()
                    .filter_map(|(x, d)| Some((x, 100.0 * d.relative.lo?, 100.0 * d.relative.hi?))),
                c.to_rgba(),
                4,
            )?;
            let all = &p.comparison.all;
            chart
                .draw_series(
                    per_box()
                        .map(|(x, d)| Circle::new((x, 100.0 * d.relative.value), 6, c.filled())),
                )?
                .label(format!(
                    "{} (gamma {}): {:+.1}% over all boxes",
                    p.label(),
                    p.comparison.gamma,
                    100.0 * all.relative.value
                ))
                .legend(move |(px, py)| Circle::new((px + 10, py), 6, c.filled()));
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}
