//! Rods from JSON: an object `{"box": [LX, LY, LZ], "origin": [X, Y, Z],
//! "periodic": "xyz", "rods": [{"center": [..], "direction": [..],
//! "length": .., "radius": .., "id": ..}, ..]}` whose box, origin,
//! periodicity and ids may be left out; each rod named by the line it
//! starts on.

use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;

use super::format::{FileBox, Raw, rod_of};
use crate::rods::system::Periodic;
use crate::{Error, Result};

/// One rod of the JSON format (the id last, and only where the rods are
/// numbered, so that files without ids keep their shape).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct JsonRod {
    pub center: [f64; 3],
    pub direction: [f64; 3],
    pub length: f64,
    pub radius: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonFile<'a> {
    #[serde(rename = "box")]
    sides: Option<[f64; 3]>,
    origin: Option<[f64; 3]>,
    periodic: Option<Periodic>,
    #[serde(borrow)]
    rods: Vec<&'a RawValue>,
}

/// The rods of a JSON file, in the file's frame, and its box.
pub(super) fn parse_json(
    text: &str,
    bad: &impl Fn(usize, String) -> Error,
) -> Result<(Vec<Raw>, FileBox)> {
    if text.trim_start().starts_with('[') {
        return Err(bad(
            1,
            "a rods JSON file is an object {\"box\": [LX, LY, LZ], \"periodic\": \"xyz\", \"rods\": [...]} (box, origin and periodic optional), not a bare list".into(),
        ));
    }
    let file: JsonFile = serde_json::from_str(text).map_err(|e| bad(e.line(), e.to_string()))?;
    // Each rod's raw text lies inside `text`, so its offset gives its line.
    let line_of = |raw: &RawValue| {
        let offset = raw.get().as_ptr() as usize - text.as_ptr() as usize;
        1 + text.as_bytes()[..offset]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    };
    let mut raws = Vec::with_capacity(file.rods.len());
    for raw in file.rods {
        let line = line_of(raw);
        let r: JsonRod =
            serde_json::from_str(raw.get()).map_err(|e| bad(line + e.line() - 1, e.to_string()))?;
        let [x, y, z] = r.center;
        let [dx, dy, dz] = r.direction;
        raws.push(Raw {
            line,
            rod: rod_of([x, y, z, dx, dy, dz, r.length, r.radius]),
            id: r.id,
        });
    }
    Ok((
        raws,
        FileBox {
            sides: file.sides,
            periodic: file.periodic,
            origin: file.origin,
        },
    ))
}
