//! Rods files in their box: the box given or carried, cores cut at walls,
//! centred boxes and centres at `L` wrapped into the box, origins, LAMMPS
//! column maps, and rod ids.

use std::path::Path;

use nalgebra::Vector3;
use rgc::Error;
use rgc::rods::file::{self, Columns, Format, Loaded, ReadOptions, Source};
use rgc::rods::{Domain, Periodic, Rod};
use serde_json::Value;

use crate::cli::{json, rgc, stdout_of};
use crate::rodfiles::{FORMATS, GOOD, bits, cli_error, file_of, malformed, options, run, write};
use crate::scratch;

/// The box of a rods file: needed for a CSV, one or three sides, agreeing
/// with the file's, not with the flags of generated rods, and large enough
/// for the longest rod along periodic sides only.
#[test]
fn cli_box_handling() {
    let dir = scratch("rodfiles-cli-box");
    let csv = write(
        &dir,
        "rods.csv",
        &file_of(Format::Csv, &GOOD, Periodic::Xyz),
    );
    let json = write(
        &dir,
        "rods.json",
        &file_of(Format::Json, &GOOD, Periodic::Xyz),
    );

    let err = cli_error(&["sample", "--rods", &csv]);
    assert!(
        err.contains("the file has no box; give it with --box"),
        "{err}"
    );
    let err = cli_error(&["sample", "--rods", &csv, "--box", "4,5"]);
    assert!(
        err.contains("--box takes one side L or three sides LX,LY,LZ, got 2 numbers"),
        "{err}"
    );
    run(&["sample", "--rods", &csv, "--box", "4,5,6"]);

    let err = cli_error(&["sample", "--rods", &json, "--box", "5"]);
    assert!(err.contains("the file's box differs"), "{err}");
    let err = cli_error(&["sample", "--rods", &json, "--periodic", "none"]);
    assert!(err.contains("the file's periodicity differs"), "{err}");
    run(&["sample", "--rods", &json, "--box", "4", "--periodic", "xyz"]);

    for flag in [["--gamma", "23"], ["--density", "40"]] {
        let err = cli_error(&[&["sample", "--rods", &csv, "--box", "4"][..], &flag].concat());
        assert!(
            err.contains(&format!("{} describes generated rods", flag[0])),
            "{err}"
        );
    }

    let long = write(
        &dir,
        "long.csv",
        &file_of(
            Format::Csv,
            &[GOOD[0], "2,2,2,1,0,0,2.5,0.02"],
            Periodic::Xyz,
        ),
    );
    let err = cli_error(&["sample", "--rods", &long, "--box", "4"]);
    assert!(
        err.contains(&format!("{long}: box side 4 along x is too small")),
        "{err}"
    );
    run(&[
        "sample",
        "--rods",
        &long,
        "--box",
        "4",
        "--periodic",
        "none",
    ]);
}

/// Through the library, a box too small for the longest rod is the box's
/// fault (a parameter error), not a line's.
#[test]
fn a_box_too_small_is_a_parameter_error() {
    let text = file_of(
        Format::Csv,
        &[GOOD[0], "2,2,2,1,0,0,2.5,0.02"],
        Periodic::Xyz,
    );
    let opts = options(Format::Csv, &Domain::cube(4.0));
    match file::parse(&text, Path::new("long.csv"), Format::Csv, &opts) {
        Err(Error::Parameter(why)) => {
            assert!(
                why.starts_with("long.csv: box side 4 along x is too small"),
                "{why}"
            )
        }
        other => panic!("{other:?}"),
    }
}

fn assert_close(a: [f64; 3], b: [f64; 3]) {
    let off = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
    assert!(off < 1e-12, "{a:?} != {b:?}");
}

/// The centre, length and axis of a rod.
fn shape(rod: &Rod) -> ([f64; 3], f64, [f64; 3]) {
    (rod.center.into(), rod.length, rod.axis.into())
}

/// Cores crossing a wall are cut to the box, with hand-computed lengths and
/// centres, and counted; a centre outside the walls whose core reaches in is
/// cut too; a core across a periodic face is not cut, and a cut centre that
/// moves through a periodic face is wrapped.
#[test]
fn cores_are_cut_at_the_walls() {
    let rows = [
        "0.2,2,2,1,0,0,1,0.02",
        "-0.3,1,1,1,0,0,1,0.02",
        "2,3,3.9,0,0.6,0.8,1,0.02",
        "2,2,2,1,0,0,1,0.02",
    ];
    let text = file_of(Format::Csv, &rows, Periodic::None);
    let none = Domain {
        sides: [4.0; 3],
        periodic: Periodic::None,
    };
    let loaded = file::parse(
        &text,
        Path::new("cut.csv"),
        Format::Csv,
        &options(Format::Csv, &none),
    )
    .unwrap();
    assert_eq!(loaded.cut, 3);
    assert_eq!(loaded.lines, vec![2, 3, 4, 5]);
    let expected = [
        ([0.35, 2.0, 2.0], 0.7, [1.0, 0.0, 0.0]),
        ([0.1, 1.0, 1.0], 0.2, [1.0, 0.0, 0.0]),
        ([2.0, 2.8875, 3.75], 0.625, [0.0, 0.6, 0.8]),
        ([2.0, 2.0, 2.0], 1.0, [1.0, 0.0, 0.0]),
    ];
    for (rod, (center, length, axis)) in loaded.system.rods.iter().zip(expected) {
        let (c, l, a) = shape(rod);
        assert_close(c, center);
        assert!((l - length).abs() < 1e-12, "{l} != {length}");
        assert_eq!(a, axis);
        assert_eq!(rod.radius, 0.02);
    }
    assert_eq!(
        loaded.system.rods[3],
        Rod::new(Vector3::new(2.0, 2.0, 2.0), Vector3::x(), 1.0, 0.02)
    );

    let slab = Domain {
        sides: [4.0; 3],
        periodic: Periodic::Xy,
    };
    let rows = ["0.1,2,2,1,0,0,1,0.02", "0.1,2,3.9,0.6,0,0.8,1,0.02"];
    let text = file_of(Format::Csv, &rows, Periodic::Xy);
    let loaded = file::parse(
        &text,
        Path::new("slab.csv"),
        Format::Csv,
        &options(Format::Csv, &slab),
    )
    .unwrap();
    assert_eq!(loaded.cut, 1);
    let rods = &loaded.system.rods;
    assert_eq!(shape(&rods[0]), ([0.1, 2.0, 2.0], 1.0, [1.0, 0.0, 0.0]));
    let (c, l, _) = shape(&rods[1]);
    assert_close(c, [3.9875, 2.0, 3.75]);
    assert!((l - 0.625).abs() < 1e-12, "{l}");
}

/// The command line reports the cut rods (`sample` and `truth` say so
/// before their report) and saves their cut parts.
#[test]
fn cli_reports_and_saves_cut_rods() {
    let dir = scratch("rodfiles-cli-cut");
    let rows = [
        "0.2,2,2,1,0,0,1,0.02",
        "-0.3,1,1,1,0,0,1,0.02",
        "2,2,2,1,0,0,1,0.02",
    ];
    let rods = write(
        &dir,
        "cut.csv",
        &file_of(Format::Csv, &rows, Periodic::None),
    );
    let saved = dir.join("saved.json");
    let out = rgc(&[
        "sample",
        "--rods",
        &rods,
        "--box",
        "4",
        "--periodic",
        "none",
        "--json",
        "--save-rods",
        saved.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["cut"], 2);
    assert_eq!(report["n_rods"], 3);
    assert_eq!(report["periodic"], "none");
    for cmd in ["sample", "truth"] {
        let out = rgc(&[cmd, "--rods", &rods, "--box", "4", "--periodic", "none"]);
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            text.starts_with("2 rods cut at the walls of the box\n3 rods,"),
            "{cmd}: {text}"
        );
    }
    let loaded: Loaded = file::read(&saved, &ReadOptions::default()).unwrap();
    assert_eq!(loaded.cut, 0);
    let lengths: Vec<f64> = loaded.system.rods.iter().map(|r| r.length).collect();
    assert!(
        (lengths[0] - 0.7).abs() < 1e-12 && (lengths[1] - 0.2).abs() < 1e-12,
        "{lengths:?}"
    );
    assert_eq!(lengths[2], 1.0);
}

/// A dump with `xu yu zu` centres and `c_o[..]` directions, its box away
/// from the origin and walls along z.
const MAPPED_DUMP: &str = "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n3\n\
ITEM: BOX BOUNDS pp pp ff\n-2 2\n-2.5 2.5\n10 14\n\
ITEM: ATOMS id type xu yu zu c_o[1] c_o[2] c_o[3]\n\
1 1 -1.5 0.5 12 1 0 0\n\
2 1 0.25 -0.75 13 0 0 1\n\
3 1 1 1 13.5 0 0 2\n";

const MAPPING: &str = "x=xu,y=yu,z=zu,dx=c_o[1],dy=c_o[2],dz=c_o[3],length=1.5,radius=0.05";

/// Columns mapped by name and by value: rods moved to the origin with the
/// given length and radius, `pp pp ff` a slab whose z walls cut.
#[test]
fn lammps_columns_map_and_the_box_moves_to_the_origin() {
    let columns = Columns::parse(MAPPING).unwrap();
    assert_eq!(columns.get("x"), Some(&Source::Column("xu".into())));
    assert_eq!(columns.get("length"), Some(&Source::Value(1.5)));
    assert_eq!(columns.get("quatw"), None);
    let opts = ReadOptions {
        columns,
        ..ReadOptions::default()
    };
    let loaded = file::parse(MAPPED_DUMP, Path::new("o.dump"), Format::Lammps, &opts).unwrap();
    let d = loaded.system.domain;
    assert_eq!(d.sides, [4.0, 5.0, 4.0]);
    assert_eq!(d.periodic, Periodic::Xy);
    assert_eq!(loaded.lines, vec![10, 11, 12]);
    assert_eq!(loaded.cut, 1);
    let v = Vector3::new;
    let rods = &loaded.system.rods;
    assert_eq!(
        rods[0],
        Rod::new(v(0.5, 3.0, 2.0), v(1.0, 0.0, 0.0), 1.5, 0.05)
    );
    assert_eq!(
        rods[1],
        Rod::new(v(2.25, 1.75, 3.0), v(0.0, 0.0, 1.0), 1.5, 0.05)
    );
    assert_eq!(
        rods[2],
        Rod::new(v(3.0, 3.5, 3.375), v(0.0, 0.0, 1.0), 1.25, 0.05)
    );

    let dir = scratch("rodfiles-lammps-columns");
    let dump = write(&dir, "o.lammpstrj", MAPPED_DUMP);
    let report = json(&[
        "sample",
        "--rods",
        &dump,
        "--lammps-columns",
        MAPPING,
        "--json",
    ]);
    assert_eq!(report["n_rods"], 3);
    assert_eq!(report["periodic"], "xy");
    assert_eq!(report["box"], serde_json::json!([4.0, 5.0, 4.0]));
    assert_eq!(report["cut"], 1);
    let radius = report["mean_radius"].as_f64().unwrap();
    assert!((radius - 0.05).abs() < 1e-15, "{radius}");
}

/// The rows of [`HOOMD`] in rgc's frame: each centre moved by 2 and the two
/// on the box's upper face wrapped to 0.
const HOOMD_IN_BOX: [&str; 4] = [
    "0.5,3.75,1,1,0,0,1,0.02",
    "2,2,2,0,0,1,1,0.02",
    "0,1,3,0,1,0,1,0.02",
    "3.5,0,0.25,1,1,0,1,0.02",
];

/// Rods in a centred box of side 4 (`[-2, 2)`, HOOMD's frame), two of them
/// with a centre on the upper face `2` (as `np.mod` can leave it).
const HOOMD: [&str; 4] = [
    "-1.5,1.75,-1,1,0,0,1,0.02",
    "0,0,0,0,0,1,1,0.02",
    "2,-1,1,0,1,0,1,0.02",
    "1.5,2,-1.75,1,1,0,1,0.02",
];

/// A centred box read with its origin: the same rods as the box at 0, two
/// centres wrapped and counted, in CSV (origin from the options), JSON (an
/// `origin` field) and a LAMMPS dump (its low bounds); a centre at exactly
/// `L`, or below 0, along a periodic axis wraps without an origin too.
#[test]
fn centred_boxes_and_centres_at_l_wrap_into_the_box() {
    let at_zero = file::parse(
        &file_of(Format::Csv, &HOOMD_IN_BOX, Periodic::Xyz),
        Path::new("zero.csv"),
        Format::Csv,
        &options(Format::Csv, &Domain::cube(4.0)),
    )
    .unwrap();
    assert_eq!(at_zero.wrapped, 0);
    let json = file_of(Format::Json, &HOOMD, Periodic::Xyz)
        .replace("\"box\":[4,4,4]", "\"box\":[4,4,4],\"origin\":[-2,-2,-2]");
    let dump = file_of(Format::Lammps, &HOOMD, Periodic::Xyz).replace("0 4\n", "-2 2\n");
    let csv = file_of(Format::Csv, &HOOMD, Periodic::Xyz);
    let csv_opts = ReadOptions {
        origin: Some([-2.0; 3]),
        ..options(Format::Csv, &Domain::cube(4.0))
    };
    for (format, text, opts) in [
        (Format::Csv, &csv, csv_opts),
        (Format::Json, &json, ReadOptions::default()),
        (Format::Lammps, &dump, ReadOptions::default()),
    ] {
        let loaded = file::parse(text, Path::new("centred"), format, &opts)
            .unwrap_or_else(|e| panic!("{format:?}: {e}"));
        assert_eq!(loaded.wrapped, 2, "{format:?}");
        assert_eq!(loaded.cut, 0, "{format:?}");
        assert_eq!(loaded.system.domain, Domain::cube(4.0), "{format:?}");
        assert!(
            loaded.system.rods == at_zero.system.rods,
            "{format:?}: {:?}",
            loaded.system.rods
        );
    }

    // Without an origin: x = 4 (np.mod's L) and y = -0.5 on periodic sides.
    let rows = ["4,1,1,1,0,0,1,0.02", "1,-0.5,1,1,0,0,1,0.02", GOOD[1]];
    for periodic in [Periodic::Xyz, Periodic::Xy] {
        let domain = Domain {
            sides: [4.0; 3],
            periodic,
        };
        for format in FORMATS {
            let text = file_of(format, &rows, periodic);
            let loaded = file::parse(&text, Path::new("l"), format, &options(format, &domain))
                .unwrap_or_else(|e| panic!("{format:?}: {e}"));
            assert_eq!(loaded.wrapped, 2, "{format:?}");
            let centres: Vec<[f64; 3]> = (loaded.system.rods.iter())
                .map(|r| r.center.into())
                .collect();
            assert_eq!(
                centres,
                [[0.0, 1.0, 1.0], [1.0, 3.5, 1.0], [2.0, 2.0, 2.0]],
                "{format:?}"
            );
        }
    }
}

/// Along a wall a centre is not wrapped: a core wholly outside the walls
/// stays an error, named in the file's own coordinates; one that reaches in
/// is cut. An origin the options and the file both give must agree.
#[test]
fn walls_do_not_wrap_and_origins_must_agree() {
    let slab = Domain {
        sides: [4.0; 3],
        periodic: Periodic::Xy,
    };
    let opts = ReadOptions {
        origin: Some([-2.0; 3]),
        ..options(Format::Csv, &slab)
    };
    let outside = file_of(
        Format::Csv,
        &[GOOD[0], "0,0,2.6,1,0,0,1,0.02"],
        Periodic::Xy,
    );
    let (line, reason) = malformed(&outside, Format::Csv, &opts);
    assert_eq!(line, 3);
    assert_eq!(
        reason,
        "rod at (0, 0, 2.6) lies wholly outside the walls of the box 4 from (-2, -2, -2)"
    );
    let reaching = file_of(
        Format::Csv,
        &[GOOD[0], "0,0,-2.25,0,0,1,1,0.02"],
        Periodic::Xy,
    );
    let loaded = file::parse(&reaching, Path::new("w.csv"), Format::Csv, &opts).unwrap();
    assert_eq!((loaded.cut, loaded.wrapped), (1, 0));
    let cut = loaded.system.rods[1];
    assert_eq!(cut.length, 0.25);
    assert_eq!(cut.center.z, 0.125);

    let json = file_of(Format::Json, &GOOD, Periodic::Xyz)
        .replace("\"box\":[4,4,4]", "\"box\":[4,4,4],\"origin\":[-2,-2,-2]");
    let other = ReadOptions {
        origin: Some([-1.0; 3]),
        ..ReadOptions::default()
    };
    match file::parse(&json, Path::new("o.json"), Format::Json, &other) {
        Err(Error::Parameter(why)) => assert!(
            why.starts_with("o.json: the file's origin differs from the one given"),
            "{why}"
        ),
        other => panic!("{other:?}"),
    }
    let same = ReadOptions {
        origin: Some([-2.0; 3]),
        ..ReadOptions::default()
    };
    file::parse(&json, Path::new("o.json"), Format::Json, &same).unwrap();
}

/// Rods read with an origin and wrapped, written out in every format (in
/// rgc's frame, the box at 0) and read back without one: the very same rods
/// and ids to the last bit, nothing wrapped again.
#[test]
fn wrapped_rods_round_trip_exactly() {
    let csv = file_of(Format::Csv, &HOOMD, Periodic::Xyz).replace("x,y,z", "id,x,y,z");
    let csv: String = csv
        .lines()
        .enumerate()
        .map(|(i, l)| match i {
            0 => format!("{l}\n"),
            _ => format!("{},{l}\n", 10 * i + 3),
        })
        .collect();
    let opts = ReadOptions {
        origin: Some([-2.0; 3]),
        ..options(Format::Csv, &Domain::cube(4.0))
    };
    let loaded = file::parse(&csv, Path::new("ids.csv"), Format::Csv, &opts).unwrap();
    assert_eq!(loaded.wrapped, 2);
    assert_eq!(loaded.ids, Some(vec![13, 23, 33, 43]));
    for format in FORMATS {
        let text = file::to_string(&loaded.system, loaded.ids.as_deref(), format);
        assert!(!text.contains("origin"), "{format:?}");
        let back = file::parse(
            &text,
            Path::new("back"),
            format,
            &options(format, &loaded.system.domain),
        )
        .unwrap_or_else(|e| panic!("{format:?}: {e}"));
        assert_eq!(back.wrapped, 0, "{format:?}");
        assert_eq!(back.ids, loaded.ids, "{format:?}");
        let differ = (loaded.system.rods.iter().zip(&back.system.rods))
            .position(|(a, b)| bits(a) != bits(b));
        assert_eq!(differ, None, "{format:?}");
    }
    let text = file::to_string(&loaded.system, loaded.ids.as_deref(), Format::Csv);
    assert!(text.starts_with("id,x,y,z,dx,dy,dz,length,radius\n13,0.5,3.75,1,"));
    let json = file::to_string(&loaded.system, loaded.ids.as_deref(), Format::Json);
    assert!(json.contains("\"radius\":0.02,\"id\":43}"), "{json}");
}

/// Ids: every rod or none, each once.
#[test]
fn ids_are_all_or_none_and_unique() {
    let opts = options(Format::Csv, &Domain::cube(4.0));
    let text = format!(
        "id,x,y,z,dx,dy,dz,length,radius\n5,{}\n5,{}\n",
        GOOD[0], GOOD[1]
    );
    let (line, reason) = malformed(&text, Format::Csv, &opts);
    assert_eq!(
        (line, reason.as_str()),
        (3, "id 5 is given twice (first on line 2)")
    );
    let text = format!(
        "id,x,y,z,dx,dy,dz,length,radius\n5,{}\nrod,{}\n",
        GOOD[0], GOOD[1]
    );
    let (line, reason) = malformed(&text, Format::Csv, &opts);
    assert_eq!(
        (line, reason.as_str()),
        (3, "id \"rod\" is not a whole number")
    );
    let json = file_of(Format::Json, &GOOD, Periodic::Xyz).replacen("}", ",\"id\":4}", 1);
    let (line, reason) = malformed(&json, Format::Json, &ReadOptions::default());
    assert_eq!(
        (line, reason.as_str()),
        (3, "this rod has no id, but the rod on line 2 has one")
    );
}

/// The command line: `--origin` reads a centred CSV, the report counts the
/// wrapped centres (text and JSON, `sample` and `truth`), and `--save-rods`
/// writes them in rgc's frame, which reads back to the same bodies.
#[test]
fn cli_origin_wraps_counts_and_saves() {
    let dir = scratch("rodfiles-cli-origin");
    let csv = write(
        &dir,
        "hoomd.csv",
        &file_of(Format::Csv, &HOOMD, Periodic::Xyz),
    );
    let saved = dir.join("saved.json").display().to_string();
    let (b1, b2) = (
        dir.join("b1.json").display().to_string(),
        dir.join("b2.json").display().to_string(),
    );
    let args = ["sample", "--rods", &csv, "--box", "4", "--origin", "-2"];
    let text = stdout_of(&[&args[..], &["--save-rods", &saved, "--save-bodies", &b1]].concat());
    assert!(
        text.starts_with("2 rod centres wrapped into the box along periodic axes\n4 rods,"),
        "{text}"
    );
    let report: Value =
        serde_json::from_slice(&rgc(&[&args[..], &["--json"]].concat()).stdout).unwrap();
    assert_eq!(report["wrapped"], 2);
    assert_eq!(report["cut"], 0);
    let truth = rgc(&[
        "truth", "--rods", &csv, "--box", "4", "--origin", "-2,-2,-2",
    ]);
    let text = String::from_utf8(truth.stdout).unwrap();
    assert!(
        text.starts_with("2 rod centres wrapped into the box along periodic axes\n4 rods,"),
        "{text}"
    );

    let back = rgc(&["sample", "--rods", &saved, "--json", "--save-bodies", &b2]);
    let back: Value = serde_json::from_slice(&back.stdout).unwrap();
    assert_eq!(back["wrapped"], 0);
    assert_eq!(back["n_contacts"], report["n_contacts"]);
    assert_eq!(std::fs::read(&b1).unwrap(), std::fs::read(&b2).unwrap());
    let loaded = file::read(Path::new(&saved), &ReadOptions::default()).unwrap();
    let expected = file::parse(
        &file_of(Format::Csv, &HOOMD_IN_BOX, Periodic::Xyz),
        Path::new("zero.csv"),
        Format::Csv,
        &options(Format::Csv, &Domain::cube(4.0)),
    )
    .unwrap();
    assert!(loaded.system.rods == expected.system.rods);

    let err = cli_error(&["sample", "--rods", &csv, "--box", "4", "--origin", "1,2"]);
    assert!(
        err.contains("--origin takes one value or three X,Y,Z, got 2 numbers"),
        "{err}"
    );
    let err = cli_error(&["sample", "--rods", &csv, "--box", "4", "--frame", "1"]);
    assert!(
        err.contains("--frame applies to LAMMPS dumps; ") && err.ends_with("is read as rods CSV"),
        "{err}"
    );
}

/// JSON rods without a box: refused unless the box is given, then read in
/// it (periodic on every axis unless told otherwise), the same rods as the
/// file that carries the box; a box without a periodicity is periodic.
#[test]
fn json_rods_without_a_box_take_the_given_one() {
    let with_box = file_of(Format::Json, &GOOD, Periodic::Xyz);
    let bare = with_box.replace("\"box\":[4,4,4],\"periodic\":\"xyz\",", "");
    assert!(bare.starts_with("{\"rods\":["), "{bare}");
    let path = Path::new("bare.json");
    match file::parse(&bare, path, Format::Json, &ReadOptions::default()) {
        Err(Error::Parameter(why)) => assert_eq!(
            why,
            "bare.json: the file has no box; give it with --box L or --box LX,LY,LZ"
        ),
        other => panic!("{other:?}"),
    }
    let given = |sides, periodic| ReadOptions {
        sides: Some(sides),
        periodic,
        ..ReadOptions::default()
    };
    let read = file::parse(&bare, path, Format::Json, &given([4.0; 3], None)).unwrap();
    let carried = file::parse(&with_box, path, Format::Json, &ReadOptions::default()).unwrap();
    assert_eq!(read.system.domain, carried.system.domain);
    assert_eq!(read.system.domain.periodic, Periodic::Xyz);
    assert_eq!(read.system.rods, carried.system.rods);
    assert_eq!(read.lines, [2, 3]);
    let walls = file::parse(
        &bare,
        path,
        Format::Json,
        &given([4.0, 5.0, 6.0], Some(Periodic::None)),
    )
    .unwrap();
    assert_eq!(
        (walls.system.domain.sides, walls.system.domain.periodic),
        ([4.0, 5.0, 6.0], Periodic::None)
    );
    let no_periodic = with_box.replace("\"periodic\":\"xyz\",", "");
    let read = file::parse(&no_periodic, path, Format::Json, &ReadOptions::default()).unwrap();
    assert_eq!(read.system.domain, carried.system.domain);
}
