//! Rods files: round trips and every bad input.

use std::path::Path;

use nalgebra::Vector3;
use rgc::Error;
use rgc::contacts::detect;
use rgc::rods::ensemble::{Dist, Ensemble, Orientation};
use rgc::rods::file::{self, Columns, Format, ReadOptions};
use rgc::rods::{Domain, Periodic, Rod, RodSystem};
use serde_json::Value;

use crate::cli::rgc;
use crate::scratch;

pub(crate) const FORMATS: [Format; 3] = [Format::Csv, Format::Json, Format::Lammps];

/// A polydisperse, partly aligned system: lognormal lengths (mean 1, sd
/// 0.2), uniform radii in [0.01, 0.03], nematic order 0.5 about z.
fn polydisperse(sides: [f64; 3], periodic: Periodic, seed: u64) -> RodSystem {
    let ensemble = Ensemble {
        domain: Domain { sides, periodic },
        density: 30.0,
        length: Dist::Lognormal { mean: 1.0, sd: 0.2 },
        radius: Dist::Uniform { lo: 0.01, hi: 0.03 },
        orientation: Orientation::Aligned {
            order: 0.5,
            director: [0.0, 0.0, 1.0],
        },
    };
    ensemble.check().unwrap();
    ensemble.generate(seed).unwrap()
}

/// How to read a file of `format` in `domain`: a CSV takes its box from the
/// options, the others carry it.
pub(crate) fn options(format: Format, domain: &Domain) -> ReadOptions {
    match format {
        Format::Csv => ReadOptions {
            sides: Some(domain.sides),
            periodic: Some(domain.periodic),
            ..ReadOptions::default()
        },
        _ => ReadOptions::default(),
    }
}

/// The line of the first rod in files written by [`file::to_string`] and [`file_of`].
fn first_line(format: Format) -> usize {
    match format {
        Format::Csv | Format::Json => 2,
        Format::Lammps => 10,
    }
}

/// The name of a format in error messages.
fn format_name(format: Format) -> &'static str {
    match format {
        Format::Csv => "rods CSV",
        Format::Json => "rods JSON",
        Format::Lammps => "LAMMPS dump",
    }
}

pub(crate) fn bits(r: &Rod) -> [u64; 8] {
    [
        r.center.x, r.center.y, r.center.z, r.axis.x, r.axis.y, r.axis.z, r.length, r.radius,
    ]
    .map(f64::to_bits)
}

/// Writes `system` in `format` and reads it back: the same rods to the last
/// bit, the same box, no rod cut again, each rod on its own line, and the
/// same contacts.
fn assert_round_trip(system: &RodSystem, format: Format) {
    let text = file::to_string(system, None, format);
    let opts = options(format, &system.domain);
    let loaded = file::parse(&text, Path::new("rods"), format, &opts)
        .unwrap_or_else(|e| panic!("{format:?}: {e}"));
    assert_eq!(loaded.cut, 0, "{format:?}");
    assert_eq!(loaded.system.domain, system.domain, "{format:?}");
    assert_eq!(loaded.system.len(), system.len(), "{format:?}");
    assert!(loaded.system.rods == system.rods, "{format:?}: rods differ");
    let differ =
        (system.rods.iter().zip(&loaded.system.rods)).position(|(a, b)| bits(a) != bits(b));
    assert_eq!(differ, None, "{format:?}: a rod differs in its bits");
    let first = first_line(format);
    assert_eq!(
        loaded.lines,
        (first..first + system.len()).collect::<Vec<_>>(),
        "{format:?}"
    );
    let (a, b) = (detect(system), detect(&loaded.system));
    assert!(!a.is_empty());
    assert!(
        a == b,
        "{format:?}: {} contacts, {} read back",
        a.len(),
        b.len()
    );
}

/// Rods of `system` with a core end on a wall (to rounding): the ones the generator cut.
fn on_walls(system: &RodSystem) -> usize {
    let d = &system.domain;
    let touches = |r: &Rod| {
        (0..3).filter(|&k| !d.wraps(k)).any(|k| {
            [-0.5, 0.5].iter().any(|s| {
                let x = r.at(s * r.length)[k];
                x.abs() < 1e-9 || (x - d.sides[k]).abs() < 1e-9
            })
        })
    };
    system.rods.iter().filter(|r| touches(r)).count()
}

/// Generated polydisperse, aligned systems in a periodic cube and a periodic
/// box of three sides read back from every format as the very same system.
#[test]
fn periodic_systems_read_back_bit_for_bit() {
    for (sides, seed) in [([5.0; 3], 1), ([5.0, 6.0, 7.0], 2)] {
        let system = polydisperse(sides, Periodic::Xyz, seed);
        for format in FORMATS {
            assert_round_trip(&system, format);
        }
    }
}

/// Systems whose rods were cut at walls (a slab and a closed box) read back
/// whole: a cut rod is not cut again, in every format.
#[test]
fn cut_systems_read_back_whole() {
    for (sides, periodic) in [([5.0, 6.0, 7.0], Periodic::Xy), ([5.0; 3], Periodic::None)] {
        let system = polydisperse(sides, periodic, 4);
        assert!(on_walls(&system) > 20, "{periodic:?}: too few cut rods");
        for format in FORMATS {
            assert_round_trip(&system, format);
        }
    }
}

/// A CSV's columns in any order, among others, give the same rods.
#[test]
fn csv_columns_in_any_order() {
    let text = "id,radius,length,dz,dy,dx,z,y,x,colour\n\
                7,0.02,1.5,2,2,1,3,2,1,red\n";
    let loaded = file::parse(
        text,
        Path::new("rods.csv"),
        Format::Csv,
        &options(Format::Csv, &Domain::cube(4.0)),
    )
    .unwrap();
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let rod = Rod::new(Vector3::new(1.0, 2.0, 3.0), axis, 1.5, 0.02);
    assert_eq!(loaded.system.rods, vec![rod]);
    assert_eq!(loaded.lines, vec![2]);
    assert_eq!(loaded.ids, Some(vec![7]));
}

/// Runs `rgc` with `args`, which must succeed.
pub(crate) fn run(args: &[&str]) {
    let out = rgc(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `rgc` with `args`, which must fail with exit code 2 and one line on
/// stderr, and gives that line.
pub(crate) fn cli_error(args: &[&str]) -> String {
    let out = rgc(args);
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err:?}");
    assert!(err.starts_with("rgc: error: "), "{err:?}");
    assert!(!err.contains("panicked"), "{err:?}");
    err.trim_end().to_string()
}

/// A generated sample saved as CSV, JSON or a LAMMPS dump and read back with
/// `--rods` gives byte-identical bodies and GraphML.
#[test]
fn cli_rods_files_give_the_same_sample() {
    let dir = scratch("rodfiles-cli-round-trip");
    let path = |name: &str| dir.join(name).display().to_string();
    for ext in ["csv", "json", "dump"] {
        let rods = path(&format!("a.{ext}"));
        let (b1, g1) = (
            path(&format!("b1-{ext}.json")),
            path(&format!("g1-{ext}.graphml")),
        );
        let (b2, g2) = (
            path(&format!("b2-{ext}.json")),
            path(&format!("g2-{ext}.graphml")),
        );
        let common = ["sample", "--seed", "3"];
        run(&[
            &common[..],
            &["--gamma", "23", "--box", "4", "--density", "40"],
            &[
                "--save-rods",
                &rods,
                "--save-bodies",
                &b1,
                "--save-graphml",
                &g1,
            ],
        ]
        .concat());
        let boxed: &[&str] = if ext == "csv" { &["--box", "4"] } else { &[] };
        run(&[
            &common[..],
            &["--rods", &rods],
            boxed,
            &["--save-bodies", &b2, "--save-graphml", &g2],
        ]
        .concat());
        let (a, b) = (std::fs::read(&g1).unwrap(), std::fs::read(&g2).unwrap());
        assert!(a.len() > 1000, "{ext}: a near-empty output");
        assert!(a == b, "{ext}: the GraphML differs");
        let (a, b) = (std::fs::read(&b1).unwrap(), std::fs::read(&b2).unwrap());
        if ext == "dump" {
            // A dump numbers its atoms (from 1): the bodies read back carry those ids.
            let mut read: Value = serde_json::from_slice(&b).unwrap();
            for body in read["bodies"].as_array_mut().unwrap() {
                let ids = body.as_object_mut().unwrap().remove("ids").unwrap();
                let rods: Vec<u64> = serde_json::from_value(body["rods"].clone()).unwrap();
                let ids: Vec<u64> = serde_json::from_value(ids).unwrap();
                assert_eq!(ids, rods.iter().map(|r| r + 1).collect::<Vec<_>>());
            }
            let written: Value = serde_json::from_slice(&a).unwrap();
            assert!(!String::from_utf8_lossy(&a).contains("\"ids\""));
            assert_eq!(written, read, "{ext}: the bodies differ");
        } else {
            assert!(a.len() > 1000, "{ext}: a near-empty output");
            assert!(a == b, "{ext}: the bodies differ");
        }
    }
}

/// A good rod, and another: the first two rods of each bad file.
pub(crate) const GOOD: [&str; 2] = ["1,1,1,1,0,0,1,0.02", "2,2,2,0,0,1,1,0.02"];
/// A good rod after the bad one.
const LAST: &str = "3,3,3,0,1,0,1,0.02";
/// A good rod whose radius, cut by one digit, is another good radius.
const WIDER: &str = "3,3,3,0,1,0,1,0.025";

/// Rods given as comma-separated `x,y,z,dx,dy,dz,length,radius` rows, as a
/// file of `format` (in a box of side 4 for JSON and LAMMPS), one rod a line
/// from [`first_line`] on, ending with a newline.
pub(crate) fn file_of(format: Format, rows: &[&str], periodic: Periodic) -> String {
    match format {
        Format::Csv => {
            let mut text = "x,y,z,dx,dy,dz,length,radius\n".to_string();
            for row in rows {
                text += &format!("{row}\n");
            }
            text
        }
        Format::Json => {
            let rods: Vec<String> = rows
                .iter()
                .map(|row| {
                    let f: Vec<&str> = row.split(',').collect();
                    format!(
                        "{{\"center\":[{},{},{}],\"direction\":[{},{},{}],\"length\":{},\"radius\":{}}}",
                        f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7]
                    )
                })
                .collect();
            format!(
                "{{\"box\":[4,4,4],\"periodic\":\"{}\",\"rods\":[\n{}\n]}}\n",
                periodic.name(),
                rods.join(",\n")
            )
        }
        Format::Lammps => {
            let flags = periodic.axes().map(|p| if p { "pp" } else { "ff" });
            let mut text = format!(
                "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS {}\n0 4\n0 4\n0 4\n\
                 ITEM: ATOMS id x y z mux muy muz length radius\n",
                rows.len(),
                flags.join(" ")
            );
            for (i, row) in rows.iter().enumerate() {
                text += &format!("{} {}\n", i + 1, row.replace(',', " "));
            }
            text
        }
    }
}

/// Parses `text`, which must be refused as malformed with a one-line
/// message of the documented shape; gives its line and reason.
pub(crate) fn malformed(text: &str, format: Format, opts: &ReadOptions) -> (usize, String) {
    let err = file::parse(text, Path::new("bad"), format, opts).expect_err("a bad file is refused");
    let message = err.to_string();
    let Error::Malformed { line, reason, .. } = err else {
        panic!("{format:?}: {message} is not a malformed-file error");
    };
    assert_eq!(
        message,
        format!(
            "malformed {} file bad: line {line}: {reason}",
            format_name(format)
        )
    );
    assert!(!message.contains('\n'), "{message:?}");
    (line, reason)
}

/// Asserts that the rows, as a file of `format` in a box of side 4, are
/// refused at `line` with a reason containing `phrase`.
fn assert_refused(format: Format, text: &str, periodic: Periodic, line: usize, phrase: &str) {
    let domain = Domain {
        sides: [4.0; 3],
        periodic,
    };
    let (at, reason) = malformed(text, format, &options(format, &domain));
    assert_eq!(at, line, "{format:?}: {reason}");
    assert!(
        reason.contains(phrase),
        "{format:?}: {reason:?} lacks {phrase:?}"
    );
}

/// Every bad rod, in every format, is refused at its own line: the bad rod,
/// the periodicity it is read with, and the key phrase of the reason in CSV
/// and LAMMPS, then in JSON (whose parser refuses what is not a number).
#[test]
fn every_bad_rod_is_refused_at_its_line() {
    let cases = [
        (
            "1,1,-0.5,1,0,0,1,0.02",
            Periodic::Xy,
            "rod at (1, 1, -0.5) lies wholly outside the walls of the box 4",
            None,
        ),
        (
            "6,2,2,1,0,0,1,0.02",
            Periodic::None,
            "rod at (6, 2, 2) lies wholly outside the walls of the box 4",
            None,
        ),
        (
            "1,1,3,1,0,0,0,0.02",
            Periodic::Xyz,
            "length 0 is not positive",
            None,
        ),
        (
            "1,1,3,1,0,0,1,-0.01",
            Periodic::Xyz,
            "radius -0.01 is not positive",
            None,
        ),
        (
            "1,NaN,3,1,0,0,1,0.02",
            Periodic::Xyz,
            "y is NaN, not a finite number",
            Some("expected value"),
        ),
        (
            "1,1,3,inf,0,0,1,0.02",
            Periodic::Xyz,
            "direction x is inf, not a finite number",
            Some("expected value"),
        ),
        (
            "1,1,3,0,0,0,1,0.02",
            Periodic::Xyz,
            "the direction is the zero vector",
            None,
        ),
        (
            "1,1,abc,1,0,0,1,0.02",
            Periodic::Xyz,
            "z \"abc\" is not a number",
            Some("expected value"),
        ),
    ];
    for (bad, periodic, phrase, json_phrase) in cases {
        for format in FORMATS {
            let text = file_of(format, &[GOOD[0], GOOD[1], bad, LAST], periodic);
            let phrase = match format {
                Format::Json => json_phrase.unwrap_or(phrase),
                _ => phrase,
            };
            assert_refused(format, &text, periodic, first_line(format) + 2, phrase);
        }
    }
}

/// A rod given twice (same centre and axis, also reversed) is refused at the
/// second copy, naming the first copy's line; the same centre with another
/// axis is a different rod.
#[test]
fn a_rod_given_twice_names_the_first_copy() {
    let rod = "1,1,1,1,2,2,1,0.02";
    for copy in [rod, "1,1,1,2,4,4,1,0.02", "1,1,1,-2,-4,-4,1,0.02"] {
        for format in FORMATS {
            let first = first_line(format);
            let text = file_of(format, &[GOOD[1], rod, GOOD[0], copy], Periodic::Xyz);
            let phrase = format!("the same rod as line {}", first + 1);
            assert_refused(format, &text, Periodic::Xyz, first + 3, &phrase);
        }
    }
    for format in FORMATS {
        let text = file_of(format, &[rod, "1,1,1,1,2,-2,1,0.02"], Periodic::Xyz);
        let opts = options(format, &Domain::cube(4.0));
        let loaded = file::parse(&text, Path::new("ok"), format, &opts).unwrap();
        assert_eq!(loaded.system.len(), 2);
    }
}

/// Why a CSV or dump whose last line has no line break is refused.
const MID_LINE: &str = "the file ends mid-line, without a line break after its last line (a cut file? its last number may be cut short)";

/// A last line without a newline is refused as a file that ends mid-line,
/// even when it parses (its last number cut short: `0.02` read as `0.0`
/// would be a rod of radius 0, `0.025` as `0.02` a silently wrong rod); a
/// short line with its newline, or a long one, is refused as such.
#[test]
fn a_file_ending_mid_line_is_named() {
    let opts = options(Format::Csv, &Domain::cube(4.0));
    let whole = file_of(Format::Csv, &[GOOD[0], GOOD[1], "3,3,3,1"], Periodic::Xyz);
    let (line, reason) = malformed(whole.trim_end(), Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (4, MID_LINE));
    let (line, reason) = malformed(&whole, Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (4, "4 of 8 fields"));
    // Cut inside the last number: every field there and a number still.
    let cut = file_of(Format::Csv, &[GOOD[0], WIDER], Periodic::Xyz);
    let cut = cut.trim_end().strip_suffix('5').unwrap();
    file::parse(&format!("{cut}\n"), Path::new("c.csv"), Format::Csv, &opts).unwrap();
    let (line, reason) = malformed(cut, Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (3, MID_LINE));
    // A last line kept whole but for its line break: still refused, since
    // a cut file cannot be told from it.
    let (line, reason) = malformed(whole.trim_end(), Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (4, MID_LINE));
    // Even a last comment line: the rule is a line break at the end.
    let commented = format!("{}# end", file_of(Format::Csv, &GOOD[..2], Periodic::Xyz));
    let (line, reason) = malformed(&commented, Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (4, MID_LINE));
    let long = file_of(
        Format::Csv,
        &[GOOD[0], "3,3,3,1,0,0,1,0.02,9"],
        Periodic::Xyz,
    );
    let (line, reason) = malformed(&long, Format::Csv, &opts);
    assert_eq!(
        (line, reason.as_str()),
        (3, "9 fields, but the header names 8")
    );

    let dump = file_of(Format::Lammps, &[GOOD[0], GOOD[1], LAST], Periodic::Xyz);
    let short = dump.trim_end().rsplit_once(' ').unwrap().0.to_string();
    let (line, reason) = malformed(&short, Format::Lammps, &ReadOptions::default());
    assert_eq!((line, reason.as_str()), (12, MID_LINE));
    let (line, reason) = malformed(&(short + "\n"), Format::Lammps, &ReadOptions::default());
    assert_eq!((line, reason.as_str()), (12, "8 of 9 fields"));
    // Cut inside the last number of the last atom: all nine fields there.
    let wider = file_of(Format::Lammps, &[GOOD[0], GOOD[1], WIDER], Periodic::Xyz);
    let digit = wider.trim_end().strip_suffix('5').unwrap();
    let (line, reason) = malformed(digit, Format::Lammps, &ReadOptions::default());
    assert_eq!((line, reason.as_str()), (12, MID_LINE));
    // JSON closes its brackets last: a cut file does not parse.
    let json = file_of(Format::Json, &GOOD[..2], Periodic::Xyz);
    let json = json.trim_end();
    file::parse(
        json,
        Path::new("j.json"),
        Format::Json,
        &options(Format::Json, &Domain::cube(4.0)),
    )
    .unwrap();
    let (_, reason) = malformed(
        &json[..json.len() - 5],
        Format::Json,
        &options(Format::Json, &Domain::cube(4.0)),
    );
    assert!(reason.contains("EOF while parsing"), "{reason}");
}

/// Comments before the header and right after it leave the rows' line numbers right.
#[test]
fn csv_comments_around_the_header() {
    let text = format!(
        "# written by hand\nx,y,z,dx,dy,dz,length,radius\n# the rods\n{}\n1,1,zz,1,0,0,1,0.02\n",
        GOOD[0]
    );
    let opts = options(Format::Csv, &Domain::cube(4.0));
    let (line, reason) = malformed(&text, Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (5, "z \"zz\" is not a number"));
}

/// Comment and blank lines between rows count: each rod, and a bad row,
/// is named by its line in the file.
#[test]
fn csv_comment_lines_between_rows_count() {
    let opts = options(Format::Csv, &Domain::cube(4.0));
    let text = format!(
        "x,y,z,dx,dy,dz,length,radius\n{}\n# more\n\n{}\n",
        GOOD[0], GOOD[1]
    );
    let loaded = file::parse(&text, Path::new("c.csv"), Format::Csv, &opts).unwrap();
    assert_eq!(loaded.lines, vec![2, 5]);
    let bad = format!("{text}# last\n1,1,zz,1,0,0,1,0.02\n");
    let (line, reason) = malformed(&bad, Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (7, "z \"zz\" is not a number"));
    let mid = format!("{text}# last\n1,1");
    let (line, reason) = malformed(&mid, Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (7, MID_LINE));
}

/// A CSV with CRLF line ends (as written on Windows) names the same lines.
#[test]
fn csv_crlf_line_ends_count() {
    let opts = options(Format::Csv, &Domain::cube(4.0));
    let text = file_of(Format::Csv, &[GOOD[0], GOOD[1], GOOD[0]], Periodic::Xyz);
    let (line, reason) = malformed(&text.replace('\n', "\r\n"), Format::Csv, &opts);
    assert_eq!(line, 4);
    assert!(reason.starts_with("the same rod as line 2 "), "{reason}");
    let mid = file_of(Format::Csv, &[GOOD[0], "1,1"], Periodic::Xyz).replace('\n', "\r\n");
    let (line, reason) = malformed(mid.trim_end(), Format::Csv, &opts);
    assert_eq!((line, reason.as_str()), (3, MID_LINE));
}

/// A missing column is refused at the header: the CSV's first line, the dump's `ITEM: ATOMS`.
#[test]
fn a_missing_column_is_refused_at_the_header() {
    let opts = options(Format::Csv, &Domain::cube(4.0));
    let (line, reason) = malformed("x,y,z,dx,dy,dz,length\n1,1,1,1,0,0,1\n", Format::Csv, &opts);
    assert_eq!(line, 1);
    assert!(
        reason.contains("the header has no column \"radius\""),
        "{reason}"
    );

    let dump = file_of(Format::Lammps, &GOOD, Periodic::Xyz).replace(" radius\n", "\n");
    let dump = dump.replace(" 0.02\n", "\n");
    let (line, reason) = malformed(&dump, Format::Lammps, &ReadOptions::default());
    assert_eq!(line, 9);
    assert!(
        reason.starts_with("no column \"radius\" for radius"),
        "{reason}"
    );

    let opts = ReadOptions {
        columns: Columns::parse("dx=c_u[1],dy=c_u[2],dz=c_u[3]").unwrap(),
        ..ReadOptions::default()
    };
    let dump = file_of(Format::Lammps, &GOOD, Periodic::Xyz);
    let (line, reason) = malformed(&dump, Format::Lammps, &opts);
    assert_eq!(line, 9);
    assert!(
        reason.starts_with("no column \"c_u[1]\" for dx"),
        "{reason}"
    );
}

/// A dump of two snapshots, with no snapshot asked for, is refused at the
/// second, naming how many there are and the flag; a triclinic box at its
/// bounds line.
#[test]
fn lammps_one_orthogonal_snapshot_unless_one_is_asked_for() {
    let dump = file_of(Format::Lammps, &GOOD, Periodic::Xyz);
    let (line, reason) = malformed(&dump.repeat(2), Format::Lammps, &ReadOptions::default());
    assert_eq!(line, 12);
    assert_eq!(
        reason,
        "a second snapshot: the dump holds 2 snapshots; choose one with --frame N (from 0) or --frame last"
    );
    let (line, reason) = malformed(
        &(dump.clone() + "1 2 3\n"),
        Format::Lammps,
        &ReadOptions::default(),
    );
    assert_eq!(line, 12);
    assert!(
        reason.starts_with("extra lines after the snapshot"),
        "{reason}"
    );

    let triclinic = dump
        .replace("BOX BOUNDS pp pp pp", "BOX BOUNDS xy xz yz pp pp pp")
        .replace("0 4\n", "0 4 0\n");
    let (line, reason) = malformed(&triclinic, Format::Lammps, &ReadOptions::default());
    assert_eq!(line, 5);
    assert!(reason.contains("a triclinic box"), "{reason}");
}

/// Writes `text` to `name` in `dir` and gives its path.
pub(crate) fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// Bad files through the command line: exit code 2 and one line naming the line.
#[test]
fn cli_names_the_bad_line() {
    let dir = scratch("rodfiles-cli-bad-line");
    let zero = write(
        &dir,
        "zero.csv",
        &file_of(
            Format::Csv,
            &[GOOD[0], GOOD[1], "1,1,3,1,0,0,0,0.02"],
            Periodic::Xyz,
        ),
    );
    assert_eq!(
        cli_error(&["sample", "--rods", &zero, "--box", "4"]),
        format!("rgc: error: malformed rods CSV file {zero}: line 4: length 0 is not positive")
    );

    let rows = [
        GOOD[0],
        "1,1,3,1,2,2,1,0.02",
        GOOD[1],
        "1,1,3,-1,-2,-2,1,0.02",
    ];
    let twice = write(
        &dir,
        "twice.json",
        &file_of(Format::Json, &rows, Periodic::Xyz),
    );
    let err = cli_error(&["sample", "--rods", &twice]);
    assert!(
        err.contains(&format!(
            "malformed rods JSON file {twice}: line 5: the same rod as line 3"
        )),
        "{err}"
    );

    let mid = file_of(Format::Csv, &[GOOD[0], "2,2"], Periodic::Xyz);
    let mid = write(&dir, "mid.csv", mid.trim_end());
    let err = cli_error(&["sample", "--rods", &mid, "--box", "4"]);
    assert!(err.contains(&format!("line 3: {MID_LINE}")), "{err}");

    let dump = file_of(Format::Lammps, &GOOD, Periodic::Xyz);
    let two = write(&dir, "two.dump", &dump.repeat(2));
    let err = cli_error(&["sample", "--rods", &two]);
    assert!(
        err.contains("LAMMPS dump file") && err.contains("line 12: a second snapshot"),
        "{err}"
    );

    let one = write(&dir, "one.lammpstrj", &dump);
    let err = cli_error(&["sample", "--rods", &one, "--lammps-columns", "dx=c_u[1]"]);
    assert!(err.contains("line 9: no column \"c_u[1]\" for dx"), "{err}");
}
