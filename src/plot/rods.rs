//! A rod system as a person would look at it: an orthographic view of the
//! box with each rod's core as a segment as wide as the rod (at least a
//! pixel), coloured by its group: a run's rigid bodies, or the true rigid
//! clusters. The group that matters (the first spanning one, else the
//! largest) is strong red; the other groups in faded colours; rods in none
//! pale grey. Rods and box edges are drawn far to near (the painter's
//! algorithm), so a near rod covers a far one whatever their groups. Box
//! edges on a wall are solid and thick, edges between periodic faces thin
//! and dashed. A legend under the title counts the rods of each kind.

use std::path::Path;

use nalgebra::Vector3;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, colour, render};
use crate::rods::RodSystem;
use crate::sample::ReportedBodies;
use crate::spanning::Criterion;
use crate::truth::Truth;
use crate::{Error, Result};

/// The rods to colour: groups largest first, each with whether it spans,
/// and what a group is called in the picture's legend (singular, plural).
#[derive(Clone, Debug)]
pub struct Groups<'a> {
    pub noun: &'static str,
    pub nouns: &'static str,
    pub groups: Vec<(&'a [u32], bool)>,
}

impl<'a> Groups<'a> {
    /// The bodies of one run.
    pub fn bodies(bodies: &'a ReportedBodies) -> Self {
        Groups {
            noun: "body",
            nouns: "bodies",
            groups: bodies
                .bodies
                .iter()
                .map(|b| (b.rods.as_slice(), b.spans))
                .collect(),
        }
    }

    /// The true rigid clusters, spanning under `criterion`.
    pub fn true_clusters(truth: &'a Truth, criterion: Criterion) -> Self {
        Groups {
            noun: "true rigid cluster",
            nouns: "true rigid clusters",
            groups: truth
                .clusters
                .iter()
                .map(|c| {
                    let spans = c.spans.is_some_and(|s| s.under(criterion));
                    (c.rods.as_slice(), spans)
                })
                .collect(),
        }
    }
}

/// The colour of the group that matters.
pub const HIGHLIGHT: RGBColor = RGBColor(214, 39, 40);
/// Box edges on a wall, and edges where only periodic faces meet.
pub const WALL: RGBColor = RGBColor(40, 40, 40);
pub const PERIODIC: RGBColor = RGBColor(110, 110, 110);

/// The picture's side in pixels.
pub const SIZE: (u32, u32) = (1000, 1000);

/// Where the viewer stands: turned `azimuth` degrees about the box's z axis,
/// then looking down `elevation` degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub azimuth: f64,
    pub elevation: f64,
}

impl Default for View {
    /// Two box faces in view and the top foreshortened, so depth reads.
    fn default() -> Self {
        View {
            azimuth: 30.0,
            elevation: 20.0,
        }
    }
}

impl View {
    /// Screen coordinates (right, up) of a point, and its depth (distance
    /// from the viewer along the line of sight, up to a constant).
    fn project(&self, p: &Vector3<f64>) -> ((f64, f64), f64) {
        let (a, e) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let right = a.cos() * p.x - a.sin() * p.y;
        // Horizontal distance away from the viewer.
        let ahead = a.sin() * p.x + a.cos() * p.y;
        let up = e.cos() * p.z + e.sin() * ahead;
        ((right, up), e.cos() * ahead - e.sin() * p.z)
    }
}

/// Draws `system` coloured by `groups` as `svg` and `png`, titled `title`.
pub fn rods_picture(
    system: &RodSystem,
    groups: &Groups,
    view: View,
    title: &str,
    svg: &Path,
    png: &Path,
) -> Result<()> {
    check(view)?;
    render(&Scene::new(system, groups, view, title), SIZE, svg, png)
}

/// The picture as RGB bytes (row by row, `SIZE`), without title or legend
/// and without files: for checks.
pub fn rods_pixels(system: &RodSystem, groups: &Groups, view: View) -> Result<Vec<u8>> {
    check(view)?;
    let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    Scene::new(system, groups, view, "")
        .draw(BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area())
        .map_err(|e| Error::Parameter(format!("drawing the rods: {e}")))?;
    Ok(buf)
}

/// The pixel (column, row) where `point` lands in [`rods_pixels`]'s
/// picture of `system` from `view`.
pub fn pixel_of(
    system: &RodSystem,
    groups: &Groups,
    view: View,
    point: Vector3<f64>,
) -> (i32, i32) {
    let scene = Scene::new(system, groups, view, "");
    scene.place(SIZE).pixel(view.project(&point).0)
}

fn check(view: View) -> Result<()> {
    if !(view.azimuth.is_finite() && view.elevation.is_finite()) || view.elevation.abs() > 90.0 {
        return Err(Error::Parameter(format!(
            "view azimuth {} and elevation {} degrees: both finite, the elevation within -90..90",
            view.azimuth, view.elevation
        )));
    }
    Ok(())
}

/// How a stroke is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// A rod of the group that matters.
    Highlight,
    /// A rod of another group, with its group's colour index.
    Faded(usize),
    /// A rod in no group.
    Free,
    /// A box edge on a wall.
    Wall,
    /// A box edge where only periodic faces meet.
    Periodic,
}

/// One rod or box edge on screen.
struct Stroke {
    segment: Segment,
    depth: f64,
    /// Width in world units (a rod's diameter; 0 for a box edge).
    width: f64,
    kind: Kind,
}

/// What is drawn: rods and box edges far to near, the legend's lines.
struct Scene {
    title: String,
    strokes: Vec<Stroke>,
    legend: Vec<(String, RGBColor)>,
    bounds: [f64; 4],
}

type Segment = [(f64, f64); 2];

/// Screen units to pixels in a picture of a given size.
struct Place {
    scale: f64,
    centre: (f64, f64),
    middle: (f64, f64),
}

impl Place {
    fn pixel(&self, (x, y): (f64, f64)) -> (i32, i32) {
        (
            (self.middle.0 + (x - self.centre.0) * self.scale).round() as i32,
            (self.middle.1 - (y - self.centre.1) * self.scale).round() as i32,
        )
    }
}

/// `1234567` as `1,234,567`.
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Opaque pale colours rather than transparency: the same look, and a PNG
/// a fraction of the size (few distinct colours).
fn pale(c: RGBColor, a: f64) -> RGBColor {
    let mix = |v: u8| (a * v as f64 + (1.0 - a) * 255.0).round() as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

fn faded(k: usize) -> RGBColor {
    pale(colour(k % 9 + 1), 0.45)
}

const FREE: RGBColor = RGBColor(211, 211, 211);

/// Pixels from the top to the drawing, for the title and the legend.
const TITLE: f64 = 44.0;
const LINE: f64 = 22.0;
const MARGIN: f64 = 30.0;

impl Scene {
    fn new(system: &RodSystem, groups: &Groups, view: View, title: &str) -> Scene {
        let n = system.len();
        // Groups come largest first: the first spanning one, else the first.
        let chosen = groups
            .groups
            .iter()
            .position(|g| g.1)
            .or((!groups.groups.is_empty()).then_some(0));
        // A rod in several groups (true clusters meet at hinge rods) takes
        // the chosen group, else the first; so the chosen group keeps all
        // its rods.
        let mut owner = vec![usize::MAX; n];
        let order = chosen.into_iter().chain(0..groups.groups.len());
        for k in order {
            for &r in groups.groups[k].0 {
                if owner[r as usize] == usize::MAX {
                    owner[r as usize] = k;
                }
            }
        }
        let mut strokes: Vec<Stroke> = system
            .rods
            .iter()
            .zip(&owner)
            .map(|(rod, &k)| {
                let (a, da) = view.project(&rod.at(-0.5 * rod.length));
                let (b, db) = view.project(&rod.at(0.5 * rod.length));
                let kind = match k {
                    usize::MAX => Kind::Free,
                    k if Some(k) == chosen => Kind::Highlight,
                    k => Kind::Faded(k),
                };
                Stroke {
                    segment: [a, b],
                    depth: (da + db) / 2.0,
                    width: 2.0 * rod.radius,
                    kind,
                }
            })
            .collect();
        let l = system.domain.sides;
        let periodic = system.domain.periodic.axes();
        let corner = |i: usize| {
            Vector3::new(
                l[0] * (i & 1) as f64,
                l[1] * ((i >> 1) & 1) as f64,
                l[2] * ((i >> 2) & 1) as f64,
            )
        };
        for (i, axis) in (0..8usize).flat_map(|i| [(i, 0), (i, 1), (i, 2)]) {
            let j = i | (1 << axis);
            if i == j {
                continue;
            }
            // The edge lies on the faces across the two other axes: on a
            // wall if either of them has walls.
            let wall = (0..3).any(|k| k != axis && !periodic[k]);
            let (a, da) = view.project(&corner(i));
            let (b, db) = view.project(&corner(j));
            strokes.push(Stroke {
                segment: [a, b],
                depth: (da + db) / 2.0,
                width: 0.0,
                kind: if wall { Kind::Wall } else { Kind::Periodic },
            });
        }
        // Far first; ties keep their order, so the picture is reproducible.
        strokes.sort_by(|a, b| b.depth.total_cmp(&a.depth));
        let mut bounds = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for &(x, y) in strokes.iter().flat_map(|s| &s.segment) {
            bounds = [
                bounds[0].min(x),
                bounds[1].max(x),
                bounds[2].min(y),
                bounds[3].max(y),
            ];
        }
        Scene {
            title: title.to_string(),
            legend: legend(groups, chosen, &owner, periodic),
            strokes,
            bounds,
        }
    }

    /// Where the drawing goes in a picture of `(w, h)` pixels.
    fn place(&self, (w, h): (u32, u32)) -> Place {
        let top = if self.title.is_empty() {
            MARGIN
        } else {
            TITLE + LINE * self.legend.len() as f64 + 10.0
        };
        let [x0, x1, y0, y1] = self.bounds;
        let scale = ((w as f64 - 2.0 * MARGIN) / (x1 - x0).max(1e-12))
            .min((h as f64 - top - MARGIN) / (y1 - y0).max(1e-12));
        Place {
            scale,
            centre: ((x0 + x1) / 2.0, (y0 + y1) / 2.0),
            middle: (w as f64 / 2.0, top + (h as f64 - top - MARGIN) / 2.0),
        }
    }
}

/// The legend's lines with their colours: the group that matters, the other
/// groups, the rods in none (each with its count), and the box's edges.
fn legend(
    groups: &Groups,
    chosen: Option<usize>,
    owner: &[usize],
    periodic: [bool; 3],
) -> Vec<(String, RGBColor)> {
    let (noun, nouns) = (groups.noun, groups.nouns);
    let mut held = vec![0usize; groups.groups.len()];
    let mut free = 0;
    for &k in owner {
        match held.get_mut(k) {
            Some(h) => *h += 1,
            None => free += 1,
        }
    }
    let mut lines = Vec::new();
    match chosen {
        Some(k) if groups.groups[k].1 => {
            lines.push((
                format!("spanning {noun}: {} rods", thousands(held[k])),
                HIGHLIGHT,
            ));
        }
        Some(k) => lines.push((
            format!("largest {noun} (none spans): {} rods", thousands(held[k])),
            HIGHLIGHT,
        )),
        None => {}
    }
    let others: Vec<usize> = (0..held.len())
        .filter(|&k| Some(k) != chosen && held[k] > 0)
        .collect();
    if !others.is_empty() {
        let rods: usize = others.iter().map(|&k| held[k]).sum();
        lines.push((
            format!(
                "other {nouns} ({}): {} rods",
                thousands(others.len()),
                thousands(rods)
            ),
            faded(others[0]),
        ));
    }
    lines.push((format!("rods in no {noun}: {}", thousands(free)), FREE));
    let box_line = match (periodic.contains(&true), periodic.contains(&false)) {
        (true, true) => "box: walls solid, periodic faces dashed",
        (true, false) => "box: periodic faces (dashed edges)",
        _ => "box: walls (solid edges)",
    };
    lines.push((box_line.to_string(), WALL));
    lines
}

impl Chart for Scene {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let place = self.place(root.dim_in_pixel());
        for s in &self.strokes {
            let ends = vec![place.pixel(s.segment[0]), place.pixel(s.segment[1])];
            // As wide as the rod, at least a pixel.
            let width = (s.width * place.scale).round().max(1.0) as u32;
            match s.kind {
                Kind::Periodic => root.draw(&DashedPathElement::new(
                    ends,
                    6,
                    5,
                    PERIODIC.stroke_width(1),
                ))?,
                kind => {
                    let style = match kind {
                        Kind::Highlight => HIGHLIGHT.stroke_width(width),
                        Kind::Faded(k) => faded(k).stroke_width(width),
                        Kind::Free => FREE.stroke_width(width),
                        _ => WALL.stroke_width(3),
                    };
                    root.draw(&PathElement::new(ends, style))?;
                }
            }
        }
        if self.title.is_empty() {
            return Ok(());
        }
        root.draw(&Text::new(
            self.title.as_str(),
            (20, 12),
            ("sans-serif", 24),
        ))?;
        for (i, (text, colour)) in self.legend.iter().enumerate() {
            let y = (TITLE + LINE * i as f64) as i32;
            root.draw(&Rectangle::new(
                [(20, y + 3), (34, y + 15)],
                colour.filled(),
            ))?;
            root.draw(&Text::new(text.as_str(), (42, y), ("sans-serif", 18)))?;
        }
        Ok(())
    }
}
