//! What a pattern node demands of its host and the host's neighbours, as
//! the compiled rules carry it and the index checks it: which host classes
//! carry which pattern kinds, a host's neighbours counted by class and
//! multiplicity ([`Profile`]), and the Hall conditions on them ([`Needs`],
//! [`CommonNeeds`]).

use crate::body::BodyClass;
use crate::pattern::NodeKind;

/// Multiplicities are counted up to this; a larger demand is clamped to it,
/// which only weakens the check.
const CAP: usize = 4;

/// The host classes as indices: rod, planar body, spatial body.
pub(super) fn class_index(c: Option<BodyClass>) -> u8 {
    match c {
        None => 0,
        Some(BodyClass::Planar) => 1,
        Some(BodyClass::Spatial) => 2,
    }
}

/// Which host classes (by [`class_index`]) a pattern node of kind `k` accepts.
pub(super) fn accepts(k: NodeKind) -> [bool; 3] {
    match k {
        NodeKind::Rod => [true, false, false],
        NodeKind::Planar => [false, true, true],
        NodeKind::Spatial => [false, false, true],
    }
}

/// A host node's kind as the matcher sees it.
pub(super) fn fits(pattern: NodeKind, host: Option<BodyClass>) -> bool {
    matches!(
        (pattern, host),
        (NodeKind::Rod, None)
            | (NodeKind::Planar, Some(_))
            | (NodeKind::Spatial, Some(BodyClass::Spatial))
    )
}

/// A host node's neighbours: `at_least[slot(c, m)]` of them are of class
/// `c` and share at least `m` contacts with it; the last slot is always 0.
#[derive(Clone, Copy, Debug)]
pub(super) struct Profile {
    at_least: [u32; 3 * CAP + 1],
}

impl Default for Profile {
    fn default() -> Self {
        Profile {
            at_least: [0; 3 * CAP + 1],
        }
    }
}

/// The slot of class `c` and at least `m` contacts (1 to [`CAP`]) in a [`Profile`].
fn slot(c: usize, m: usize) -> u8 {
    (c * CAP + m - 1) as u8
}

/// The slot that is always 0.
const NONE: u8 = 3 * CAP as u8;

impl Profile {
    /// A profile every [`Needs`] admits.
    pub(super) const ANY: Profile = {
        let mut at_least = [u32::MAX / 4; 3 * CAP + 1];
        at_least[NONE as usize] = 0;
        Profile { at_least }
    };

    /// Counts a neighbour of class `c` sharing `m` contacts.
    pub(super) fn add(&mut self, c: usize, m: usize) {
        for k in 1..=m.min(CAP) {
            self.at_least[slot(c, k) as usize] += 1;
        }
    }

    /// Whether every Hall condition of `needs` holds.
    pub fn admits(&self, needs: &Needs) -> bool {
        let p = &self.at_least;
        needs.0.iter().all(|h| {
            p[h.slots[0] as usize] + p[h.slots[1] as usize] + p[h.slots[2] as usize] >= h.need
        })
    }
}

/// One Hall condition: the host neighbours that fit some demand of a set
/// must number at least the set's size. `slots[c]` counts the neighbours
/// of class `c` that fit (the [`Profile`] slot of the least contacts a
/// demand of the set accepts from class `c`, or [`NONE`]).
#[derive(Clone, Debug, PartialEq, Eq)]
struct Hall {
    need: u32,
    slots: [u8; 3],
}

/// The Hall conditions of one pattern node's neighbours on its host's [`Profile`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Needs(Vec<Hall>);

/// The sets of `t` demand types Hall's condition is checked on: every set
/// while they are few, else each one and all of them.
fn hall_sets(t: usize) -> Vec<u32> {
    if t <= 6 {
        (1..1u32 << t).collect()
    } else {
        (0..t).map(|i| 1 << i).chain([(1 << t) - 1]).collect()
    }
}

impl Needs {
    /// Conditions for demands given as (kind, contacts) of each pattern neighbour.
    pub fn new(demands: &[(NodeKind, usize)]) -> Self {
        let mut types: Vec<((NodeKind, usize), u32)> = Vec::new();
        for &(k, m) in demands {
            let key = (k, m.clamp(1, CAP));
            match types.iter_mut().find(|(t, _)| *t == key) {
                Some((_, n)) => *n += 1,
                None => types.push((key, 1)),
            }
        }
        let halls: Vec<Hall> = hall_sets(types.len())
            .into_iter()
            .map(|set| {
                let mut need = 0;
                let mut least = [usize::MAX; 3];
                for (i, &((k, m), n)) in types.iter().enumerate() {
                    if set & (1 << i) == 0 {
                        continue;
                    }
                    need += n;
                    for (c, ok) in accepts(k).into_iter().enumerate() {
                        if ok {
                            least[c] = least[c].min(m);
                        }
                    }
                }
                let slots = [0, 1, 2].map(|c| match least[c] {
                    usize::MAX => NONE,
                    m => slot(c, m),
                });
                Hall { need, slots }
            })
            .collect();
        // A condition is implied by one that needs as many and accepts no
        // more from any class (a higher slot of a class counts fewer).
        let implies = |b: &Hall, a: &Hall| {
            b.need >= a.need
                && (0..3)
                    .all(|c| b.slots[c] == NONE || (a.slots[c] != NONE && a.slots[c] <= b.slots[c]))
        };
        let mut kept: Vec<Hall> = Vec::new();
        for (i, a) in halls.iter().enumerate() {
            let implied = halls
                .iter()
                .enumerate()
                .any(|(j, b)| j != i && implies(b, a) && (b != a || j < i));
            if !implied {
                kept.push(a.clone());
            }
        }
        let halls = kept;
        Needs(halls)
    }
}

/// A common neighbour of a changed pair: its class index and its contacts with each end.
pub(super) type Common = (u8, u32, u32);

/// What the pattern nodes touching both ends of a pattern contact demand of
/// the host pair's common neighbours: (kind, contacts with each end).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
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
        hall_sets(d.len()).into_iter().all(|set| {
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
