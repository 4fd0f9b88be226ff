//! What every chart shares: the drawing trait, rendering to SVG and PNG,
//! legends, error bars, colours and ticks.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::output;
use crate::threshold::fss::Estimate;
use crate::{Error, Result};

/// What drawing on a backend returns.
pub(super) type Drawn<DB> =
    std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The series legend every chart uses: framed, on a pale ground, at `position`.
pub(super) fn legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Drawn<DB>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 16))
        .draw()
}

/// A chart that draws the same picture on any backend.
pub(super) trait Chart {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB>;
}

/// Draws `chart` as `svg` and `png` of `size` pixels, so both files always
/// show the same picture; a drawing error names the file it concerns. Each
/// file is drawn beside its target and renamed when complete.
pub(super) fn render(chart: &impl Chart, size: (u32, u32), svg: &Path, png: &Path) -> Result<()> {
    plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        epaint_default_fonts::UBUNTU_LIGHT,
    )
    .map_err(|_| Error::Parameter("the embedded chart font does not load".into()))?;
    let fail = |path: &Path, e: String| Error::io(path, std::io::Error::other(e));
    output::replace_with(svg, |tmp| {
        chart
            .draw(SVGBackend::new(tmp, size).into_drawing_area())
            .map_err(|e| fail(svg, e.to_string()))
    })?;
    output::replace_with(png, |tmp| {
        chart
            .draw(BitMapBackend::new(tmp, size).into_drawing_area())
            .map_err(|e| fail(png, e.to_string()))
    })
}

/// Colours of the series (matplotlib's tab10, then again).
pub(super) const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

pub(super) const RHO: &str = "rods per unit volume";

pub(super) fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// `value [lo, hi]` with three decimals, or the value alone.
pub(super) fn show(e: &Estimate, digits: usize) -> String {
    match (e.lo, e.hi) {
        (Some(lo), Some(hi)) => format!("{:.digits$} [{lo:.digits$}, {hi:.digits$}]", e.value),
        _ => format!("{:.digits$}", e.value),
    }
}

/// The smallest and largest of `values`, widened by `pad` of the span (or
/// by `pad` of the value when all are equal).
pub(super) fn span(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let w = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    (lo - pad * w, hi + pad * w)
}

/// Vertical error bars `(x, lo, hi)` with caps `cap` pixels wide (plotters'
/// own need a feature this crate does not enable).
pub(super) fn error_bars<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    bars: impl IntoIterator<Item = (f64, f64, f64)>,
    colour: RGBAColor,
    cap: i32,
) -> Drawn<DB>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let style = colour.stroke_width(2);
    for (x, lo, hi) in bars {
        chart.draw_series([PathElement::new(vec![(x, lo), (x, hi)], style)])?;
        chart.draw_series([lo, hi].map(|y| {
            EmptyElement::at((x, y)) + PathElement::new(vec![(-cap, 0), (cap, 0)], style)
        }))?;
    }
    Ok(())
}

/// Tick values of a log axis: 1-2-5 per decade, denser when the range is
/// short (plotters' own ticks leave a 5..10 range bare).
pub(super) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let decades = lo.log10().floor() as i32..=hi.log10().ceil() as i32;
    [
        &[1.0, 2.0, 5.0][..],
        &[1.0, 2.0, 3.0, 5.0],
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
    ]
    .iter()
    .map(|mantissas| {
        decades
            .clone()
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| *v >= lo && *v <= hi)
            .collect::<Vec<f64>>()
    })
    .find(|t| t.len() >= 4)
    .unwrap_or_else(|| vec![lo, hi])
}

/// A tick label without the float noise of `3 * 0.1`.
pub(super) fn tick(v: f64) -> String {
    format!("{}", (v * 1e9).round() / 1e9)
}
