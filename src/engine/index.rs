//! Cheap necessary conditions for a loaded rule to match, checked before the
//! matcher backtracks.
//!
//! A match maps the pattern neighbours of a pattern node to distinct host
//! neighbours of its host, each of a fitting class and sharing at least the
//! pattern's contacts with it. So the host's neighbours, counted by class and
//! multiplicity ([`Profile`]), must satisfy Hall's condition for the pattern
//! node's demands ([`Needs`]); the common neighbours of a changed pair must
//! do the same for the pattern nodes that touch both ends of a pattern
//! contact; and, for the rods-only rules, a rod's free neighbours must have
//! at least the free neighbours its pattern neighbours have.
//!
//! Each check only rejects attempts that could not have matched: the engine
//! still tries the remaining attempts in the same order with the same random
//! draws, so it finds exactly the motifs the plain matcher finds.

use crate::body::BodyClass;
use crate::pattern::NodeKind;

use super::state::State;

/// Multiplicities are counted up to this; a larger demand is clamped to it,
/// which only weakens the check.
const CAP: usize = 4;

/// The host classes as indices: rod, planar body, spatial body.
fn class_index(c: Option<BodyClass>) -> usize {
    match c {
        None => 0,
        Some(BodyClass::Planar) => 1,
        Some(BodyClass::Spatial) => 2,
    }
}

/// Which host classes (by [`class_index`]) a pattern node of kind `k` accepts.
fn accepts(k: NodeKind) -> [bool; 3] {
    match k {
        NodeKind::Rod => [true, false, false],
        NodeKind::Planar => [false, true, true],
        NodeKind::Spatial => [false, false, true],
    }
}

/// A host node's neighbours: `at_least[c][m - 1]` of them are of class `c`
/// and share at least `m` contacts with it.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Profile {
    at_least: [[u32; CAP]; 3],
}

impl Profile {
    /// Free rods among the neighbours.
    pub fn free_rods(&self) -> u32 {
        self.at_least[0][0]
    }

    /// Whether every Hall condition of `needs` holds.
    pub fn admits(&self, needs: &Needs) -> bool {
        needs.0.iter().all(|h| {
            let fitting: u32 = (0..3)
                .filter(|&c| h.min[c] > 0)
                .map(|c| self.at_least[c][h.min[c] as usize - 1])
                .sum();
            fitting >= h.need
        })
    }
}

/// One Hall condition: the host neighbours that fit some demand of a set
/// must number at least the set's size. A neighbour of class `c` fits when
/// it shares at least `min[c]` contacts with the host (0: no demand of the
/// set accepts class `c`).
#[derive(Clone, Debug)]
struct Hall {
    need: u32,
    min: [u8; 3],
}

/// The Hall conditions of one pattern node's neighbours on its host's [`Profile`].
#[derive(Clone, Debug, Default)]
pub(super) struct Needs(Vec<Hall>);

impl Needs {
    /// Conditions for demands given as (kind, contacts) of each pattern neighbour.
    pub fn new(demands: &[(NodeKind, usize)]) -> Self {
        // Identical demands form one type; Hall's condition over the sets of
        // types (every set while few, else each type and all of them).
        let mut types: Vec<((NodeKind, usize), u32)> = Vec::new();
        for &(k, m) in demands {
            let key = (k, m.clamp(1, CAP));
            match types.iter_mut().find(|(t, _)| *t == key) {
                Some((_, n)) => *n += 1,
                None => types.push((key, 1)),
            }
        }
        let t = types.len();
        let sets: Vec<u32> = if t <= 6 {
            (1..1u32 << t).collect()
        } else {
            (0..t).map(|i| 1 << i).chain([(1 << t) - 1]).collect()
        };
        let halls = sets
            .into_iter()
            .map(|set| {
                let mut h = Hall {
                    need: 0,
                    min: [0; 3],
                };
                for (i, &((k, m), n)) in types.iter().enumerate() {
                    if set & (1 << i) == 0 {
                        continue;
                    }
                    h.need += n;
                    for (c, ok) in accepts(k).into_iter().enumerate() {
                        if ok && (h.min[c] == 0 || (m as u8) < h.min[c]) {
                            h.min[c] = m as u8;
                        }
                    }
                }
                h
            })
            .collect();
        Needs(halls)
    }
}

/// A common neighbour of a changed pair: its class index and its contacts with each end.
pub(super) type Common = (u8, u32, u32);

/// What the pattern nodes touching both ends of a pattern contact demand of
/// the host pair's common neighbours: (kind, contacts with each end).
#[derive(Clone, Debug, Default)]
pub(super) struct CommonNeeds(Vec<(NodeKind, usize, usize)>);

impl CommonNeeds {
    pub fn new(demands: Vec<(NodeKind, usize, usize)>) -> Self {
        CommonNeeds(demands)
    }

    /// Whether `common` satisfies Hall's condition for these demands.
    pub fn admitted_by(&self, common: &[Common]) -> bool {
        let d = &self.0;
        if d.is_empty() {
            return true;
        }
        if common.len() < d.len() {
            return false;
        }
        let fits = |&(k, ma, mb): &(NodeKind, usize, usize), &(c, mx, my): &Common| {
            accepts(k)[c as usize] && mx as usize >= ma && my as usize >= mb
        };
        let sets: Vec<u32> = if d.len() <= 6 {
            (1..1u32 << d.len()).collect()
        } else {
            (0..d.len())
                .map(|i| 1 << i)
                .chain([(1 << d.len()) - 1])
                .collect()
        };
        sets.into_iter().all(|set| {
            let fitting = common
                .iter()
                .filter(|z| {
                    d.iter()
                        .enumerate()
                        .any(|(i, dem)| set & (1 << i) != 0 && fits(dem, z))
                })
                .count();
            fitting >= set.count_ones() as usize
        })
    }
}

/// Host profiles, computed when first needed and dropped when a merge
/// changes a node's neighbours, and the views of one task.
pub(super) struct Index {
    /// Whether skipped attempts are matched anyway, to prove them impossible.
    pub audit: bool,
    profile: Vec<Profile>,
    fresh: Vec<bool>,
    /// Scratch: a rod's neighbouring nodes with their contact counts.
    grouped: Vec<(u32, u32)>,
    /// The free degrees of a rod task's free neighbours, largest first.
    free_degrees: Vec<u32>,
    /// The common neighbours of a pair task.
    common: Vec<Common>,
}

impl Index {
    pub fn new(n_rods: usize, audit: bool) -> Self {
        Index {
            audit,
            profile: vec![Profile::default(); n_rods],
            fresh: vec![false; n_rods],
            grouped: Vec::new(),
            free_degrees: Vec::new(),
            common: Vec::new(),
        }
    }

    /// For free rod `r`: its free neighbours' numbers of free neighbours, largest first.
    pub fn rod_view(&mut self, state: &mut State, r: u32) -> &[u32] {
        group_rod(state, r, &mut self.grouped);
        let free: Vec<u32> = self
            .grouped
            .iter()
            .filter(|&&(y, _)| state.class(y).is_none())
            .map(|&(y, _)| y)
            .collect();
        self.free_degrees.clear();
        for y in free {
            let f = self.profile(state, y).free_rods();
            self.free_degrees.push(f);
        }
        self.free_degrees.sort_unstable_by(|a, b| b.cmp(a));
        &self.free_degrees
    }

    /// For a changed pair `x`, `y`: their profiles and common neighbours.
    pub fn pair_view(
        &mut self,
        state: &mut State,
        x: u32,
        y: u32,
    ) -> (Profile, Profile, &[Common]) {
        let (px, py) = (self.profile(state, x), self.profile(state, y));
        let mut common = std::mem::take(&mut self.common);
        self.common_neighbours(state, x, y, &mut common);
        self.common = common;
        (px, py, &self.common)
    }

    /// Forgets node `x`'s profile: its neighbours or their classes changed.
    pub fn invalidate(&mut self, x: u32) {
        self.fresh[x as usize] = false;
    }

    /// The profile of node `x` (a current node).
    fn profile(&mut self, state: &mut State, x: u32) -> Profile {
        if !self.fresh[x as usize] {
            let mut p = Profile::default();
            let mut add = |c: Option<BodyClass>, m: usize| {
                let row = &mut p.at_least[class_index(c)];
                for slot in row.iter_mut().take(m.min(CAP)) {
                    *slot += 1;
                }
            };
            if state.class(x).is_some() {
                for (&y, links) in &state.nodes[x as usize].adj {
                    add(state.class(y), links.len());
                }
            } else {
                group_rod(state, x, &mut self.grouped);
                for &(y, m) in &self.grouped {
                    add(state.class(y), m as usize);
                }
            }
            self.profile[x as usize] = p;
            self.fresh[x as usize] = true;
        }
        self.profile[x as usize]
    }

    /// The common neighbours of nodes `x` and `y`, into `out`.
    fn common_neighbours(&mut self, state: &mut State, x: u32, y: u32, out: &mut Vec<Common>) {
        out.clear();
        let (small, large, flip) = match (state.class(x), state.class(y)) {
            (None, _) => (x, y, false),
            (_, None) => (y, x, true),
            _ if state.nodes[x as usize].adj.len() <= state.nodes[y as usize].adj.len() => {
                (x, y, false)
            }
            _ => (y, x, true),
        };
        let mut push = |state: &State, z: u32, m_small: u32| {
            if z == large {
                return;
            }
            let m_large = state.multiplicity(large, z) as u32;
            if m_large > 0 {
                let c = class_index(state.class(z)) as u8;
                out.push(if flip {
                    (c, m_large, m_small)
                } else {
                    (c, m_small, m_large)
                });
            }
        };
        if state.class(small).is_some() {
            for (&z, links) in &state.nodes[small as usize].adj {
                push(state, z, links.len() as u32);
            }
        } else {
            group_rod(state, small, &mut self.grouped);
            for &(z, m) in &self.grouped {
                push(state, z, m);
            }
        }
    }
}

/// The nodes rod `x` touches, with the number of its contacts with each.
fn group_rod(state: &mut State, x: u32, out: &mut Vec<(u32, u32)>) {
    out.clear();
    let g = state.g;
    for &(nb, _) in g.neighbors(x) {
        let y = state.find(nb);
        match out.iter_mut().find(|(n, _)| *n == y) {
            Some((_, m)) => *m += 1,
            None => out.push((y, 1)),
        }
    }
}
