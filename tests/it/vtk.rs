//! `--save-vtk`: VTK XML PolyData with raw appended data, read back whole by
//! a reader of the test's own (so the test does not trust the writer): the
//! box as field data, every array of the rods' piece and of the box
//! outline's, and every byte of the appended block accounted for.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use crate::cli::{json, rgc, stdout_of};
use rgc::sample::{SampleOptions, sample};
use rgc::spanning::Criterion;

/// One array's values.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Float(Vec<f64>),
    Int(Vec<i64>),
}

impl Values {
    pub fn floats(&self) -> &[f64] {
        match self {
            Values::Float(v) => v,
            Values::Int(_) => panic!("an integer array where floats were expected"),
        }
    }

    pub fn ints(&self) -> &[i64] {
        match self {
            Values::Int(v) => v,
            Values::Float(_) => panic!("a float array where integers were expected"),
        }
    }
}

/// One `DataArray`: its type, components and values.
#[derive(Clone, Debug)]
pub struct Array {
    pub ty: String,
    pub comps: usize,
    pub values: Values,
}

/// One `Piece`: its declared sizes and arrays by section and name.
#[derive(Clone, Debug, Default)]
pub struct Piece {
    pub points: usize,
    pub lines: usize,
    pub arrays: BTreeMap<(String, String), Array>,
}

impl Piece {
    pub fn get(&self, section: &str, name: &str) -> &Values {
        &self
            .arrays
            .get(&(section.to_string(), name.to_string()))
            .unwrap_or_else(|| panic!("no {section} array {name}"))
            .values
    }

    /// A cell array's integers.
    pub fn cells(&self, name: &str) -> &[i64] {
        self.get("CellData", name).ints()
    }
}

/// A `.vtp` file read back.
#[derive(Clone, Debug, Default)]
pub struct Vtp {
    pub field: BTreeMap<String, Array>,
    pub pieces: Vec<Piece>,
}

fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    Some(&tag[at..at + tag[at..].find('"')?])
}

/// Reads a PolyData file with raw appended data, checking as it goes that
/// it is what VTK expects: the header, one appended block with each array's
/// UInt64 byte count, the arrays back to back with nothing left over.
pub fn read_vtp(path: &Path) -> Vtp {
    let bytes = std::fs::read(path).unwrap();
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("an appended data block");
    let head = std::str::from_utf8(&bytes[..at]).expect("the XML head is text");
    assert!(head.starts_with("<?xml version=\"1.0\"?>\n"));
    assert!(head.contains(
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    ));
    let underscore = at + bytes[at..].iter().position(|&b| b == b'_').unwrap();
    assert!(
        bytes[at + marker.len()..underscore]
            .iter()
            .all(u8::is_ascii_whitespace)
    );
    let data = &bytes[underscore + 1..];
    let mut vtp = Vtp::default();
    let mut section = String::new();
    let mut end = 0usize;
    for tag in head.split('<').skip(1) {
        let tag = tag.split('>').next().unwrap();
        let name = tag.split_whitespace().next().unwrap_or_default();
        match name {
            "Piece" => vtp.pieces.push(Piece {
                points: attr(tag, "NumberOfPoints").unwrap().parse().unwrap(),
                lines: attr(tag, "NumberOfLines").unwrap().parse().unwrap(),
                ..Piece::default()
            }),
            "FieldData" | "Points" | "Lines" | "PointData" | "CellData" => {
                section = name.to_string();
            }
            "DataArray" => {
                assert_eq!(attr(tag, "format"), Some("appended"), "{tag}");
                let offset: usize = attr(tag, "offset").unwrap().parse().unwrap();
                assert_eq!(offset, end, "arrays back to back: {tag}");
                let len = u64::from_le_bytes(data[offset..offset + 8].try_into().unwrap()) as usize;
                let raw = &data[offset + 8..offset + 8 + len];
                end = offset + 8 + len;
                let ty = attr(tag, "type").unwrap().to_string();
                let values = match ty.as_str() {
                    "Float64" => Values::Float(
                        raw.chunks(8)
                            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                            .collect(),
                    ),
                    "Int64" => Values::Int(
                        raw.chunks(8)
                            .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
                            .collect(),
                    ),
                    "Int32" => Values::Int(
                        raw.chunks(4)
                            .map(|c| i64::from(i32::from_le_bytes(c.try_into().unwrap())))
                            .collect(),
                    ),
                    "Int8" => Values::Int(raw.iter().map(|&b| i64::from(b as i8)).collect()),
                    other => panic!("unexpected type {other}"),
                };
                let comps: usize = attr(tag, "NumberOfComponents").unwrap().parse().unwrap();
                let array = Array { ty, comps, values };
                let name = attr(tag, "Name").unwrap().to_string();
                if section == "FieldData" {
                    assert_eq!(attr(tag, "NumberOfTuples"), Some("1"));
                    vtp.field.insert(name, array);
                } else {
                    let piece = vtp.pieces.last_mut().expect("an array inside a piece");
                    let key = (section.clone(), name);
                    assert!(piece.arrays.insert(key, array).is_none(), "{tag} twice");
                }
            }
            _ => {}
        }
    }
    assert_eq!(
        &data[end..],
        b"\n  </AppendedData>\n</VTKFile>\n",
        "nothing after the last array"
    );
    vtp
}

/// Checks the piece and field data that every file has: sizes, lines,
/// radii, the box outline and the box's field data; returns the rods' piece.
fn check_frame(vtp: &Vtp, system: &rgc::rods::RodSystem, fields: &[&str]) {
    let n = system.len();
    let d = &system.domain;
    assert_eq!(vtp.field["box_sides"].values.floats(), &d.sides);
    assert_eq!(vtp.field["box_origin"].values.floats(), &[0.0; 3]);
    let periodic: Vec<i64> = d.periodic.axes().iter().map(|&p| i64::from(p)).collect();
    assert_eq!(vtp.field["periodic"].values.ints(), periodic.as_slice());
    assert_eq!(vtp.field.len(), 3);
    assert_eq!(vtp.pieces.len(), 2);
    for (piece, lines) in vtp.pieces.iter().zip([n, 12]) {
        assert_eq!((piece.points, piece.lines), (2 * lines, lines));
        let want: Vec<(String, String)> = [
            ("Points", "points"),
            ("Lines", "connectivity"),
            ("Lines", "offsets"),
            ("PointData", "radius"),
            ("CellData", "radius"),
            ("CellData", "outline"),
        ]
        .into_iter()
        .chain(fields.iter().map(|f| ("CellData", *f)))
        .map(|(s, k)| (s.to_string(), k.to_string()))
        .collect();
        let mut want = want;
        want.sort();
        assert_eq!(piece.arrays.keys().cloned().collect::<Vec<_>>(), want);
        assert_eq!(piece.arrays[&want[0]].comps, 1);
        let connectivity = piece.get("Lines", "connectivity").ints();
        assert_eq!(connectivity, (0..2 * lines as i64).collect::<Vec<_>>());
        let offsets = piece.get("Lines", "offsets").ints();
        let ends: Vec<i64> = (1..=lines as i64).map(|i| 2 * i).collect();
        assert_eq!(offsets, ends);
        for f in fields {
            assert_eq!(piece.cells(f).len(), lines, "{f}");
        }
    }
    let rods = &vtp.pieces[0];
    let points = rods.get("Points", "points").floats();
    assert_eq!(points.len(), 6 * n);
    let (per_point, per_cell) = (
        rods.get("PointData", "radius").floats(),
        rods.get("CellData", "radius").floats(),
    );
    for (i, r) in system.rods.iter().enumerate() {
        let (a, b) = (r.at(-0.5 * r.length), r.at(0.5 * r.length));
        let want = [a.x, a.y, a.z, b.x, b.y, b.z];
        assert_eq!(
            points[6 * i..6 * i + 6],
            want,
            "rod {i}'s core, bit for bit"
        );
        assert_eq!(per_point[2 * i..2 * i + 2], [r.radius; 2]);
        assert_eq!(per_cell[i], r.radius);
    }
    assert!(rods.cells("outline").iter().all(|&o| o == 0));
    // The outline: 12 distinct edges, each joining two corners of the box
    // along one axis, over its whole side; -1 in every rod field.
    let outline = &vtp.pieces[1];
    let corners = outline.get("Points", "points").floats();
    let mut edges = Vec::new();
    for e in corners.chunks(6) {
        let (p, q) = (&e[..3], &e[3..]);
        for k in 0..3 {
            assert!(p[k] == 0.0 || p[k] == d.sides[k]);
            assert!(q[k] == 0.0 || q[k] == d.sides[k]);
        }
        let along: Vec<usize> = (0..3).filter(|&k| p[k] != q[k]).collect();
        assert_eq!(along.len(), 1, "an edge runs along one axis");
        edges.push(format!("{p:?}{q:?}"));
    }
    edges.sort();
    edges.dedup();
    assert_eq!(edges.len(), 12);
    assert!(outline.cells("outline").iter().all(|&o| o == 1));
    assert!(
        outline
            .get("CellData", "radius")
            .floats()
            .iter()
            .all(|&r| r == 0.0)
    );
    for f in fields {
        assert!(outline.cells(f).iter().all(|&v| v == -1), "{f}");
    }
}

/// The true cluster of each rod (the first, i.e. largest, holding it, or
/// -1) and whether a cluster of it spans, from `clusters` as (rods, spans).
fn per_rod(n: usize, clusters: &[(Vec<u64>, bool)]) -> (Vec<i64>, Vec<i64>) {
    let (mut cluster, mut spans) = (vec![-1i64; n], vec![0i64; n]);
    for (k, (rods, s)) in clusters.iter().enumerate() {
        for &r in rods {
            if cluster[r as usize] < 0 {
                cluster[r as usize] = k as i64;
            }
            if *s {
                spans[r as usize] = 1;
            }
        }
    }
    (cluster, spans)
}

/// `sample --truth --save-vtk` read back whole against the library's own
/// sample of the same system: every rod's core and radius bit for bit,
/// `body` and `spans` from the reported run's bodies, `degree` from the
/// contact graph, `true_cluster` and `true_spans` from its truth.
#[test]
fn a_sample_vtk_file_reads_back_to_the_librarys_rods_bodies_and_clusters() {
    let dir = crate::scratch("vtk-sample");
    let (vtp, bodies) = (dir.join("s.vtp"), dir.join("b.json"));
    stdout_of(&[
        "sample",
        "--gamma",
        "10",
        "--box",
        "4",
        "--density",
        "12",
        "--seed",
        "9",
        "--runs",
        "3",
        "--criterion",
        "faces",
        "--truth",
        "--save-vtk",
        vtp.to_str().unwrap(),
        "--save-bodies",
        bodies.to_str().unwrap(),
    ]);
    let s = sample(&SampleOptions {
        rods: rgc::rods::RodParams::new(10.0, 4.0, 12.0).unwrap().into(),
        seed: 9,
        runs: 3,
        rules: rgc::engine::RuleSet::Sound,
        criterion: Criterion::Faces,
        truth: true,
    })
    .unwrap();
    let n = s.system.len();
    let file = read_vtp(&vtp);
    check_frame(
        &file,
        &s.system,
        &["body", "spans", "degree", "true_cluster", "true_spans"],
    );
    let rods = &file.pieces[0];
    // Body and spans per rod, from the bodies file the same run wrote.
    let saved: Value = serde_json::from_slice(&std::fs::read(&bodies).unwrap()).unwrap();
    let (mut body, mut spans) = (vec![-1i64; n], vec![0i64; n]);
    let list = saved["bodies"].as_array().unwrap();
    for (k, b) in list.iter().enumerate() {
        for r in b["rods"].as_array().unwrap() {
            body[r.as_u64().unwrap() as usize] = k as i64;
            spans[r.as_u64().unwrap() as usize] = i64::from(b["spans"].as_bool().unwrap());
        }
    }
    assert!(list.len() > 1 && body.contains(&-1), "bodies and free rods");
    assert_eq!(rods.cells("body"), body.as_slice());
    assert_eq!(rods.cells("spans"), spans.as_slice());
    let degree: Vec<i64> = (0..n as u32).map(|r| s.graph.degree(r) as i64).collect();
    assert_eq!(rods.cells("degree"), degree.as_slice());
    let t = s.truth.as_ref().unwrap();
    let clusters: Vec<(Vec<u64>, bool)> = t
        .clusters
        .iter()
        .map(|c| {
            let rods = c.rods.iter().map(|&r| u64::from(r)).collect();
            (rods, c.spans.unwrap().faces)
        })
        .collect();
    let (cluster, true_spans) = per_rod(n, &clusters);
    assert!(t.clusters.len() > 1, "several true clusters");
    assert_eq!(rods.cells("true_cluster"), cluster.as_slice());
    assert_eq!(rods.cells("true_spans"), true_spans.as_slice());
    // Flags fit a byte: the narrowest type, and much smaller than ASCII.
    let flag = &rods.arrays[&("CellData".to_string(), "spans".to_string())];
    assert_eq!(flag.ty, "Int8");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `sample --truth --save-vtk` on unequal rods in a slab with walls: each
/// line cell runs along its own rod's core with its own radius (checked
/// against `--save-rods`), the walls are in the field data, and the true
/// rigid clusters in the file are the ones the report counts.
#[test]
fn vtk_carries_each_rods_size_its_box_and_its_true_rigid_cluster() {
    let dir = crate::scratch("vtk-truth");
    let (vtk, rods) = (dir.join("s.vtp"), dir.join("s.csv"));
    let report = json(&[
        "sample",
        "--box",
        "4,4,3",
        "--periodic",
        "xy",
        "--density",
        "30",
        "--length",
        "uniform:0.8,1.2",
        "--radius",
        "uniform:0.02,0.03",
        "--truth",
        "--save-vtk",
        vtk.to_str().unwrap(),
        "--save-rods",
        rods.to_str().unwrap(),
        "--json",
    ]);
    let truth = &report["truth"];
    assert_eq!(truth["method"], "exact");
    let system = rgc::rods::file::read(
        &rods,
        &rgc::rods::file::ReadOptions {
            sides: Some([4.0, 4.0, 3.0]),
            periodic: Some(rgc::rods::Periodic::Xy),
            ..Default::default()
        },
    )
    .unwrap()
    .system;
    let file = read_vtp(&vtk);
    check_frame(
        &file,
        &system,
        &["body", "spans", "degree", "true_cluster", "true_spans"],
    );
    assert_eq!(file.field["periodic"].values.ints(), &[1, 1, 0]);
    let (cluster, spans) = (
        file.pieces[0].cells("true_cluster"),
        file.pieces[0].cells("true_spans"),
    );
    let clusters = cluster.iter().max().unwrap() + 1;
    assert_eq!(clusters, truth["clusters"].as_i64().unwrap());
    let largest = cluster.iter().filter(|&&c| c == 0).count();
    assert_eq!(
        largest as u64,
        truth["largest_cluster_rods"].as_u64().unwrap()
    );
    assert!(largest >= 2);
    assert_eq!(Some(spans.contains(&1)), truth["spanning"].as_bool());
    assert!(spans.iter().zip(cluster).all(|(&s, &c)| s == 0 || c >= 0));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `truth --save-vtk --save-clusters` on rods read with ids: the clusters
/// file holds truth's clusters (as `--json` prints them) with each one's
/// spanning flag and ids; the VTK file's `true_cluster` gives each rod the
/// first (largest) cluster holding it, its `true_spans` whether one of them
/// spans, its `id` the file's id.
#[test]
fn truth_writes_its_clusters_as_json_and_vtk() {
    let dir = crate::scratch("vtk-truth-outputs");
    let p = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (plain, csv, vtp, json) = (p("plain.csv"), p("ids.csv"), p("t.vtp"), p("c.json"));
    let generated = [
        "--gamma",
        "23",
        "--box",
        "3",
        "--density",
        "40",
        "--seed",
        "4",
    ];
    let out = rgc(&[&["sample", "--save-rods", plain.as_str()], &generated[..]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The same rods numbered from 500 down, by an id column.
    let text = std::fs::read_to_string(&plain).unwrap();
    let mut lines = text.lines();
    let mut with_ids = format!("id,{}\n", lines.next().unwrap());
    for (i, l) in lines.enumerate() {
        with_ids += &format!("{},{l}\n", 500 - i);
    }
    std::fs::write(&csv, with_ids).unwrap();
    let run = |extra: &[&str]| {
        let args = [&["truth", "--rods", csv.as_str(), "--box", "3"][..], extra].concat();
        crate::cli::json(&args)
    };
    let printed = run(&["--save-vtk", &vtp, "--save-clusters", &json, "--json"]);
    let saved: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(saved["method"], printed["method"]);
    assert_eq!(saved["criterion"], "wrap");
    assert_eq!(saved["spanning"], printed["spanning"]);
    let (a, b) = (
        saved["clusters"].as_array().unwrap(),
        printed["clusters"].as_array().unwrap(),
    );
    assert_eq!(a.len(), b.len());
    assert!(a.len() > 1, "several clusters");
    let mut clusters = Vec::new();
    for (s, p) in a.iter().zip(b) {
        assert_eq!(s["rods"], p["rods"]);
        assert_eq!(s["ids"], p["ids"]);
        assert_eq!(s["spans"], p["spans"]["wrap"]);
        let rods: Vec<u64> = s["rods"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r.as_u64().unwrap())
            .collect();
        let ids: Vec<u64> = rods.iter().map(|r| 500 - r).collect();
        assert_eq!(s["ids"], serde_json::json!(ids));
        clusters.push((rods, s["spans"].as_bool().unwrap()));
    }
    assert_eq!(
        printed["spanning"].as_bool(),
        Some(clusters.iter().any(|c| c.1))
    );
    let loaded = rgc::rods::file::read(
        Path::new(&csv),
        &rgc::rods::file::ReadOptions {
            sides: Some([3.0; 3]),
            ..Default::default()
        },
    )
    .unwrap();
    let system = loaded.system;
    let n = system.len();
    let file = read_vtp(Path::new(&vtp));
    check_frame(
        &file,
        &system,
        &["degree", "true_cluster", "true_spans", "id"],
    );
    let (cluster, spans) = per_rod(n, &clusters);
    let rods = &file.pieces[0];
    assert_eq!(rods.cells("true_cluster"), cluster.as_slice());
    assert_eq!(rods.cells("true_spans"), spans.as_slice());
    let ids: Vec<i64> = (0..n as i64).map(|i| 500 - i).collect();
    assert_eq!(rods.cells("id"), ids.as_slice());
    let contacts = rgc::contacts::detect(&system);
    let graph = rgc::graph::ContactGraph::from_contacts(n, &contacts);
    let degree: Vec<i64> = (0..n as u32).map(|r| graph.degree(r) as i64).collect();
    assert_eq!(rods.cells("degree"), degree.as_slice());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `truth`'s outputs are checked before the work: two flags naming one
/// file, a VTK file of a graph (no rods to draw) and a legacy `.vtk` name
/// are refused on one line; a graph's clusters are written without spans.
#[test]
fn truth_outputs_are_checked_before_the_work() {
    let dir = crate::scratch("vtk-truth-refusals");
    let same = dir.join("x.vtp");
    let generated = ["truth", "--gamma", "23", "--box", "3", "--density", "30"];
    let refused = |args: &[&str], needle: &str| {
        let out = rgc(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(out.stdout.is_empty());
    };
    let both = same.to_str().unwrap();
    refused(
        &[
            &generated[..],
            &["--save-vtk", both, "--save-clusters", both],
        ]
        .concat(),
        &format!("--save-vtk and --save-clusters both write {both}"),
    );
    refused(
        &["truth", "--graph6", "Bw", "--save-vtk", both],
        "--save-vtk draws rods: it needs a rod system",
    );
    let legacy = dir.join("x.vtk");
    refused(
        &[&generated[..], &["--save-vtk", legacy.to_str().unwrap()]].concat(),
        "--save-vtk writes VTK XML PolyData: name the file .vtp",
    );
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "nothing written"
    );
    // A triangle of rods is one rigid cluster of a finite framework: no spans.
    let json = dir.join("c.json");
    stdout_of(&[
        "truth",
        "--graph6",
        "Bw",
        "--save-clusters",
        json.to_str().unwrap(),
    ]);
    let saved: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(
        saved,
        serde_json::json!({"method": "exact", "clusters": [{"rods": [0, 1, 2]}]})
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
