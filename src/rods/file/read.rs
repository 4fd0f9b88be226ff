//! Reading a rods file: the rods and box its format's reader gives, moved
//! into rgc's frame and checked.
//!
//! The box's lowest corner (its origin: the options', a JSON `origin`, a
//! dump's low bounds; 0 by default) moves to 0, and along a periodic axis a
//! centre outside `[0, L)` is wrapped into it and counted, so that centred
//! frames (`[-L/2, L/2)`, HOOMD's) and centres at exactly `L` (after
//! `np.mod`) read as they are meant. Along a wall a centre is not moved:
//! cores that cross a wall are cut to the box ([`Domain::cut`]) and
//! counted, and a core wholly outside the walls is refused.
//!
//! Every rod is checked, and the first problem stops the read with its line:
//! a field that is not a finite number, a zero direction, a length or radius
//! that is not positive, a rod wider than long, a core entirely outside the
//! walls, a rod given twice, ids given to some rods only or twice, and a
//! CSV or dump that ends mid-line (without a line break after its last line:
//! a cut file, whose last number may be cut short and still parse).

use nalgebra::Vector3;
use std::io::Read;
use std::path::Path;

use super::columns::Columns;
use super::format::{FileBox, Format, Raw};
use super::json::parse_json;
use super::lammps::{Frame, Pick, parse_lammps};
use super::table::parse_csv;
use crate::error::short;
use crate::rods::system::{Cut, Domain, Periodic, Rod, RodSystem, wrap};
use crate::{Error, Result};

/// How to read a rods file: its format, the box where the file does not
/// carry one (or to check the file's against), and what to take from a
/// LAMMPS dump.
#[derive(Clone, Debug, Default)]
pub struct ReadOptions {
    /// `None`: by the extension.
    pub format: Option<Format>,
    pub sides: Option<[f64; 3]>,
    pub periodic: Option<Periodic>,
    /// The box's lowest corner in the file's coordinates (`None`: the
    /// file's, else 0).
    pub origin: Option<[f64; 3]>,
    pub columns: Columns,
    /// The snapshot of a dump (`None`: the dump must hold one).
    pub frame: Option<Frame>,
    /// Only the atoms of a dump of these types (`None`: all).
    pub types: Option<Vec<String>>,
}

/// A system read from a file.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub system: RodSystem,
    /// Rods whose cores were cut at a wall.
    pub cut: usize,
    /// Rods whose centres were wrapped into the box along a periodic axis.
    pub wrapped: usize,
    /// The line of each rod in the file.
    pub lines: Vec<usize>,
    /// Each rod's id, when the file numbers its rods (a CSV `id` column, a
    /// JSON `id`, a dump's atom ids).
    pub ids: Option<Vec<u64>>,
}

/// What placing a file's rods in the box did to them, one line each for a
/// report: the rods `cut` at a wall and the centres `wrapped` into the box.
pub fn placement(cut: usize, wrapped: usize) -> Vec<String> {
    let mut lines = Vec::new();
    if cut > 0 {
        let rods = if cut == 1 { "rod" } else { "rods" };
        lines.push(format!("{cut} {rods} cut at the walls of the box"));
    }
    if wrapped > 0 {
        let centres = if wrapped == 1 { "centre" } else { "centres" };
        lines.push(format!(
            "{wrapped} rod {centres} wrapped into the box along periodic axes"
        ));
    }
    lines
}

/// The path that stands for standard input.
pub const STDIN: &str = "-";

/// Reads and checks the rods of `path`, or of standard input for
/// [`STDIN`], whose format is the options' or else told by its first
/// characters ([`Format::sniff`]); see the module docs.
pub fn read(path: &Path, opts: &ReadOptions) -> Result<Loaded> {
    if path == Path::new(STDIN) {
        let name = Path::new("standard input");
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|e| Error::io(name, e))?;
        let format = opts.format.unwrap_or_else(|| Format::sniff(&text));
        return parse(&text, name, format, opts);
    }
    let format = match opts.format {
        Some(f) => f,
        None => Format::of_path(path)?,
    };
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse(&text, path, format, opts)
}

/// [`read`] on text already in memory; `path` names it in errors.
pub fn parse(text: &str, path: &Path, format: Format, opts: &ReadOptions) -> Result<Loaded> {
    let bad = |line: usize, reason: String| Error::Malformed {
        format: format.name(),
        path: path.to_path_buf(),
        line,
        reason,
    };
    if format != Format::Lammps {
        let dump_only = [
            ("--lammps-columns", opts.columns != Columns::default()),
            ("--frame", opts.frame.is_some()),
            ("--atom-type", opts.types.is_some()),
        ];
        if let Some((flag, _)) = dump_only.iter().find(|(_, on)| *on) {
            return Err(Error::Parameter(format!(
                "{flag} applies to LAMMPS dumps; {} is read as {}",
                path.display(),
                format.name()
            )));
        }
    }
    if format != Format::Json
        && let Some(line) = unterminated(text)
    {
        return Err(bad(line, MID_LINE.into()));
    }
    let (raws, file_box) = match format {
        Format::Csv => (parse_csv(text, &bad)?, FileBox::default()),
        Format::Json => parse_json(text, &bad)?,
        Format::Lammps => {
            let pick = Pick {
                frame: opts.frame,
                types: opts.types.as_deref(),
                columns: &opts.columns,
            };
            parse_lammps(text, path, &pick, &bad)?
        }
    };
    if raws.is_empty() {
        return Err(Error::Parameter(format!(
            "{}: the file holds no rods",
            path.display()
        )));
    }
    let (domain, origin) = box_of(path, opts, file_box)?;
    let ids = ids_of(&raws, &bad)?;
    let mut rods = Vec::with_capacity(raws.len());
    let mut lines = Vec::with_capacity(raws.len());
    let (mut cut, mut wrapped) = (0, 0);
    for Raw { line, rod, .. } in raws {
        if let Some(reason) = rod.defect() {
            return Err(bad(line, reason));
        }
        let mut placed = Rod::new(rod.center - origin, rod.axis, rod.length, rod.radius);
        let mut moved = false;
        for k in (0..3).filter(|&k| domain.wraps(k)) {
            let x = placed.center[k];
            placed.center[k] = wrap(x, domain.sides[k]);
            moved |= placed.center[k] != x;
        }
        wrapped += usize::from(moved);
        let placed = match domain.cut(&placed) {
            Cut::Whole(r) => r,
            Cut::Cut(r) => {
                cut += 1;
                r
            }
            Cut::Outside => return Err(bad(line, outside(&rod, &domain, origin))),
        };
        rods.push(placed);
        lines.push(line);
    }
    let system = RodSystem::checked(domain, rods, |i| format!("line {}", lines[i])).map_err(
        |(rod, why)| match rod {
            Some(i) => bad(lines[i], why),
            None => Error::Parameter(format!("{}: {why}", path.display())),
        },
    )?;
    Ok(Loaded {
        system,
        cut,
        wrapped,
        lines,
        ids,
    })
}

/// Why a file whose last line has no line break is refused.
const MID_LINE: &str = "the file ends mid-line, without a line break after its last line (a cut file? its last number may be cut short)";

/// The number of the last line when no line break ends it (`\n`, `\r\n`
/// and a lone `\r` each end a line).
fn unterminated(text: &str) -> Option<usize> {
    let b = text.as_bytes();
    let cut = !matches!(b.last(), None | Some(b'\n' | b'\r'));
    cut.then(|| {
        let lone_cr = (0..b.len())
            .filter(|&i| b[i] == b'\r' && b.get(i + 1) != Some(&b'\n'))
            .count();
        1 + b.iter().filter(|&&c| c == b'\n').count() + lone_cr
    })
}

/// The rods' ids: none, or one for every rod and each once.
fn ids_of(raws: &[Raw], bad: &impl Fn(usize, String) -> Error) -> Result<Option<Vec<u64>>> {
    let Some(numbered) = raws.iter().find(|r| r.id.is_some()) else {
        return Ok(None);
    };
    let mut first = rustc_hash::FxHashMap::default();
    let mut ids = Vec::with_capacity(raws.len());
    for r in raws {
        let Some(id) = r.id else {
            return Err(bad(
                r.line,
                format!(
                    "this rod has no id, but the rod on line {} has one",
                    numbered.line
                ),
            ));
        };
        if let Some(line) = first.insert(id, r.line) {
            return Err(bad(
                r.line,
                format!("id {id} is given twice (first on line {line})"),
            ));
        }
        ids.push(id);
    }
    Ok(Some(ids))
}

/// Why a rod, in the file's frame, is outside the box: only a core wholly
/// beyond the walls is (a centre on a periodic axis is wrapped).
fn outside(rod: &Rod, domain: &Domain, origin: Vector3<f64>) -> String {
    let c = rod.center;
    let at = if origin == Vector3::zeros() {
        String::new()
    } else {
        format!(
            " from ({}, {}, {})",
            short(origin.x),
            short(origin.y),
            short(origin.z)
        )
    };
    format!(
        "rod at ({}, {}, {}) lies wholly outside the walls of the box {}{at}",
        short(c.x),
        short(c.y),
        short(c.z),
        domain.describe()
    )
}

/// The box and its origin from the options and the file: both may give
/// each, and must then agree.
fn box_of(path: &Path, opts: &ReadOptions, file: FileBox) -> Result<(Domain, Vector3<f64>)> {
    let clash = |what: &str| {
        Error::Parameter(format!(
            "{}: the file's {what} differs from the one given on the command line; give one or make them agree",
            path.display()
        ))
    };
    let sides = match (opts.sides, file.sides) {
        (Some(a), Some(b)) if a != b => return Err(clash("box")),
        (Some(s), _) | (None, Some(s)) => s,
        (None, None) => {
            return Err(Error::Parameter(format!(
                "{}: the file has no box; give it with --box L or --box LX,LY,LZ",
                path.display()
            )));
        }
    };
    let periodic = match (opts.periodic, file.periodic) {
        (Some(a), Some(b)) if a != b => return Err(clash("periodicity")),
        (Some(p), _) | (None, Some(p)) => p,
        (None, None) => Periodic::Xyz,
    };
    let origin = match (opts.origin, file.origin) {
        (Some(a), Some(b)) if a != b => return Err(clash("origin")),
        (Some(o), _) | (None, Some(o)) => o,
        (None, None) => [0.0; 3],
    };
    if let Some(o) = origin.iter().find(|o| !o.is_finite()) {
        return Err(Error::Parameter(format!(
            "{}: the box's origin must be finite, got {o}",
            path.display()
        )));
    }
    Ok((Domain::new(sides, periodic)?, Vector3::from(origin)))
}

#[cfg(test)]
mod tests {
    use super::{placement, unterminated};

    #[test]
    fn a_last_line_without_a_line_break_is_found_with_its_number() {
        assert_eq!(unterminated("a\nb\n"), None);
        assert_eq!(unterminated("a\r\nb\r\n"), None);
        assert_eq!(unterminated("a\rb\r"), None);
        assert_eq!(unterminated("a\nb\n# end"), Some(3));
        assert_eq!(unterminated(""), None);
        assert_eq!(unterminated("a"), Some(1));
        assert_eq!(unterminated("a\nb\n1,0.0"), Some(3));
        assert_eq!(unterminated("a\r\nb\r\n1,0.0"), Some(3));
        assert_eq!(unterminated("a\rb\r\n\n1"), Some(4));
    }

    #[test]
    fn placement_says_only_what_happened_in_words_that_agree() {
        assert!(placement(0, 0).is_empty());
        assert_eq!(placement(1, 0), ["1 rod cut at the walls of the box"]);
        assert_eq!(
            placement(3, 1),
            [
                "3 rods cut at the walls of the box",
                "1 rod centre wrapped into the box along periodic axes"
            ]
        );
    }
}
