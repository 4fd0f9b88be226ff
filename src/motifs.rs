//! Motifs as typed patterns: nodes that are rods or bodies (planar or
//! spatial), and contacts that say which rod of each node they sit on
//! (DESIGN §6). The enumerator produces them, the rank decides them, rule
//! files store them and the engine matches them.

use serde::{Deserialize, Serialize};

use crate::contacts::ContactGraph;
use crate::engine::{Body, BodyClass};
use crate::{Error, Result};

/// What a pattern node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NodeKind {
    /// A single rod: 5 degrees of freedom, all its contacts on one line.
    Rod,
    /// A rigid body whose rods lie in one plane.
    Planar,
    /// A rigid body in general position.
    Spatial,
}

impl NodeKind {
    pub fn is_body(self) -> bool {
        self != NodeKind::Rod
    }

    /// The body class of a body kind.
    pub fn class(self) -> Option<BodyClass> {
        match self {
            NodeKind::Rod => None,
            NodeKind::Planar => Some(BodyClass::Planar),
            NodeKind::Spatial => Some(BodyClass::Spatial),
        }
    }

    /// Degrees of freedom of a free node: 5 for a rod, 6 for a body.
    pub fn dof(self) -> usize {
        if self.is_body() { 6 } else { 5 }
    }
}

/// A contact between two pattern nodes, with the rod it sits on in each
/// (rod labels are local to a node; a rod node has only rod 0). Two contacts
/// of a body with the same label share that rod: they are collinear.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PatternContact {
    pub nodes: [u8; 2],
    pub rods: [u8; 2],
}

/// A typed contact pattern.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Pattern {
    pub kinds: Vec<NodeKind>,
    pub contacts: Vec<PatternContact>,
}

/// Largest pattern the toolkit handles (nodes, and contacts).
pub const MAX_PATTERN_NODES: usize = 24;
pub const MAX_PATTERN_CONTACTS: usize = 96;

impl Pattern {
    /// A rods-only pattern from a simple graph.
    pub fn from_graph(g: &ContactGraph) -> Result<Self> {
        if g.n_nodes() > MAX_PATTERN_NODES || g.n_edges() > MAX_PATTERN_CONTACTS {
            return Err(Error::Parameter(format!(
                "a pattern has at most {MAX_PATTERN_NODES} nodes and {MAX_PATTERN_CONTACTS} contacts, got {} and {}",
                g.n_nodes(),
                g.n_edges()
            )));
        }
        Ok(Pattern {
            kinds: vec![NodeKind::Rod; g.n_nodes()],
            contacts: g
                .edges()
                .iter()
                .map(|&[a, b]| PatternContact {
                    nodes: [a as u8, b as u8],
                    rods: [0, 0],
                })
                .collect(),
        })
    }

    /// Checks the pattern is well formed: sizes, node indices, no self-contact,
    /// rods carry only rod label 0, two rods touch at most once and a body's
    /// rod touches another rod at most once.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Parameter(m));
        if self.kinds.is_empty() || self.kinds.len() > MAX_PATTERN_NODES {
            return bad(format!(
                "a pattern has 1 to {MAX_PATTERN_NODES} nodes, got {}",
                self.kinds.len()
            ));
        }
        if self.contacts.len() > MAX_PATTERN_CONTACTS {
            return bad(format!(
                "a pattern has at most {MAX_PATTERN_CONTACTS} contacts, got {}",
                self.contacts.len()
            ));
        }
        let mut seen = std::collections::HashSet::new();
        for (k, c) in self.contacts.iter().enumerate() {
            let [a, b] = c.nodes;
            if a as usize >= self.kinds.len() || b as usize >= self.kinds.len() {
                return bad(format!(
                    "contact {k} names a node outside 0..{}",
                    self.kinds.len()
                ));
            }
            if a == b {
                return bad(format!("contact {k} joins node {a} to itself"));
            }
            for side in 0..2 {
                if self.kinds[c.nodes[side] as usize] == NodeKind::Rod && c.rods[side] != 0 {
                    return bad(format!(
                        "contact {k}: node {} is a rod and has only rod 0",
                        c.nodes[side]
                    ));
                }
            }
            let key = if (a, c.rods[0]) <= (b, c.rods[1]) {
                (a, c.rods[0], b, c.rods[1])
            } else {
                (b, c.rods[1], a, c.rods[0])
            };
            if !seen.insert(key) {
                return bad(format!(
                    "contact {k} repeats rod {} of node {a} touching rod {} of node {b}: two rods touch at most once",
                    c.rods[0], c.rods[1]
                ));
            }
        }
        Ok(())
    }

    pub fn n_nodes(&self) -> usize {
        self.kinds.len()
    }

    pub fn n_rods(&self) -> usize {
        self.kinds.iter().filter(|k| !k.is_body()).count()
    }

    pub fn n_bodies(&self) -> usize {
        self.kinds.len() - self.n_rods()
    }

    /// Maxwell's necessary count for rigidity: `3 contacts >= 5 rods + 6 bodies - 6`.
    pub fn maxwell(&self) -> bool {
        3 * self.contacts.len() + 6 >= 5 * self.n_rods() + 6 * self.n_bodies()
    }

    /// Number of contacts between nodes `a` and `b`.
    pub fn multiplicity(&self, a: u8, b: u8) -> usize {
        self.contacts
            .iter()
            .filter(|c| c.nodes == [a, b] || c.nodes == [b, a])
            .count()
    }

    /// The rods of node `i`: the distinct labels its contacts use (at least one).
    pub fn rods_of(&self, i: u8) -> Vec<u8> {
        let mut rods: Vec<u8> = self
            .contacts
            .iter()
            .flat_map(|c| {
                (0..2)
                    .filter(move |&s| c.nodes[s] == i)
                    .map(move |s| c.rods[s])
            })
            .collect();
        rods.push(0);
        rods.sort_unstable();
        rods.dedup();
        if self.kinds[i as usize] == NodeKind::Rod {
            rods.truncate(1);
        }
        rods
    }

    /// The pattern as a rods-level host: one rod per (node, rod label), the
    /// pattern's bodies declared rigid. Returns the graph, the declared bodies
    /// and, for each pattern node, its rods in the host. A body with a single
    /// rod label gets a second, contact-free rod so that it is a body.
    pub fn to_host(&self) -> Result<(ContactGraph, Vec<Body>, Vec<Vec<u32>>)> {
        self.validate()?;
        let mut rod_of = std::collections::HashMap::new();
        let mut members: Vec<Vec<u32>> = Vec::with_capacity(self.kinds.len());
        let mut next = 0u32;
        for (i, kind) in self.kinds.iter().enumerate() {
            let mut rods = Vec::new();
            for label in self.rods_of(i as u8) {
                rod_of.insert((i as u8, label), next);
                rods.push(next);
                next += 1;
            }
            if kind.is_body() && rods.len() < 2 {
                rods.push(next);
                next += 1;
            }
            members.push(rods);
        }
        let edges = self
            .contacts
            .iter()
            .map(|c| {
                [
                    rod_of[&(c.nodes[0], c.rods[0])],
                    rod_of[&(c.nodes[1], c.rods[1])],
                ]
            })
            .collect();
        let graph = ContactGraph::new(next as usize, edges)?;
        let bodies = self
            .kinds
            .iter()
            .zip(&members)
            .filter_map(|(k, rods)| k.class().map(|class| Body::new(rods.clone(), class)))
            .collect();
        Ok((graph, bodies, members))
    }

    /// The pattern of a rods-level host: each declared body becomes a body
    /// node whose rods are its member rods that have contacts, every other rod
    /// a rod node. Contacts inside one body are dropped (the body is rigid).
    pub fn from_host(graph: &ContactGraph, bodies: &[Body]) -> Result<Self> {
        let mut node_of = vec![None; graph.n_nodes()];
        let mut kinds = Vec::new();
        let mut label_of = vec![0u8; graph.n_nodes()];
        for body in bodies {
            let node = kinds.len() as u8;
            kinds.push(match body.class {
                BodyClass::Planar => NodeKind::Planar,
                BodyClass::Spatial => NodeKind::Spatial,
            });
            for (label, &r) in body.rods.iter().enumerate() {
                let slot = node_of.get_mut(r as usize).ok_or_else(|| {
                    Error::Parameter(format!("body rod {r} is outside 0..{}", graph.n_nodes()))
                })?;
                *slot = Some(node);
                label_of[r as usize] = u8::try_from(label).map_err(|_| {
                    Error::Parameter(format!(
                        "a body has more than 255 rods ({})",
                        body.rods.len()
                    ))
                })?;
            }
        }
        for slot in node_of.iter_mut().filter(|s| s.is_none()) {
            *slot = Some(kinds.len() as u8);
            kinds.push(NodeKind::Rod);
        }
        if kinds.len() > MAX_PATTERN_NODES {
            return Err(Error::Parameter(format!(
                "a pattern has at most {MAX_PATTERN_NODES} nodes, this host makes {}",
                kinds.len()
            )));
        }
        let contacts = graph
            .edges()
            .iter()
            .filter_map(|&[a, b]| {
                let (na, nb) = (node_of[a as usize]?, node_of[b as usize]?);
                (na != nb).then(|| PatternContact {
                    nodes: [na, nb],
                    rods: [label_of[a as usize], label_of[b as usize]],
                })
            })
            .collect();
        let mut p = Pattern { kinds, contacts };
        p.compact_labels();
        p.validate()?;
        Ok(p)
    }

    /// Renumbers each body's rod labels `0..` in order of first use, so that
    /// labels of rods without contacts leave no gaps.
    fn compact_labels(&mut self) {
        for node in 0..self.kinds.len() as u8 {
            let mut map: Vec<u8> = Vec::new();
            for c in &mut self.contacts {
                for side in 0..2 {
                    if c.nodes[side] == node {
                        let old = c.rods[side];
                        let new = match map.iter().position(|&x| x == old) {
                            Some(k) => k,
                            None => {
                                map.push(old);
                                map.len() - 1
                            }
                        };
                        c.rods[side] = new as u8;
                    }
                }
            }
        }
    }
}

/// How a rule was found, for the people who will trust it.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    /// `base` (a published motif), `audit` (missed by the engine) or `user`.
    pub source: String,
    /// The enumeration that produced it, e.g. `rods n=6, min degree 2, Maxwell`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enumeration: Option<String>,
    /// The engine rule set it was audited against.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub audited_against: Option<String>,
    /// The command that wrote it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub command: Option<String>,
    /// The rgc version that wrote it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
}

/// The exact-rank verdict stored with a rule.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RuleVerdict {
    pub class: String,
    pub dof: usize,
    /// Seed of the exact realizations.
    pub seed: u64,
    pub components: Vec<crate::rigidity::ComponentReport>,
}

/// A motif rule: a typed pattern proven rigid on every realization component.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rule {
    pub id: String,
    pub pattern: Pattern,
    /// Canonical form of the pattern: equal for isomorphic patterns.
    pub canonical: String,
    pub verdict: RuleVerdict,
    pub provenance: Provenance,
}

/// A rule file: a list of rules.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RuleFile {
    /// Always [`RULE_FORMAT`].
    pub format: String,
    pub rules: Vec<Rule>,
}

pub const RULE_FORMAT: &str = "rgc-rules/1";

/// Largest rule file read (a hostile file fails before it is parsed).
pub const MAX_RULE_FILE_BYTES: u64 = 64 << 20;

/// Seed of the exact verdicts of rules written by rgc.
pub const RULE_SEED: u64 = 20_261_122;

impl Rule {
    /// A rule for `pattern`, verified now: fails unless rigid on every component.
    pub fn new(id: String, pattern: Pattern, provenance: Provenance) -> Result<Self> {
        let verdict = verify(&pattern, &id)?;
        Ok(Rule {
            id,
            canonical: canonical_form(&pattern),
            pattern,
            verdict,
            provenance,
        })
    }
}

/// The canonical form of a pattern as a string (kinds, then sorted contacts).
pub fn canonical_form(p: &Pattern) -> String {
    let c = crate::enumerate::canonical_pattern(p);
    let kinds: String = c
        .kinds
        .iter()
        .map(|k| match k {
            NodeKind::Rod => 'r',
            NodeKind::Planar => 'p',
            NodeKind::Spatial => 's',
        })
        .collect();
    let mut contacts: Vec<String> = c
        .contacts
        .iter()
        .map(|x| format!("{}.{}-{}.{}", x.nodes[0], x.rods[0], x.nodes[1], x.rods[1]))
        .collect();
    contacts.sort();
    format!("{kinds}:{}", contacts.join(","))
}

/// The exact verdict of a rule's pattern; an error unless rigid everywhere.
fn verify(pattern: &Pattern, id: &str) -> Result<RuleVerdict> {
    let v = crate::rigidity::check_exact(pattern, RULE_SEED)
        .map_err(|e| Error::Parameter(format!("rule {id}: {}", detail(&e))))?;
    if v.rigid != Some(true) {
        return Err(Error::Parameter(format!(
            "rule {id} is not rigid on every realization component (exact rank: {}, {} DOF): \
             loading it would create false rigidity",
            v.class,
            v.dof.map_or("?".into(), |d| d.to_string())
        )));
    }
    Ok(RuleVerdict {
        class: v.class,
        dof: 0,
        seed: RULE_SEED,
        components: v.components,
    })
}

/// Reads rule files (a file, or every `*.json` in a directory, in name
/// order), checking each rule: well formed, canonical form matching its
/// pattern, unique id, and rigid by exact rank.
pub fn load_rules(paths: &[std::path::PathBuf]) -> Result<Vec<Rule>> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            let mut inside: Vec<std::path::PathBuf> = std::fs::read_dir(path)
                .map_err(|e| Error::io(path, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "json"))
                .collect();
            inside.sort();
            files.extend(inside);
        } else {
            files.push(path.clone());
        }
    }
    let mut rules: Vec<Rule> = Vec::new();
    let mut ids = std::collections::HashMap::new();
    for file in &files {
        let bad = |m: String| Error::Parameter(format!("rule file {}: {m}", file.display()));
        let size = std::fs::metadata(file)
            .map_err(|e| Error::io(file, e))?
            .len();
        if size > MAX_RULE_FILE_BYTES {
            return Err(bad(format!(
                "{size} bytes is larger than the {MAX_RULE_FILE_BYTES} a rule file may have"
            )));
        }
        let text = std::fs::read_to_string(file).map_err(|e| Error::io(file, e))?;
        let parsed: RuleFile = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
        if parsed.format != RULE_FORMAT {
            return Err(bad(format!(
                "format {:?} is not {RULE_FORMAT:?}",
                parsed.format
            )));
        }
        for rule in parsed.rules {
            if let Some(prev) = ids.insert(rule.id.clone(), file.clone()) {
                return Err(bad(format!(
                    "duplicate rule id {:?} (also in {})",
                    rule.id,
                    prev.display()
                )));
            }
            rule.pattern
                .validate()
                .map_err(|e| bad(format!("rule {}: {}", rule.id, detail(&e))))?;
            let canonical = canonical_form(&rule.pattern);
            if canonical != rule.canonical {
                return Err(bad(format!(
                    "rule {}: canonical form {:?} does not match its pattern ({canonical:?})",
                    rule.id, rule.canonical
                )));
            }
            verify(&rule.pattern, &rule.id).map_err(|e| bad(detail(&e)))?;
            rules.push(rule);
        }
    }
    Ok(rules)
}

/// An error's message without the "invalid parameter" prefix, for nesting.
fn detail(e: &Error) -> String {
    match e {
        Error::Parameter(m) => m.clone(),
        other => other.to_string(),
    }
}

/// Writes rules as one rule file.
pub fn write_rules(path: &std::path::Path, rules: &[Rule]) -> Result<()> {
    let file = RuleFile {
        format: RULE_FORMAT.into(),
        rules: rules.to_vec(),
    };
    let text = serde_json::to_string_pretty(&file).expect("rules serialize");
    std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))
}
