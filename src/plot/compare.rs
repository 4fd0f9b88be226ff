//! Charts of the variants of a study against each other (`rgc compare`,
//! `rgc tradeoff`): how far each variant moves the threshold and `nu` from
//! the first, and how much accuracy each buys for its CPU time.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, TAU};
use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{Chart, Drawn, RHO, colour, error_bars, log_ticks, render, span, tick};
use crate::threshold::fss::Estimate;
use crate::threshold::tradeoff::Panel;
use crate::threshold::variants::VariantOutcome;
use crate::{Error, Result};

/// Pixel size of the comparison chart (two panels side by side).
const COMPARE_SIZE: (u32, u32) = (1500, 800);
/// Pixel size of the speed-accuracy chart (two panels and a legend strip).
const TRADEOFF_SIZE: (u32, u32) = (1700, 880);
/// Pixel size of the speed-accuracy chart across aspect ratios (a panel each).
const GAMMAS_SIZE: (u32, u32) = (2100, 820);
const MARGIN: i32 = 16;
/// Width of the y label area, which the category slots must leave free.
const Y_AREA: i32 = 85;
/// Size of a family's marker in the speed-accuracy chart (radius, pixels).
const MARKER: f64 = 6.5;

/// What drawing returns when it also yields a value.
type Drawing<DB, T> =
    std::result::Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Draws the threshold and `nu` of each variant with their intervals, side
/// by side, each point labelled with its relative difference to the first
/// variant, which a dashed line marks as the reference.
pub fn compare_chart(
    outcomes: &[VariantOutcome],
    title: &str,
    svg: &Path,
    png: &Path,
) -> Result<()> {
    check(outcomes, false)?;
    render(&Compare { outcomes, title }, COMPARE_SIZE, svg, png)
}

/// Draws (a) each variant's difference to the first (the exact truth in
/// `rgc tradeoff`): the paired difference of critical densities where there
/// is one, else of thresholds, with its interval, and (b) the width of the
/// threshold's interval, against CPU seconds, a colour and marker per
/// `family`, so that the cheapest variant of acceptable accuracy stands out.
pub fn speed_accuracy_chart(
    outcomes: &[VariantOutcome],
    title: &str,
    svg: &Path,
    png: &Path,
) -> Result<()> {
    check(outcomes, true)?;
    let mut families: Vec<&str> = Vec::new();
    for o in outcomes {
        if !families.contains(&o.family.as_str()) {
            families.push(&o.family);
        }
    }
    let chart = Tradeoff {
        outcomes,
        title,
        families,
    };
    render(&chart, TRADEOFF_SIZE, svg, png)
}

/// Draws panel (a) of [`speed_accuracy_chart`] for several aspect ratios
/// side by side, the bias in percent of each one's own truth threshold on
/// one shared scale, the colours and markers of the families shared too:
/// where motifs cannot see the rigidity, a family runs flat however much
/// CPU it spends.
pub fn speed_accuracy_gammas(panels: &[Panel], title: &str, svg: &Path, png: &Path) -> Result<()> {
    if panels.is_empty() {
        return Err(Error::Analysis("no aspect ratios to chart".into()));
    }
    let mut families: Vec<&str> = Vec::new();
    for p in panels {
        check(&p.outcomes, true)?;
        for o in &p.outcomes {
            if !families.contains(&o.family.as_str()) {
                families.push(&o.family);
            }
        }
    }
    render(
        &Gammas {
            panels,
            title,
            families,
        },
        GAMMAS_SIZE,
        svg,
        png,
    )
}

/// Refuses what would draw nothing or nonsense: no variants, an estimate
/// that is not finite, and (for a log axis) CPU time that is not positive.
fn check(outcomes: &[VariantOutcome], cpu: bool) -> Result<()> {
    if outcomes.is_empty() {
        return Err(Error::Analysis("no variants to chart".into()));
    }
    for o in outcomes {
        let (t, nu) = (&o.threshold, &o.nu);
        let values = [Some(t.value), t.lo, t.hi, Some(nu.value), nu.lo, nu.hi];
        if values
            .into_iter()
            .chain([o.interval_width])
            .chain(
                o.difference()
                    .into_iter()
                    .flat_map(|d| [Some(d.value), d.lo, d.hi]),
            )
            .flatten()
            .any(|v| !v.is_finite())
        {
            return Err(Error::Analysis(format!(
                "variant {:?}: its threshold, nu or an interval is not finite",
                o.label
            )));
        }
        if cpu && !(o.cpu_seconds > 0.0 && o.cpu_seconds.is_finite()) {
            return Err(Error::Analysis(format!(
                "variant {:?}: {} CPU seconds cannot go on a log axis",
                o.label, o.cpu_seconds
            )));
        }
    }
    Ok(())
}

/// A relative difference in percent with a typographic minus, with more
/// digits when it is small so that it never reads as a bare zero.
fn percent(d: f64) -> String {
    if !d.is_finite() {
        return "n/a".into();
    }
    let digits = if d.abs() < 1e-3 { 2 } else { 1 };
    format!("{:+.digits$}%", 100.0 * d).replace('-', "−")
}

/// `text` broken at spaces into lines no wider than `width` pixels (a word
/// longer than that keeps a line of its own).
fn wrap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    width: i32,
) -> Drawing<DB, Vec<String>> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        if let Some(last) = lines.last_mut() {
            let joined = format!("{last} {word}");
            if area.estimate_text_size(&joined, style)?.0 as i32 <= width {
                *last = joined;
                continue;
            }
        }
        lines.push(word.to_string());
    }
    Ok(lines)
}

/// The threshold and `nu` per variant.
struct Compare<'a> {
    outcomes: &'a [VariantOutcome],
    title: &'a str,
}

impl Chart for Compare<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let body = root
            .margin(8, 0, 0, 0)
            .titled(self.title, ("sans-serif", 26))?;
        let body = body.titled(
            "error bars: 95% intervals     dashed line and band: the first variant     \
             labels: difference to the first variant",
            ("sans-serif", 17).into_font().color(&BLACK.mix(0.7)),
        )?;
        let panels = body.split_evenly((1, 2));
        categories(
            &root,
            &panels[0],
            self.outcomes,
            &|o| o.threshold,
            "threshold ρc",
            &format!("threshold ρc ({RHO})"),
        )?;
        categories(
            &root,
            &panels[1],
            self.outcomes,
            &|o| o.nu,
            "correlation-length exponent ν",
            "exponent ν",
        )?;
        root.present()
    }
}

/// One panel of the comparison: `estimate` of each variant in a slot of
/// its own, the labels of the slots wrapped to fit their width.
fn categories<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    area: &DrawingArea<DB, Shift>,
    outcomes: &[VariantOutcome],
    estimate: &dyn Fn(&VariantOutcome) -> Estimate,
    caption: &str,
    y_desc: &str,
) -> Drawn<DB> {
    let n = outcomes.len();
    let end = n as f64 - 0.5;
    let reference = estimate(&outcomes[0]);
    let values = outcomes.iter().flat_map(|o| {
        let e = estimate(o);
        [Some(e.value), e.lo, e.hi]
    });
    let (y0, y1) = span(values.flatten(), 0.15);
    // The slots' width sets the wrapping of the labels, and the wrapping the
    // height of the label area, so both come before the chart.
    let slot = (area.dim_in_pixel().0 as i32 - Y_AREA - 2 * MARGIN) / n as i32;
    let size = if slot >= 110 { 17 } else { 15 };
    let style =
        TextStyle::from(("sans-serif", size).into_font()).pos(Pos::new(HPos::Center, VPos::Top));
    let labels = outcomes
        .iter()
        .map(|o| wrap(area, &o.label, &style, slot - 10))
        .collect::<Drawing<DB, Vec<_>>>()?;
    let line_height = size + 4;
    let rows = labels.iter().map(Vec::len).max().unwrap_or(1).max(1) as i32;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 22))
        .margin(MARGIN)
        .x_label_area_size(14 + rows * line_height)
        .y_label_area_size(Y_AREA)
        .build_cartesian_2d(-0.5..end, y0..y1)?;
    // Plotters' category axes cannot carry intervals: the ticks and labels
    // of the slots are drawn below.
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(0)
        .y_desc(y_desc)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .draw()?;
    let first = colour(0);
    if let (Some(lo), Some(hi)) = (reference.lo, reference.hi) {
        chart.draw_series([Rectangle::new(
            [(-0.5, lo), (end, hi)],
            first.mix(0.12).filled(),
        )])?;
    }
    chart.draw_series(DashedLineSeries::new(
        [(-0.5, reference.value), (end, reference.value)],
        8,
        6,
        first.mix(0.8).stroke_width(2),
    ))?;
    // Above right of the point, clear of the dashed line through the first.
    let tag =
        TextStyle::from(("sans-serif", 16).into_font()).pos(Pos::new(HPos::Left, VPos::Bottom));
    for (i, o) in outcomes.iter().enumerate() {
        let (e, c, x) = (estimate(o), colour(i), i as f64);
        if let (Some(lo), Some(hi)) = (e.lo, e.hi) {
            error_bars(&mut chart, [(x, lo, hi)], c.to_rgba(), 8)?;
        }
        chart.draw_series([Circle::new((x, e.value), 6, c.filled())])?;
        let text = match i {
            0 if slot >= 100 => "reference".to_string(),
            0 => "ref.".to_string(),
            _ => percent((e.value - reference.value) / reference.value),
        };
        chart.draw_series([
            EmptyElement::at((x, e.value)) + Text::new(text, (8, -3), tag.clone())
        ])?;
    }
    let bottom = chart.plotting_area().get_pixel_range().1.end;
    for (i, lines) in labels.iter().enumerate() {
        let (x, _) = chart.backend_coord(&(i as f64, y0));
        root.draw(&PathElement::new(
            [(x, bottom), (x, bottom + 5)],
            BLACK.stroke_width(1),
        ))?;
        for (k, line) in lines.iter().enumerate() {
            root.draw_text(line, &style, (x, bottom + 9 + k as i32 * line_height))?;
        }
    }
    Ok(())
}

/// A label's or an obstacle's box in backend pixels.
#[derive(Clone, Copy, Debug)]
struct Rect {
    x0: i32,
    y0: i32,
    x1: i32,
    y1: i32,
}

impl Rect {
    fn around((x, y): (i32, i32), rx: i32, ry: i32) -> Self {
        Rect {
            x0: x - rx,
            y0: y - ry,
            x1: x + rx,
            y1: y + ry,
        }
    }

    fn overlap(&self, o: &Rect) -> i64 {
        let w = (self.x1.min(o.x1) - self.x0.max(o.x0)).max(0);
        let h = (self.y1.min(o.y1) - self.y0.max(o.y0)).max(0);
        i64::from(w) * i64::from(h)
    }

    fn area(&self) -> i64 {
        i64::from(self.x1 - self.x0) * i64::from(self.y1 - self.y0)
    }
}

/// Where a label of `size` goes beside the point `p`: the first of a
/// sequence of positions, near ones first, that overlaps no obstacle and
/// stays inside `bounds`; else the one that overlaps least. Returns the box
/// and whether it is far enough from the point to want a leader line.
fn place(p: (i32, i32), (w, h): (i32, i32), obstacles: &[Rect], bounds: &Rect) -> (Rect, bool) {
    let g = MARKER as i32 + 4;
    let (far, farther) = (h + 6, 2 * h + 10);
    let offsets = [
        (g, -h / 2),
        (g, -h - 1),
        (g, 1),
        (-g - w, -h / 2),
        (-w / 2, -g - h),
        (-w / 2, g),
        (-g - w, -h - 1),
        (-g - w, 1),
        (g, -h - far),
        (g, far),
        (-g - w, -h - far),
        (-g - w, far),
        (-w / 2, -g - h - far),
        (-w / 2, g + far),
        (g, -h - farther),
        (g, farther),
        (-g - w, -h - farther),
        (-g - w, farther),
    ];
    let cost = |r: &Rect| {
        let outside = r.area() - r.overlap(bounds);
        obstacles.iter().map(|o| r.overlap(o)).sum::<i64>() + 20 * outside
    };
    let (k, best) = offsets
        .iter()
        .map(|&(dx, dy)| Rect {
            x0: p.0 + dx,
            y0: p.1 + dy,
            x1: p.0 + dx + w,
            y1: p.1 + dy + h,
        })
        .enumerate()
        .min_by_key(|(k, r)| (cost(r), *k))
        .expect("offsets are not empty");
    (best, k >= 8)
}

/// The outline of marker `shape` around the origin, in pixels: circle,
/// triangle, square, diamond, inverted triangle, then again.
fn marker(shape: usize) -> Vec<(i32, i32)> {
    let polygon = |n: usize, phase: f64, r: f64| {
        (0..n)
            .map(|k| {
                let a = phase + TAU * k as f64 / n as f64;
                ((r * a.cos()).round() as i32, (-r * a.sin()).round() as i32)
            })
            .collect()
    };
    match shape % 5 {
        0 => polygon(24, 0.0, MARKER),
        1 => polygon(3, FRAC_PI_2, 1.35 * MARKER),
        2 => polygon(4, FRAC_PI_4, 1.3 * MARKER),
        3 => polygon(4, 0.0, 1.35 * MARKER),
        _ => polygon(3, -FRAC_PI_2, 1.35 * MARKER),
    }
}

/// Draws marker `shape` filled with `c` at the backend pixel `p`, with a
/// white rim so that overlapping markers stay apart.
fn draw_marker<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: (i32, i32),
    shape: usize,
    c: RGBColor,
) -> Drawn<DB> {
    let outline: Vec<(i32, i32)> = marker(shape)
        .into_iter()
        .map(|(x, y)| (p.0 + x, p.1 + y))
        .collect();
    let mut closed = outline.clone();
    closed.push(outline[0]);
    root.draw(&Polygon::new(outline, c.filled()))?;
    root.draw(&PathElement::new(closed, WHITE.stroke_width(1)))
}

/// Threshold and interval width against CPU time, per family.
struct Tradeoff<'a> {
    outcomes: &'a [VariantOutcome],
    title: &'a str,
    /// Families in order of first appearance: their colour and marker.
    families: Vec<&'a str>,
}

impl Tradeoff<'_> {
    /// The CPU axis: every variant, with room on the right for the labels
    /// of the slowest.
    fn cpu_range(&self) -> (f64, f64) {
        let cpu = self.outcomes.iter().map(|o| o.cpu_seconds);
        let (c0, c1) = (
            cpu.clone().fold(f64::INFINITY, f64::min),
            cpu.fold(0.0, f64::max),
        );
        (c0 / 1.6, c1 * 2.2)
    }

    /// The white page, the title and the legend strip; the area below them.
    fn frame<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Drawing<DB, DrawingArea<DB, Shift>> {
        root.fill(&WHITE)?;
        let body = root
            .margin(8, 0, 0, 0)
            .titled(self.title, ("sans-serif", 26))?;
        let (strip, body) = body.split_vertically(40);
        self.legend(root, &strip)?;
        Ok(body)
    }

    /// A panel of `value` against CPU on `area`, a dashed line at zero (the
    /// reference).
    fn bias_panel<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        area: &DrawingArea<DB, Shift>,
        caption: &str,
        (y0, y1): (f64, f64),
        y_desc: &str,
        value: &dyn Fn(&VariantOutcome) -> Option<Estimate>,
    ) -> Drawn<DB> {
        let (x0, x1) = self.cpu_range();
        let x_axis = (x0..x1).log_scale().with_key_points(log_ticks(x0, x1));
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 22))
            .margin(MARGIN)
            .x_label_area_size(55)
            .y_label_area_size(Y_AREA)
            .build_cartesian_2d(x_axis, y0..y1)?;
        cpu_mesh(&mut chart, y_desc, false)?;
        chart.draw_series(DashedLineSeries::new(
            [(x0, 0.0), (x1, 0.0)],
            8,
            6,
            BLACK.mix(0.6).stroke_width(2),
        ))?;
        self.points(root, &mut chart, value, Some(0.0))
    }

    /// What panel (a) plots: the difference to the first variant (zero for
    /// the first itself, which the dashed line marks).
    fn bias(&self, o: &VariantOutcome) -> Option<Estimate> {
        if std::ptr::eq(o, &self.outcomes[0]) {
            return Some(Estimate {
                value: 0.0,
                lo: None,
                hi: None,
            });
        }
        o.difference()
    }

    fn family(&self, o: &VariantOutcome) -> usize {
        self.families
            .iter()
            .position(|f| *f == o.family)
            .unwrap_or(0)
    }

    /// A row of family markers and names centred in `strip`, and what the
    /// dashed line means.
    fn legend<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        strip: &DrawingArea<DB, Shift>,
    ) -> Drawn<DB> {
        let style =
            TextStyle::from(("sans-serif", 18).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
        let reference = format!("{}: the reference", self.outcomes[0].label);
        let (key, gap) = (34, 30);
        let mut entries = Vec::new();
        for name in self
            .families
            .iter()
            .map(|f| f.to_string())
            .chain([reference])
        {
            let w = root.estimate_text_size(&name, &style)?.0 as i32;
            entries.push((name, w));
        }
        let total: i32 = entries.iter().map(|(_, w)| key + w + gap).sum::<i32>() - gap;
        let (xs, ys) = strip.get_pixel_range();
        let mut x = (xs.start + xs.end - total) / 2;
        let y = (ys.start + ys.end) / 2;
        let last = entries.len() - 1;
        for (k, (name, w)) in entries.iter().enumerate() {
            if k < last {
                let c = colour(k);
                root.draw(&PathElement::new(
                    [(x, y), (x + 26, y)],
                    c.mix(0.6).stroke_width(2),
                ))?;
                draw_marker(root, (x + 13, y), k, c)?;
            } else {
                let grey = BLACK.mix(0.6).stroke_width(2);
                root.draw(&PathElement::new([(x, y), (x + 10, y)], grey))?;
                root.draw(&PathElement::new([(x + 16, y), (x + 26, y)], grey))?;
            }
            root.draw_text(name, &style, (x + key, y))?;
            x += key + w + gap;
        }
        Ok(())
    }

    /// The points `value` of every family on a panel: a line joining each
    /// family in order of CPU time, each value's interval where it has one,
    /// the markers, and each label where it overlaps the least (also the
    /// horizontal line at `level`).
    fn points<DB, X, Y>(
        &self,
        root: &DrawingArea<DB, Shift>,
        chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
        value: &dyn Fn(&VariantOutcome) -> Option<Estimate>,
        level: Option<f64>,
    ) -> Drawn<DB>
    where
        DB: DrawingBackend,
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let shown: Vec<(&VariantOutcome, Estimate)> = self
            .outcomes
            .iter()
            .filter_map(|o| Some((o, value(o)?)))
            .collect();
        let (xs, ys) = chart.plotting_area().get_pixel_range();
        let mut obstacles = Vec::new();
        if let Some(y) = level {
            let (_, y) = chart.backend_coord(&(self.outcomes[0].cpu_seconds, y));
            obstacles.push(Rect {
                x0: xs.start,
                y0: y - 1,
                x1: xs.end,
                y1: y + 1,
            });
        }
        for k in 0..self.families.len() {
            let mut line: Vec<(f64, f64)> = shown
                .iter()
                .filter(|(o, _)| self.family(o) == k)
                .map(|(o, v)| (o.cpu_seconds, v.value))
                .collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.draw_series(LineSeries::new(
                line.iter().copied(),
                colour(k).mix(0.55).stroke_width(2),
            ))?;
            // Lines get in a label's way less than markers do: thin boxes along them.
            for pair in line.windows(2) {
                let (a, b) = (chart.backend_coord(&pair[0]), chart.backend_coord(&pair[1]));
                let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 6).max(1);
                obstacles.extend((0..=steps).map(|s| {
                    let t = s as f64 / steps as f64;
                    let at = |u: i32, v: i32| u + (t * f64::from(v - u)).round() as i32;
                    Rect::around((at(a.0, b.0), at(a.1, b.1)), 1, 1)
                }));
            }
        }
        for (o, e) in &shown {
            let c = colour(self.family(o));
            if let (Some(lo), Some(hi)) = (e.lo, e.hi) {
                error_bars(chart, [(o.cpu_seconds, lo, hi)], c.mix(0.7), 5)?;
                let (x, top) = chart.backend_coord(&(o.cpu_seconds, hi));
                let (_, bottom) = chart.backend_coord(&(o.cpu_seconds, lo));
                obstacles.push(Rect {
                    x0: x - 5,
                    y0: top - 1,
                    x1: x + 5,
                    y1: bottom + 1,
                });
            }
        }
        let mut at: Vec<(i32, i32)> = Vec::new();
        for (o, v) in &shown {
            let p = chart.backend_coord(&(o.cpu_seconds, v.value));
            let k = self.family(o);
            draw_marker(root, p, k, colour(k))?;
            let r = MARKER as i32 + 2;
            obstacles.push(Rect::around(p, r, r));
            at.push(p);
        }
        let bounds = Rect {
            x0: xs.start + 2,
            y0: ys.start + 2,
            x1: xs.end - 2,
            y1: ys.end - 2,
        };
        let ink = BLACK.mix(0.85);
        let style = TextStyle::from(("sans-serif", 15).into_font()).color(&ink);
        // Left to right, so that each label sees the ones beside it placed.
        let mut order: Vec<usize> = (0..shown.len()).collect();
        order.sort_by_key(|&i| (at[i].0, at[i].1));
        for i in order {
            let label = &shown[i].0.label;
            let (w, h) = root.estimate_text_size(label, &style)?;
            let (r, far) = place(at[i], (w as i32 + 2, h as i32), &obstacles, &bounds);
            if far {
                let near = (at[i].0.clamp(r.x0, r.x1), at[i].1.clamp(r.y0, r.y1));
                root.draw(&PathElement::new(
                    [at[i], near],
                    BLACK.mix(0.35).stroke_width(1),
                ))?;
            }
            root.draw_text(label, &style, (r.x0 + 1, r.y0))?;
            obstacles.push(r);
        }
        Ok(())
    }
}

/// The mesh of a speed-accuracy panel: CPU seconds on a log x axis.
fn cpu_mesh<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    y_desc: &str,
    log_y: bool,
) -> Drawn<DB>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let plain = |v: &f64| tick(*v);
    let mut mesh = chart.configure_mesh();
    mesh.x_desc("CPU seconds of the analysed sequences, log scale")
        .y_desc(y_desc)
        .x_label_formatter(&plain)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18));
    if log_y {
        mesh.y_label_formatter(&plain);
    }
    mesh.draw()
}

impl Chart for Tradeoff<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        let panels = self.frame(&root)?.split_evenly((1, 2));
        let (x0, x1) = self.cpu_range();
        let x_axis = || (x0..x1).log_scale().with_key_points(log_ticks(x0, x1));

        let bias = |o: &VariantOutcome| self.bias(o);
        let values = self
            .outcomes
            .iter()
            .filter_map(bias)
            .flat_map(|e| [Some(e.value), e.lo, e.hi]);
        let (y0, y1) = span(values.flatten().chain([0.0]), 0.12);
        let caption = format!(
            "(a) ρc minus {}'s: paired per sequence (nested), of thresholds (fixed)",
            self.outcomes[0].label
        );
        let y_desc = format!("difference of critical densities ({RHO})");
        self.bias_panel(&root, &panels[0], &caption, (y0, y1), &y_desc, &bias)?;

        let caption = "(b) width of the 95% interval of ρc";
        let width = |o: &VariantOutcome| o.interval_width;
        let widths: Vec<f64> = self.outcomes.iter().filter_map(width).collect();
        let width = |o: &VariantOutcome| {
            o.interval_width.map(|value| Estimate {
                value,
                lo: None,
                hi: None,
            })
        };
        let (w0, w1) = (
            widths.iter().copied().fold(f64::INFINITY, f64::min),
            widths.iter().copied().fold(0.0, f64::max),
        );
        let builder = || {
            let mut b = ChartBuilder::on(&panels[1]);
            b.caption(caption, ("sans-serif", 22))
                .margin(MARGIN)
                .x_label_area_size(55)
                .y_label_area_size(Y_AREA);
            b
        };
        if w0 > 0.0 && w1 > 10.0 * w0 {
            let (w0, w1) = (w0 / 1.5, w1 * 1.5);
            let y_axis = (w0..w1).log_scale().with_key_points(log_ticks(w0, w1));
            let mut chart = builder().build_cartesian_2d(x_axis(), y_axis)?;
            cpu_mesh(
                &mut chart,
                &format!("interval width ({RHO}), log scale"),
                true,
            )?;
            self.points(&root, &mut chart, &width, None)?;
        } else {
            let top = if w1 > 0.0 { 1.15 * w1 } else { 1.0 };
            let mut chart = builder().build_cartesian_2d(x_axis(), 0.0..top)?;
            cpu_mesh(&mut chart, &format!("interval width ({RHO})"), false)?;
            if widths.is_empty() {
                let centre = TextStyle::from(("sans-serif", 20).into_font())
                    .pos(Pos::new(HPos::Center, VPos::Center));
                let (xs, ys) = chart.plotting_area().get_pixel_range();
                root.draw_text(
                    "no variant has an interval",
                    &centre,
                    ((xs.start + xs.end) / 2, (ys.start + ys.end) / 2),
                )?;
            }
            self.points(&root, &mut chart, &width, None)?;
        }
        root.present()
    }
}

/// The speed-accuracy panel of each aspect ratio, side by side.
struct Gammas<'a> {
    panels: &'a [Panel],
    title: &'a str,
    families: Vec<&'a str>,
}

impl Gammas<'_> {
    fn tradeoff<'b>(&'b self, p: &'b Panel) -> Tradeoff<'b> {
        Tradeoff {
            outcomes: &p.outcomes,
            title: self.title,
            families: self.families.clone(),
        }
    }
}

/// A panel's variant `o` by its relative bias, in percent.
fn percent_bias(p: &Panel, o: &VariantOutcome) -> Option<Estimate> {
    let k = p.outcomes.iter().position(|x| std::ptr::eq(x, o))?;
    let (value, lo, hi) = p.relative_bias(k)?;
    Some(Estimate {
        value: 100.0 * value,
        lo: lo.map(|v| 100.0 * v),
        hi: hi.map(|v| 100.0 * v),
    })
}

impl Chart for Gammas<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        let body = self.tradeoff(&self.panels[0]).frame(&root)?;
        let areas = body.split_evenly((1, self.panels.len()));
        let values = self.panels.iter().flat_map(|p| {
            p.outcomes
                .iter()
                .filter_map(|o| percent_bias(p, o))
                .flat_map(|e| [Some(e.value), e.lo, e.hi])
        });
        let (y0, y1) = span(values.flatten().chain([0.0]), 0.12);
        for (p, area) in self.panels.iter().zip(&areas) {
            let bias = |o: &VariantOutcome| percent_bias(p, o);
            self.tradeoff(p).bias_panel(
                &root,
                area,
                &format!("γ = {}", p.gamma),
                (y0, y1),
                "ρc minus truth's, % of truth's threshold",
                &bias,
            )?;
        }
        root.present()
    }
}
