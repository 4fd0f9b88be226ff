//! GraphML: a contact graph with its geometry, for networkx
//! (`nx.read_graphml(path, node_type=int)`), Gephi or yEd.
//!
//! Nodes are rods, numbered from 0, with their centre (`cx`, `cy`, `cz`),
//! unit axis (`ax`, `ay`, `az`), core `length` and `radius`; edges are
//! contacts with the axis parameter of the contact on each rod (`s0` on the
//! lower-numbered rod, `s1` on the other, as arc length from the centre), the
//! contact point (`px`, `py`, `pz`, in the primary box) and the periodic image
//! of the second rod that touches the first (`kx`, `ky`, `kz`, in boxes). The
//! graph carries the box sides (`box_x`, `box_y`, `box_z`) and which axes are
//! `periodic` (`xyz`, `xy` or `none`). Numbers are written in their shortest
//! exact form, so a file read back gives the very same contacts.
//!
//! The reader is for files of this shape (rgc's own, or another program's
//! with the same attribute names, e.g. networkx's `write_graphml`, whose
//! keys are `d0`, `d1` ... declared with their `attr.name`): elements and
//! attributes in any order and layout, nodes in any order (numbered 0 to
//! n - 1), an edge's ends either way round, without entities, comments
//! inside elements or CDATA. It gives back the rods with their box and the
//! contacts.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use nalgebra::Vector3;

use crate::contacts::Contact;
use crate::output;
use crate::rods::{Domain, Periodic, Rod, RodSystem};
use crate::{Error, Result};

/// Node keys, in file order.
const NODE_KEYS: [&str; 8] = ["cx", "cy", "cz", "ax", "ay", "az", "length", "radius"];
/// Edge keys of type double, then of type int.
const EDGE_DOUBLES: [&str; 5] = ["s0", "s1", "px", "py", "pz"];
const EDGE_INTS: [&str; 3] = ["kx", "ky", "kz"];

/// The GraphML document of a rod system and its contacts.
pub fn to_graphml(system: &RodSystem, contacts: &[Contact]) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    s.push_str("<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\">\n");
    let key = |s: &mut String, id: &str, domain: &str, ty: &str| {
        let _ = writeln!(
            s,
            "  <key id=\"{id}\" for=\"{domain}\" attr.name=\"{id}\" attr.type=\"{ty}\"/>"
        );
    };
    for k in ["box_x", "box_y", "box_z"] {
        key(&mut s, k, "graph", "double");
    }
    key(&mut s, "periodic", "graph", "string");
    for k in NODE_KEYS {
        key(&mut s, k, "node", "double");
    }
    for k in EDGE_DOUBLES {
        key(&mut s, k, "edge", "double");
    }
    for k in EDGE_INTS {
        key(&mut s, k, "edge", "int");
    }
    s.push_str("  <graph id=\"contacts\" edgedefault=\"undirected\">\n");
    let d = &system.domain;
    for (k, v) in ["box_x", "box_y", "box_z"].iter().zip(d.sides) {
        let _ = writeln!(s, "    <data key=\"{k}\">{v}</data>");
    }
    let _ = writeln!(s, "    <data key=\"periodic\">{}</data>", d.periodic.name());
    let data = |s: &mut String, k: &str, v: &dyn std::fmt::Display| {
        let _ = write!(s, "<data key=\"{k}\">{v}</data>");
    };
    for (i, r) in system.rods.iter().enumerate() {
        let _ = write!(s, "    <node id=\"{i}\">");
        let sizes = [r.length, r.radius];
        for (k, v) in NODE_KEYS
            .iter()
            .zip(r.center.iter().chain(r.axis.iter()).chain(&sizes))
        {
            data(&mut s, k, v);
        }
        s.push_str("</node>\n");
    }
    for c in contacts {
        let _ = write!(
            s,
            "    <edge source=\"{}\" target=\"{}\">",
            c.rods[0], c.rods[1]
        );
        for (k, v) in EDGE_DOUBLES
            .iter()
            .zip(c.params.iter().chain(c.point.iter()))
        {
            data(&mut s, k, v);
        }
        for (k, v) in EDGE_INTS.iter().zip(&c.shift) {
            data(&mut s, k, v);
        }
        s.push_str("</edge>\n");
    }
    s.push_str("  </graph>\n</graphml>\n");
    s
}

/// Writes [`to_graphml`] to `path` atomically.
pub fn save_graphml(system: &RodSystem, contacts: &[Contact], path: &Path) -> Result<()> {
    output::write_atomic(path, to_graphml(system, contacts))
}

/// A GraphML file read back: the rods with their box, and their contacts.
#[derive(Clone, Debug)]
pub struct GraphmlContacts {
    pub system: RodSystem,
    pub contacts: Vec<Contact>,
}

/// An element being read: its line, what it names (a node's id, an edge's
/// rods) and its data as (key id, value).
type Open<'a, T> = Option<(usize, T, Vec<(&'a str, &'a str)>)>;

/// One element's start tag: its name, attributes, and whether it closes itself.
struct Tag<'a> {
    name: &'a str,
    attributes: Vec<(&'a str, &'a str)>,
    closed: bool,
}

/// Reads the rods, box and contacts of a GraphML document written by
/// [`to_graphml`], or by another program with the same attribute names
/// (networkx names its keys `d0`, `d1` ... and gives the names in
/// `<key attr.name=..>`; data are matched through those declarations);
/// `path` names it in errors, which give the line.
pub fn parse_graphml(text: &str, path: &Path) -> Result<GraphmlContacts> {
    let fail = |line: usize, reason: String| Error::Malformed {
        format: "GraphML",
        path: path.to_path_buf(),
        line,
        reason,
    };
    // Attribute names by key id; an undeclared key is its own name.
    let mut names: HashMap<&str, &str> = HashMap::new();
    let mut graph_data: Vec<(&str, &str)> = Vec::new();
    let mut rods: Vec<Option<Rod>> = Vec::new();
    // Node ids index the rods: none may pass the number of node elements.
    let most = text.matches("<node").count();
    let mut contacts = Vec::new();
    let mut rest = text;
    let mut line = 1;
    let mut seen_end = false;
    let mut node: Open<usize> = None;
    let mut edge: Open<[u32; 2]> = None;
    while let Some(at) = rest.find('<') {
        line += rest[..at].matches('\n').count();
        rest = &rest[at..];
        let close = rest
            .find('>')
            .ok_or_else(|| fail(line, "a tag is not closed: the file ends inside it".into()))?;
        let inner = &rest[1..close];
        let tag_line = line;
        line += inner.matches('\n').count();
        rest = &rest[close + 1..];
        if inner.starts_with('?') || inner.starts_with('!') {
            continue;
        }
        if let Some(name) = inner.strip_prefix('/') {
            match name.trim() {
                "edge" => {
                    let (l, ends, data) = edge
                        .take()
                        .ok_or_else(|| fail(tag_line, "</edge> without <edge>".into()))?;
                    contacts.push(contact(ends, &named(&data, &names)).map_err(|r| fail(l, r))?);
                }
                "node" => {
                    let (l, id, data) = node
                        .take()
                        .ok_or_else(|| fail(tag_line, "</node> without <node>".into()))?;
                    rods[id] = Some(rod(id, &named(&data, &names)).map_err(|r| fail(l, r))?);
                }
                "graphml" => seen_end = true,
                _ => {}
            }
            continue;
        }
        let tag = parse_tag(inner).map_err(|r| fail(tag_line, r))?;
        let attr = |name: &str| {
            tag.attributes
                .iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| *v)
                .ok_or_else(|| fail(tag_line, format!("<{}> has no {name} attribute", tag.name)))
        };
        let index = |name: &str| -> Result<u32> {
            let v = attr(name)?;
            v.parse::<u32>().map_err(|_| {
                fail(
                    tag_line,
                    format!("{name} {v:?} is not a rod number (0, 1, 2 ...)"),
                )
            })
        };
        match tag.name {
            "key" => {
                let id = attr("id")?;
                let name = tag
                    .attributes
                    .iter()
                    .find(|(k, _)| *k == "attr.name")
                    .map_or(id, |(_, v)| *v);
                names.insert(id, name);
            }
            "node" => {
                if node.is_some() || edge.is_some() {
                    return Err(fail(tag_line, "a <node> inside another element".into()));
                }
                let id = index("id")? as usize;
                if id >= most {
                    return Err(fail(
                        tag_line,
                        format!(
                            "node {id} is out of range: the file has {most} nodes, numbered 0, 1, 2 ..."
                        ),
                    ));
                }
                if id >= rods.len() {
                    rods.resize(id + 1, None);
                }
                if rods[id].is_some() {
                    return Err(fail(tag_line, format!("node {id} is given twice")));
                }
                if tag.closed {
                    return Err(fail(tag_line, format!("node {id} has no geometry")));
                }
                node = Some((tag_line, id, Vec::new()));
            }
            "edge" => {
                if node.is_some() || edge.is_some() {
                    return Err(fail(tag_line, "an <edge> inside another element".into()));
                }
                let (a, b) = (index("source")?, index("target")?);
                if tag.closed {
                    return Err(fail(tag_line, "an edge without its contact data".into()));
                }
                edge = Some((tag_line, [a, b], Vec::new()));
            }
            "data" => {
                let key = attr("key")?;
                let end = rest
                    .find("</data>")
                    .ok_or_else(|| fail(tag_line, format!("<data key={key:?}> is not closed")))?;
                let value = (key, rest[..end].trim());
                match (node.as_mut(), edge.as_mut()) {
                    (Some((_, _, data)), _) | (_, Some((_, _, data))) => data.push(value),
                    (None, None) => graph_data.push(value),
                }
            }
            _ => {}
        }
    }
    if edge.is_some() || node.is_some() || !seen_end {
        return Err(fail(line, "the file ends before </graphml>".into()));
    }
    let n_rods = rods.len();
    let rods: Vec<Rod> = rods
        .into_iter()
        .enumerate()
        .map(|(i, r)| {
            r.ok_or_else(|| {
                fail(
                    line,
                    format!(
                        "node {i} is missing: rods are numbered 0, 1, 2 ... up to {}",
                        n_rods - 1
                    ),
                )
            })
        })
        .collect::<Result<_>>()?;
    for c in &contacts {
        if c.rods[1] as usize >= n_rods {
            return Err(fail(
                line,
                format!(
                    "a contact names rod {}, but the file has {n_rods} rods",
                    c.rods[1]
                ),
            ));
        }
    }
    let domain = domain(&named(&graph_data, &names)).map_err(|r| fail(line, r))?;
    Ok(GraphmlContacts {
        system: RodSystem { domain, rods },
        contacts,
    })
}

/// Data as (attribute name, value).
fn named(data: &[(&str, &str)], names: &HashMap<&str, &str>) -> Vec<(String, String)> {
    data.iter()
        .map(|(k, v)| (names.get(k).unwrap_or(k).to_string(), v.to_string()))
        .collect()
}

/// Reads a GraphML file (see [`parse_graphml`]).
pub fn read_graphml(path: &Path) -> Result<GraphmlContacts> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_graphml(&text, path)
}

/// A start tag's name and `key="value"` attributes.
fn parse_tag(inner: &str) -> std::result::Result<Tag<'_>, String> {
    let (inner, closed) = match inner.strip_suffix('/') {
        Some(i) => (i, true),
        None => (inner, false),
    };
    let inner = inner.trim();
    let name_end = inner.find(char::is_whitespace).unwrap_or(inner.len());
    let (name, mut rest) = inner.split_at(name_end);
    let mut attributes = Vec::new();
    loop {
        rest = rest.trim_start();
        if rest.is_empty() {
            break;
        }
        let eq = rest
            .find('=')
            .ok_or_else(|| format!("<{name}>: attribute without a value"))?;
        let key = rest[..eq].trim();
        let value = rest[eq + 1..].trim_start();
        let quote = value
            .chars()
            .next()
            .filter(|c| *c == '"' || *c == '\'')
            .ok_or_else(|| format!("<{name}>: attribute {key} is not quoted"))?;
        let end = value[1..]
            .find(quote)
            .ok_or_else(|| format!("<{name}>: attribute {key} is not closed"))?;
        attributes.push((key, &value[1..1 + end]));
        rest = &value[end + 2..];
    }
    Ok(Tag {
        name,
        attributes,
        closed,
    })
}

/// The value of attribute `key` in `data`, or why there is none; `what`
/// names the element.
fn value<'a>(
    data: &'a [(String, String)],
    key: &str,
    what: &str,
) -> std::result::Result<&'a str, String> {
    data.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
        .ok_or_else(|| format!("{what} has no {key}"))
}

/// A finite number.
fn double(data: &[(String, String)], key: &str, what: &str) -> std::result::Result<f64, String> {
    let v = value(data, key, what)?;
    v.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{what}: {key} {v:?} is not a finite number"))
}

/// A node's rod from its data.
fn rod(id: usize, data: &[(String, String)]) -> std::result::Result<Rod, String> {
    let what = format!("node {id}");
    let [cx, cy, cz, ax, ay, az, length, radius] = NODE_KEYS.map(|k| double(data, k, &what));
    let (length, radius) = (length?, radius?);
    if length <= 0.0 || radius <= 0.0 {
        return Err(format!(
            "{what}: a rod needs a positive length and radius, not {length} and {radius}"
        ));
    }
    Ok(Rod::new(
        Vector3::new(cx?, cy?, cz?),
        Vector3::new(ax?, ay?, az?),
        length,
        radius,
    ))
}

/// The box from the graph's data.
fn domain(data: &[(String, String)]) -> std::result::Result<Domain, String> {
    let [x, y, z] = ["box_x", "box_y", "box_z"].map(|k| double(data, k, "the graph"));
    let sides = [x?, y?, z?];
    if sides.iter().any(|&l| l <= 0.0) {
        return Err(format!("the box sides {sides:?} must be positive"));
    }
    let periodic = match value(data, "periodic", "the graph")? {
        "xyz" => Periodic::Xyz,
        "xy" => Periodic::Xy,
        "none" => Periodic::None,
        other => {
            return Err(format!("periodic {other:?} is none of xyz, xy and none"));
        }
    };
    Ok(Domain { sides, periodic })
}

/// An edge's contact from its data; `s0` and the image belong to the
/// lower-numbered rod whichever end the edge names first.
fn contact(ends: [u32; 2], data: &[(String, String)]) -> std::result::Result<Contact, String> {
    let rods = [ends[0].min(ends[1]), ends[0].max(ends[1])];
    let what = format!("edge {} {}", ends[0], ends[1]);
    if rods[0] == rods[1] {
        return Err(format!("{what}: a rod does not touch itself"));
    }
    let int = |key: &str| -> std::result::Result<i32, String> {
        let v = value(data, key, &what)?;
        v.parse::<i32>()
            .map_err(|_| format!("{what}: {key} {v:?} is not an integer"))
    };
    let [s0, s1, px, py, pz] = EDGE_DOUBLES.map(|k| double(data, k, &what));
    let [kx, ky, kz] = EDGE_INTS.map(int);
    Ok(Contact {
        rods,
        params: [s0?, s1?],
        point: Vector3::new(px?, py?, pz?),
        shift: [kx?, ky?, kz?],
    })
}
