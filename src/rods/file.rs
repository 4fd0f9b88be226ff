//! Rods from and to files: a CSV table, JSON, and a LAMMPS dump.
//!
//! The CSV has a header naming the columns `x,y,z,dx,dy,dz,length,radius`
//! (in any order; other columns are ignored): the centre, the direction
//! (normalized on reading), the core length and the radius. JSON is an
//! object `{"box": [LX, LY, LZ], "periodic": "xyz", "rods": [{"center": [..],
//! "direction": [..], "length": .., "radius": ..}, ..]}` whose box and
//! periodicity may be left out. A LAMMPS dump holds one snapshot; its box and
//! boundary flags give the box (moved to the origin), and [`Columns`] says
//! which per-atom column holds which quantity.
//!
//! Every rod is checked, and the first problem stops the read with its line:
//! a field that is not a finite number, a zero direction, a length or radius
//! that is not positive, a centre outside a periodic side, a core entirely
//! outside the walls, a rod given twice, and a file that ends mid-line. Cores
//! that cross a wall are cut to the box ([`Domain::cut`]) and counted.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;
use std::path::Path;

use super::system::{Cut, Domain, Periodic, Rod, RodSystem};
use crate::{Error, Result, output};

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

/// Where a LAMMPS dump keeps each quantity of [`FIELDS`]: a per-atom column
/// by name, or one value for every rod.
#[derive(Clone, Debug, PartialEq)]
pub struct Columns(pub [Source; 8]);

/// One quantity's place in a LAMMPS dump.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// The per-atom column of this name.
    Column(String),
    /// This value for every rod.
    Value(f64),
}

impl Default for Columns {
    /// `x y z` for the centre, `mux muy muz` for the direction (a dipole or
    /// orientation vector), `length` and `radius`.
    fn default() -> Self {
        let names = ["x", "y", "z", "mux", "muy", "muz", "length", "radius"];
        Columns(names.map(|n| Source::Column(n.into())))
    }
}

impl Columns {
    /// Parses `KEY=COLUMN` or `KEY=VALUE` pairs, comma-separated, over the
    /// defaults: e.g. `dx=c_u[1],dy=c_u[2],dz=c_u[3],length=1,radius=0.02`.
    pub fn parse(text: &str) -> Result<Self> {
        let mut cols = Columns::default();
        let mut given = [false; FIELDS.len()];
        for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let Some((key, value)) = pair.split_once('=') else {
                return Err(Error::Parameter(format!(
                    "LAMMPS column mapping {pair:?}: expected KEY=COLUMN or KEY=VALUE"
                )));
            };
            let Some(k) = FIELDS.iter().position(|f| *f == key.trim()) else {
                return Err(Error::Parameter(format!(
                    "LAMMPS column mapping: unknown key {key:?} (keys: {})",
                    FIELDS.join(", ")
                )));
            };
            if std::mem::replace(&mut given[k], true) {
                return Err(Error::Parameter(format!(
                    "LAMMPS column mapping: {:?} is given twice",
                    FIELDS[k]
                )));
            }
            let value = value.trim();
            cols.0[k] = match value.parse::<f64>() {
                Ok(v) => Source::Value(v),
                Err(_) if !value.is_empty() => Source::Column(value.into()),
                Err(_) => {
                    return Err(Error::Parameter(format!(
                        "LAMMPS column mapping: no column for {key:?}"
                    )));
                }
            };
        }
        Ok(cols)
    }
}

/// How to read a rods file: its format, and the box where the file does not
/// carry one (or to check the file's against).
#[derive(Clone, Debug, Default)]
pub struct ReadOptions {
    /// `None`: by the extension.
    pub format: Option<Format>,
    pub sides: Option<[f64; 3]>,
    pub periodic: Option<Periodic>,
    pub columns: Columns,
}

/// A system read from a file.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub system: RodSystem,
    /// Rods whose cores were cut at a wall.
    pub cut: usize,
    /// The line of each rod in the file.
    pub lines: Vec<usize>,
}

/// One rod as read, before the box is known.
struct Raw {
    line: usize,
    rod: Rod,
}

/// What a file says about its box.
#[derive(Default)]
struct FileBox {
    sides: Option<[f64; 3]>,
    periodic: Option<Periodic>,
}

/// Reads and checks the rods of `path` (see the module docs).
pub fn read(path: &Path, opts: &ReadOptions) -> Result<Loaded> {
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
    let (raws, file_box) = match format {
        Format::Csv => (parse_csv(text, &bad)?, FileBox::default()),
        Format::Json => parse_json(text, &bad)?,
        Format::Lammps => parse_lammps(text, &opts.columns, &bad)?,
    };
    if raws.is_empty() {
        return Err(Error::Parameter(format!(
            "{}: the file holds no rods",
            path.display()
        )));
    }
    let domain = box_of(path, opts, file_box)?;
    let mut rods = Vec::with_capacity(raws.len());
    let mut lines = Vec::with_capacity(raws.len());
    let mut cut = 0;
    for Raw { line, rod } in raws {
        if let Some(reason) = rod.defect() {
            return Err(bad(line, reason));
        }
        let rod = Rod::new(rod.center, rod.axis, rod.length, rod.radius);
        let rod = match domain.cut(&rod) {
            Cut::Whole(r) => r,
            Cut::Cut(r) => {
                cut += 1;
                r
            }
            Cut::Outside => {
                return Err(bad(line, outside(&rod, &domain)));
            }
        };
        rods.push(rod);
        lines.push(line);
    }
    let system = RodSystem::checked(domain, rods, |i| format!("line {}", lines[i])).map_err(
        |(rod, why)| match rod {
            Some(i) => bad(lines[i], why),
            None => Error::Parameter(format!("{}: {why}", path.display())),
        },
    )?;
    Ok(Loaded { system, cut, lines })
}

/// Why a rod is outside the box, for the error.
fn outside(rod: &Rod, domain: &Domain) -> String {
    let c = rod.center;
    let axes = ["x", "y", "z"];
    for k in 0..3 {
        let l = domain.sides[k];
        if domain.wraps(k) && !(0.0..l).contains(&c[k]) {
            return format!(
                "centre {} = {} is outside the box [0, {l}) on a periodic side (wrap centres into the box)",
                axes[k], c[k]
            );
        }
    }
    format!(
        "rod at ({}, {}, {}) lies wholly outside the walls of the box {}",
        c.x,
        c.y,
        c.z,
        domain.describe()
    )
}

/// The box from the options and the file: both may give it, and must then agree.
fn box_of(path: &Path, opts: &ReadOptions, file: FileBox) -> Result<Domain> {
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
    Domain::new(sides, periodic)
}

fn parse_csv(text: &str, bad: &impl Fn(usize, String) -> Error) -> Result<Vec<Raw>> {
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| bad(1, e.to_string()))?.clone();
    if let Some(twice) = FIELDS
        .iter()
        .find(|f| header.iter().filter(|h| h == *f).count() > 1)
    {
        return Err(bad(
            1,
            format!("the header names the column {twice:?} twice"),
        ));
    }
    let at: Vec<usize> = FIELDS
        .iter()
        .map(|f| {
            header.iter().position(|h| h == *f).ok_or_else(|| {
                bad(
                    1,
                    format!(
                        "the header has no column {f:?} (it needs {})",
                        FIELDS.join(",")
                    ),
                )
            })
        })
        .collect::<Result<_>>()?;
    let mut raws = Vec::new();
    let mut record = csv::StringRecord::new();
    // The csv crate's own line count skips comment lines and counts CRLF
    // line ends twice, so lines are counted here, from each record's offset.
    let mut lines = LineCounter::new(text);
    loop {
        let line = lines.at(reader.position().byte() as usize);
        match reader.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => return Err(bad(line, e.to_string())),
        }
        let line = record
            .position()
            .map_or(line, |p| lines.record(p.byte() as usize));
        if record.len() < header.len() {
            let end = if lines.is_last(line) {
                "; the file ends mid-line"
            } else {
                ""
            };
            return Err(bad(
                line,
                format!("{} of {} fields{end}", record.len(), header.len()),
            ));
        }
        if record.len() > header.len() {
            return Err(bad(
                line,
                format!(
                    "{} fields, but the header names {}",
                    record.len(),
                    header.len()
                ),
            ));
        }
        let mut v = [0.0; 8];
        for (k, &col) in at.iter().enumerate() {
            v[k] = number(&record[col], FIELDS[k]).map_err(|why| bad(line, why))?;
        }
        raws.push(Raw {
            line,
            rod: rod_of(v),
        });
    }
    Ok(raws)
}

/// Line numbers of byte offsets met in increasing order, with `\n`, `\r\n`
/// and a lone `\r` each ending a line.
struct LineCounter<'a> {
    text: &'a [u8],
    offset: usize,
    line: usize,
}

impl<'a> LineCounter<'a> {
    fn new(text: &'a str) -> Self {
        LineCounter {
            text: text.as_bytes(),
            offset: 0,
            line: 1,
        }
    }

    /// The line holding byte `offset` (not before the last one asked).
    fn at(&mut self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        while self.offset < end {
            let b = self.text[self.offset];
            let next = self.text.get(self.offset + 1);
            if b == b'\n' || (b == b'\r' && next != Some(&b'\n')) {
                self.line += 1;
            }
            self.offset += 1;
        }
        self.line
    }

    /// The line of the record the csv crate places at `offset`: where it
    /// started reading, before the line breaks and comment lines it skipped.
    fn record(&mut self, offset: usize) -> usize {
        let mut at = offset;
        self.at(at);
        while let Some(&b) = self.text.get(at) {
            match b {
                b'\n' | b'\r' => at += 1,
                b'#' => {
                    while self.text.get(at).is_some_and(|&c| c != b'\n' && c != b'\r') {
                        at += 1;
                    }
                }
                _ => break,
            }
            self.at(at);
        }
        self.line
    }

    /// Whether `line` is the file's last and ends without a line break.
    fn is_last(&self, line: usize) -> bool {
        let unterminated = !self.text.ends_with(b"\n") && !self.text.ends_with(b"\r");
        let mut counter = LineCounter {
            text: self.text,
            offset: self.offset,
            line: self.line,
        };
        unterminated && counter.at(self.text.len()) == line
    }
}

fn number(field: &str, name: &str) -> std::result::Result<f64, String> {
    field
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("{name} {field:?} is not a number"))
}

fn rod_of(v: [f64; 8]) -> Rod {
    Rod {
        center: Vector3::new(v[0], v[1], v[2]),
        axis: Vector3::new(v[3], v[4], v[5]),
        length: v[6],
        radius: v[7],
    }
}

/// One rod of the JSON format.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonRod {
    center: [f64; 3],
    direction: [f64; 3],
    length: f64,
    radius: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonFile<'a> {
    #[serde(rename = "box")]
    sides: Option<[f64; 3]>,
    periodic: Option<Periodic>,
    #[serde(borrow)]
    rods: Vec<&'a RawValue>,
}

fn parse_json(text: &str, bad: &impl Fn(usize, String) -> Error) -> Result<(Vec<Raw>, FileBox)> {
    if text.trim_start().starts_with('[') {
        return Err(bad(
            1,
            "a rods JSON file is an object {\"box\": [LX, LY, LZ], \"periodic\": \"xyz\", \"rods\": [...]} (box and periodic optional), not a bare list".into(),
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
        });
    }
    Ok((
        raws,
        FileBox {
            sides: file.sides,
            periodic: file.periodic,
        },
    ))
}

fn parse_lammps(
    text: &str,
    columns: &Columns,
    bad: &impl Fn(usize, String) -> Error,
) -> Result<(Vec<Raw>, FileBox)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut k = 0;
    // The next line, with its number, or an error naming what was expected.
    let mut next = |what: &str| -> Result<(usize, &str)> {
        let at = k;
        k += 1;
        lines
            .get(at)
            .map(|l| (at + 1, l.trim()))
            .ok_or_else(|| bad(at + 1, format!("the file ends where {what} was expected")))
    };
    let (n, head) = next("ITEM: TIMESTEP")?;
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
    let mut lo = [0.0; 3];
    let mut sides = [0.0; 3];
    for axis in 0..3 {
        let (n, bounds) = next("the box bounds")?;
        let v: Vec<f64> = bounds
            .split_whitespace()
            .map(|x| x.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad(n, format!("box bounds {bounds:?} are not numbers")))?;
        let [a, b] = v[..] else {
            return Err(bad(n, format!("expected two box bounds, got {bounds:?}")));
        };
        lo[axis] = a;
        sides[axis] = b - a;
    }
    let (n, head) = next("ITEM: ATOMS")?;
    let Some(names) = head.strip_prefix("ITEM: ATOMS") else {
        return Err(bad(n, format!("expected \"ITEM: ATOMS\", got {head:?}")));
    };
    let names: Vec<&str> = names.split_whitespace().collect();
    let at: Vec<std::result::Result<usize, f64>> = columns
        .0
        .iter()
        .zip(FIELDS)
        .map(|(src, field)| match src {
            Source::Value(v) => Ok(Err(*v)),
            Source::Column(c) => names.iter().position(|h| h == c).map(Ok).ok_or_else(|| {
                bad(
                    n,
                    format!(
                        "no column {c:?} for {field} (columns: {}; map them with --lammps-columns)",
                        names.join(" ")
                    ),
                )
            }),
        })
        .collect::<Result<_>>()?;
    let mut raws = Vec::with_capacity(count);
    for _ in 0..count {
        let (n, row) = next("an atom line")?;
        let fields: Vec<&str> = row.split_whitespace().collect();
        if fields.len() != names.len() {
            let end = if n == lines.len() && !text.ends_with('\n') {
                "; the file ends mid-line"
            } else {
                ""
            };
            return Err(bad(
                n,
                format!("{} of {} fields{end}", fields.len(), names.len()),
            ));
        }
        let mut v = [0.0; 8];
        for (j, src) in at.iter().enumerate() {
            v[j] = match *src {
                Ok(col) => number(fields[col], FIELDS[j]).map_err(|why| bad(n, why))?,
                Err(value) => value,
            };
        }
        for (j, l) in lo.iter().enumerate() {
            v[j] -= l;
        }
        raws.push(Raw {
            line: n,
            rod: rod_of(v),
        });
    }
    if let Some((i, _)) = lines
        .iter()
        .enumerate()
        .skip(k)
        .find(|(_, l)| !l.trim().is_empty())
    {
        return Err(bad(
            i + 1,
            "a second snapshot or extra lines: the dump must hold one snapshot".into(),
        ));
    }
    Ok((
        raws,
        FileBox {
            sides: Some(sides),
            periodic: Some(periodic),
        },
    ))
}

/// The rods of a system in `format`, every number in its shortest exact form
/// so that reading them back gives the same rods bit for bit.
pub fn to_string(system: &RodSystem, format: Format) -> String {
    match format {
        Format::Csv => {
            let mut out = format!("{}\n", FIELDS.join(","));
            for r in &system.rods {
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
                .map(|r| JsonRod {
                    center: r.center.into(),
                    direction: r.axis.into(),
                    length: r.length,
                    radius: r.radius,
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
                out.push_str(&format!("{} {}\n", i + 1, join(&values(r), " ")));
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

/// Writes a system's rods atomically, in the format of the path's extension.
pub fn save(system: &RodSystem, path: &Path) -> Result<()> {
    let format = Format::of_path(path)?;
    output::write_atomic(path, to_string(system, format))
}
