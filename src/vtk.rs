//! Rod systems as VTK PolyData (`.vtp`, XML with raw binary appended data),
//! for ParaView and other VTK readers.
//!
//! The file is standard VTK XML: `header_type="UInt64"`, little endian, every
//! array `format="appended"` in one `<AppendedData encoding="raw">` block
//! (each array a UInt64 byte count, then its values), so it is about half
//! the size of ASCII and reads without parsing numbers.
//!
//! Piece 0 holds the rods: each rod is one line cell from
//! `centre - axis/2` to `centre + axis/2` (its core; lengths in rod lengths),
//! with the centre as stored: a rod across a periodic face pokes out of the
//! box rather than being cut, so that every rod stays whole. Piece 1 is the
//! box outline: its 8 corners and 12 edges as line cells. VTK readers join
//! the pieces into one data set, so both carry the same arrays: `outline`
//! (0 on a rod, 1 on a box edge; threshold on it to keep only the rods), the
//! radius per point and per cell (ParaView's Tube filter varies the radius
//! by a point array; 0 on the outline), and every further per-rod field (-1
//! on the outline). The data set's `<FieldData>` holds the box: `box_sides`
//! (LX, LY, LZ), `box_origin` (its lowest corner, always 0, 0, 0: the frame
//! of the coordinates) and `periodic` (1 per periodic axis, 0 per axis with
//! walls).
//!
//! The fields of a sample: the body of the reported run (`-1` for a free
//! rod), whether that body spans, the rod's degree, and, when the sample
//! decided its exact rigidity, the rod's true rigid cluster and whether that
//! cluster spans; for rods read with ids, the rod's id. Integer fields are
//! written in the narrowest of Int8, Int32 and Int64 that holds them.

use std::fmt::Write as _;
use std::path::Path;

use crate::Result;
use crate::graph::ContactGraph;
use crate::output;
use crate::rods::RodSystem;
use crate::sample::Sample;
use crate::spanning::Criterion;
use crate::truth::Truth;

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

impl Field {
    /// An integer field.
    pub fn int(name: &str, values: Vec<i64>) -> Field {
        Field {
            name: name.into(),
            values: Values::Int(values),
        }
    }
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Int(v) => v.len(),
            Values::Float(v) => v.len(),
        }
    }
}

/// The value a per-rod field takes on the box outline's cells.
const OUTLINE_INT: i64 = -1;
const OUTLINE_FLOAT: f64 = -1.0;

/// The XML and the appended bytes being written.
struct Writer {
    xml: String,
    data: Vec<u8>,
}

impl Writer {
    /// One `DataArray` element at `indent`, its values appended; `tuples` is
    /// written for field data, which VTK needs it for.
    fn array(
        &mut self,
        indent: usize,
        ty: &str,
        name: &str,
        comps: usize,
        tuples: Option<usize>,
        bytes: &[u8],
    ) {
        let tuples = tuples.map_or(String::new(), |t| format!(" NumberOfTuples=\"{t}\""));
        let _ = writeln!(
            self.xml,
            "{:indent$}<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\"{tuples} format=\"appended\" offset=\"{}\"/>",
            "",
            self.data.len()
        );
        self.data
            .extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        self.data.extend_from_slice(bytes);
    }

    fn floats(&mut self, indent: usize, name: &str, comps: usize, values: &[f64]) {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.array(indent, "Float64", name, comps, None, &bytes);
    }

    /// Integers as the narrowest type `ty` chose for them.
    fn ints(&mut self, indent: usize, name: &str, ty: IntType, values: &[i64]) {
        let bytes: Vec<u8> = match ty {
            IntType::I8 => values.iter().map(|&v| v as i8 as u8).collect(),
            IntType::I32 => values
                .iter()
                .flat_map(|&v| (v as i32).to_le_bytes())
                .collect(),
            IntType::I64 => values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        };
        self.array(indent, ty.name(), name, 1, None, &bytes);
    }
}

#[derive(Clone, Copy)]
enum IntType {
    I8,
    I32,
    I64,
}

impl IntType {
    /// The narrowest type that holds `values` and the outline's value.
    fn of(values: &[i64]) -> IntType {
        let (lo, hi) = values
            .iter()
            .fold((OUTLINE_INT, OUTLINE_INT), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        if i8::try_from(lo).is_ok() && i8::try_from(hi).is_ok() {
            IntType::I8
        } else if i32::try_from(lo).is_ok() && i32::try_from(hi).is_ok() {
            IntType::I32
        } else {
            IntType::I64
        }
    }

    fn name(self) -> &'static str {
        match self {
            IntType::I8 => "Int8",
            IntType::I32 => "Int32",
            IntType::I64 => "Int64",
        }
    }
}

/// One piece: its points (x, y, z each), line cells as point pairs in
/// order, the radius per cell and the fields per cell.
struct Piece<'a> {
    points: Vec<f64>,
    radii: Vec<f64>,
    outline: i64,
    fields: Vec<(&'a str, Values)>,
}

impl Writer {
    fn piece(&mut self, p: &Piece, types: &[Option<IntType>]) {
        let lines = p.radii.len();
        let _ = writeln!(
            self.xml,
            "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{lines}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
            2 * lines
        );
        self.xml.push_str("      <Points>\n");
        self.floats(8, "points", 3, &p.points);
        self.xml.push_str("      </Points>\n      <Lines>\n");
        let connectivity: Vec<i64> = (0..2 * lines as i64).collect();
        let offsets: Vec<i64> = (1..=lines as i64).map(|i| 2 * i).collect();
        // Offsets reach 2n: Int32 unless that passes its range.
        let index = if 2 * lines <= i32::MAX as usize {
            IntType::I32
        } else {
            IntType::I64
        };
        self.ints(8, "connectivity", index, &connectivity);
        self.ints(8, "offsets", index, &offsets);
        self.xml.push_str("      </Lines>\n");
        self.xml.push_str("      <PointData Scalars=\"radius\">\n");
        let per_point: Vec<f64> = p.radii.iter().flat_map(|&r| [r, r]).collect();
        self.floats(8, "radius", 1, &per_point);
        self.xml.push_str("      </PointData>\n      <CellData>\n");
        self.floats(8, "radius", 1, &p.radii);
        self.ints(8, "outline", IntType::I8, &vec![p.outline; lines]);
        for ((name, values), ty) in p.fields.iter().zip(types) {
            match (values, ty) {
                (Values::Int(v), Some(ty)) => self.ints(8, name, *ty, v),
                (Values::Float(v), _) => self.floats(8, name, 1, v),
                (Values::Int(_), None) => unreachable!("an integer field has its type"),
            }
        }
        self.xml.push_str("      </CellData>\n    </Piece>\n");
    }
}

/// The PolyData file of `system` with `fields` on its rods: XML head, then
/// the raw appended values (see the module doc).
///
/// # Panics
///
/// When a field does not hold one value per rod.
pub fn to_vtp(system: &RodSystem, fields: &[Field]) -> Vec<u8> {
    let n = system.len();
    for f in fields {
        assert_eq!(
            f.values.len(),
            n,
            "field {} needs one value per rod",
            f.name
        );
    }
    let types: Vec<Option<IntType>> = fields
        .iter()
        .map(|f| match &f.values {
            Values::Int(v) => Some(IntType::of(v)),
            Values::Float(_) => None,
        })
        .collect();
    let rods = Piece {
        points: system
            .rods
            .iter()
            .flat_map(|r| {
                let (a, b) = (r.at(-0.5 * r.length), r.at(0.5 * r.length));
                [a.x, a.y, a.z, b.x, b.y, b.z]
            })
            .collect(),
        radii: system.rods.iter().map(|r| r.radius).collect(),
        outline: 0,
        fields: fields
            .iter()
            .map(|f| (f.name.as_str(), f.values.clone()))
            .collect(),
    };
    let l = system.domain.sides;
    let corner = |i: usize| [0, 1, 2].map(|k| l[k] * ((i >> k) & 1) as f64);
    // The 12 edges: corner pairs that differ in one axis.
    let edges: Vec<(usize, usize)> = (0..8usize)
        .flat_map(|i| [1, 2, 4].map(move |bit| (i, i | bit)))
        .filter(|&(i, j)| i != j)
        .collect();
    let outline = Piece {
        points: edges
            .iter()
            .flat_map(|&(i, j)| corner(i).into_iter().chain(corner(j)))
            .collect(),
        radii: vec![0.0; edges.len()],
        outline: 1,
        fields: fields
            .iter()
            .map(|f| {
                let v = match f.values {
                    Values::Int(_) => Values::Int(vec![OUTLINE_INT; edges.len()]),
                    Values::Float(_) => Values::Float(vec![OUTLINE_FLOAT; edges.len()]),
                };
                (f.name.as_str(), v)
            })
            .collect(),
    };
    let mut w = Writer {
        xml: String::new(),
        data: Vec::new(),
    };
    w.xml.push_str("<?xml version=\"1.0\"?>\n");
    w.xml.push_str("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    w.xml.push_str("  <PolyData>\n    <FieldData>\n");
    let sides: Vec<u8> = l.iter().flat_map(|v| v.to_le_bytes()).collect();
    w.array(6, "Float64", "box_sides", 3, Some(1), &sides);
    w.array(6, "Float64", "box_origin", 3, Some(1), &[0u8; 24]);
    let periodic = system.domain.periodic.axes().map(u8::from);
    w.array(6, "Int8", "periodic", 3, Some(1), &periodic);
    w.xml.push_str("    </FieldData>\n");
    w.piece(&rods, &types);
    w.piece(&outline, &types);
    w.xml
        .push_str("  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _");
    let mut file = w.xml.into_bytes();
    file.extend_from_slice(&w.data);
    file.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
    file
}

/// `degree`: each rod's contacts.
pub fn degree_field(graph: &ContactGraph) -> Field {
    let n = graph.n_nodes() as u32;
    Field::int("degree", (0..n).map(|r| graph.degree(r) as i64).collect())
}

/// `true_cluster` (the index of the rod's true rigid cluster, largest first,
/// or -1; where clusters meet at a rod, the largest of them) and
/// `true_spans` (1 when a cluster of the rod spans under `criterion`) for
/// `n` rods.
pub fn truth_fields(truth: &Truth, n: usize, criterion: Criterion) -> [Field; 2] {
    let (mut cluster, mut spans) = (vec![-1i64; n], vec![0i64; n]);
    for (k, c) in truth.clusters.iter().enumerate() {
        let s = c.spans.is_some_and(|s| s.under(criterion));
        // A rod where clusters meet belongs to each: keep the largest.
        for &r in &c.rods {
            if cluster[r as usize] < 0 {
                cluster[r as usize] = k as i64;
            }
            spans[r as usize] |= i64::from(s);
        }
    }
    [
        Field::int("true_cluster", cluster),
        Field::int("true_spans", spans),
    ]
}

/// `id`: the ids of rods read from a file that numbers them.
pub fn id_field(ids: &[u64]) -> Field {
    Field::int("id", ids.iter().map(|&i| i as i64).collect())
}

/// A sample's per-rod fields: `body` (the index of the rod's body in the
/// reported run, largest first, or -1), `spans` (1 when that body spans
/// under `criterion`) and `degree` (contacts); with its truth, also
/// [`truth_fields`]; with the ids of rods read from a file that numbers
/// them, `id`.
pub fn sample_fields(sample: &Sample, criterion: Criterion) -> Vec<Field> {
    let n = sample.system.len();
    let (mut body, mut spans) = (vec![-1i64; n], vec![0i64; n]);
    for (k, b) in sample.reported_bodies(criterion).bodies.iter().enumerate() {
        for &r in &b.rods {
            body[r as usize] = k as i64;
            spans[r as usize] = i64::from(b.spans);
        }
    }
    let mut fields = vec![
        Field::int("body", body),
        Field::int("spans", spans),
        degree_field(&sample.graph),
    ];
    if let Some(t) = &sample.truth {
        fields.extend(truth_fields(t, n, criterion));
    }
    if let Some(ids) = &sample.ids {
        fields.push(id_field(ids));
    }
    fields
}

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

/// Writes `system` with `fields` to `path` atomically.
pub fn save(system: &RodSystem, fields: &[Field], path: &Path) -> Result<()> {
    output::write_atomic(path, to_vtp(system, fields))
}

/// Writes a sample's rods with [`sample_fields`] to `path` atomically.
pub fn save_sample(sample: &Sample, criterion: Criterion, path: &Path) -> Result<()> {
    save(&sample.system, &sample_fields(sample, criterion), path)
}
