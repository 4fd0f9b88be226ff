//! GraphML: rgc's own files read back whole (every rod, the box, every
//! contact), a file in networkx's shape (keys `d0`, `d1` ... named by their
//! declarations) read back the same, and broken files refused with their line.

use std::fmt::Write as _;
use std::path::Path;

use rgc::contacts::{self, Contact};
use rgc::graph::graphml::{GraphmlContacts, parse_graphml, to_graphml};
use rgc::rods::{Domain, Periodic, RodParams, RodSystem};

fn system() -> (RodSystem, Vec<Contact>) {
    let s = RodSystem::generate(RodParams::new(10.0, 3.0, 12.0).unwrap(), 5);
    let c = contacts::detect(&s);
    (s, c)
}

/// The file gives back `s` and `c`: every rod bit for bit, the box, and
/// the contacts (in any order).
fn same(back: &GraphmlContacts, s: &RodSystem, c: &[Contact]) {
    assert_eq!(back.system.domain, s.domain);
    assert_eq!(back.system.rods.len(), s.rods.len());
    for (i, (a, b)) in back.system.rods.iter().zip(&s.rods).enumerate() {
        assert_eq!(a, b, "rod {i}");
    }
    let mut got = back.contacts.clone();
    got.sort_by_key(|c| c.rods);
    let mut want = c.to_vec();
    want.sort_by_key(|c| c.rods);
    assert_eq!(got, want, "bit for bit");
}

#[test]
fn a_graphml_file_reads_back_to_the_same_rods_box_and_contacts() {
    let (s, c) = system();
    // Contacts through the periodic boundary, so the images are exercised too.
    assert!(c.iter().any(|c| c.shift != [0, 0, 0]));
    let text = to_graphml(&s, &c);
    let back = parse_graphml(&text, Path::new("t.graphml")).unwrap();
    same(&back, &s, &c);
    assert_eq!(back.contacts, c, "in the order written");
    // Layout does not matter: one element per line, attributes reordered.
    let spread = text
        .replace("><", ">\n<")
        .replace("<edge source=\"", "<edge\n target_first=\"x\" source=\"");
    let again = parse_graphml(&spread, Path::new("t.graphml")).unwrap();
    same(&again, &s, &c);
    // A slab with walls keeps its sides and periodic axes.
    let slab = RodSystem {
        domain: Domain {
            sides: [3.0, 3.0, 2.5],
            periodic: Periodic::Xy,
        },
        rods: s.rods.clone(),
    };
    let back = parse_graphml(&to_graphml(&slab, &c), Path::new("t.graphml")).unwrap();
    same(&back, &slab, &c);
}

/// The file networkx writes for rgc's graph (`nx.write_graphml` after
/// `nx.read_graphml`): keys `d0` ... `d19` declared last key first, each
/// data element naming its key id; the graph's data after the edges. Here
/// nodes come in reverse order and every other edge names its ends the
/// other way round, which networkx may do for a graph built otherwise.
fn networkx_style(s: &RodSystem, c: &[Contact]) -> String {
    let keys = [
        ("graph", "box_x", "double"),
        ("graph", "box_y", "double"),
        ("graph", "box_z", "double"),
        ("graph", "periodic", "string"),
        ("node", "cx", "double"),
        ("node", "cy", "double"),
        ("node", "cz", "double"),
        ("node", "ax", "double"),
        ("node", "ay", "double"),
        ("node", "az", "double"),
        ("node", "length", "double"),
        ("node", "radius", "double"),
        ("edge", "s0", "double"),
        ("edge", "s1", "double"),
        ("edge", "px", "double"),
        ("edge", "py", "double"),
        ("edge", "pz", "double"),
        ("edge", "kx", "long"),
        ("edge", "ky", "long"),
        ("edge", "kz", "long"),
    ];
    let id = |name: &str| format!("d{}", keys.iter().position(|k| k.1 == name).unwrap());
    let mut t = String::from(
        "<?xml version='1.0' encoding='utf-8'?>\n<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\" xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">\n",
    );
    for (k, (domain, name, ty)) in keys.iter().enumerate().rev() {
        let _ = writeln!(
            t,
            "  <key id=\"d{k}\" for=\"{domain}\" attr.name=\"{name}\" attr.type=\"{ty}\" />"
        );
    }
    t.push_str("  <graph edgedefault=\"undirected\">\n");
    let data = |t: &mut String, name: &str, v: String| {
        let _ = writeln!(t, "      <data key=\"{}\">{v}</data>", id(name));
    };
    for (i, r) in s.rods.iter().enumerate().rev() {
        let _ = writeln!(t, "    <node id=\"{i}\">");
        for (k, v) in ["cx", "cy", "cz"].iter().zip(r.center.iter()) {
            data(&mut t, k, format!("{v:?}"));
        }
        for (k, v) in ["ax", "ay", "az"].iter().zip(r.axis.iter()) {
            data(&mut t, k, format!("{v:?}"));
        }
        data(&mut t, "length", format!("{:?}", r.length));
        data(&mut t, "radius", format!("{:?}", r.radius));
        t.push_str("    </node>\n");
    }
    for (e, x) in c.iter().enumerate() {
        let [a, b] = if e % 2 == 0 {
            x.rods
        } else {
            [x.rods[1], x.rods[0]]
        };
        let _ = writeln!(t, "    <edge source=\"{a}\" target=\"{b}\">");
        for (k, v) in ["s0", "s1"].iter().zip(x.params) {
            data(&mut t, k, format!("{v:?}"));
        }
        for (k, v) in ["px", "py", "pz"].iter().zip(x.point.iter()) {
            data(&mut t, k, format!("{v:?}"));
        }
        for (k, v) in ["kx", "ky", "kz"].iter().zip(x.shift) {
            data(&mut t, k, v.to_string());
        }
        t.push_str("    </edge>\n");
    }
    for (k, v) in ["box_x", "box_y", "box_z"].iter().zip(s.domain.sides) {
        let _ = writeln!(t, "    <data key=\"{}\">{v:?}</data>", id(k));
    }
    let _ = writeln!(
        t,
        "    <data key=\"{}\">{}</data>",
        id("periodic"),
        s.domain.periodic.name()
    );
    t.push_str("  </graph>\n</graphml>\n");
    t
}

#[test]
fn a_graphml_file_in_networkx_shape_reads_back_by_its_key_names() {
    let (s, c) = system();
    let text = networkx_style(&s, &c);
    // The names only appear in the key declarations.
    assert!(!text.contains("key=\"cx\"") && text.contains("<key id=\"d19\""));
    let back = parse_graphml(&text, Path::new("nx.graphml")).unwrap();
    same(&back, &s, &c);
    // A data key declared nowhere is its own name: rgc's own keys without
    // their declarations still read.
    let own = to_graphml(&s, &c);
    let bare: String = own
        .lines()
        .filter(|l| !l.trim_start().starts_with("<key "))
        .map(|l| format!("{l}\n"))
        .collect();
    same(
        &parse_graphml(&bare, Path::new("t.graphml")).unwrap(),
        &s,
        &c,
    );
}

#[test]
fn broken_graphml_is_refused_with_its_line() {
    let (s, c) = system();
    let good = to_graphml(&s, &c);
    let err = |text: &str| {
        parse_graphml(text, Path::new("bad.graphml"))
            .unwrap_err()
            .to_string()
    };
    let line_of = |needle: &str| good.lines().position(|l| l.contains(needle)).unwrap() + 1;
    let first_edge = line_of("<edge ");
    // Cut after the last node: the file ends on that node's line.
    let cut: String = good
        .lines()
        .take(first_edge - 1)
        .map(|l| format!("{l}\n"))
        .collect();
    let cases: Vec<(String, String)> = vec![
        (
            cut,
            format!("line {}: the file ends before </graphml>", first_edge - 1),
        ),
        (
            good[..good.find("<edge ").unwrap() + 7].to_string(),
            format!("line {first_edge}: a tag is not closed"),
        ),
        (
            good.replacen("<data key=\"s0\">", "<data key=\"s0\">x", 1),
            format!(
                "line {first_edge}: edge {} {}: s0 \"x",
                c[0].rods[0], c[0].rods[1]
            ),
        ),
        (
            good.replacen("<data key=\"kx\">0", "<data key=\"kx\">0.5", 1),
            "kx \"0.5\" is not an integer".to_string(),
        ),
        (
            good.replacen("<data key=\"pz\">", "<data key=\"qz\">", 1),
            "has no pz".to_string(),
        ),
        (
            good.replacen("<node id=\"1\">", "<node id=\"7\">", 1),
            format!("line {}: node 7 is given twice", line_of("<node id=\"7\">")),
        ),
        (
            good.replacen("<data key=\"radius\">", "<data key=\"radius\">-", 1),
            format!(
                "line {}: node 0: a rod needs a positive length and radius",
                line_of("<node id=\"0\">")
            ),
        ),
        (
            good.replacen("<data key=\"periodic\">xyz", "<data key=\"periodic\">xz", 1),
            "periodic \"xz\" is none of xyz, xy and none".to_string(),
        ),
        (
            good.replacen("target=\"", "target=\"9999", 1),
            "but the file has".to_string(),
        ),
        (
            good.replacen("<node id=\"1\">", "<node id=\"4000000000\">", 1),
            format!(
                "line {}: node 4000000000 is out of range: the file has {} nodes",
                line_of("<node id=\"1\">"),
                s.len()
            ),
        ),
    ];
    for (text, want) in cases {
        let e = err(&text);
        assert!(
            e.starts_with("malformed GraphML file bad.graphml: line ") && e.contains(&want),
            "{e} (wanted {want:?})"
        );
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    assert!(err("<graphml>").contains("line 1: the file ends before </graphml>"));
}
