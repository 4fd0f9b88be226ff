//! Charts (SVG, and PNG with an embedded font): the float-rank stability
//! study and the finite-size scaling of the thresholds.
//!
//! Text is rendered with a font compiled into the binary (Ubuntu Light from
//! `epaint_default_fonts`, through plotters' `ab_glyph` feature), so PNG
//! output needs no system font library: it works on any machine with cargo.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::{Error, Result};

mod stability;
mod threshold;

pub use stability::stability_chart;
pub use threshold::{threshold_charts, threshold_vs_vex};

/// What drawing on a backend returns.
type Drawn<DB> = std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A chart that draws the same picture on any backend.
trait Chart {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB>;
}

/// Draws `chart` as `svg` and `png` of `size` pixels, so both files always
/// show the same picture; a drawing error names the file it concerns.
fn render(chart: &impl Chart, size: (u32, u32), svg: &Path, png: &Path) -> Result<()> {
    plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        epaint_default_fonts::UBUNTU_LIGHT,
    )
    .map_err(|_| Error::Parameter("the embedded chart font does not load".into()))?;
    let fail = |path: &Path, e: String| Error::io(path, std::io::Error::other(e));
    chart
        .draw(SVGBackend::new(svg, size).into_drawing_area())
        .map_err(|e| fail(svg, e.to_string()))?;
    chart
        .draw(BitMapBackend::new(png, size).into_drawing_area())
        .map_err(|e| fail(png, e.to_string()))?;
    Ok(())
}
