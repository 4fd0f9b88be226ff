//! The crate's modules form layers: a top-level module may use only the
//! modules that `src/lib.rs` declares before it, so there is no cycle and a
//! reader can take the layers one at a time.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

const SRC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/src");

/// Top-level modules in the order `lib.rs` declares them.
fn declared_order() -> Vec<String> {
    let lib = std::fs::read_to_string(Path::new(SRC).join("lib.rs")).unwrap();
    lib.lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|m| m.trim_end_matches(';').to_string())
        .collect()
}

fn rust_files(path: &Path, out: &mut Vec<PathBuf>) {
    if path.is_dir() {
        for e in std::fs::read_dir(path).unwrap() {
            rust_files(&e.unwrap().path(), out);
        }
    } else if path.is_file() && path.extension().is_some_and(|e| e == "rs") {
        out.push(path.to_path_buf());
    }
}

/// The top-level modules named by `crate::` paths in `text`, comments removed.
fn used_modules(text: &str) -> BTreeSet<String> {
    let code: String = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let mut used = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = &group[..group.find('}').unwrap_or(group.len())];
            used.extend(group.split(',').filter_map(|item| {
                let name = item.trim().split("::").next()?.trim();
                (!name.is_empty()).then(|| name.to_string())
            }));
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            used.insert(name);
        }
    }
    used
}

#[test]
fn every_module_uses_only_the_layers_below_it() {
    let order = declared_order();
    assert!(order.len() > 10, "lib.rs declares {order:?}");
    let mut violations = Vec::new();
    for (rank, module) in order.iter().enumerate() {
        let mut files = Vec::new();
        rust_files(&Path::new(SRC).join(module), &mut files);
        rust_files(&Path::new(SRC).join(format!("{module}.rs")), &mut files);
        assert!(!files.is_empty(), "no source for module {module}");
        for file in files {
            let text = std::fs::read_to_string(&file).unwrap();
            for used in used_modules(&text) {
                if let Some(above) = order.iter().position(|m| *m == used)
                    && above > rank
                {
                    violations.push(format!(
                        "{} uses {used}, which lib.rs declares after {module}",
                        file.display()
                    ));
                }
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn the_scanner_sees_grouped_and_plain_paths() {
    let used = used_modules(
        "use crate::a::X;\nuse crate::{b::Y, c, Result};\nfn f() { crate::d::g() } // crate::e",
    );
    let names: Vec<&str> = used.iter().map(String::as_str).collect();
    assert_eq!(names, ["Result", "a", "b", "c", "d"]);
}

/// Every module of the library as its path (`truth::clusters` is
/// `["truth", "clusters"]`), with its source file; `lib.rs` is the root and
/// is left out, as is the binary.
fn modules() -> Vec<(Vec<String>, PathBuf)> {
    let mut files = Vec::new();
    rust_files(Path::new(SRC), &mut files);
    files
        .into_iter()
        .filter(|f| !f.starts_with(Path::new(SRC).join("bin")) && !f.ends_with("lib.rs"))
        .map(|f| {
            let rel = f.strip_prefix(SRC).unwrap().with_extension("");
            let mut path: Vec<String> = rel
                .iter()
                .map(|c| c.to_string_lossy().into_owned())
                .collect();
            if path.last().is_some_and(|l| l == "mod") {
                path.pop();
            }
            (path, f)
        })
        .collect()
}

/// Every path `a::b::c` in `code`, with `use` groups `a::{b, c::d}` expanded.
fn paths(code: &str) -> Vec<Vec<String>> {
    fn ident(s: &str) -> usize {
        s.char_indices()
            .find(|(_, c)| !(c.is_alphanumeric() || *c == '_'))
            .map_or(s.len(), |(i, _)| i)
    }
    /// The paths starting at `s` under `prefix`, and how much of `s` they take.
    fn walk(s: &str, prefix: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
        let n = ident(s);
        if n == 0 {
            if let Some(group) = s.strip_prefix('{') {
                let mut rest = group;
                loop {
                    rest = rest.trim_start_matches(|c: char| c.is_whitespace() || c == ',');
                    if rest.is_empty() || rest.starts_with('}') {
                        return s.len() - rest.len() + 1;
                    }
                    let took = walk(rest, prefix.clone(), out);
                    if took == 0 {
                        // `self`, `*` and the like: skip one character.
                        rest = &rest[rest.chars().next().map_or(0, char::len_utf8)..];
                    } else {
                        rest = &rest[took..];
                    }
                }
            }
            return 0;
        }
        let mut path = prefix;
        path.push(s[..n].to_string());
        match s[n..].strip_prefix("::") {
            Some(rest) => {
                let took = walk(rest, path.clone(), out);
                if took == 0 {
                    out.push(path);
                }
                n + 2 + took
            }
            None => {
                out.push(path);
                n
            }
        }
    }
    let mut out = Vec::new();
    let mut i = 0;
    while let Some(c) = code[i..].chars().next() {
        let before = code[..i].chars().next_back().unwrap_or(' ');
        let starts = (c.is_alphabetic() || c == '_')
            && !(before.is_alphanumeric() || before == '_' || before == ':' || before == '.');
        let n = if starts { ident(&code[i..]) } else { 0 };
        if n > 0 && code[i + n..].starts_with("::") {
            let mut found = Vec::new();
            i += walk(&code[i..], Vec::new(), &mut found);
            out.extend(found.into_iter().filter(|p| p.len() > 1));
        } else {
            i += n.max(c.len_utf8());
        }
    }
    out
}

/// The code of a module file: comments, `mod` declarations and the test
/// module at its end (where `super` means the file's own module) left out.
fn module_code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or(text);
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .filter(|l| {
            let t = l.trim();
            !(t.starts_with("mod ") || t.starts_with("pub mod ")) || !t.ends_with(';')
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The code whose paths a module uses: [`module_code`], and its test module,
/// where one `super` less names the same module (a test that reaches back up
/// closes a cycle as surely as the code it tests).
fn uses_code(text: &str) -> String {
    let tests = text.split_once("#[cfg(test)]").map_or("", |(_, t)| t);
    let tests = tests
        .replace("super::super::", "\u{0}")
        .replace("super::", "self::")
        .replace('\u{0}', "super::");
    format!("{}\n{}", module_code(text), module_code(&tests))
}

/// The modules each module uses: `crate::`, `super::` and `self::` paths,
/// and paths through its own children, each to the deepest module it names.
fn module_graph() -> Vec<(Vec<String>, BTreeSet<Vec<String>>)> {
    let all = modules();
    let known: BTreeSet<Vec<String>> = all.iter().map(|(m, _)| m.clone()).collect();
    all.iter()
        .map(|(m, file)| {
            let code = uses_code(&std::fs::read_to_string(file).unwrap());
            let mut uses = BTreeSet::new();
            for p in paths(&code) {
                let (mut base, rest) = match p[0].as_str() {
                    "crate" => (Vec::new(), &p[1..]),
                    "self" => (m.clone(), &p[1..]),
                    "super" => {
                        let mut b = m.clone();
                        let mut rest = &p[..];
                        while rest.first().is_some_and(|s| s == "super") {
                            b.pop();
                            rest = &rest[1..];
                        }
                        (b, rest)
                    }
                    _ => (m.clone(), &p[..]),
                };
                let start = base.len();
                base.extend(rest.iter().cloned());
                let deepest = (start..=base.len())
                    .rev()
                    .map(|k| base[..k].to_vec())
                    .find(|q| known.contains(q));
                if let Some(target) = deepest
                    && target != *m
                {
                    uses.insert(target);
                }
            }
            (m.clone(), uses)
        })
        .collect()
}

#[test]
fn no_module_or_submodule_is_part_of_an_import_cycle() {
    let graph = module_graph();
    assert!(graph.len() > 40, "{} modules", graph.len());
    let index: std::collections::BTreeMap<&Vec<String>, usize> =
        graph.iter().enumerate().map(|(i, (m, _))| (m, i)).collect();
    let n = graph.len();
    // reach[i][j]: j is reachable from i (the graph is small).
    let mut reach = vec![vec![false; n]; n];
    for (i, (_, uses)) in graph.iter().enumerate() {
        for u in uses {
            reach[i][index[u]] = true;
        }
    }
    for k in 0..n {
        let via = reach[k].clone();
        for row in &mut reach {
            if row[k] {
                for (to, &from_k) in row.iter_mut().zip(&via) {
                    *to |= from_k;
                }
            }
        }
    }
    let name = |i: usize| graph[i].0.join("::");
    let mut cycles: Vec<String> = (0..n)
        .filter(|&i| reach[i][i])
        .map(|i| {
            let mut with: Vec<String> = (0..n)
                .filter(|&j| reach[i][j] && reach[j][i])
                .map(name)
                .collect();
            with.sort();
            with.join(" <-> ")
        })
        .collect();
    cycles.sort();
    cycles.dedup();
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

#[test]
fn the_module_scanner_resolves_relative_paths_and_groups() {
    let p = paths(
        "use super::{planes::Offset, Topology};\nfn f() { crate::math::sparse::rank(\"…\") }\nuse self::a::*;",
    );
    let p: Vec<String> = p.iter().map(|p| p.join("::")).collect();
    assert_eq!(
        p,
        [
            "super::planes::Offset",
            "super::Topology",
            "crate::math::sparse::rank",
            "self::a"
        ]
    );
    // Comments, declarations and the test module are no uses.
    let code = module_code(
        "pub mod a;\n// use crate::b;\nuse crate::c;\n#[cfg(test)]\nmod tests { use super::*; }",
    );
    assert_eq!(code.trim(), "use crate::c;");
    // The test module's uses count, `super` there being the module itself
    // (whose glob is no use of another module).
    let code = uses_code(
        "use crate::c;\n#[cfg(test)]\nmod tests { use super::*; use super::super::d::E; use crate::f; }",
    );
    assert_eq!(
        paths(&code),
        [
            vec!["crate", "c"],
            vec!["super", "d", "E"],
            vec!["crate", "f"],
        ]
    );
}

/// The statements of a folder's module file that are not declarations or
/// re-exports (attributes and the test module left out).
fn definitions(text: &str) -> Vec<String> {
    module_code(text)
        .lines()
        .filter(|l| !l.trim_start().starts_with("#["))
        .collect::<Vec<_>>()
        .join("\n")
        .split(';')
        .map(|s| s.trim().to_string())
        .filter(|s| {
            !s.is_empty()
                && !["use ", "pub use ", "pub(crate) use ", "mod ", "pub mod "]
                    .iter()
                    .any(|k| s.starts_with(k))
        })
        .collect()
}

#[test]
fn a_folder_module_only_declares_and_reexports() {
    let mut folders = Vec::new();
    for (module, file) in modules() {
        let dir = Path::new(SRC).join(module.join("/"));
        if dir.is_dir() {
            folders.push(module.join("::"));
            let defined = definitions(&std::fs::read_to_string(&file).unwrap());
            assert!(
                defined.is_empty(),
                "{} defines more than its submodules: {defined:?}",
                file.display()
            );
        }
    }
    assert!(folders.len() >= 10, "folders found: {folders:?}");
}

#[test]
fn definitions_are_what_is_neither_declared_nor_reexported() {
    let text = "//! doc\nmod a;\npub use a::{\n    B, C,\n};\n#[doc(hidden)]\npub mod d;\nconst E: u8 = 1;\n#[cfg(test)]\nmod tests { fn f() {} }";
    assert_eq!(definitions(text), ["const E: u8 = 1"]);
}
