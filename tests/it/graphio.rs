//! graph6 and edge-list I/O: known strings, nauty conventions (checked against
//! networkx output and the graph6-rs crate), round trips, every error message,
//! and fuzzing for panics.

use std::path::{Path, PathBuf};

use graph6_rs::WriteGraph;
use proptest::prelude::*;
use rgc::Error;
use rgc::graph::ContactGraph;
use rgc::graph::io::{
    parse_edge_list, parse_graph6, read_edge_list, read_graph6_file, to_graph6, write_edge_list,
};

fn graph(n: usize, edges: &[[u32; 2]]) -> ContactGraph {
    ContactGraph::new(n, edges.to_vec()).unwrap()
}

/// Deterministic pseudo-random numbers (splitmix64), so the graph sets need no
/// RNG crate API.
struct Mix(u64);

impl Mix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// True with probability `p`.
    fn chance(&mut self, p: f64) -> bool {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 <= p
    }
}

/// A random graph with edges in graph6 bit order (by `j`, then `i`), the order
/// `parse_graph6` returns.
fn random_graph(n: usize, p: f64, rng: &mut Mix) -> ContactGraph {
    let mut edges = Vec::new();
    for j in 1..n as u32 {
        for i in 0..j {
            if rng.chance(p) {
                edges.push([i, j]);
            }
        }
    }
    graph(n, &edges)
}

/// Graphs of every order 0..=70 (so both size forms) at several densities,
/// plus a few larger ones.
fn graph_set() -> Vec<ContactGraph> {
    let mut rng = Mix(42);
    let mut set = Vec::new();
    for n in 0..=70 {
        for p in [0.0, 0.1, 0.5, 0.9, 1.0] {
            set.push(random_graph(n, p, &mut rng));
        }
    }
    for n in [100, 300, 1000] {
        set.push(random_graph(n, 0.01, &mut rng));
        set.push(random_graph(n, 0.5, &mut rng));
    }
    set
}

fn adjacency(g: &ContactGraph) -> Vec<usize> {
    let n = g.n_nodes();
    let mut adj = vec![0; n * n];
    for &[a, b] in g.edges() {
        adj[a as usize * n + b as usize] = 1;
        adj[b as usize * n + a as usize] = 1;
    }
    adj
}

fn graph6_reason(input: &str) -> String {
    match parse_graph6(input) {
        Err(Error::Graph6 { reason, .. }) => reason,
        other => panic!("{input:?} should be malformed graph6, got {other:?}"),
    }
}

fn assert_graph6_error(input: &str, expected: &str) {
    let reason = graph6_reason(input);
    assert!(
        reason.contains(expected),
        "{input:?}: reason {reason:?} lacks {expected:?}"
    );
}

fn temp_file(name: &str, contents: &[u8]) -> PathBuf {
    let path = std::env::temp_dir().join(format!("rgc-graphio-{}-{name}", std::process::id()));
    std::fs::write(&path, contents).unwrap();
    path
}

#[test]
fn known_small_strings() {
    let cases: [(&str, usize, &[[u32; 2]]); 7] = [
        ("?", 0, &[]),
        ("@", 1, &[]),
        ("A?", 2, &[]),
        ("A_", 2, &[[0, 1]]),
        // networkx writes the path 0-1-2 as "Bg"; "Bw" sets all three bits.
        ("Bg", 3, &[[0, 1], [1, 2]]),
        ("Bw", 3, &[[0, 1], [0, 2], [1, 2]]),
        ("C~", 4, &[[0, 1], [0, 2], [1, 2], [0, 3], [1, 3], [2, 3]]),
    ];
    for (s, n, edges) in cases {
        let g = parse_graph6(s).unwrap();
        assert_eq!(g, graph(n, edges), "{s}");
        assert_eq!(to_graph6(&g), s);
    }
}

#[test]
fn writer_uses_graph6_bit_order_whatever_the_edge_order() {
    // x(0,2) is the second bit and x(1,2) the third: 0b011000 + 63 = 'W'.
    assert_eq!(to_graph6(&graph(3, &[[2, 1], [0, 2]])), "BW");
    assert_eq!(parse_graph6("BW").unwrap().edges(), &[[0, 2], [1, 2]]);
}

#[test]
fn long_form_matches_networkx() {
    // nx.to_graph6_bytes(nx.empty_graph(63), header=False)
    let empty63 = format!("~??~{}", "?".repeat(326));
    assert_eq!(parse_graph6(&empty63).unwrap(), graph(63, &[]));
    assert_eq!(to_graph6(&graph(63, &[])), empty63);

    // 64 nodes, edges (0,1), (5,63), (62,63), (0,63).
    let s64 = format!("~?@?_{}CG{}@", "?".repeat(324), "?".repeat(8));
    let g64 = graph(64, &[[0, 1], [0, 63], [5, 63], [62, 63]]);
    assert_eq!(parse_graph6(&s64).unwrap(), g64);
    assert_eq!(to_graph6(&g64), s64);

    // 300 nodes, edges (0,299), (17,42), (298,299).
    let s300 = format!(
        "~?Ck{}G{}O{}@",
        "?".repeat(146),
        "?".repeat(7278),
        "?".repeat(48)
    );
    let g300 = graph(300, &[[17, 42], [0, 299], [298, 299]]);
    assert_eq!(parse_graph6(&s300).unwrap(), g300);
    assert_eq!(to_graph6(&g300), s300);
}

#[test]
fn header_and_surrounding_whitespace_are_ignored() {
    let k2 = graph(2, &[[0, 1]]);
    for s in [">>graph6<<A_", ">>graph6<<A_\n", "  A_\r\n", "\tA_ "] {
        assert_eq!(parse_graph6(s).unwrap(), k2, "{s:?}");
    }
}

#[test]
fn round_trip_graph_set() {
    for g in graph_set() {
        let s = to_graph6(&g);
        let back = parse_graph6(&s).unwrap();
        assert_eq!(back, g, "n = {}", g.n_nodes());
        assert_eq!(to_graph6(&back), s);
    }
}

#[test]
fn agrees_with_graph6_rs_up_to_62_nodes() {
    // n = 0 is left out: graph6-rs computes n - 1 and overflows in debug builds.
    for g in graph_set()
        .into_iter()
        .filter(|g| (1..=62).contains(&g.n_nodes()))
    {
        let ours = to_graph6(&g);
        let reference = graph6_rs::Graph::from_adj(&adjacency(&g)).unwrap();
        assert_eq!(ours, reference.write_graph());
        let decoded = graph6_rs::Graph::from_g6(&ours).unwrap();
        assert_eq!(decoded.n, g.n_nodes());
        assert_eq!(decoded.bit_vec, adjacency(&parse_graph6(&ours).unwrap()));
    }
}

#[test]
fn graph6_rs_is_lax_so_we_validate_ourselves() {
    // Trailing bytes and nonzero padding are accepted by graph6-rs 0.2.1 ...
    assert!(graph6_rs::Graph::from_g6("A_?").is_ok());
    assert!(graph6_rs::Graph::from_g6("A`").is_ok());
    // ... and its writer puts n + 63 in one byte even for n >= 63.
    let n63 = graph6_rs::Graph::from_adj(&vec![0; 63 * 63]).unwrap();
    let written = n63.write_graph();
    assert!(written.starts_with('~'));
    assert!(graph6_rs::Graph::from_g6(&written).is_err());
    // We reject all three.
    assert_graph6_error("A_?", "too long");
    assert_graph6_error("A`", "padding");
    assert_graph6_error(&written, "non-canonical size");
}

#[test]
fn errors_empty() {
    for s in ["", "   \n", ">>graph6<<", " >>graph6<< "] {
        assert_graph6_error(s, "empty string");
    }
}

#[test]
fn errors_bad_character() {
    assert_graph6_error("A!", "character '!' at byte 1 is outside");
    assert_graph6_error("A\u{7f}", "character '\\u{7f}' at byte 1");
    assert_graph6_error("Aé", "character 'é' at byte 1");
    assert_graph6_error("A _", "character ' ' at byte 1");
    assert_graph6_error("0", "character '0' at byte 0");
}

#[test]
fn errors_length() {
    assert_graph6_error(
        "A",
        "too short: 2 nodes need 1 data bytes after the size, found 0",
    );
    assert_graph6_error(
        "C~?",
        "too long: 4 nodes need 1 data bytes after the size, found 2",
    );
    assert_graph6_error("??", "too long: 0 nodes need 0");
    assert_graph6_error("@?", "too long: 1 nodes need 0");
    assert_graph6_error("~??~", "too short: 63 nodes need 326 data bytes");
    assert_graph6_error(&format!("~??~{}", "?".repeat(327)), "too long: 63 nodes");
}

#[test]
fn errors_nonzero_padding() {
    // n = 3: three bits, then three padding bits; 'x' = 0b111001.
    assert_graph6_error("Bx", "3 padding bit(s) of the last byte are not zero");
    // n = 63: 1953 bits, the last of 326 bytes has 3 padding bits.
    assert_graph6_error(
        &format!("~??~{}@", "?".repeat(325)),
        "padding bit(s) of the last byte are not zero, as nauty's canonical graph6 requires",
    );
    // n = 4: six bits, no padding, so any last byte is fine.
    assert!(parse_graph6("C@").is_ok());
}

#[test]
fn errors_other_formats() {
    assert_graph6_error("&AG", "digraph6");
    assert_graph6_error(">>digraph6<<&AG", "digraph6");
    assert_graph6_error(":A_", "sparse6");
    assert_graph6_error(";A_", "sparse6");
    assert_graph6_error(">>sparse6<<:A_", "sparse6");
}

#[test]
fn errors_size_field_of_63_or_more_nodes() {
    // What graph6-rs writes for 63 nodes: '~' then data, read as a 4-byte size.
    assert_graph6_error(
        &format!("~{}", "?".repeat(326)),
        "non-canonical size: 0 nodes",
    );
    assert_graph6_error("~", "truncated size: '~' must be followed by 3 bytes");
    assert_graph6_error("~?~", "truncated size");
    assert_graph6_error("~~????", "truncated size: '~~' must be followed by 6 bytes");
    // 62 nodes written in the 4-byte form.
    assert_graph6_error(
        &format!("~??}}{}", "?".repeat(314)),
        "non-canonical size: 62 nodes written in the 4-byte form",
    );
    assert_graph6_error(
        "~~?????~",
        "non-canonical size: 63 nodes written in the 8-byte form",
    );
    // 2^36 - 1 nodes: more than a ContactGraph holds, reported before the length.
    assert_graph6_error("~~~~~~~~", "nodes are too many");
    // 258048 nodes in the 8-byte form decode, then fail on length.
    assert_graph6_error("~~???~??", "too short: 258048 nodes");
}

#[test]
fn error_quotes_long_input_truncated() {
    let long = format!("A{}", "?".repeat(500));
    match parse_graph6(&long) {
        Err(Error::Graph6 { input, .. }) => {
            assert!(input.chars().count() <= 61, "{input}");
            assert!(input.starts_with("A???"));
            assert!(input.ends_with('…'));
        }
        other => panic!("expected an error, got {other:?}"),
    }
    let message = parse_graph6("A!").unwrap_err().to_string();
    assert_eq!(
        message,
        "malformed graph6 \"A!\": character '!' at byte 1 is outside the graph6 range '?'..='~'"
    );
}

#[test]
fn graph6_file_one_graph_per_line() {
    let path = temp_file("ok.g6", b">>graph6<<A_\n\nBw\r\n  \n?\nC~");
    let graphs = read_graph6_file(&path).unwrap();
    assert_eq!(
        graphs,
        vec![
            graph(2, &[[0, 1]]),
            graph(3, &[[0, 1], [0, 2], [1, 2]]),
            graph(0, &[]),
            graph(4, &[[0, 1], [0, 2], [1, 2], [0, 3], [1, 3], [2, 3]]),
        ]
    );
    std::fs::remove_file(&path).unwrap();

    let path = temp_file("bad.g6", b"A_\n\nBw?\nC~\n");
    let message = read_graph6_file(&path).unwrap_err().to_string();
    assert!(message.contains("line 3 of "), "{message}");
    assert!(message.contains("too long"), "{message}");
    std::fs::remove_file(&path).unwrap();

    let path = temp_file("utf8.g6", b"A_\n\xffA\n");
    let message = read_graph6_file(&path).unwrap_err().to_string();
    assert!(message.contains("line 2 of "), "{message}");
    assert!(message.contains("'\u{fffd}'"), "{message}");
    std::fs::remove_file(&path).unwrap();

    let missing = Path::new("/nonexistent/rgc/graphs.g6");
    match read_graph6_file(missing) {
        Err(Error::Io { path, .. }) => assert_eq!(path, missing),
        other => panic!("expected an I/O error, got {other:?}"),
    }
}

fn edge_list_error(text: &str) -> (usize, String) {
    match parse_edge_list(text, Path::new("contacts.txt")) {
        Err(Error::EdgeList { path, line, reason }) => {
            assert_eq!(path, Path::new("contacts.txt"));
            (line, reason)
        }
        other => panic!("{text:?} should be a malformed edge list, got {other:?}"),
    }
}

fn assert_edge_list_error(text: &str, line: usize, expected: &str) {
    let (got_line, reason) = edge_list_error(text);
    assert_eq!(got_line, line, "{text:?}: {reason}");
    assert!(
        reason.contains(expected),
        "{text:?}: reason {reason:?} lacks {expected:?}"
    );
}

#[test]
fn edge_list_round_trip() {
    for g in graph_set().into_iter().filter(|g| g.n_nodes() <= 70) {
        let mut out = Vec::new();
        write_edge_list(&g, &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with(&format!("# nodes {}\n", g.n_nodes())));
        assert_eq!(text.lines().count(), g.n_edges() + 1);
        assert_eq!(parse_edge_list(&text, Path::new("x")).unwrap(), g);
    }
}

#[test]
fn edge_list_formats() {
    let g = parse_edge_list(
        "# written by hand\n\n0 1\n  2\t1  \n3,0\n4, 2 # trailing comment\n",
        Path::new("x"),
    )
    .unwrap();
    assert_eq!(g, graph(5, &[[0, 1], [2, 1], [3, 0], [4, 2]]));

    let g = parse_edge_list("# comment first\n# nodes 7\n0 1\n", Path::new("x")).unwrap();
    assert_eq!(g, graph(7, &[[0, 1]]));
    // A comment that merely starts with "nodes" is a comment.
    let g = parse_edge_list("# nodes are rods\n0 1\n", Path::new("x")).unwrap();
    assert_eq!(g, graph(2, &[[0, 1]]));
    // Isolated nodes only.
    assert_eq!(
        parse_edge_list("# nodes 3\n", Path::new("x")).unwrap(),
        graph(3, &[])
    );
    assert_eq!(
        parse_edge_list("# nodes 0", Path::new("x")).unwrap(),
        graph(0, &[])
    );
}

#[test]
fn edge_list_errors_name_the_line() {
    assert_edge_list_error(
        "0 1\n1 2 3\n",
        2,
        "expected two node indices 'u v', found 3",
    );
    assert_edge_list_error("0 1\n\n7\n", 3, "found 1 field(s)");
    assert_edge_list_error("0,1,2\n", 1, "found 3 field(s)");
    assert_edge_list_error("0 x\n", 1, "node index \"x\" is not a non-negative integer");
    assert_edge_list_error("0 1.5\n", 1, "is not a non-negative integer");
    assert_edge_list_error("0 +1\n", 1, "is not a non-negative integer");
    assert_edge_list_error("0 1\n-3 1\n", 2, "node index \"-3\" is negative");
    assert_edge_list_error(
        "# nodes 3\n0 1\n1 3\n",
        3,
        "node 3 is outside 0..3 declared on line 1",
    );
    assert_edge_list_error("0 1\n2 2\n", 2, "self-loop on node 2");
    assert_edge_list_error("0 1\n1 2\n\n2 1\n", 4, "edge 1 2 repeats line 2");
    assert_edge_list_error("0 1\n0 1\n", 2, "edge 0 1 repeats line 1");
    assert_edge_list_error("0 50000000\n", 1, "is too large (at most 49999999)");
    assert_edge_list_error("0 99999999999999999999999\n", 1, "is too large");
    assert_edge_list_error("", 1, "no edges and no '# nodes N' line");
    assert_edge_list_error(
        "# only a comment\n\n",
        2,
        "no edges and no '# nodes N' line",
    );
    assert_edge_list_error("0 1\n# nodes 3\n", 2, "must come before the first edge");
    assert_edge_list_error(
        "# nodes 3\n# nodes 4\n",
        2,
        "second '# nodes N' line (first on line 1)",
    );
    assert_edge_list_error("0 1 # nodes 3\n", 1, "on a line of its own");
    assert_edge_list_error("# nodes -1\n", 1, "node count \"-1\" is negative");
    assert_edge_list_error("# nodes three\n", 1, "node count \"three\" is not");
    assert_edge_list_error("# nodes 50000001\n", 1, "is too large (at most 50000000)");

    let message = parse_edge_list("0 1\n2 2\n", Path::new("c.txt"))
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        "malformed edge list c.txt: line 2: self-loop on node 2"
    );
}

#[test]
fn edge_list_files() {
    let g = graph(4, &[[0, 3], [1, 2]]);
    let mut out = Vec::new();
    write_edge_list(&g, &mut out).unwrap();
    let path = temp_file("ok.edges", &out);
    assert_eq!(read_edge_list(&path).unwrap(), g);
    std::fs::remove_file(&path).unwrap();

    let path = temp_file("utf8.edges", b"0 1\n1 2\n2 \xff\n");
    match read_edge_list(&path) {
        Err(Error::EdgeList { line, reason, .. }) => {
            assert_eq!(line, 3);
            assert!(reason.contains("UTF-8"), "{reason}");
        }
        other => panic!("expected an edge-list error, got {other:?}"),
    }
    std::fs::remove_file(&path).unwrap();

    let missing = Path::new("/nonexistent/rgc/contacts.txt");
    let err = read_edge_list(missing).unwrap_err();
    assert!(matches!(&err, Error::Io { path, .. } if path == missing));
    assert!(
        err.to_string()
            .starts_with("/nonexistent/rgc/contacts.txt: ")
    );
}

/// A graph of up to `max_n` nodes with edges in graph6 order.
fn arb_graph(max_n: usize) -> impl Strategy<Value = ContactGraph> {
    (0..=max_n).prop_flat_map(|n| {
        let pairs = n * n.saturating_sub(1) / 2;
        proptest::collection::vec(any::<bool>(), pairs).prop_map(move |bits| {
            let mut edges = Vec::new();
            let mut k = 0;
            for j in 1..n as u32 {
                for i in 0..j {
                    if bits[k] {
                        edges.push([i, j]);
                    }
                    k += 1;
                }
            }
            graph(n, &edges)
        })
    })
}

proptest! {
    #[test]
    fn arbitrary_strings_never_panic(s in any::<String>()) {
        let _ = parse_graph6(&s);
        let _ = parse_edge_list(&s, Path::new("fuzz"));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let s = String::from_utf8_lossy(&bytes);
        let _ = parse_graph6(&s);
        let _ = parse_edge_list(&s, Path::new("fuzz"));
    }

    /// Strings in the graph6 alphabet reach the deeper checks; whatever parses
    /// must be canonical, i.e. written back unchanged.
    #[test]
    fn graph6_alphabet_parses_canonically(s in "(>>graph6<<)?[?-~]{0,40}") {
        if let Ok(g) = parse_graph6(&s) {
            prop_assert_eq!(to_graph6(&g), s.trim_start_matches(">>graph6<<"));
        }
    }

    #[test]
    fn long_form_prefixes_never_panic(s in "~~?[?-~]{0,12}") {
        let _ = parse_graph6(&s);
    }

    #[test]
    fn edge_list_alphabet_never_panics(s in "[0-9 ,#\\-nodes\n]{0,80}") {
        let _ = parse_edge_list(&s, Path::new("fuzz"));
    }

    #[test]
    fn valid_encodings_round_trip(g in arb_graph(80)) {
        let s = to_graph6(&g);
        let back = parse_graph6(&s).unwrap();
        prop_assert_eq!(&back, &g);
        prop_assert_eq!(to_graph6(&back), s);
    }

    #[test]
    fn edge_lists_round_trip(g in arb_graph(30)) {
        let mut out = Vec::new();
        write_edge_list(&g, &mut out).unwrap();
        let back = parse_edge_list(std::str::from_utf8(&out).unwrap(), Path::new("x")).unwrap();
        prop_assert_eq!(back, g);
    }
}
