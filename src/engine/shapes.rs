//! The base motifs as rules, verified by exact rank (MODEL §5, §6).
//!
//! Every rod-sharing variant of each base shape that the published
//! conditions accept is checked under every planar/spatial assignment of its
//! bodies. The rigid ones become rules; the `sound` engine uses them in
//! place of the published conditions for 3D3A, 3D3B and 3D4, which exact
//! rank refutes for some variants with planar bodies. They are derived here
//! by running the engine, so the engine reads the committed copy
//! (`motifs/base.json`, see `sound`) instead.

use super::ruleset::RuleSet;
use super::run::Engine;
use crate::Result;
use crate::pattern::{NodeKind, Pattern, PatternContact};
use crate::rule_file::{Provenance, Rule, canonical_form};

/// Motif orders tried before saying the engine compresses a pattern.
pub const ORDERS: u64 = 8;

/// Every set partition of `m` items, as restricted growth strings.
fn partitions(m: usize) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut cur = vec![0u8; m];
    fn go(i: usize, max: u8, cur: &mut Vec<u8>, out: &mut Vec<Vec<u8>>) {
        if i == cur.len() {
            out.push(cur.clone());
            return;
        }
        for v in 0..=max + 1 {
            cur[i] = v;
            go(i + 1, max.max(v), cur, out);
        }
    }
    if m == 0 {
        out.push(Vec::new());
    } else {
        cur[0] = 0;
        go(1, 0, &mut cur, &mut out);
    }
    out
}

/// Every way the contacts of `shape` can share rods on its bodies (labels
/// on rods are always 0), keeping the well-formed ones.
pub fn rod_sharing_variants(kinds: &[NodeKind], pairs: &[(u8, u8)]) -> Vec<Pattern> {
    // The contact ends on each body, as (contact, side).
    let ends: Vec<Vec<(usize, usize)>> = (0..kinds.len() as u8)
        .map(|v| {
            if !kinds[v as usize].is_body() {
                return Vec::new();
            }
            pairs
                .iter()
                .enumerate()
                .flat_map(|(k, &(a, b))| {
                    let mut e = Vec::new();
                    if a == v {
                        e.push((k, 0));
                    }
                    if b == v {
                        e.push((k, 1));
                    }
                    e
                })
                .collect()
        })
        .collect();
    let choices: Vec<Vec<Vec<u8>>> = ends.iter().map(|e| partitions(e.len())).collect();
    let mut out = Vec::new();
    let mut index = vec![0usize; kinds.len()];
    loop {
        let mut contacts: Vec<PatternContact> = pairs
            .iter()
            .map(|&(a, b)| PatternContact {
                nodes: [a, b],
                rods: [0, 0],
            })
            .collect();
        for (v, e) in ends.iter().enumerate() {
            for (slot, &(k, side)) in e.iter().enumerate() {
                contacts[k].rods[side] = choices[v][index[v]][slot];
            }
        }
        let p = Pattern {
            kinds: kinds.to_vec(),
            contacts,
        };
        if p.validate().is_ok() {
            out.push(p);
        }
        // Next combination (odometer).
        let mut v = 0;
        while v < kinds.len() {
            index[v] += 1;
            if index[v] < choices[v].len() {
                break;
            }
            index[v] = 0;
            v += 1;
        }
        if v == kinds.len() {
            break;
        }
    }
    out
}

/// A motif's name, node kinds and contacts (pairs of nodes).
pub type Shape = (&'static str, Vec<NodeKind>, Vec<(u8, u8)>);

/// The base motifs as shapes: kinds (planar where every class assignment is
/// rigid, so the rule matches any body) and contacts.
pub fn base_shapes() -> Vec<Shape> {
    use NodeKind::{Planar as P, Rod as R, Spatial as S};
    let k24: Vec<(u8, u8)> = (2..6).flat_map(|k| [(0, k), (1, k)]).collect();
    vec![
        ("3D3C", vec![R, R, R], vec![(0, 1), (1, 2), (0, 2)]),
        ("3D2B", vec![R, P], vec![(0, 1), (0, 1)]),
        ("3D2A", vec![S, P], vec![(0, 1), (0, 1), (0, 1)]),
        (
            "3D3A",
            vec![P, P, P],
            vec![(0, 1), (0, 2), (0, 2), (1, 2), (1, 2)],
        ),
        ("3D3B", vec![P, P, R], vec![(0, 1), (0, 1), (0, 2), (1, 2)]),
        (
            "3D4",
            vec![P, R, R, R],
            vec![(0, 1), (0, 2), (0, 3), (1, 2), (2, 3)],
        ),
        ("3D6", vec![R; 6], k24),
    ]
}

/// The base motifs written as rules, from every rod-sharing variant of each
/// base shape that the published conditions accept (the built-in `paper`
/// engine compresses it in every order) and every planar/spatial assignment
/// of its bodies: the assignments exact rank proves rigid, keeping the ones
/// with the most planar bodies (a planar pattern body matches any body).
/// Also returns the variants the published conditions accept but exact rank
/// refutes for some assignment: false rigidity in the paper's engine.
pub fn base_rules() -> Result<(Vec<Rule>, Vec<Refuted>)> {
    let paper = Engine::base(RuleSet::Paper);
    let mut rules: Vec<Rule> = Vec::new();
    let mut refuted = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (name, kinds, pairs) in base_shapes() {
        let bodies: Vec<usize> = (0..kinds.len()).filter(|&v| kinds[v].is_body()).collect();
        for p in rod_sharing_variants(&kinds, &pairs) {
            if !seen.insert(canonical_form(&p)) || !paper.always_compresses(&p, ORDERS)? {
                continue;
            }
            let mut rigid: Vec<(u32, Pattern)> = Vec::new();
            for mask in 0..1u32 << bodies.len() {
                let mut q = p.clone();
                for (i, &v) in bodies.iter().enumerate() {
                    q.kinds[v] = if mask >> i & 1 == 1 {
                        NodeKind::Planar
                    } else {
                        NodeKind::Spatial
                    };
                }
                let v = crate::rigidity::check_exact(&q, crate::rule_file::RULE_SEED)?;
                if v.rigid == Some(true) {
                    rigid.push((mask, q));
                } else {
                    refuted.push(Refuted {
                        motif: name.to_string(),
                        pattern: q,
                        class: v.class,
                        dof: v.dof,
                    });
                }
            }
            let maximal = rigid
                .iter()
                .filter(|(m, _)| !rigid.iter().any(|(o, _)| o != m && o & m == *m));
            for (mask, q) in maximal {
                let provenance = Provenance {
                    source: "base".into(),
                    enumeration: Some(format!(
                        "rod-sharing variants of {name} accepted by the published conditions"
                    )),
                    audited_against: Some("exact rank on every planar/spatial assignment".into()),
                    command: Some("rgc rules --base".into()),
                    version: Some(env!("CARGO_PKG_VERSION").into()),
                    frequency: Vec::new(),
                };
                let id = format!("base-{name}-{}-{mask:b}", rules.len());
                rules.push(Rule::new(id, q.clone(), provenance)?);
            }
        }
    }
    Ok((rules, refuted))
}

/// A variant the published conditions accept that exact rank refutes.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Refuted {
    pub motif: String,
    pub pattern: Pattern,
    pub class: String,
    pub dof: Option<usize>,
}

#[cfg(test)]
mod tests {
    use super::super::sound::{committed_base_rules, sound_rules, sound_subset};
    use super::*;

    /// The rules the engine reads are the ones exact rank derives now.
    #[test]
    fn the_committed_base_rules_are_the_derived_ones() {
        let (derived, _) = base_rules().unwrap();
        let committed = committed_base_rules();
        let patterns = |rules: &[Rule]| -> Vec<(String, Pattern)> {
            sound_subset(rules)
                .map(|r| (r.id.clone(), r.pattern.clone()))
                .collect()
        };
        assert_eq!(patterns(&committed), patterns(&derived));
        let ids: Vec<&str> = sound_rules().iter().map(|r| r.id.as_str()).collect();
        assert_eq!(ids.len(), patterns(&derived).len());
        assert!(ids.iter().all(|id| !id.starts_with("base-3D3C")), "{ids:?}");
    }
}
