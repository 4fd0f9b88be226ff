//! The chart of every variant's bias against truth (`rgc bias`): per box,
//! the paired difference of critical densities with its interval, so the
//! accuracy of each variant reads off at a glance, and whether it shrinks
//! with the box.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, colour, error_bars, legend, render, span, tick};
use crate::threshold::bias::VariantBias;
use crate::{Error, Result};

const SIZE: (u32, u32) = (1200, 760);

/// Draws the paired bias of every variant but truth against the box side,
/// variants side by side within a box, and a line at zero (truth).
pub fn bias_chart(out: &[VariantBias], title: &str, svg: &Path, png: &Path) -> Result<()> {
    let measured: Vec<&VariantBias> = out.iter().filter(|v| !v.boxes.is_empty()).collect();
    if measured.is_empty() {
        return Err(Error::Analysis(
            "no variant has a bias against truth to chart".into(),
        ));
    }
    let values = measured
        .iter()
        .flat_map(|v| v.boxes.iter())
        .flat_map(|b| [Some(b.bias.value), b.bias.lo, b.bias.hi])
        .flatten();
    if values.clone().any(|x| !x.is_finite()) {
        return Err(Error::Analysis(
            "a bias or its interval is not finite".into(),
        ));
    }
    render(&Bias { measured, title }, SIZE, svg, png)
}

struct Bias<'a> {
    measured: Vec<&'a VariantBias>,
    title: &'a str,
}

impl Chart for Bias<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let mut boxes: Vec<f64> = self
            .measured
            .iter()
            .flat_map(|v| v.boxes.iter().map(|b| b.box_len))
            .collect();
        boxes.sort_by(f64::total_cmp);
        boxes.dedup();
        let (ylo, yhi) = span(
            self.measured
                .iter()
                .flat_map(|v| v.boxes.iter())
                .flat_map(|b| {
                    [
                        b.bias.lo.unwrap_or(b.bias.value),
                        b.bias.hi.unwrap_or(b.bias.value),
                    ]
                })
                .chain([0.0]),
            0.08,
        );
        let n = self.measured.len() as f64;
        // Box k sits at x = k; variant i at an offset inside [-0.35, 0.35].
        let x = |k: usize, i: usize| k as f64 + 0.7 * ((i as f64 + 0.5) / n - 0.5);
        let mut chart = ChartBuilder::on(&root)
            .caption(self.title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(85)
            .build_cartesian_2d(-0.5..boxes.len() as f64 - 0.5, ylo..yhi)?;
        let labels = boxes.clone();
        chart
            .configure_mesh()
            .x_desc("box side L (rod lengths)")
            .y_desc("critical density minus truth's (rods per unit volume)")
            .x_labels(boxes.len() * 2 + 1)
            .x_label_formatter(&|v| {
                let k = v.round();
                if (v - k).abs() < 1e-9 && k >= 0.0 && (k as usize) < labels.len() {
                    tick(labels[k as usize])
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|v| tick(*v))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        chart.draw_series([PathElement::new(
            vec![(-0.5, 0.0), (boxes.len() as f64 - 0.5, 0.0)],
            BLACK.mix(0.6).stroke_width(1),
        )])?;
        for (i, v) in self.measured.iter().enumerate() {
            let c = colour(i);
            let points: Vec<(f64, f64)> = v
                .boxes
                .iter()
                .filter_map(|b| {
                    let k = boxes.iter().position(|&l| l == b.box_len)?;
                    Some((x(k, i), b.bias.value))
                })
                .collect();
            error_bars(
                &mut chart,
                v.boxes.iter().filter_map(|b| {
                    let k = boxes.iter().position(|&l| l == b.box_len)?;
                    Some((x(k, i), b.bias.lo?, b.bias.hi?))
                }),
                c.to_rgba(),
                4,
            )?;
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 6, c.filled())))?
                .label(format!(
                    "{}{}",
                    v.label,
                    v.false_span_share.map_or(String::new(), |s| format!(
                        " (false spans {:.1}%)",
                        100.0 * s
                    ))
                ))
                .legend(move |(px, py)| Circle::new((px + 10, py), 6, c.filled()));
        }
        legend(&mut chart, SeriesLabelPosition::LowerRight)
    }
}
