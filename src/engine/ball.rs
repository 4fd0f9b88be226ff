//! The free rods around a rod task's rod as bit sets, where the index
//! replays the plain matcher's search of a rods-only rule with bit
//! operations (see [`Ball`]).

use super::rule::Step;

/// Ball rods are told apart by their neighbours in the ball up to this many.
pub(super) const MAX_DEGREE: usize = 8;

/// The free rods within the index's radius of a rod task's rod (through
/// rods of the least core the rods-only rules need), sorted, as bits of one
/// integer, with their contacts among them as bit rows: a match of
/// a rods-only rule lies there, and bit operations list a pattern node's
/// candidates in the plain matcher's order (by node). Larger balls (none at
/// density 40, box 10) are searched on the cached lists instead.
#[derive(Default)]
pub(super) struct Ball {
    /// Whether the rows are those of the current rod task.
    pub built: bool,
    pub rods: Vec<u32>,
    pub rows: Vec<Bits>,
    /// By distance `d`: the rods within `d` of the root.
    pub near: Vec<Bits>,
    /// By `k`: the rods with at least `k` neighbours in the ball.
    pub wide: [Bits; MAX_DEGREE + 1],
    /// By distance `d` and `k` up to [`MAX_CORE`], once needed: the
    /// `k`-core of the rods within `d` of the root (a match with no node
    /// of fewer than `k` neighbours, within `d`, lies there).
    pub core: Vec<[Option<Bits>; MAX_CORE + 1]>,
    pub root: usize,
    /// The largest distance from the root of its rods.
    pub radius: usize,
}

/// The largest core order a [`Ball`] computes.
pub(super) const MAX_CORE: usize = 4;

/// Words of a [`Bits`].
const WORDS: usize = 4;

/// A set of ball rods, as bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Bits([u64; WORDS]);

/// The largest ball built: one set of bits.
pub(super) const MAX_BALL: usize = 64 * WORDS;

impl Bits {
    /// The set of ball rod `i` alone.
    pub fn one(i: usize) -> Self {
        let mut b = Bits::default();
        b.insert(i);
        b
    }

    pub fn is_empty(&self) -> bool {
        self.0.iter().all(|&w| w == 0)
    }

    pub fn has(&self, i: usize) -> bool {
        self.0[i / 64] & (1 << (i % 64)) != 0
    }

    pub fn insert(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }

    pub fn remove(&mut self, i: usize) {
        self.0[i / 64] &= !(1 << (i % 64));
    }

    pub fn count(&self) -> u32 {
        self.0.iter().map(|w| w.count_ones()).sum()
    }

    /// Removes and returns the least rod of the set.
    pub fn pop(&mut self) -> Option<usize> {
        for (w, word) in self.0.iter_mut().enumerate() {
            if *word != 0 {
                let b = word.trailing_zeros() as usize;
                *word &= *word - 1;
                return Some(64 * w + b);
            }
        }
        None
    }
}

/// A set of ball rods: one word for a ball of at most 64 rods (the most
/// common, where a search's bit operations are one instruction each), two
/// for one of at most 128, or [`Bits`].
pub(super) trait Set:
    Copy
    + Default
    + std::ops::BitAnd<Output = Self>
    + std::ops::BitAndAssign
    + std::ops::Not<Output = Self>
{
    /// The set of the rods of `bits`, all below the set's size.
    fn of(bits: Bits) -> Self;
    fn is_empty(&self) -> bool;
    fn insert(&mut self, i: usize);
    fn remove(&mut self, i: usize);
    /// Removes and returns the least rod of the set.
    fn pop(&mut self) -> Option<usize>;
}

/// [`Set`] for an unsigned integer of `$words` words: the rods of
/// `bits` (all in those words) as one number.
macro_rules! integer_set {
    ($t:ty, $words:expr) => {
        impl Set for $t {
            fn of(bits: Bits) -> Self {
                debug_assert!(bits.0[$words..].iter().all(|&w| w == 0));
                bits.0[..$words]
                    .iter()
                    .rev()
                    .fold(0, |n, &w| n << 32 << 32 | <$t>::from(w))
            }

            fn is_empty(&self) -> bool {
                *self == 0
            }

            fn insert(&mut self, i: usize) {
                *self |= 1 << i;
            }

            fn remove(&mut self, i: usize) {
                *self &= !(1 << i);
            }

            fn pop(&mut self) -> Option<usize> {
                (*self != 0).then(|| {
                    let i = self.trailing_zeros() as usize;
                    *self &= *self - 1;
                    i
                })
            }
        }
    };
}

integer_set!(u64, 1);
integer_set!(u128, 2);

impl Set for Bits {
    fn of(bits: Bits) -> Self {
        bits
    }

    fn is_empty(&self) -> bool {
        Bits::is_empty(self)
    }

    fn insert(&mut self, i: usize) {
        Bits::insert(self, i);
    }

    fn remove(&mut self, i: usize) {
        Bits::remove(self, i);
    }

    fn pop(&mut self) -> Option<usize> {
        Bits::pop(self)
    }
}

impl std::ops::BitAnd for Bits {
    type Output = Bits;
    fn bitand(mut self, other: Bits) -> Bits {
        self &= other;
        self
    }
}

impl std::ops::BitAndAssign for Bits {
    fn bitand_assign(&mut self, other: Bits) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a &= b;
        }
    }
}

impl std::ops::BitOrAssign for Bits {
    fn bitor_assign(&mut self, other: Bits) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a |= b;
        }
    }
}

impl std::ops::Not for Bits {
    type Output = Bits;
    fn not(mut self) -> Bits {
        for a in &mut self.0 {
            *a = !*a;
        }
        self
    }
}

/// The state of one search in a [`Ball`]: ball rods by pattern node, the
/// rods used, and the map in host rods.
#[derive(Default)]
pub(super) struct Search {
    local: Vec<usize>,
    used: Bits,
    /// The rods a match can use.
    pub within: Bits,
    map: Vec<Option<u32>>,
}

impl Ball {
    /// The rods that can carry `step`, given the map so far: not used,
    /// touching the rods its mapped neighbours are on, within its pattern
    /// distance of the root (a complete map is a homomorphism), and with at
    /// least its neighbours in the ball (all of a complete map is).
    fn candidates(&self, step: &Step, s: &Search) -> Bits {
        let mut bits = !s.used
            & s.within
            & self.near[step.distance as usize]
            & self.wide[(step.degree as usize).min(MAX_DEGREE)];
        for &b in &step.back {
            bits &= self.rows[s.local[b]];
        }
        bits
    }

    /// The `k`-core (`k` up to [`MAX_CORE`]) of the rods within `d` of
    /// the root (`d` up to the radius), computed once per ball.
    pub fn within(&mut self, d: usize, k: usize) -> Bits {
        match self.core[d][k] {
            Some(core) => core,
            None => {
                let core = self.peel(self.near[d], k as u32);
                self.core[d][k] = Some(core);
                core
            }
        }
    }

    /// The `k`-core of the ball rods `set`: its rods with at least `k`
    /// neighbours in it, repeatedly.
    pub fn peel(&self, mut set: Bits, k: u32) -> Bits {
        loop {
            let mut kept = set;
            let mut bits = set;
            while let Some(i) = bits.pop() {
                if (self.rows[i] & set).count() < k {
                    kept.remove(i);
                }
            }
            if kept == set {
                return set;
            }
            set = kept;
        }
    }

    /// Calls `complete` on every complete map (host rods by pattern node)
    /// of the plain matcher's search from pattern node `start` on the root,
    /// in its order, until it returns true; whether it did.
    pub fn search(
        &self,
        start: usize,
        plan: &[Step],
        n: usize,
        s: &mut Search,
        complete: &mut dyn FnMut(&[Option<u32>]) -> bool,
    ) -> bool {
        if !s.within.has(self.root) {
            return false;
        }
        s.local.clear();
        s.local.resize(n, usize::MAX);
        s.local[start] = self.root;
        s.used = Bits::one(self.root);
        s.map.clear();
        s.map.resize(n, None);
        s.map[start] = Some(self.rods[self.root]);
        self.viable(plan, s) && self.extend(plan, 0, s, complete)
    }

    /// Whether every step of `plan` whose mapped neighbours are all among
    /// the starts has a candidate (else no map can be completed; checking
    /// again deeper in the search costs more than it saves).
    fn viable(&self, plan: &[Step], s: &Search) -> bool {
        plan.iter()
            .all(|step| step.ready != 0 || !self.candidates(step, s).is_empty())
    }

    fn extend(
        &self,
        plan: &[Step],
        done: usize,
        s: &mut Search,
        complete: &mut dyn FnMut(&[Option<u32>]) -> bool,
    ) -> bool {
        let Some(step) = plan.get(done) else {
            return complete(&s.map);
        };
        let mut bits = self.candidates(step, s);
        while let Some(i) = bits.pop() {
            s.local[step.node] = i;
            s.map[step.node] = Some(self.rods[i]);
            s.used.insert(i);
            if self.extend(plan, done + 1, s, complete) {
                return true;
            }
            s.used.remove(i);
        }
        s.map[step.node] = None;
        false
    }
}
