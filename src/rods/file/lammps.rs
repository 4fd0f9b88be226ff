//! Rods from a LAMMPS text dump (`dump custom`): one snapshot of it, picked
//! by its index; `ITEM: UNITS` and `ITEM: TIME` (`dump_modify units yes`,
//! `time yes`) skipped; the box and boundary flags from its header (the low
//! bounds are the box's origin; shrink-wrapped axes are walls at those
//! bounds); atoms picked by type; each atom's `id` kept as the rod's id.

use std::collections::BTreeSet;
use std::path::Path;

use super::columns::Columns;
use super::format::{FileBox, Raw, id_of};
use crate::rods::system::Periodic;
use crate::{Error, Result};

/// Which snapshot of a dump to read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// The snapshot at this index in the file, from 0.
    Index(usize),
    /// The file's last snapshot.
    Last,
}

impl Frame {
    /// `N` (an index from 0) or `last`.
    pub fn parse(text: &str) -> Result<Self> {
        let t = text.trim();
        if t == "last" {
            return Ok(Frame::Last);
        }
        t.parse().map(Frame::Index).map_err(|_| {
            Error::Parameter(format!(
                "--frame takes a snapshot's index, from 0, or last; got {text:?}"
            ))
        })
    }
}

/// The header of one snapshot.
struct Header<'a> {
    /// The index of its first atom line, and how many there are.
    atoms: usize,
    count: usize,
    /// The line of `ITEM: ATOMS` and the column names it gives.
    names_line: usize,
    names: Vec<&'a str>,
    bounds: [(f64, f64); 3],
    periodic: Periodic,
}

/// Whether a line starts a snapshot.
fn starts_snapshot(line: &str) -> bool {
    ["ITEM: TIMESTEP", "ITEM: UNITS", "ITEM: TIME"].contains(&line.trim())
}

/// The header of the snapshot that starts at index `k` of `lines`.
fn header<'a>(
    lines: &[&'a str],
    k: usize,
    bad: &impl Fn(usize, String) -> Error,
) -> Result<Header<'a>> {
    let mut k = k;
    // The next line, with its number, or an error naming what was expected.
    let mut next = |what: &str| -> Result<(usize, &'a str)> {
        let at = k;
        k += 1;
        lines
            .get(at)
            .map(|l| (at + 1, l.trim()))
            .ok_or_else(|| bad(at + 1, format!("the file ends where {what} was expected")))
    };
    let (mut n, mut head) = next("ITEM: TIMESTEP")?;
    while let Some(value) = match head {
        "ITEM: UNITS" => Some("the unit style"),
        "ITEM: TIME" => Some("the time"),
        _ => None,
    } {
        next(value)?;
        (n, head) = next("ITEM: TIMESTEP")?;
    }
    if head != "ITEM: TIMESTEP" {
        return Err(bad(n, format!("expected \"ITEM: TIMESTEP\", got {head:?}")));
    }
    next("the timestep")?;
    let (n, head) = next("ITEM: NUMBER OF ATOMS")?;
    if head != "ITEM: NUMBER OF ATOMS" {
        return Err(bad(
            n,
            format!("expected \"ITEM: NUMBER OF ATOMS\", got {head:?}"),
        ));
    }
    let (n, count) = next("the number of atoms")?;
    let count: usize = count
        .parse()
        .map_err(|_| bad(n, format!("number of atoms {count:?} is not a count")))?;
    let (n, head) = next("ITEM: BOX BOUNDS")?;
    let Some(flags) = head.strip_prefix("ITEM: BOX BOUNDS") else {
        return Err(bad(
            n,
            format!("expected \"ITEM: BOX BOUNDS\", got {head:?}"),
        ));
    };
    let flags: Vec<&str> = flags.split_whitespace().collect();
    if flags.iter().any(|f| ["xy", "xz", "yz"].contains(f)) {
        return Err(bad(
            n,
            "a triclinic box: only orthogonal boxes are supported".into(),
        ));
    }
    if flags.len() != 3 {
        return Err(bad(
            n,
            format!(
                "expected three boundary flags (pp, ff ...), got {}",
                flags.len()
            ),
        ));
    }
    // Each axis has a flag per end: p (periodic, both ends or neither), f
    // (fixed), s or m (shrink-wrapped). A non-periodic axis has walls at the
    // bounds the snapshot gives, which for s and m enclose its atoms.
    if let Some(f) = flags.iter().find(|f| {
        let ends: Vec<char> = f.chars().collect();
        !(ends.len() == 2
            && ends.iter().all(|c| "pfsm".contains(*c))
            && (ends[0] == 'p') == (ends[1] == 'p'))
    }) {
        return Err(bad(
            n,
            format!("boundary flag {f:?}: each axis takes pp, or two of f, s and m (one per end)"),
        ));
    }
    let wraps: Vec<bool> = flags.iter().map(|f| *f == "pp").collect();
    let periodic = match wraps[..] {
        [true, true, true] => Periodic::Xyz,
        [true, true, false] => Periodic::Xy,
        [false, false, false] => Periodic::None,
        _ => {
            return Err(bad(
                n,
                format!(
                    "boundary flags {}: rgc supports periodic xyz, xy or none",
                    flags.join(" ")
                ),
            ));
        }
    };
    let mut bounds = [(0.0, 0.0); 3];
    for b in &mut bounds {
        let (n, text) = next("the box bounds")?;
        let v: Vec<f64> = text
            .split_whitespace()
            .map(|x| x.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad(n, format!("box bounds {text:?} are not numbers")))?;
        let [lo, hi] = v[..] else {
            return Err(bad(n, format!("expected two box bounds, got {text:?}")));
        };
        *b = (lo, hi);
    }
    let (names_line, head) = next("ITEM: ATOMS")?;
    let Some(names) = head.strip_prefix("ITEM: ATOMS") else {
        return Err(bad(
            names_line,
            format!("expected \"ITEM: ATOMS\", got {head:?}"),
        ));
    };
    Ok(Header {
        atoms: k,
        count,
        names_line,
        names: names.split_whitespace().collect(),
        bounds,
        periodic,
    })
}

/// What to take from a dump: the snapshot (by default the only one), the
/// atom types (by default all) and which column holds what.
pub(super) struct Pick<'a> {
    pub frame: Option<Frame>,
    pub types: Option<&'a [String]>,
    pub columns: &'a Columns,
}

/// The rods of one snapshot of a dump, in the file's frame, and its box.
pub(super) fn parse_lammps(
    text: &str,
    path: &Path,
    pick: &Pick,
    bad: &impl Fn(usize, String) -> Error,
) -> Result<(Vec<Raw>, FileBox)> {
    let lines: Vec<&str> = text.lines().collect();
    let filled = |from: usize| (from..lines.len()).find(|&i| !lines[i].trim().is_empty());
    let (mut k, mut index) = (0, 0);
    let chosen = loop {
        let h = header(&lines, k, bad)?;
        let end = h.atoms + h.count;
        // A snapshot with fewer atom lines than it announces ends at the
        // next item or at the end of the file: named, never read as atoms.
        let item =
            (h.atoms..end.min(lines.len())).find(|&i| lines[i].trim_start().starts_with("ITEM:"));
        if let Some(i) = item {
            return Err(bad(
                i + 1,
                format!(
                    "the snapshot holds {} atom lines where ITEM: NUMBER OF ATOMS says {}",
                    i - h.atoms,
                    h.count
                ),
            ));
        }
        if end > lines.len() {
            return Err(bad(
                lines.len() + 1,
                format!(
                    "the file ends where an atom line was expected: {} atom lines where ITEM: NUMBER OF ATOMS says {}",
                    lines.len() - h.atoms,
                    h.count
                ),
            ));
        }
        let next = filled(end);
        match (pick.frame, next) {
            (Some(Frame::Index(i)), _) if i == index => break h,
            (Some(Frame::Last), None) | (None, None) => break h,
            (None, Some(j)) if starts_snapshot(lines[j]) => {
                let more = lines[j..]
                    .iter()
                    .filter(|l| l.trim() == "ITEM: TIMESTEP")
                    .count();
                return Err(bad(
                    j + 1,
                    format!(
                        "a second snapshot: the dump holds {} snapshots; choose one with --frame N (from 0) or --frame last",
                        1 + more
                    ),
                ));
            }
            (None, Some(j)) => {
                return Err(bad(
                    j + 1,
                    format!(
                        "extra lines after the snapshot: expected the end of the file or a next snapshot, got {:?}",
                        lines[j].trim()
                    ),
                ));
            }
            (Some(Frame::Index(i)), None) => {
                return Err(Error::Parameter(format!(
                    "{}: --frame {i}: the dump holds {} snapshots, 0 to {index}",
                    path.display(),
                    index + 1
                )));
            }
            (Some(_), Some(j)) => {
                k = j;
                index += 1;
            }
        }
    };
    let Header {
        atoms,
        count,
        names_line,
        names,
        bounds,
        periodic,
    } = chosen;
    let layout = pick
        .columns
        .layout(&names, bounds)
        .map_err(|why| bad(names_line, why))?;
    let id_column = names.iter().position(|c| *c == "id");
    let type_column = match pick.types {
        Some(_) => Some(names.iter().position(|c| *c == "type").ok_or_else(|| {
            bad(
                names_line,
                format!(
                    "no column \"type\" to pick atoms by --atom-type (columns: {})",
                    names.join(" ")
                ),
            )
        })?),
        None => None,
    };
    let mut raws = Vec::with_capacity(count);
    let mut other_types = BTreeSet::new();
    for (i, line) in lines.iter().enumerate().skip(atoms).take(count) {
        let n = i + 1;
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.len() != names.len() {
            return Err(bad(
                n,
                format!("{} of {} fields", fields.len(), names.len()),
            ));
        }
        if let (Some(t), Some(types)) = (type_column, pick.types)
            && !types.iter().any(|x| x == fields[t])
        {
            other_types.insert(fields[t]);
            continue;
        }
        let rod = layout.rod(&fields).map_err(|why| bad(n, why))?;
        let id = id_column
            .map(|c| id_of(fields[c]))
            .transpose()
            .map_err(|why| bad(n, why))?;
        raws.push(Raw { line: n, rod, id });
    }
    if let Some(types) = pick.types
        && raws.is_empty()
        && count > 0
    {
        let there: Vec<&str> = other_types.into_iter().take(10).collect();
        return Err(Error::Parameter(format!(
            "{}: no atom of type {} in the snapshot (types there: {})",
            path.display(),
            types.join(", "),
            there.join(", ")
        )));
    }
    Ok((
        raws,
        FileBox {
            sides: Some(bounds.map(|(lo, hi)| hi - lo)),
            periodic: Some(periodic),
            origin: Some(bounds.map(|(lo, _)| lo)),
        },
    ))
}
