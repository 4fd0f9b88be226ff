//! Rod systems as VTK PolyData (`.vtp`, XML, ASCII), for ParaView and
//! other VTK readers.
//!
//! Each rod is one line cell from `centre - axis/2` to `centre + axis/2`
//! (its core; lengths in rod lengths), with the centre as stored: a rod
//! across a periodic face pokes out of the box rather than being cut, so
//! that every rod stays whole. The radius is given per point and per cell
//! (ParaView's Tube filter varies the radius by a point array), and every
//! further field per cell. For a sample: the body of the reported run
//! (`-1` for a free rod), whether that body spans, the rod's degree, and,
//! when the sample decided its exact rigidity, the rod's true rigid cluster
//! and whether that cluster spans; for rods read with ids, the rod's id.

use std::fmt::Write as _;
use std::path::Path;

use crate::Result;
use crate::output;
use crate::rods::RodSystem;
use crate::sample::Sample;
use crate::spanning::Criterion;

/// Values of one field, one per rod.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Int(Vec<i64>),
    Float(Vec<f64>),
}

/// A named per-rod field.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub name: String,
    pub values: Values,
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Int(v) => v.len(),
            Values::Float(v) => v.len(),
        }
    }
}

fn array<T: std::fmt::Display>(s: &mut String, ty: &str, name: &str, comps: usize, values: &[T]) {
    let _ = write!(
        s,
        "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">"
    );
    for (i, v) in values.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{v}");
    }
    s.push_str("</DataArray>\n");
}

/// The PolyData document of `system` with `fields` on its rods.
///
/// # Panics
///
/// When a field does not hold one value per rod.
pub fn to_vtp(system: &RodSystem, fields: &[Field]) -> String {
    let n = system.len();
    for f in fields {
        assert_eq!(
            f.values.len(),
            n,
            "field {} needs one value per rod",
            f.name
        );
    }
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    s.push_str("  <PolyData>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{n}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
        2 * n
    );
    let points: Vec<f64> = system
        .rods
        .iter()
        .flat_map(|r| {
            let (a, b) = (r.at(-0.5 * r.length), r.at(0.5 * r.length));
            [a.x, a.y, a.z, b.x, b.y, b.z]
        })
        .collect();
    s.push_str("      <Points>\n");
    array(&mut s, "Float64", "points", 3, &points);
    s.push_str("      </Points>\n");
    s.push_str("      <Lines>\n");
    array(
        &mut s,
        "Int64",
        "connectivity",
        1,
        &(0..2 * n).collect::<Vec<_>>(),
    );
    array(
        &mut s,
        "Int64",
        "offsets",
        1,
        &(1..=n).map(|i| 2 * i).collect::<Vec<_>>(),
    );
    s.push_str("      </Lines>\n");
    let radii: Vec<f64> = system.rods.iter().map(|r| r.radius).collect();
    let per_point: Vec<f64> = radii.iter().flat_map(|&r| [r, r]).collect();
    s.push_str("      <PointData Scalars=\"radius\">\n");
    array(&mut s, "Float64", "radius", 1, &per_point);
    s.push_str("      </PointData>\n");
    s.push_str("      <CellData>\n");
    array(&mut s, "Float64", "radius", 1, &radii);
    for f in fields {
        match &f.values {
            Values::Int(v) => array(&mut s, "Int64", &f.name, 1, v),
            Values::Float(v) => array(&mut s, "Float64", &f.name, 1, v),
        }
    }
    s.push_str("      </CellData>\n    </Piece>\n  </PolyData>\n</VTKFile>\n");
    s
}

/// A sample's per-rod fields: `body` (the index of the rod's body in the
/// reported run, largest first, or -1), `spans` (1 when that body spans
/// under `criterion`) and `degree` (contacts); with its truth, also
/// `true_cluster` (the index of the rod's true rigid cluster, largest
/// first, or -1; where clusters meet at a rod, the largest of them) and
/// `true_spans` (1 when a cluster of the rod spans); with the ids of rods
/// read from a file that numbers them, `id`.
pub fn sample_fields(sample: &Sample, criterion: Criterion) -> Vec<Field> {
    let n = sample.system.len();
    let (mut body, mut spans) = (vec![-1i64; n], vec![0i64; n]);
    for (k, b) in sample.reported_bodies(criterion).bodies.iter().enumerate() {
        for &r in &b.rods {
            body[r as usize] = k as i64;
            spans[r as usize] = i64::from(b.spans);
        }
    }
    let degree = (0..n as u32)
        .map(|r| sample.graph.degree(r) as i64)
        .collect();
    let mut fields = vec![("body", body), ("spans", spans), ("degree", degree)];
    if let Some(t) = &sample.truth {
        let (mut cluster, mut spans) = (vec![-1i64; n], vec![0i64; n]);
        for (k, c) in t.clusters.iter().enumerate() {
            let s = c.spans.is_some_and(|s| s.under(criterion));
            // A rod where clusters meet belongs to each: keep the largest.
            for &r in &c.rods {
                if cluster[r as usize] < 0 {
                    cluster[r as usize] = k as i64;
                }
                spans[r as usize] |= i64::from(s);
            }
        }
        fields.extend([("true_cluster", cluster), ("true_spans", spans)]);
    }
    if let Some(ids) = &sample.ids {
        fields.push(("id", ids.iter().map(|&i| i as i64).collect()));
    }
    fields
        .into_iter()
        .map(|(name, v)| Field {
            name: name.into(),
            values: Values::Int(v),
        })
        .collect()
}

/// Writes a sample's rods with [`sample_fields`] to `path` atomically.
/// The file is VTK XML PolyData, which VTK reads by the `.vtp` extension;
/// its legacy reader refuses XML under `.vtk`, so that name is refused.
pub fn check_extension(path: &Path) -> Result<()> {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("vtp") => Ok(()),
        _ => Err(crate::Error::Parameter(format!(
            "--save-vtk writes VTK XML PolyData: name the file .vtp, not {} (VTK's legacy reader refuses XML under .vtk)",
            path.display()
        ))),
    }
}

pub fn save_sample(sample: &Sample, criterion: Criterion, path: &Path) -> Result<()> {
    output::write_atomic(
        path,
        to_vtp(&sample.system, &sample_fields(sample, criterion)),
    )
}
