//! Rods to files, in rgc's frame: centres in `[0, L)` along periodic axes
//! and the box at the origin (no `origin` is written), every number in its
//! shortest exact form, so that reading a file back gives the same rods bit
//! for bit. Rods read with ids keep them (an `id` column, field or the
//! dump's `id`).

use serde::Serialize;
use std::path::Path;

use super::format::{FIELDS, Format};
use super::json::JsonRod;
use crate::output;
use crate::rods::system::{Periodic, Rod, RodSystem};
use crate::{Error, Result};

/// The rods of a system in `format`, with their `ids` if they have them
/// (one per rod; otherwise a dump numbers them from 1).
///
/// # Panics
///
/// When `ids` does not hold one id per rod.
pub fn to_string(system: &RodSystem, ids: Option<&[u64]>, format: Format) -> String {
    if let Some(ids) = ids {
        assert_eq!(ids.len(), system.len(), "one id per rod");
    }
    let id = |i: usize| ids.map_or(i as u64 + 1, |ids| ids[i]);
    match format {
        Format::Csv => {
            let head = if ids.is_some() { "id," } else { "" };
            let mut out = format!("{head}{}\n", FIELDS.join(","));
            for (i, r) in system.rods.iter().enumerate() {
                if ids.is_some() {
                    out.push_str(&format!("{},", id(i)));
                }
                out.push_str(&join(&values(r), ","));
                out.push('\n');
            }
            out
        }
        Format::Json => {
            #[derive(Serialize)]
            struct Out {
                #[serde(rename = "box")]
                sides: [f64; 3],
                periodic: Periodic,
                rods: Vec<JsonRod>,
            }
            let rods = system
                .rods
                .iter()
                .enumerate()
                .map(|(i, r)| JsonRod {
                    center: r.center.into(),
                    direction: r.axis.into(),
                    length: r.length,
                    radius: r.radius,
                    id: ids.map(|_| id(i)),
                })
                .collect();
            let out = Out {
                sides: system.domain.sides,
                periodic: system.domain.periodic,
                rods,
            };
            // One rod per line, so that errors in an edited file name a useful line.
            let body = serde_json::to_string(&out).expect("rods serialize");
            body.replace("{\"center\"", "\n{\"center\"") + "\n"
        }
        Format::Lammps => {
            let d = &system.domain;
            let flag = |k: usize| if d.wraps(k) { "pp" } else { "ff" };
            let mut out = format!(
                "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS {} {} {}\n",
                system.len(),
                flag(0),
                flag(1),
                flag(2)
            );
            for s in d.sides {
                out.push_str(&format!("0 {s}\n"));
            }
            out.push_str("ITEM: ATOMS id x y z mux muy muz length radius\n");
            for (i, r) in system.rods.iter().enumerate() {
                out.push_str(&format!("{} {}\n", id(i), join(&values(r), " ")));
            }
            out
        }
    }
}

fn values(r: &Rod) -> [f64; 8] {
    [
        r.center.x, r.center.y, r.center.z, r.axis.x, r.axis.y, r.axis.z, r.length, r.radius,
    ]
}

fn join(v: &[f64], sep: &str) -> String {
    v.iter().map(f64::to_string).collect::<Vec<_>>().join(sep)
}

/// Writes a system's rods (with their ids, if any) atomically, in the
/// format of the path's extension.
pub fn save(system: &RodSystem, ids: Option<&[u64]>, path: &Path) -> Result<()> {
    let format = Format::of_path(path)?;
    if ids.is_some_and(|ids| ids.len() != system.len()) {
        return Err(Error::Parameter(format!(
            "{}: not one id per rod",
            path.display()
        )));
    }
    output::write_atomic(path, to_string(system, ids, format))
}
