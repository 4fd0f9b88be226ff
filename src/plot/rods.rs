//! A rod system as a person would look at it: an orthographic view of the
//! box with each rod's core as a segment, coloured by its group: a run's
//! rigid bodies, or the true rigid clusters. The group that matters (the
//! first spanning one, else the largest) is drawn last, strong and wide; the
//! other groups in faded colours; rods in none pale grey; the box as a wire
//! frame.

use std::path::Path;

use nalgebra::Vector3;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Chart, Drawn, colour, render};
use crate::rods::RodSystem;
use crate::sample::ReportedBodies;
use crate::spanning::Criterion;
use crate::truth::Truth;
use crate::{Error, Result};

/// The rods to colour: groups largest first, each with whether it spans,
/// and what a group is called in the picture's label.
#[derive(Clone, Debug)]
pub struct Groups<'a> {
    pub noun: &'static str,
    pub groups: Vec<(&'a [u32], bool)>,
}

impl<'a> Groups<'a> {
    /// The bodies of one run.
    pub fn bodies(bodies: &'a ReportedBodies) -> Self {
        Groups {
            noun: "body",
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
    /// Screen coordinates (right, up) of a point.
    fn project(&self, p: &Vector3<f64>) -> (f64, f64) {
        let (a, e) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let x = a.cos() * p.x - a.sin() * p.y;
        let depth = a.sin() * p.x + a.cos() * p.y;
        (x, e.cos() * p.z - e.sin() * depth)
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

/// The picture as RGB bytes (row by row, `SIZE`), without files: for checks.
pub fn rods_pixels(system: &RodSystem, groups: &Groups, view: View) -> Result<Vec<u8>> {
    check(view)?;
    let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    Scene::new(system, groups, view, "")
        .draw(BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area())
        .map_err(|e| Error::Parameter(format!("drawing the rods: {e}")))?;
    Ok(buf)
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

/// What is drawn: rods' screen segments by layer, and the box's edges.
struct Scene {
    title: String,
    free: Vec<Segment>,
    /// Other groups' rods, with their group's colour index.
    faded: Vec<(Segment, usize)>,
    highlight: Vec<Segment>,
    label: String,
    frame: Vec<Segment>,
    bounds: [f64; 4],
}

type Segment = [(f64, f64); 2];

impl Scene {
    fn new(system: &RodSystem, groups: &Groups, view: View, title: &str) -> Scene {
        let n = system.len();
        // A rod in several groups (true clusters meet at hinge rods) takes the first.
        let mut owner = vec![usize::MAX; n];
        for (k, (rods, _)) in groups.groups.iter().enumerate() {
            for &r in rods.iter() {
                if owner[r as usize] == usize::MAX {
                    owner[r as usize] = k;
                }
            }
        }
        // Groups come largest first: the first spanning one, else the first.
        let chosen = groups
            .groups
            .iter()
            .position(|g| g.1)
            .or((!groups.groups.is_empty()).then_some(0));
        let segment = |r: usize| {
            let rod = &system.rods[r];
            [
                view.project(&rod.at(-0.5 * rod.length)),
                view.project(&rod.at(0.5 * rod.length)),
            ]
        };
        let (mut free, mut faded, mut highlight) = (Vec::new(), Vec::new(), Vec::new());
        for (r, &k) in owner.iter().enumerate() {
            match k {
                usize::MAX => free.push(segment(r)),
                k if Some(k) == chosen => highlight.push(segment(r)),
                k => faded.push((segment(r), k)),
            }
        }
        let noun = groups.noun;
        let label = match chosen {
            Some(k) if groups.groups[k].1 => {
                format!("spanning {noun}: {} of {n} rods", groups.groups[k].0.len())
            }
            Some(k) => format!(
                "largest {noun} (none spans): {} of {n} rods",
                groups.groups[k].0.len()
            ),
            None => format!("no {noun} among {n} rods"),
        };
        let l = system.domain.sides;
        let corner = |i: usize| {
            Vector3::new(
                l[0] * (i & 1) as f64,
                l[1] * ((i >> 1) & 1) as f64,
                l[2] * ((i >> 2) & 1) as f64,
            )
        };
        let frame: Vec<Segment> = (0..8usize)
            .flat_map(|i| [1, 2, 4].map(move |bit| (i, i | bit)))
            .filter(|&(i, j)| i != j)
            .map(|(i, j)| [view.project(&corner(i)), view.project(&corner(j))])
            .collect();
        let points = frame
            .iter()
            .chain(&free)
            .chain(&highlight)
            .chain(faded.iter().map(|(s, _)| s))
            .flatten();
        let mut bounds = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for &(x, y) in points {
            bounds = [
                bounds[0].min(x),
                bounds[1].max(x),
                bounds[2].min(y),
                bounds[3].max(y),
            ];
        }
        Scene {
            title: title.to_string(),
            free,
            faded,
            highlight,
            label,
            frame,
            bounds,
        }
    }
}

impl Chart for Scene {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        let (w, h) = root.dim_in_pixel();
        let (top, margin) = (70.0, 30.0);
        let [x0, x1, y0, y1] = self.bounds;
        let scale = ((w as f64 - 2.0 * margin) / (x1 - x0).max(1e-12))
            .min((h as f64 - top - margin) / (y1 - y0).max(1e-12));
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let (mx, my) = (w as f64 / 2.0, top + (h as f64 - top - margin) / 2.0);
        let pixel = |(x, y): (f64, f64)| {
            (
                (mx + (x - cx) * scale).round() as i32,
                (my - (y - cy) * scale).round() as i32,
            )
        };
        let line = |s: &Segment, style: ShapeStyle| {
            root.draw(&PathElement::new(vec![pixel(s[0]), pixel(s[1])], style))
        };
        for s in &self.frame {
            line(s, RGBColor(120, 120, 120).stroke_width(1))?;
        }
        // Opaque pale colours rather than transparency: the same look, and
        // a PNG a fraction of the size (few distinct colours).
        let pale = |c: RGBColor, a: f64| {
            let mix = |v: u8| (a * v as f64 + (1.0 - a) * 255.0).round() as u8;
            RGBColor(mix(c.0), mix(c.1), mix(c.2))
        };
        for s in &self.free {
            line(s, pale(RGBColor(150, 150, 150), 0.3).stroke_width(1))?;
        }
        for (s, k) in &self.faded {
            line(s, pale(colour(*k % 9 + 1), 0.45).stroke_width(1))?;
        }
        // Thinner as the body grows, so that a large one keeps its texture.
        let width = if self.highlight.len() > 1500 { 1 } else { 2 };
        for s in &self.highlight {
            line(s, RGBColor(214, 39, 40).stroke_width(width))?;
        }
        if !self.title.is_empty() {
            root.draw(&Text::new(
                self.title.as_str(),
                (20, 12),
                ("sans-serif", 24),
            ))?;
            root.draw(&Text::new(
                self.label.as_str(),
                (20, 42),
                ("sans-serif", 18).into_font().color(&RGBColor(214, 39, 40)),
            ))?;
        }
        Ok(())
    }
}
