//! Charts of the finite-size scaling (the paper's Fig. "scaling"): spanning
//! probability per box size, the scaling collapse, the extrapolation of
//! `rho_x(L)`, the width `Delta rho(L)`, and the threshold against `1/V_ex`.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{
    Chart, Drawn, RHO, colour, error_bars, legend, log_ticks, render, show, span, tick,
};
use crate::threshold::aspect::{PowerLaw, VexFit};
use crate::threshold::fss::{self, BoxData, Estimate, Fss, Protocol};
use crate::threshold::report::StudyReport;
use crate::threshold::sequence::Kind;
use crate::threshold::study::StudySpec;
use crate::{Error, Result};

/// Pixel size of each threshold chart.
const SIZE: (u32, u32) = (1200, 850);

/// The charts of a written study, titled by what it measured.
pub fn study_charts(spec: &StudySpec, report: &StudyReport, dir: &Path) -> Result<Vec<PathBuf>> {
    let title = format!(
        "{}, gamma {}, {:?}{}, K={}, {:?}, {:?}",
        match spec.kind {
            Kind::Contact => "contact",
            Kind::Rigid => "rigidity",
            Kind::Truth => "true rigidity",
        },
        spec.gamma,
        spec.rules,
        if spec.motifs.rules > 0 {
            format!(" + {} motifs", spec.motifs.rules)
        } else {
            String::new()
        },
        spec.runs,
        spec.criterion,
        spec.method,
    )
    .to_lowercase()
    .replace("k=", "K=");
    threshold_charts(&report.summary.fss, &report.data, &title, dir)
}

/// Writes `pi`, `collapse`, `rho_x` and `delta_rho`, each as SVG and PNG,
/// into `dir` (created if missing); returns the paths written.
pub fn threshold_charts(
    fss: &Fss,
    data: &[BoxData],
    title: &str,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let curves: Vec<Vec<(f64, f64, usize)>> = fss
        .boxes
        .iter()
        .map(|b| {
            data.iter()
                .find(|d| d.box_len == b.box_len)
                .map(|d| fss::pi_curve(d, fss.protocol))
                .unwrap_or_default()
        })
        .collect();
    let mut written = Vec::new();
    let mut write = |name: &str, chart: &dyn Fn(&Path, &Path) -> Result<()>| -> Result<()> {
        let (svg, png) = (
            dir.join(format!("{name}.svg")),
            dir.join(format!("{name}.png")),
        );
        chart(&svg, &png)?;
        written.extend([svg, png]);
        Ok(())
    };
    let pi = Pi {
        fss,
        curves: &curves,
        title,
        collapse: false,
    };
    write("pi", &|s, p| render(&pi, SIZE, s, p))?;
    let collapse = Pi {
        collapse: true,
        ..pi
    };
    write("collapse", &|s, p| render(&collapse, SIZE, s, p))?;
    write("rho_x", &|s, p| render(&RhoX { fss, title }, SIZE, s, p))?;
    write("delta_rho", &|s, p| {
        render(&Width { fss, title }, SIZE, s, p)
    })?;
    Ok(written)
}

/// `pi(rho, L)` with the fitted logistics, against `rho` or against the
/// collapse variable `(rho - rho_c) L^(1/nu)`.
#[derive(Clone, Copy)]
struct Pi<'a> {
    fss: &'a Fss,
    curves: &'a [Vec<(f64, f64, usize)>],
    title: &'a str,
    collapse: bool,
}

impl Pi<'_> {
    fn abscissa(&self, box_len: f64, rho: f64) -> f64 {
        if self.collapse {
            (rho - self.fss.threshold.value) / self.fss.scaled(box_len)
        } else {
            rho
        }
    }
}

impl Chart for Pi<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let fss = self.fss;
        // The fits set the range: nested curves have a point per sequence
        // and collapsed grids reach far out, both would squeeze the transition.
        let grid = fss.protocol == Protocol::Fixed && !self.collapse;
        let xs = fss.boxes.iter().zip(self.curves).flat_map(|(b, c)| {
            c.iter()
                .filter(move |_| grid)
                .map(move |p| self.abscissa(b.box_len, p.0))
                .chain([b.mu - 5.0 * b.s, b.mu + 5.0 * b.s].map(|r| self.abscissa(b.box_len, r)))
        });
        let (x0, x1) = span(xs, 0.02);
        let inside = |x: f64| x >= x0 && x <= x1;
        let (caption, x_desc) = if self.collapse {
            (
                format!(
                    "{}: scaling collapse, π against (ρ − ρc) L^(1/ν)",
                    self.title
                ),
                format!(
                    "(ρ − ρc) L^(1/ν)   with ρc = {:.3}, ν = {:.3}   (ρ in {RHO}, L in rod lengths)",
                    fss.threshold.value, fss.nu.value
                ),
            )
        } else {
            (
                format!(
                    "{}: spanning probability π(ρ, L) with logistic fits",
                    self.title
                ),
                format!("number density ρ ({RHO})"),
            )
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(caption, ("sans-serif", 26))
            .margin(16)
            .x_label_area_size(55)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, -0.02..1.02)?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("spanning probability π(ρ, L)")
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        let dense = self.curves.iter().map(Vec::len).max().unwrap_or(0) > 60;
        for (i, (b, curve)) in fss.boxes.iter().zip(self.curves).enumerate() {
            let c = colour(i);
            let l = b.box_len;
            if fss.protocol == Protocol::Fixed {
                let bars = curve.iter().map(|&(rho, p, n)| {
                    let e = 1.96 * (p * (1.0 - p) / n as f64).sqrt();
                    (self.abscissa(l, rho), (p - e).max(0.0), (p + e).min(1.0))
                });
                error_bars(&mut chart, bars, c.mix(0.5), 3)?;
            }
            let size = if dense { 2 } else { 4 };
            chart
                .draw_series(
                    curve
                        .iter()
                        .map(|&(rho, p, _)| (self.abscissa(l, rho), p))
                        .filter(|p| inside(p.0))
                        .map(|p| Circle::new(p, size, c.filled())),
                )?
                .label(format!(
                    "L = {l} ({} sequences): μ = {:.3}, Δρ = {:.3}",
                    b.sequences, b.mu, b.delta_rho
                ))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
            let fit = b.logistic();
            let (r0, r1) = (b.mu - 6.0 * b.s, b.mu + 6.0 * b.s);
            let line = (0..=300).map(|k| {
                let rho = r0 + (r1 - r0) * k as f64 / 300.0;
                (self.abscissa(l, rho), fit.cdf(rho))
            });
            let line: Vec<(f64, f64)> = line.filter(|p| inside(p.0)).collect();
            chart.draw_series(LineSeries::new(line, c.stroke_width(2)))?;
        }
        if !self.collapse {
            let rc = fss.threshold.value;
            let grey = BLACK.mix(0.6).stroke_width(2);
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(rc, -0.02), (rc, 1.02)],
                    8,
                    6,
                    grey,
                ))?
                .label(format!("threshold ρc = {}", show(&fss.threshold, 3)))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey));
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present()
    }
}

/// `rho_x(L)` against `L^(-1/nu)` with the common-intercept lines.
struct RhoX<'a> {
    fss: &'a Fss,
    title: &'a str,
}

impl Chart for RhoX<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let fss = self.fss;
        let t: Vec<f64> = fss.boxes.iter().map(|b| fss.scaled(b.box_len)).collect();
        let t_max = t.iter().copied().fold(0.0, f64::max) * 1.1;
        let ys = fss
            .boxes
            .iter()
            .flat_map(|b| {
                b.rho_x
                    .iter()
                    .copied()
                    .chain(b.rho_x_intervals.iter().flat_map(|i| [i.0, i.1]))
            })
            .chain([fss.threshold.value])
            .chain(fss.threshold.lo)
            .chain(fss.threshold.hi);
        let (y0, y1) = span(ys, 0.06);
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "{}: ρx(L) extrapolated to L = ∞ with a common intercept",
                    self.title
                ),
                ("sans-serif", 26),
            )
            .margin(16)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(-0.03 * t_max..t_max, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(format!(
                "L^(−1/ν)   with ν = {:.3}   (L in rod lengths)",
                fss.nu.value
            ))
            .y_desc(format!("ρx(L), where π(ρx, L) = x   ({RHO})"))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        for (&ti, b) in t.iter().zip(&fss.boxes) {
            chart.draw_series(DashedLineSeries::new(
                vec![(ti, y0), (ti, y1)],
                3,
                5,
                BLACK.mix(0.15).stroke_width(1),
            ))?;
            chart.draw_series([Text::new(
                format!("L = {}", b.box_len),
                (ti, y1 - 0.02 * (y1 - y0)),
                ("sans-serif", 15).into_font(),
            )])?;
        }
        for (j, (x, slope)) in fss.xs.iter().zip(&fss.slopes).enumerate() {
            let c = colour(j);
            let rc = fss.threshold.value;
            chart.draw_series(LineSeries::new(
                vec![(0.0, rc), (t_max, rc + slope * t_max)],
                c.stroke_width(2),
            ))?;
            let bars = fss.boxes.iter().zip(&t).filter_map(|(b, &ti)| {
                let i = b.rho_x_intervals.get(j)?;
                Some((ti, i.0, i.1))
            });
            error_bars(&mut chart, bars, c.to_rgba(), 4)?;
            chart
                .draw_series(
                    fss.boxes
                        .iter()
                        .zip(&t)
                        .map(|(b, &ti)| Circle::new((ti, b.rho_x[j]), 5, c.filled())),
                )?
                .label(format!("x = {x}: slope {slope:.3}"))
                .legend(move |(px, py)| Circle::new((px + 10, py), 5, c.filled()));
        }
        let th = fss.threshold;
        if let (Some(lo), Some(hi)) = (th.lo, th.hi) {
            error_bars(&mut chart, [(0.0, lo, hi)], BLACK.to_rgba(), 7)?;
        }
        chart
            .draw_series([Cross::new((0.0, th.value), 8, BLACK.stroke_width(3))])?
            .label(format!(
                "threshold ρc = {} ({:.0}% interval), R² = {:.4}",
                show(&th, 3),
                100.0 * fss.confidence,
                fss.r2_extrapolation
            ))
            .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(3)));
        legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        root.present()
    }
}

/// `Delta rho` against `L` on log-log axes with the fitted power law.
struct Width<'a> {
    fss: &'a Fss,
    title: &'a str,
}

impl Chart for Width<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let fss = self.fss;
        let (l0, l1) = span(fss.boxes.iter().map(|b| b.box_len), 0.0);
        let (d0, d1) = span(
            fss.boxes.iter().flat_map(|b| {
                [b.delta_rho]
                    .into_iter()
                    .chain(b.delta_rho_interval.iter().flat_map(|i| [i.0, i.1]))
            }),
            0.0,
        );
        let (l0, l1, d0, d1) = (l0 / 1.15, l1 * 1.15, d0 / 1.3, d1 * 1.3);
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("{}: width of the transition Δρ(L) = s π / √3", self.title),
                ("sans-serif", 26),
            )
            .margin(16)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(
                (l0..l1)
                    .log_scale()
                    .with_key_points(fss.boxes.iter().map(|b| b.box_len).collect()),
                (d0..d1).log_scale().with_key_points(log_ticks(d0, d1)),
            )?;
        chart
            .configure_mesh()
            .x_desc("box length L (rod lengths), log scale")
            .y_desc(format!("Δρ ({RHO}), log scale"))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        let c = colour(0);
        let red = colour(3);
        let (f, nu) = (fss.delta_rho_prefactor, fss.nu.value);
        let line = (0..=100).map(|k| {
            let l = l0 * (l1 / l0).powf(k as f64 / 100.0);
            (l, f * l.powf(-1.0 / nu))
        });
        chart
            .draw_series(LineSeries::new(line, red.stroke_width(2)))?
            .label(format!(
                "fit Δρ = {f:.3} L^(−1/ν), ν = {} ({:.0}% interval), R² = {:.4}",
                show(&fss.nu, 3),
                100.0 * fss.confidence,
                fss.r2_nu
            ))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red.stroke_width(2)));
        let bars = fss
            .boxes
            .iter()
            .filter_map(|b| Some((b.box_len, b.delta_rho_interval?.0, b.delta_rho_interval?.1)));
        error_bars(&mut chart, bars, c.to_rgba(), 5)?;
        chart
            .draw_series(
                fss.boxes
                    .iter()
                    .map(|b| Circle::new((b.box_len, b.delta_rho), 6, c.filled())),
            )?
            .label("Δρ(L) of the logistic fit")
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present()
    }
}

/// Draws thresholds against `1/V_ex` on log-log axes: each series (one kind
/// of study, with its label) in its own colour, with its intervals, its fit
/// at exponent 1 (dashed) and its free power law.
pub fn threshold_vs_vex(
    series: &[VexSeries<'_>],
    title: &str,
    svg: &Path,
    png: &Path,
) -> Result<()> {
    if series.iter().all(|s| s.points.is_empty()) {
        return Err(Error::Parameter(
            "no thresholds to plot against 1/V_ex".into(),
        ));
    }
    render(&Vex { title, series }, SIZE, svg, png)
}

/// One kind of threshold on the `1/V_ex` chart.
pub struct VexSeries<'a> {
    pub label: &'a str,
    /// `(gamma, 1/V_ex, threshold)`.
    pub points: &'a [(f64, f64, Estimate)],
    pub fit: &'a VexFit,
}

struct Vex<'a> {
    title: &'a str,
    series: &'a [VexSeries<'a>],
}

impl Chart for Vex<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let points = || self.series.iter().flat_map(|s| s.points.iter());
        let (x0, x1) = span(points().map(|p| p.1), 0.0);
        let (y0, y1) = span(
            points()
                .flat_map(|p| [Some(p.2.value), p.2.lo, p.2.hi])
                .flatten(),
            0.0,
        );
        let (x0, x1, y0, y1) = (x0 / 1.6, x1 * 1.6, y0 / 1.6, y1 * 1.6);
        let mut chart = ChartBuilder::on(&root)
            .caption(self.title, ("sans-serif", 26))
            .margin(16)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(
                (x0..x1).log_scale().with_key_points(log_ticks(x0, x1)),
                (y0..y1).log_scale().with_key_points(log_ticks(y0, y1)),
            )?;
        chart
            .configure_mesh()
            .x_desc("inverse excluded volume 1/V_ex (per rod length cubed), log scale")
            .y_desc(format!("threshold ρc ({RHO}), log scale"))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()?;
        let ends = |f: &dyn Fn(f64) -> f64| vec![(x0, f(x0)), (x1, f(x1))];
        for (i, s) in self.series.iter().enumerate() {
            let c = colour(i);
            let dashed = c.stroke_width(2);
            let k = s.fit.fixed;
            let k_text = s.fit.fixed_interval.map_or(format!("{k:.3}"), |(lo, hi)| {
                format!("{k:.3} [{lo:.3}, {hi:.3}]")
            });
            chart
                .draw_series(DashedLineSeries::new(ends(&|x| k * x), 4, 6, dashed))?
                .label(format!(
                    "{}: ρc = {k_text} / V_ex (exponent fixed to 1)",
                    s.label
                ))
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (6, 0)], dashed)
                        + PathElement::new(vec![(12, 0), (18, 0)], dashed)
                });
            if let Some(PowerLaw {
                a,
                m,
                m_interval,
                r2,
            }) = s.fit.free
            {
                let line = c.mix(0.45).stroke_width(3);
                let m_text = m_interval.map_or(format!("{m:.3}"), |(lo, hi)| {
                    format!("{m:.3} [{lo:.3}, {hi:.3}]")
                });
                chart
                    .draw_series(LineSeries::new(ends(&|x| a * x.powf(m)), line))?
                    .label(format!(
                        "{}: ρc = {a:.3} (1/V_ex)^m, m = {m_text}, R² = {r2:.4}",
                        s.label
                    ))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], line));
            }
            let bars = s
                .points
                .iter()
                .filter_map(|p| Some((p.1, p.2.lo?, p.2.hi?)));
            error_bars(&mut chart, bars, c.to_rgba(), 5)?;
            chart
                .draw_series(
                    s.points
                        .iter()
                        .map(|p| Circle::new((p.1, p.2.value), 6, c.filled())),
                )?
                .label(format!("{}: threshold with its interval", s.label))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
        }
        // Each aspect ratio is named once, under its first point.
        let mut named: Vec<f64> = Vec::new();
        let labelled: Vec<_> = points()
            .filter(|p| {
                let fresh = !named.contains(&p.0);
                named.push(p.0);
                fresh
            })
            .collect();
        chart.draw_series(labelled.iter().map(|p| {
            Text::new(
                format!("γ = {}", p.0),
                (p.1 * 1.06, p.2.value * 0.9),
                ("sans-serif", 16).into_font(),
            )
        }))?;
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present()
    }
}
