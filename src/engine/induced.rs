//! Exact verdicts of the patterns that matched parts induce in the host
//! (MODEL §5): under `sound`, extra host contacts among the parts of a
//! rigid rule can make them flex, so every 3D3A, 3D3B and 3D4 instance and
//! every loaded rule's match is checked on what it induces.

use rustc_hash::FxHashMap;

use super::state::{NO_PLANE, State};
use crate::body::BodyClass;
use crate::pattern::{NodeKind, Pattern, PatternContact};

/// Exact verdicts of induced patterns, shared by all runs.
#[derive(Default)]
struct Verdicts {
    /// By canonical pattern (contacts sorted): one exact rank per
    /// isomorphism class, without formatting the canonical form as text.
    canonical: FxHashMap<Pattern, bool>,
    /// By the pattern as induced: the same motif induces the same few
    /// labelings again and again, and hashing one is far cheaper than its
    /// canonical form.
    raw: FxHashMap<Pattern, bool>,
}

static VERDICTS: std::sync::LazyLock<std::sync::Mutex<Verdicts>> =
    std::sync::LazyLock::new(Default::default);

/// Induced patterns remembered as they are, at most (beyond it the raw
/// cache starts again; the canonical one keeps every verdict).
const MAX_RAW_VERDICTS: usize = 1 << 16;

/// Largest induced pattern verified by exact rank; larger ones fall back to
/// the verified base rules.
const MAX_VERIFIED_CONTACTS: usize = 24;

impl State<'_> {
    /// Under `sound`, whether the pattern `parts` induce (every contact
    /// among them, on the host's rods, with the host's classes) is rigid by
    /// exact rank: extra contacts among the parts of a rigid rule can open a
    /// realization component on which they flex. Patterns too large to check
    /// pass on the rule alone.
    pub fn induced_rigid(&mut self, parts: &[u32]) -> bool {
        let Some(p) = self.induced(parts) else {
            return true;
        };
        if let Some(&known) = VERDICTS.lock().expect("verdict cache").raw.get(&p) {
            return known;
        }
        let mut key = crate::enumerate::canonical_pattern(&p);
        key.contacts.sort_unstable();
        let known = VERDICTS
            .lock()
            .expect("verdict cache")
            .canonical
            .get(&key)
            .copied();
        let rigid = known.unwrap_or_else(|| {
            crate::rigidity::check_exact(&p, crate::rule_file::RULE_SEED)
                .is_ok_and(|v| v.rigid == Some(true))
        });
        let mut verdicts = VERDICTS.lock().expect("verdict cache");
        verdicts.canonical.insert(key, rigid);
        if verdicts.raw.len() >= MAX_RAW_VERDICTS {
            verdicts.raw.clear();
        }
        verdicts.raw.insert(p, rigid);
        rigid
    }

    /// The pattern `parts` induce, or `None` when it is too large to verify
    /// or a spatial part carries planar parts a pattern cannot express.
    fn induced(&mut self, parts: &[u32]) -> Option<Pattern> {
        let mut kinds = Vec::with_capacity(parts.len());
        for &x in parts {
            kinds.push(match self.class(x) {
                None => NodeKind::Rod,
                Some(BodyClass::Planar) => NodeKind::Planar,
                Some(BodyClass::Spatial) => {
                    if self.nodes[x as usize]
                        .members
                        .iter()
                        .any(|&r| self.plane(r) != NO_PLANE)
                    {
                        return None;
                    }
                    NodeKind::Spatial
                }
            });
        }
        let mut labels: Vec<Vec<u32>> = vec![Vec::new(); parts.len()];
        let mut contacts = Vec::new();
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                for l in self.links_between(parts[i], parts[j]) {
                    let mut label = |k: usize, rod: u32| -> u8 {
                        match labels[k].iter().position(|&r| r == rod) {
                            Some(p) => p as u8,
                            None => {
                                labels[k].push(rod);
                                (labels[k].len() - 1) as u8
                            }
                        }
                    };
                    let rods = [label(i, l.own), label(j, l.other)];
                    contacts.push(PatternContact {
                        nodes: [i as u8, j as u8],
                        rods,
                    });
                    if contacts.len() > MAX_VERIFIED_CONTACTS {
                        return None;
                    }
                }
            }
        }
        Some(Pattern { kinds, contacts })
    }
}
