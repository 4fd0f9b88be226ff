//! LAMMPS dumps as simulations write them: several snapshots, `ITEM: UNITS`
//! and `ITEM: TIME`, matrix atoms of other types, scaled coordinates, atom
//! ids, and orientations as quaternions.

use std::path::Path;

use nalgebra::Vector3;
use rgc::Error;
use rgc::rods::Periodic;
use rgc::rods::file::{self, Columns, Format, Frame, Loaded, ReadOptions};
use rgc::rods::rotate;
use serde_json::Value;

use crate::cli::{json, rgc};
use crate::scratch;

/// One snapshot of `rows` (`id type x y z mux muy muz` each) at `step`, in a
/// periodic box `[0, 4)^3`, with `extra` items before its timestep.
fn snapshot(step: u64, extra: &str, rows: &[&str]) -> String {
    let mut text = format!(
        "{extra}ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n\
         ITEM: ATOMS id type x y z mux muy muz\n",
        rows.len()
    );
    for row in rows {
        text += &format!("{row}\n");
    }
    text
}

const FIRST: [&str; 2] = ["1 1 1 1 1 1 0 0", "2 1 2 2 2 0 0 1"];
const SECOND: [&str; 3] = ["1 1 1.5 1 1 1 0 0", "2 1 2 2.5 2 0 0 1", "3 1 3 3 3 0 1 0"];

/// Length and radius for every rod of these dumps.
fn options() -> ReadOptions {
    ReadOptions {
        columns: Columns::parse("length=1,radius=0.02").unwrap(),
        ..ReadOptions::default()
    }
}

fn parse(text: &str, opts: &ReadOptions) -> Result<Loaded, Error> {
    file::parse(text, Path::new("d.dump"), Format::Lammps, opts)
}

fn xs(loaded: &Loaded) -> Vec<f64> {
    loaded.system.rods.iter().map(|r| r.center.x).collect()
}

/// A two-snapshot dump: refused without --frame (naming the count and the
/// flag), each snapshot by its index from 0 or `last`, and an index past the
/// end refused naming how many there are; UNITS and TIME items are skipped.
#[test]
fn a_snapshot_is_picked_by_its_index() {
    let two = snapshot(0, "ITEM: UNITS\nlj\nITEM: TIME\n0\n", &FIRST)
        + &snapshot(100, "ITEM: TIME\n0.5\n", &SECOND);
    let err = parse(&two, &options()).unwrap_err().to_string();
    assert_eq!(
        err,
        "malformed LAMMPS dump file d.dump: line 16: a second snapshot: the dump holds 2 snapshots; \
         choose one with --frame N (from 0) or --frame last"
    );
    let pick = |frame| {
        parse(
            &two,
            &ReadOptions {
                frame: Some(frame),
                ..options()
            },
        )
    };
    let first = pick(Frame::Index(0)).unwrap();
    assert_eq!(xs(&first), [1.0, 2.0]);
    assert_eq!(first.lines, [14, 15]);
    let second = pick(Frame::Index(1)).unwrap();
    assert_eq!(xs(&second), [1.5, 2.0, 3.0]);
    assert_eq!(second.lines, [27, 28, 29]);
    assert_eq!(second.ids, Some(vec![1, 2, 3]));
    assert!(pick(Frame::Last).unwrap().system.rods == second.system.rods);
    match pick(Frame::Index(2)) {
        Err(Error::Parameter(why)) => {
            assert_eq!(why, "d.dump: --frame 2: the dump holds 2 snapshots, 0 to 1")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(Frame::parse("last").unwrap(), Frame::Last);
    assert_eq!(Frame::parse("3").unwrap(), Frame::Index(3));
    assert!(Frame::parse("-1").is_err());

    let dir = scratch("dumps-frames");
    let path = dir.join("two.lammpstrj");
    std::fs::write(&path, &two).unwrap();
    let path = path.display().to_string();
    let map = ["--lammps-columns", "length=1,radius=0.02"];
    let out = rgc(&[&["sample", "--rods", &path, "--json"][..], &map].concat());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("the dump holds 2 snapshots; choose one with --frame"),
        "{err}"
    );
    for (frame, rods) in [("0", 2), ("1", 3), ("last", 3)] {
        let report = json(
            &[
                &["sample", "--rods", &path, "--json", "--frame", frame][..],
                &map,
            ]
            .concat(),
        );
        assert_eq!(report["n_rods"], rods, "--frame {frame}");
    }
}

/// Matrix atoms (type 2, no orientation) stop the read unless the rods'
/// type is picked: one type or a list; a type that is not there, or a dump
/// without types, is refused.
#[test]
fn atoms_are_picked_by_type() {
    let rows = [
        "1 1 1 1 1 1 0 0",
        "2 2 0.5 0.5 0.5 0 0 0",
        "3 1 2 2 2 0 0 1",
        "4 3 3 3 3 0 1 0",
    ];
    let dump = snapshot(0, "", &rows);
    let err = parse(&dump, &options()).unwrap_err().to_string();
    assert!(
        err.ends_with("line 11: the direction is the zero vector"),
        "{err}"
    );
    let types = |t: &[&str]| ReadOptions {
        types: Some(t.iter().map(|s| s.to_string()).collect()),
        ..options()
    };
    let rods = parse(&dump, &types(&["1"])).unwrap();
    assert_eq!(xs(&rods), [1.0, 2.0]);
    assert_eq!(rods.lines, [10, 12]);
    assert_eq!(rods.ids, Some(vec![1, 3]));
    let rods = parse(&dump, &types(&["1", "3"])).unwrap();
    assert_eq!(rods.ids, Some(vec![1, 3, 4]));
    match parse(&dump, &types(&["5"])) {
        Err(Error::Parameter(why)) => assert_eq!(
            why,
            "d.dump: no atom of type 5 in the snapshot (types there: 1, 2, 3)"
        ),
        other => panic!("{other:?}"),
    }
    let untyped = dump.replace("id type x", "id kind x");
    let err = parse(&untyped, &types(&["1"])).unwrap_err().to_string();
    assert!(
        err.contains("line 9: no column \"type\" to pick atoms by --atom-type"),
        "{err}"
    );

    let dir = scratch("dumps-types");
    let path = dir.join("matrix.dump");
    std::fs::write(&path, &dump).unwrap();
    let report = json(&[
        "sample",
        "--rods",
        path.to_str().unwrap(),
        "--lammps-columns",
        "length=1,radius=0.02",
        "--atom-type",
        "1,3",
        "--json",
    ]);
    assert_eq!(report["n_rods"], 3);
}

/// A dump with scaled coordinates in a box away from the origin.
const SCALED: &str = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n\
-2 2\n0 5\n10 14\nITEM: ATOMS id xs ys zs mux muy muz\n\
1 0.25 0.5 0.75 1 0 0\n2 0.5 0.125 1 0 0 1\n";

/// Scaled coordinates mapped to the centre are made absolute with the box
/// bounds (`xs` 0.25 of `[-2, 2)` is x = -1, at 1 in rgc's frame; `zs` 1 is
/// the upper face, wrapped to 0); mapped to another axis or quantity they
/// are refused, and an unmapped dump of them is told how to map them.
#[test]
fn scaled_coordinates_become_absolute() {
    let opts = ReadOptions {
        columns: Columns::parse("x=xs,y=ys,z=zs,length=1,radius=0.02").unwrap(),
        ..ReadOptions::default()
    };
    let loaded = parse(SCALED, &opts).unwrap();
    let centres: Vec<[f64; 3]> = loaded.system.rods.iter().map(|r| r.center.into()).collect();
    assert_eq!(centres, [[1.0, 2.5, 3.0], [2.0, 0.625, 0.0]]);
    assert_eq!(loaded.system.domain.sides, [4.0, 5.0, 4.0]);
    assert_eq!(loaded.wrapped, 1);
    let unwrapped = SCALED.replace("xs ys zs", "xsu ysu zsu");
    let opts_u = ReadOptions {
        columns: Columns::parse("x=xsu,y=ysu,z=zsu,length=1,radius=0.02").unwrap(),
        ..ReadOptions::default()
    };
    assert!(parse(&unwrapped, &opts_u).unwrap().system.rods == loaded.system.rods);

    for (map, phrase) in [
        (
            "x=ys",
            "x=ys: ys is the scaled y coordinate; map x to xs or xsu",
        ),
        (
            "dx=xs",
            "dx=xs: xs is a scaled coordinate, which gives only a centre (x=xs)",
        ),
    ] {
        match Columns::parse(map) {
            Err(Error::Parameter(why)) => {
                assert_eq!(why, format!("LAMMPS column mapping: {phrase}"))
            }
            other => panic!("{map}: {other:?}"),
        }
    }
    let plain = ReadOptions {
        columns: Columns::parse("length=1,radius=0.02").unwrap(),
        ..ReadOptions::default()
    };
    let err = parse(SCALED, &plain).unwrap_err().to_string();
    assert!(
        err.ends_with(
            "line 9: no column \"x\" for x (columns: id xs ys zs mux muy muz; map them with \
             --lammps-columns, e.g. x=xs,y=ys,z=zs for scaled coordinates)"
        ),
        "{err}"
    );
}

/// A dump of quaternions `(w, i, j, k)` rotating the body x axis: the
/// identity keeps x, 90 degrees about z turns it to y, 120 degrees about
/// (1, 1, 1) to y, 90 degrees about y to -z, a scaled quaternion is
/// normalized; the zero quaternion is refused, and a direction and a
/// quaternion cannot both be mapped.
#[test]
fn quaternions_rotate_the_body_x_axis() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let rows = [
        "1 0.5 0.5 0.5 1 0 0 0".to_string(),
        format!("2 1.5 1.5 1.5 {h} 0 0 {h}"),
        "3 2.5 2.5 2.5 0.5 0.5 0.5 0.5".to_string(),
        format!("4 3.5 3.5 3.5 {h} 0 {h} 0"),
        "5 1 3 1 2 0 0 0".to_string(),
    ];
    let dump = format!(
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n5\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n\
         ITEM: ATOMS id x y z quatw quati quatj quatk\n{}\n",
        rows.join("\n")
    );
    let loaded = parse(&dump, &options()).unwrap();
    let expected = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
    ];
    for (rod, axis) in loaded.system.rods.iter().zip(expected) {
        let off = (rod.axis - Vector3::from(axis)).norm();
        assert!(off < 1e-14, "{:?} is not {axis:?}", rod.axis);
    }
    assert_eq!(rotate([0.0; 4], [1.0, 0.0, 0.0]), None);
    let zero = dump.replace("5 1 3 1 2 0 0 0", "5 1 3 1 0 0 0 0");
    let err = parse(&zero, &options()).unwrap_err().to_string();
    assert!(
        err.ends_with("line 14: the quaternion (0, 0, 0, 0) is not a rotation"),
        "{err}"
    );
    let mapped = dump.replace("quatw quati quatj quatk", "c_q[1] c_q[2] c_q[3] c_q[4]");
    let opts = ReadOptions {
        columns: Columns::parse(
            "quatw=c_q[1],quati=c_q[2],quatj=c_q[3],quatk=c_q[4],length=1,radius=0.02",
        )
        .unwrap(),
        ..ReadOptions::default()
    };
    assert!(parse(&mapped, &opts).unwrap().system.rods == loaded.system.rods);
    match Columns::parse("dx=c_u[1],quatw=c_q[1]") {
        Err(Error::Parameter(why)) => assert!(why.contains("not both"), "{why}"),
        other => panic!("{other:?}"),
    }
    let none = dump.replace("quatw quati quatj quatk", "a b c d");
    let err = parse(&none, &options()).unwrap_err().to_string();
    assert!(
        err.contains("no column \"mux\" for dx") && err.contains("or dump the quaternion"),
        "{err}"
    );
}

/// Atom ids travel with the rods: the bodies, the VTK cells, truth's
/// clusters and the rods written back carry them; the same rods without ids
/// give the same bodies, without an `ids` key.
#[test]
fn atom_ids_reach_the_outputs() {
    let dir = scratch("dumps-ids");
    let path = |name: &str| dir.join(name).display().to_string();
    let plain = path("plain.csv");
    let out = rgc(&[
        "sample",
        "--gamma",
        "23",
        "--box",
        "4",
        "--density",
        "40",
        "--seed",
        "3",
        "--save-rods",
        &plain,
    ]);
    assert!(out.status.success());
    // The same rods as a dump whose atom ids run backwards from 9000.
    let loaded = file::read(
        Path::new(&plain),
        &ReadOptions {
            sides: Some([4.0; 3]),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    let n = loaded.system.len() as u64;
    let ids: Vec<u64> = (0..n).map(|i| 9000 - i).collect();
    let dump = path("ids.dump");
    file::save(&loaded.system, Some(&ids[..]), Path::new(&dump)).unwrap();

    let (b1, b2, vtp) = (path("b1.json"), path("b2.json"), path("ids.vtp"));
    let saved = path("saved.csv");
    let run = |args: &[&str]| {
        let out = rgc(args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    run(&[
        "sample",
        "--rods",
        &plain,
        "--box",
        "4",
        "--seed",
        "3",
        "--save-bodies",
        &b1,
    ]);
    run(&[
        "sample",
        "--rods",
        &dump,
        "--seed",
        "3",
        "--save-bodies",
        &b2,
        "--save-vtk",
        &vtp,
        "--save-rods",
        &saved,
    ]);
    let (without, with): (Value, Value) = (
        serde_json::from_slice(&std::fs::read(&b1).unwrap()).unwrap(),
        serde_json::from_slice(&std::fs::read(&b2).unwrap()).unwrap(),
    );
    let bodies = with["bodies"].as_array().unwrap();
    assert!(!bodies.is_empty());
    for (a, b) in without["bodies"].as_array().unwrap().iter().zip(bodies) {
        assert!(a.get("ids").is_none());
        assert_eq!(a["rods"], b["rods"]);
        let named: Vec<u64> = (b["rods"].as_array().unwrap().iter())
            .map(|r| 9000 - r.as_u64().unwrap())
            .collect();
        assert_eq!(b["ids"], serde_json::json!(named));
    }
    let vtk = crate::vtk::read_vtp(Path::new(&vtp));
    let named: Vec<i64> = (0..n as i64).map(|i| 9000 - i).collect();
    assert_eq!(vtk.pieces[0].cells("id"), named.as_slice());
    let back = file::read(
        Path::new(&saved),
        &ReadOptions {
            sides: Some([4.0; 3]),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(back.ids, Some(ids.clone()));
    assert!(back.system.rods == loaded.system.rods);

    let truth: Value = serde_json::from_slice(&run(&["truth", "--rods", &dump, "--json"])).unwrap();
    let clusters = truth["clusters"].as_array().unwrap();
    assert!(!clusters.is_empty());
    for c in clusters {
        let named: Vec<u64> = (c["rods"].as_array().unwrap().iter())
            .map(|r| 9000 - r.as_u64().unwrap())
            .collect();
        assert_eq!(c["ids"], serde_json::json!(named));
    }
    let plain_truth: Value =
        serde_json::from_slice(&run(&["truth", "--rods", &plain, "--box", "4", "--json"])).unwrap();
    assert!(plain_truth["clusters"][0].get("ids").is_none());
    assert_eq!(plain_truth["clusters"][0]["rods"], clusters[0]["rods"]);
}

/// Boundary flags: `pp` on every axis, `pp` on x and y, or none; fixed and
/// shrink-wrapped ends (`f`, `s`, `m`, mixed per end) are walls at the
/// bounds the snapshot gives; a periodic axis between walls (`pp ff pp`), a
/// flag periodic at one end only and an unknown flag are refused at the
/// header's line.
#[test]
fn boundary_flags_give_walls_or_periodic_axes_or_a_refusal() {
    let with = |flags: &str| snapshot(0, "", &FIRST).replace("BOX BOUNDS pp pp pp", flags);
    for (flags, periodic) in [
        ("BOX BOUNDS pp pp pp", Periodic::Xyz),
        ("BOX BOUNDS ss ss ss", Periodic::None),
        ("BOX BOUNDS mm mm mm", Periodic::None),
        ("BOX BOUNDS fs sm mf", Periodic::None),
        ("BOX BOUNDS pp pp ff", Periodic::Xy),
        ("BOX BOUNDS pp pp sm", Periodic::Xy),
    ] {
        let loaded = parse(&with(flags), &options()).unwrap();
        assert_eq!(loaded.system.domain.periodic, periodic, "{flags}");
        assert_eq!(loaded.system.domain.sides, [4.0; 3], "{flags}");
        assert_eq!((loaded.system.len(), loaded.cut), (2, 0), "{flags}");
    }
    let refused = |flags: &str| match parse(&with(flags), &options()) {
        Err(Error::Malformed { line, reason, .. }) => (line, reason),
        other => panic!("{flags}: {other:?}"),
    };
    for flags in ["pp ff pp", "ff pp pp", "pp ss pp", "ss pp ss"] {
        assert_eq!(
            refused(&format!("BOX BOUNDS {flags}")),
            (
                5,
                format!("boundary flags {flags}: rgc supports periodic xyz, xy or none")
            )
        );
    }
    for (flags, bad) in [
        ("pf pp pp", "pf"),
        ("pp sp pp", "sp"),
        ("pp pp xx", "xx"),
        ("pp pp f", "f"),
    ] {
        assert_eq!(
            refused(&format!("BOX BOUNDS {flags}")),
            (
                5,
                format!(
                    "boundary flag {bad:?}: each axis takes pp, or two of f, s and m (one per end)"
                )
            )
        );
    }
}

/// A snapshot with fewer atom lines than `ITEM: NUMBER OF ATOMS` says is
/// refused with both counts, whether the next snapshot or the end of the
/// file comes early, and whichever snapshot is asked for: its atoms are
/// never read from the next snapshot's header.
#[test]
fn a_truncated_atom_list_is_refused_with_its_counts() {
    let short = snapshot(0, "", &FIRST).replace("NUMBER OF ATOMS\n2", "NUMBER OF ATOMS\n3");
    let two = short.clone() + &snapshot(100, "", &SECOND);
    for frame in [None, Some(Frame::Index(1)), Some(Frame::Last)] {
        let opts = ReadOptions { frame, ..options() };
        match parse(&two, &opts) {
            Err(Error::Malformed { line, reason, .. }) => {
                assert_eq!(line, 12, "{frame:?}");
                assert_eq!(
                    reason,
                    "the snapshot holds 2 atom lines where ITEM: NUMBER OF ATOMS says 3"
                );
            }
            other => panic!("{frame:?}: {other:?}"),
        }
    }
    match parse(&short, &options()) {
        Err(Error::Malformed { line, reason, .. }) => {
            assert_eq!(line, 12);
            assert_eq!(
                reason,
                "the file ends where an atom line was expected: 2 atom lines where ITEM: NUMBER OF ATOMS says 3"
            );
        }
        other => panic!("{other:?}"),
    }
    // With the count right, both read.
    let fixed = short.replace("NUMBER OF ATOMS\n3", "NUMBER OF ATOMS\n2");
    assert_eq!(parse(&fixed, &options()).unwrap().system.len(), 2);
}
