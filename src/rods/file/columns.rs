//! Which column of a LAMMPS dump holds which quantity of a rod, and how an
//! atom line becomes a rod: centres absolute or scaled (`xs`, `xsu`: a
//! fraction of the box side, made absolute with the box bounds), the axis
//! as a direction or as a quaternion rotating the body x axis.

use nalgebra::Vector3;

use super::format::{FIELDS, number};
use crate::rods::system::{Rod, rotate};
use crate::{Error, Result};

/// The keys of a column mapping: the quantities of [`FIELDS`], then the
/// four parts of an orientation quaternion `(w, i, j, k)`.
pub const KEYS: [&str; 12] = [
    "x", "y", "z", "dx", "dy", "dz", "length", "radius", "quatw", "quati", "quatj", "quatk",
];

/// The column each key reads when not mapped. The direction is `mux muy
/// muz` (a dipole or orientation vector) or, in a dump without them, the
/// quaternion `quatw quati quatj quatk`.
const DEFAULTS: [&str; 12] = [
    "x", "y", "z", "mux", "muy", "muz", "length", "radius", "quatw", "quati", "quatj", "quatk",
];

/// Where a LAMMPS dump keeps each quantity of [`KEYS`]: the keys mapped on
/// the command line, the others at their default columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Columns {
    given: [Option<Source>; 12],
}

/// One quantity's place in a LAMMPS dump.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// The per-atom column of this name.
    Column(String),
    /// This value for every rod.
    Value(f64),
}

/// The axis a scaled coordinate column (`xs`, `ys`, `zs`, or unwrapped
/// `xsu`, `ysu`, `zsu`) measures, if `name` is one.
fn scaled_axis(name: &str) -> Option<usize> {
    ["x", "y", "z"]
        .iter()
        .position(|a| name == format!("{a}s") || name == format!("{a}su"))
}

impl Columns {
    /// Parses `KEY=COLUMN` or `KEY=VALUE` pairs, comma-separated, over the
    /// defaults: e.g. `dx=c_u[1],dy=c_u[2],dz=c_u[3],length=1,radius=0.02`.
    /// A direction and a quaternion exclude each other, and a scaled
    /// coordinate column gives only the centre along its own axis.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |why: String| Error::Parameter(format!("LAMMPS column mapping: {why}"));
        let mut cols = Columns::default();
        for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let Some((key, value)) = pair.split_once('=') else {
                return Err(Error::Parameter(format!(
                    "LAMMPS column mapping {pair:?}: expected KEY=COLUMN or KEY=VALUE"
                )));
            };
            let key = key.trim();
            let Some(k) = KEYS.iter().position(|f| *f == key) else {
                return Err(bad(format!(
                    "unknown key {key:?} (keys: {})",
                    KEYS.join(", ")
                )));
            };
            if cols.given[k].is_some() {
                return Err(bad(format!("{key:?} is given twice")));
            }
            let value = value.trim();
            let source = match value.parse::<f64>() {
                Ok(v) => Source::Value(v),
                Err(_) if !value.is_empty() => Source::Column(value.into()),
                Err(_) => return Err(bad(format!("no column for {key:?}"))),
            };
            if let Some(axis) = scaled_axis(value) {
                let centre = ["x", "y", "z"][axis];
                if k >= 3 {
                    return Err(bad(format!(
                        "{key}={value}: {value} is a scaled coordinate, which gives only a centre ({centre}={value})"
                    )));
                }
                if k != axis {
                    return Err(bad(format!(
                        "{key}={value}: {value} is the scaled {centre} coordinate; map {key} to {key}s or {key}su"
                    )));
                }
            }
            cols.given[k] = Some(source);
        }
        if cols.given[3..6].iter().any(Option::is_some)
            && cols.given[8..].iter().any(Option::is_some)
        {
            return Err(bad(
                "give the axis either as a direction (dx, dy, dz) or as a quaternion (quatw, quati, quatj, quatk), not both"
                    .into(),
            ));
        }
        Ok(cols)
    }

    /// Where `key` was mapped, if it was.
    pub fn get(&self, key: &str) -> Option<&Source> {
        let k = KEYS.iter().position(|f| *f == key)?;
        self.given[k].as_ref()
    }

    /// The source of key `k`: as mapped, or its default column.
    fn source(&self, k: usize) -> Source {
        self.given[k]
            .clone()
            .unwrap_or_else(|| Source::Column(DEFAULTS[k].into()))
    }

    /// How the atom lines under the header `names` become rods in a box of
    /// `bounds` (low and high per axis); the reason when a column is missing.
    pub(super) fn layout(
        &self,
        names: &[&str],
        bounds: [(f64, f64); 3],
    ) -> std::result::Result<Layout, String> {
        let place = |k: usize| -> std::result::Result<Place, String> {
            match self.source(k) {
                Source::Value(v) => Ok(Place::Value(v)),
                Source::Column(c) => {
                    let Some(at) = names.iter().position(|h| *h == c) else {
                        let scaled = k < 3
                            && self.given[k].is_none()
                            && names.iter().any(|h| scaled_axis(h) == Some(k));
                        let hint = if scaled {
                            ", e.g. x=xs,y=ys,z=zs for scaled coordinates"
                        } else if k == 3 && self.given[3].is_none() {
                            ", or dump the quaternion quatw quati quatj quatk"
                        } else {
                            ""
                        };
                        return Err(format!(
                            "no column {c:?} for {} (columns: {}; map them with --lammps-columns{hint})",
                            KEYS[k],
                            names.join(" ")
                        ));
                    };
                    Ok(match scaled_axis(&c) {
                        Some(axis) => {
                            let (lo, hi) = bounds[axis];
                            Place::Scaled(at, lo, hi - lo)
                        }
                        None => Place::Column(at),
                    })
                }
            }
        };
        let center = [place(0)?, place(1)?, place(2)?];
        let has = |k: usize| names.contains(&DEFAULTS[k]);
        let quaternion = self.given[8..].iter().any(Option::is_some)
            || (self.given[3..6].iter().all(Option::is_none) && !has(3) && has(8));
        let axis = if quaternion {
            Axis::Quaternion([place(8)?, place(9)?, place(10)?, place(11)?])
        } else {
            Axis::Direction([place(3)?, place(4)?, place(5)?])
        };
        Ok(Layout {
            center,
            axis,
            length: place(6)?,
            radius: place(7)?,
        })
    }
}

/// Where one number of a rod is in an atom line.
#[derive(Clone, Copy, Debug)]
pub(super) enum Place {
    /// A column, as it is.
    Column(usize),
    /// A scaled coordinate column, and its axis's low bound and side.
    Scaled(usize, f64, f64),
    /// The same value for every rod.
    Value(f64),
}

impl Place {
    fn read(self, fields: &[&str], name: &str) -> std::result::Result<f64, String> {
        match self {
            Place::Column(at) => number(fields[at], name),
            Place::Scaled(at, lo, side) => Ok(lo + number(fields[at], name)? * side),
            Place::Value(v) => Ok(v),
        }
    }
}

/// How a rod's axis is given.
#[derive(Clone, Copy, Debug)]
pub(super) enum Axis {
    Direction([Place; 3]),
    /// `(w, i, j, k)`, rotating the body x axis.
    Quaternion([Place; 4]),
}

/// How an atom line becomes a rod.
#[derive(Clone, Copy, Debug)]
pub(super) struct Layout {
    center: [Place; 3],
    axis: Axis,
    length: Place,
    radius: Place,
}

impl Layout {
    /// The rod of one atom line's fields (its centre absolute, in the
    /// file's frame), or why not.
    pub fn rod(&self, fields: &[&str]) -> std::result::Result<Rod, String> {
        let c = self.center;
        let center = Vector3::new(
            c[0].read(fields, FIELDS[0])?,
            c[1].read(fields, FIELDS[1])?,
            c[2].read(fields, FIELDS[2])?,
        );
        let axis = match self.axis {
            Axis::Direction(d) => Vector3::new(
                d[0].read(fields, FIELDS[3])?,
                d[1].read(fields, FIELDS[4])?,
                d[2].read(fields, FIELDS[5])?,
            ),
            Axis::Quaternion(q) => {
                let mut v = [0.0; 4];
                for (k, p) in q.iter().enumerate() {
                    v[k] = p.read(fields, KEYS[8 + k])?;
                }
                rotate(v, [1.0, 0.0, 0.0]).ok_or_else(|| {
                    format!(
                        "the quaternion ({}, {}, {}, {}) is not a rotation",
                        v[0], v[1], v[2], v[3]
                    )
                })?
            }
        };
        Ok(Rod {
            center,
            axis,
            length: self.length.read(fields, FIELDS[6])?,
            radius: self.radius.read(fields, FIELDS[7])?,
        })
    }
}
