//! graph6 and edge-list input and output.
//!
//! graph6 is nauty's format (see nauty's `formats.txt`): a size field and then
//! the upper triangle of the adjacency matrix, six bits per printable byte, in
//! the order `for j in 1..n { for i in 0..j { x(i, j) } }`. Parsing validates
//! the whole string itself and rejects non-canonical encodings (a size written
//! in a longer form than needed, nonzero padding bits), so that a graph has
//! exactly one graph6 string and the strings can serve as keys. The `graph6-rs`
//! crate is used only in tests as a reference: it indexes an empty string,
//! underflows on `n = 0`, ignores trailing bytes and padding, and writes
//! unreadable strings for `n >= 63`.
//!
//! Edge lists are plain text, one `u v` pair per line, readable by networkx's
//! `read_edgelist(path, nodetype=int)`; a `# nodes N` line keeps isolated rods.
//! They are read line by line, and an undeclared node count far beyond what
//! the edges can touch is refused before anything is allocated for it.

use std::io::{BufRead, BufReader, Write};
use std::path::Path;

use rustc_hash::FxHashMap;

use super::adjacency::ContactGraph;
use crate::error::{Error, Result};
use crate::output;

/// Optional header that nauty writes before graph6 data (`-h` option).
const GRAPH6_HEADER: &str = ">>graph6<<";

/// Largest order graph6 writes in the one-byte size form.
const MAX_SHORT_N: usize = 62;

/// Largest order graph6 writes in the four-byte size form.
pub const MAX_MEDIUM_N: usize = 258_047;

/// Largest node count read from a file: a contact graph is a graph of rods, and
/// a declared count beyond what fits in memory should fail fast, not abort.
pub const MAX_NODES: usize = crate::rods::MAX_RODS;

/// Largest edge count a [`ContactGraph`] can index: its degree sum is a `u32`.
pub const MAX_EDGES: usize = (u32::MAX / 2) as usize;

/// Longest piece of the offending input quoted in an error message.
const SNIPPET_CHARS: usize = 60;

/// Parses one graph6 string.
///
/// Surrounding whitespace and a `>>graph6<<` header are ignored. Edges come out
/// as `[i, j]` with `i < j`, ordered by `j` and then `i` (the graph6 bit order),
/// so `to_graph6(&parse_graph6(s)?) == s` for every canonical `s`.
pub fn parse_graph6(s: &str) -> Result<ContactGraph> {
    let trimmed = s.trim();
    let fail = |reason: String| Error::Graph6 {
        input: snippet(trimmed),
        reason,
    };
    let body = trimmed.strip_prefix(GRAPH6_HEADER).unwrap_or(trimmed);
    reject_other_formats(body).map_err(|r| fail(r.to_string()))?;
    if let Some((pos, c)) = body
        .char_indices()
        .find(|&(_, c)| !('?'..='~').contains(&c))
    {
        return Err(fail(format!(
            "character {c:?} at byte {pos} is outside the graph6 range '?'..='~'"
        )));
    }
    let bytes = body.as_bytes();
    let (n, size_len) = decode_size(bytes).map_err(fail)?;
    let data = &bytes[size_len..];
    let bits = pair_count(n);
    let expected = bits.div_ceil(6);
    if (data.len() as u64) < expected {
        return Err(fail(format!(
            "too short: {n} nodes need {expected} data bytes after the size, found {}",
            data.len()
        )));
    }
    if (data.len() as u64) > expected {
        return Err(fail(format!(
            "too long: {n} nodes need {expected} data bytes after the size, found {}",
            data.len()
        )));
    }
    let padding = (expected * 6 - bits) as u32;
    if let Some(&last) = data.last()
        && (last - 63) & ((1u8 << padding) - 1) != 0
    {
        return Err(fail(format!(
            "the {padding} padding bit(s) of the last byte are not zero, \
             as nauty's canonical graph6 requires"
        )));
    }
    let edges = decode_edges(data, n).map_err(fail)?;
    ContactGraph::new(n, edges).map_err(|e| fail(e.to_string()))
}

/// Writes a graph as a canonical graph6 string without header or newline.
///
/// Orders up to 62 use the one-byte size form, up to 258047 the four-byte
/// form, and larger ones nauty's eight-byte form. The string has about
/// `n² / 12` bytes whatever the edge count, so it suits small graphs only.
pub fn to_graph6(graph: &ContactGraph) -> String {
    let n = graph.n_nodes();
    let mut data = vec![0u8; pair_count(n).div_ceil(6) as usize];
    for &[a, b] in graph.edges() {
        let (i, j) = (u64::from(a.min(b)), u64::from(a.max(b)));
        let k = j * (j - 1) / 2 + i;
        data[(k / 6) as usize] |= 1 << (5 - k % 6);
    }
    let mut out = String::with_capacity(data.len() + 8);
    out.extend(encode_size(n).iter().map(|&b| char::from(b)));
    out.extend(data.iter().map(|&b| char::from(b + 63)));
    out
}

/// Reads a file of graph6 strings, one graph per non-empty line.
///
/// Errors name the line (counting from 1) and the file.
pub fn read_graph6_file(path: &Path) -> Result<Vec<ContactGraph>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let mut graphs = Vec::new();
    for (k, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        // Invalid UTF-8 becomes U+FFFD, which the parser reports as a bad character.
        let line = String::from_utf8_lossy(raw);
        if line.trim().is_empty() {
            continue;
        }
        let graph = parse_graph6(&line).map_err(|e| match e {
            Error::Graph6 { input, reason } => Error::Graph6 {
                input,
                reason: format!("line {} of {}: {reason}", k + 1, path.display()),
            },
            other => other,
        })?;
        graphs.push(graph);
    }
    Ok(graphs)
}

/// Writes graphs as a graph6 file, one per line (what [`read_graph6_file`]
/// and nauty read), atomically.
pub fn save_graph6_file<'a>(
    graphs: impl IntoIterator<Item = &'a ContactGraph>,
    path: &Path,
) -> Result<()> {
    let mut text = String::new();
    for g in graphs {
        text += &to_graph6(g);
        text.push('\n');
    }
    output::write_atomic(path, text)
}

/// Parses a contact edge list held in memory; `path` only labels error
/// messages. See [`read_edge_list_from`] for the format.
pub fn parse_edge_list(text: &str, path: &Path) -> Result<ContactGraph> {
    read_edge_list_from(text.as_bytes(), path)
}

/// Reads a contact edge list file (see [`read_edge_list_from`]).
pub fn read_edge_list(path: &Path) -> Result<ContactGraph> {
    read_edge_list_within(path, |_, _| Ok(()))
}

/// [`read_edge_list`], with `admit` asked about the numbers of nodes and
/// edges before the graph is built: a node count read from the file (a
/// `# nodes N` line, a large index) sizes everything after it, so what
/// will hold it is checked against the memory limit before any of it is
/// allocated.
pub fn read_edge_list_within(
    path: &Path,
    admit: impl FnOnce(usize, usize) -> Result<()>,
) -> Result<ContactGraph> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    read_edges(BufReader::new(file), path, admit)
}

/// Bytes a contact graph of `nodes` nodes and `edges` edges holds: per
/// node its offsets and degree, per edge the pair and both adjacency
/// entries.
pub fn graph_bytes(nodes: usize, edges: usize) -> u64 {
    16 * nodes as u64 + 40 * edges as u64
}

/// Largest node count an edge list may imply without declaring it: nodes
/// that no edge names are isolated rods, and an index far beyond what the
/// edges can touch is far more likely a typo than a system of mostly
/// isolated rods (which `write_edge_list` declares with `# nodes N`).
fn implied_node_limit(edges: usize) -> usize {
    (2 * edges).saturating_add(IMPLIED_SLACK).min(MAX_NODES)
}

/// Isolated rods an edge list may imply beyond the ends of its edges.
const IMPLIED_SLACK: usize = 1 << 16;

/// Reads a contact edge list line by line; `path` only labels error messages.
///
/// Each data line holds two non-negative node indices separated by whitespace
/// or by one comma. Blank lines and text after `#` are ignored, except that a
/// comment of the exact form `# nodes N` before the first edge sets the node
/// count; without it the count is the largest index plus one, which must
/// not exceed twice the number of edges plus 65536. Self-loops, repeated
/// pairs (in either order) and indices outside the declared count are
/// errors, since a pair of rods touches at most once. A UTF-8 byte order
/// mark at the start is skipped; other invalid UTF-8 is an error.
pub fn read_edge_list_from(reader: impl BufRead, path: &Path) -> Result<ContactGraph> {
    read_edges(reader, path, |_, _| Ok(()))
}

/// [`read_edge_list_from`], with `admit` asked before the graph is built.
fn read_edges(
    mut reader: impl BufRead,
    path: &Path,
    admit: impl FnOnce(usize, usize) -> Result<()>,
) -> Result<ContactGraph> {
    let fail = |line: usize, reason: String| Error::EdgeList {
        path: path.to_path_buf(),
        line,
        reason,
    };
    // Declared node count and the line that declared it.
    let mut declared: Option<(usize, usize)> = None;
    let mut edges: Vec<[u32; 2]> = Vec::new();
    let mut first_seen: FxHashMap<(u32, u32), usize> = FxHashMap::default();
    // Largest index seen and the line it is on.
    let mut max_index: Option<(u32, usize)> = None;
    let mut last_line = 0;
    let mut bytes = Vec::new();
    loop {
        bytes.clear();
        let read = reader
            .read_until(b'\n', &mut bytes)
            .map_err(|e| Error::io(path, e))?;
        if read == 0 {
            break;
        }
        let line = last_line + 1;
        last_line = line;
        let mut raw =
            std::str::from_utf8(&bytes).map_err(|_| fail(line, "not valid UTF-8".into()))?;
        if line == 1 {
            raw = raw.strip_prefix('\u{feff}').unwrap_or(raw);
        }
        let raw = raw.strip_suffix('\n').unwrap_or(raw);
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let (data, comment) = match raw.split_once('#') {
            Some((data, comment)) => (data.trim(), Some(comment)),
            None => (raw.trim(), None),
        };
        if let Some(count) = comment.and_then(nodes_directive) {
            if !data.is_empty() {
                return Err(fail(
                    line,
                    "'# nodes N' must be on a line of its own".into(),
                ));
            }
            if let Some((_, at)) = declared {
                return Err(fail(
                    line,
                    format!("second '# nodes N' line (first on line {at})"),
                ));
            }
            if !edges.is_empty() {
                return Err(fail(
                    line,
                    "'# nodes N' must come before the first edge".into(),
                ));
            }
            let n =
                parse_index(count, "node count", MAX_NODES as u32).map_err(|r| fail(line, r))?;
            declared = Some((n as usize, line));
            continue;
        }
        if data.is_empty() {
            continue;
        }
        let fields: Vec<&str> = if data.contains(',') {
            data.split(',').map(str::trim).collect()
        } else {
            data.split_whitespace().collect()
        };
        let [a, b] = fields[..] else {
            return Err(fail(
                line,
                format!(
                    "expected two node indices 'u v', found {} field(s)",
                    fields.len()
                ),
            ));
        };
        let u = parse_index(a, "node index", MAX_NODES as u32 - 1).map_err(|r| fail(line, r))?;
        let v = parse_index(b, "node index", MAX_NODES as u32 - 1).map_err(|r| fail(line, r))?;
        if let Some((n, at)) = declared
            && let Some(w) = [u, v].into_iter().find(|&w| w as usize >= n)
        {
            return Err(fail(
                line,
                format!("node {w} is outside 0..{n} declared on line {at}"),
            ));
        }
        if u == v {
            return Err(fail(line, format!("self-loop on node {u}")));
        }
        let key = (u.min(v), u.max(v));
        if let Some(&first) = first_seen.get(&key) {
            return Err(fail(
                line,
                format!("edge {} {} repeats line {first}", key.0, key.1),
            ));
        }
        if edges.len() >= MAX_EDGES {
            return Err(fail(line, format!("more than {MAX_EDGES} edges")));
        }
        first_seen.insert(key, line);
        edges.push([u, v]);
        if max_index.is_none_or(|(m, _)| key.1 > m) {
            max_index = Some((key.1, line));
        }
    }
    let end = last_line.max(1);
    let n = match (declared, max_index) {
        (Some((n, _)), _) => n,
        (None, Some((m, at))) => {
            let limit = implied_node_limit(edges.len());
            if m as usize >= limit {
                return Err(fail(
                    at,
                    format!(
                        "node {m} would make {} rods, but {} edge(s) touch at most {}: \
                         declare the count with a '# nodes N' line first",
                        m as usize + 1,
                        edges.len(),
                        2 * edges.len()
                    ),
                ));
            }
            m as usize + 1
        }
        (None, None) => {
            return Err(fail(end, "no edges and no '# nodes N' line".into()));
        }
    };
    drop(first_seen);
    admit(n, edges.len())?;
    ContactGraph::new(n, edges).map_err(|e| fail(end, e.to_string()))
}

/// Writes `graph` as an edge list file (see [`write_edge_list`]) atomically.
pub fn save_edge_list(graph: &ContactGraph, path: &Path) -> Result<()> {
    let mut text = Vec::new();
    write_edge_list(graph, &mut text).expect("writing to memory cannot fail");
    output::write_atomic(path, text)
}

/// Writes `# nodes N` and then one `u v` line per edge, in edge order.
///
/// The node line keeps isolated rods for [`read_edge_list`]; networkx reads it
/// as a comment.
pub fn write_edge_list(graph: &ContactGraph, w: &mut impl Write) -> std::io::Result<()> {
    writeln!(w, "# nodes {}", graph.n_nodes())?;
    for [u, v] in graph.edges() {
        writeln!(w, "{u} {v}")?;
    }
    Ok(())
}

/// Names the sibling formats so that their users get a clear message instead
/// of "bad character".
fn reject_other_formats(body: &str) -> std::result::Result<(), &'static str> {
    if body.is_empty() {
        Err("empty string")
    } else if body.starts_with('&') || body.starts_with(">>digraph6<<") {
        Err("this is digraph6 (leading '&'); only undirected graph6 is supported")
    } else if body.starts_with(':') || body.starts_with(';') || body.starts_with(">>sparse6<<") {
        Err("this is sparse6 (leading ':' or ';'); only graph6 is supported")
    } else {
        Ok(())
    }
}

/// Decodes the size field of graph6 bytes already known to lie in 63..=126,
/// returning the order and the field's length.
fn decode_size(bytes: &[u8]) -> std::result::Result<(usize, usize), String> {
    // At most 36 bits: u64 holds it on every target.
    let value = |field: &[u8]| {
        field
            .iter()
            .fold(0u64, |acc, &b| (acc << 6) | u64::from(b - 63))
    };
    match bytes {
        [] => Err("empty string".into()),
        [b, ..] if *b < 126 => Ok((usize::from(b - 63), 1)),
        [_, 126, rest @ ..] => {
            let Some(field) = rest.get(..6) else {
                return Err("truncated size: '~~' must be followed by 6 bytes".into());
            };
            let n = value(field);
            if n <= MAX_MEDIUM_N as u64 {
                Err(format!(
                    "non-canonical size: {n} nodes written in the 8-byte form, \
                     which graph6 reserves for more than {MAX_MEDIUM_N}"
                ))
            } else if n > MAX_NODES as u64 {
                Err(format!("{n} nodes are too many (at most {MAX_NODES})"))
            } else {
                Ok((n as usize, 8))
            }
        }
        [_, rest @ ..] => {
            let Some(field) = rest.get(..3) else {
                return Err("truncated size: '~' must be followed by 3 bytes".into());
            };
            let n = value(field) as usize;
            if n <= MAX_SHORT_N {
                Err(format!(
                    "non-canonical size: {n} nodes written in the 4-byte form, \
                     which graph6 reserves for {} to {MAX_MEDIUM_N}",
                    MAX_SHORT_N + 1
                ))
            } else {
                Ok((n, 4))
            }
        }
    }
}

/// The size field for `n` nodes: one byte up to 62, `~` and 3 bytes up to
/// 258047, `~~` and 6 bytes beyond (36 bits, more than any `ContactGraph`).
fn encode_size(n: usize) -> Vec<u8> {
    let field = |len: usize| {
        (0..len)
            .rev()
            .map(move |k| 63 + ((n >> (6 * k)) & 63) as u8)
    };
    if n <= MAX_SHORT_N {
        vec![63 + n as u8]
    } else if n <= MAX_MEDIUM_N {
        std::iter::once(126).chain(field(3)).collect()
    } else {
        [126, 126].into_iter().chain(field(6)).collect()
    }
}

/// Number of node pairs, i.e. of data bits; `n <= MAX_NODES` keeps it in `u64`.
fn pair_count(n: usize) -> u64 {
    let n = n as u64;
    n * n.saturating_sub(1) / 2
}

/// Reads the edges from validated data bytes in graph6 bit order.
fn decode_edges(data: &[u8], n: usize) -> std::result::Result<Vec<[u32; 2]>, String> {
    let mut edges = Vec::new();
    let (mut i, mut j) = (0u32, 1u32);
    for &byte in data {
        let bits = byte - 63;
        for shift in (0..6).rev() {
            if j as usize >= n {
                break;
            }
            if (bits >> shift) & 1 == 1 {
                if edges.len() >= MAX_EDGES {
                    return Err(format!("more than {MAX_EDGES} edges"));
                }
                edges.push([i, j]);
            }
            i += 1;
            if i == j {
                j += 1;
                i = 0;
            }
        }
    }
    Ok(edges)
}

/// The count of a `# nodes N` comment (text after the `#`), if it is one.
fn nodes_directive(comment: &str) -> Option<&str> {
    match comment.split_whitespace().collect::<Vec<_>>()[..] {
        ["nodes", count] => Some(count),
        _ => None,
    }
}

/// Parses a decimal index at most `max`; `what` names it in the message.
fn parse_index(token: &str, what: &str, max: u32) -> std::result::Result<u32, String> {
    let digits = token.strip_prefix('-').unwrap_or(token);
    let problem = if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        "is not a non-negative integer (decimal digits only)".to_string()
    } else if digits.len() < token.len() {
        "is negative".to_string()
    } else {
        // Only overflow can fail on a string of digits.
        match token.parse::<u64>() {
            Ok(v) if v <= u64::from(max) => return Ok(v as u32),
            _ => format!("is too large (at most {max})"),
        }
    };
    Err(format!("{what} {token:?} {problem}"))
}

/// The input quoted in an error, cut to [`SNIPPET_CHARS`] characters.
fn snippet(s: &str) -> String {
    match s.char_indices().nth(SNIPPET_CHARS) {
        Some((cut, _)) => format!("{}…", &s[..cut]),
        None => s.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_field_round_trips_in_every_form() {
        for n in [
            0,
            1,
            62,
            63,
            64,
            4095,
            4096,
            MAX_MEDIUM_N,
            MAX_MEDIUM_N + 1,
            MAX_NODES,
        ] {
            let field = encode_size(n);
            let mut padded = field.clone();
            padded.extend_from_slice(b"??????????");
            assert_eq!(decode_size(&padded), Ok((n, field.len())), "n = {n}");
        }
        assert_eq!(encode_size(63), b"~??~");
        assert_eq!(encode_size(MAX_MEDIUM_N), b"~}~~");
        assert_eq!(encode_size(MAX_MEDIUM_N + 1), b"~~???~??");
    }

    #[test]
    fn eight_byte_form_below_its_range_is_non_canonical() {
        let err = decode_size(b"~~?????~").unwrap_err();
        assert!(err.contains("non-canonical"), "{err}");
    }

    fn edges(text: &[u8]) -> Result<ContactGraph> {
        read_edge_list_from(text, Path::new("contacts.txt"))
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let plain = edges(b"# nodes 4\n0 1\n2 3\n").unwrap();
        assert_eq!(edges(b"\xef\xbb\xbf# nodes 4\n0 1\n2 3\n").unwrap(), plain);
        assert_eq!(edges(b"\xef\xbb\xbf0 1\r\n2 3\r\n").unwrap(), plain);
        // Only at the start of the file.
        let err = edges(b"0 1\n\xef\xbb\xbf2 3\n").unwrap_err().to_string();
        assert!(err.contains("line 2: node index"), "{err}");
    }

    #[test]
    fn an_undeclared_node_count_must_fit_the_edges() {
        let err = edges(b"49999999 0\n").unwrap_err().to_string();
        assert_eq!(
            err,
            "malformed edge list contacts.txt: line 1: node 49999999 would make 50000000 rods, \
             but 1 edge(s) touch at most 2: declare the count with a '# nodes N' line first"
        );
        // The line of the largest index is named, wherever it is.
        let err = edges(b"0 1\n1 2\n900000 3\n3 4\n").unwrap_err().to_string();
        assert!(err.contains("line 3: node 900000"), "{err}");
        // Within the slack, and with a declared count, isolated rods are fine.
        let limit = implied_node_limit(1);
        assert_eq!(limit, 2 + IMPLIED_SLACK);
        let g = edges(format!("{} 0\n", limit - 1).as_bytes()).unwrap();
        assert_eq!(g.n_nodes(), limit);
        assert!(edges(format!("{limit} 0\n").as_bytes()).is_err());
        let g = edges(b"# nodes 1000000\n999999 0\n").unwrap();
        assert_eq!((g.n_nodes(), g.n_edges()), (1_000_000, 1));
    }

    #[test]
    fn saved_graph6_files_read_back() {
        let graphs = [
            ContactGraph::new(3, vec![[0, 1], [1, 2]]).unwrap(),
            ContactGraph::new(70, vec![[0, 69]]).unwrap(),
        ];
        let path = std::env::temp_dir().join(format!("rgc-io-{}.g6", std::process::id()));
        save_graph6_file(&graphs, &path).unwrap();
        assert_eq!(read_graph6_file(&path).unwrap(), graphs);
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn saved_edge_lists_read_back() {
        let g = ContactGraph::new(5, vec![[0, 3], [1, 2]]).unwrap();
        let path = std::env::temp_dir().join(format!("rgc-io-{}.edges", std::process::id()));
        save_edge_list(&g, &path).unwrap();
        assert_eq!(read_edge_list(&path).unwrap(), g);
        std::fs::remove_file(path).unwrap();
    }
}
