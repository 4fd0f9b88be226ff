//! The formats of rods files, and what each reader hands on: the rods as
//! written, with their lines and ids, and what the file says about its box.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::path::Path;

use crate::rods::system::{Periodic, Rod};
use crate::{Error, Result};

/// The file formats of rods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Format {
    Csv,
    Json,
    /// A LAMMPS text dump (`dump custom`).
    Lammps,
}

impl Format {
    /// The format a file name's extension means: `.csv`, `.json`, or
    /// `.dump`, `.lammpstrj` for LAMMPS.
    pub fn of_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Ok(Format::Csv),
            "json" => Ok(Format::Json),
            "dump" | "lammpstrj" => Ok(Format::Lammps),
            _ => Err(Error::Parameter(format!(
                "{}: unknown rods file extension {ext:?} (use .csv, .json, .dump or .lammpstrj, or give --rods-format)",
                path.display()
            ))),
        }
    }

    /// The format text read without a name is in: JSON when it opens with
    /// `{` or `[`, a LAMMPS dump with `ITEM:`, else CSV (whose header the
    /// reader then checks).
    pub fn sniff(text: &str) -> Self {
        let start = text.trim_start();
        if start.starts_with(['{', '[']) {
            Format::Json
        } else if start.starts_with("ITEM:") {
            Format::Lammps
        } else {
            Format::Csv
        }
    }

    /// What a file of this format is called in messages.
    pub fn name(self) -> &'static str {
        match self {
            Format::Csv => "rods CSV",
            Format::Json => "rods JSON",
            Format::Lammps => "LAMMPS dump",
        }
    }
}

/// The quantities of a rod, in the order of the CSV header.
pub const FIELDS: [&str; 8] = ["x", "y", "z", "dx", "dy", "dz", "length", "radius"];

/// One rod as read, before the box is known: in the file's frame, with its
/// line and, where the file numbers its rods, its id.
pub(super) struct Raw {
    pub line: usize,
    pub rod: Rod,
    pub id: Option<u64>,
}

/// What a file says about its box.
#[derive(Default)]
pub(super) struct FileBox {
    pub sides: Option<[f64; 3]>,
    pub periodic: Option<Periodic>,
    /// The box's lowest corner in the file's frame.
    pub origin: Option<[f64; 3]>,
}

/// A field as a finite or infinite number, or why not.
pub(super) fn number(field: &str, name: &str) -> std::result::Result<f64, String> {
    field
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("{name} {field:?} is not a number"))
}

/// A field as a rod's id: a whole number, or why not.
pub(super) fn id_of(field: &str) -> std::result::Result<u64, String> {
    field
        .trim()
        .parse::<u64>()
        .map_err(|_| format!("id {field:?} is not a whole number"))
}

/// A rod of the values of [`FIELDS`], its axis as given.
pub(super) fn rod_of(v: [f64; 8]) -> Rod {
    Rod {
        center: Vector3::new(v[0], v[1], v[2]),
        axis: Vector3::new(v[3], v[4], v[5]),
        length: v[6],
        radius: v[7],
    }
}
