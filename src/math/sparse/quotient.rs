//! The quotient graph of a sparse elimination: what is left of the matrix,
//! as dense elements over column groups, and which group goes next.
//!
//! An element is a set of rows over a few groups, stored dense. At the start
//! the rows of one contact (or one spin) form an element over its two parts
//! (or one). Eliminating a group absorbs every element that touches it into
//! one front; what the front leaves is a new element over the groups the
//! absorbed ones touched. Unlike the symbolic Cholesky model, where the
//! neighbours of an eliminated group always become a clique, a front that
//! has no more rows than pivots leaves nothing: in a floppy network most
//! fronts do, so fill stays local where the network is underconstrained.
//! That is why the order is chosen here, on the live rows, and not by a
//! symbolic analysis of the group graph.
//!
//! The next group is one of minimum degree (neighbouring groups through live
//! elements, exact, ties by index). A front also eliminates every other
//! group whose elements it absorbed all of, or whose other elements lie
//! inside the front's groups and are absorbed as well: such a group then
//! has no row outside the front, so eliminating it there adds no column
//! (mass elimination, and a supernodal amalgamation), and a network that
//! has become one dense block is eliminated in one front.
//!
//! The last group may be *deferred*: eliminated after all the others. It
//! never counts in a degree, is never a front's own group and never pulls
//! an element into a front, so the order and the fronts are those of the
//! matrix without it; rows left over it alone are set aside, and what
//! remains of them at the end is its Schur complement (truth's strain
//! columns, MODEL §10).

use rustc_hash::FxHashMap;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::math::echelon::Modulus;
use crate::math::{Field, Fp};

/// A sparse row: `(column, value)` with increasing columns and no zeros;
/// over F_p unless said otherwise (the float fallback builds `f64` rows).
/// It lives here, with the elements made of it, so that the folder's
/// modules only import downwards.
pub type SparseRow<S = Fp> = Vec<(u32, S)>;

/// With fewer groups left than this, the elimination never switches to the
/// dense tail: a small rest is eliminated group by group to the end.
const DENSE_TAIL: usize = 32;

/// Rows over a few column groups, stored dense.
#[derive(Clone, Debug)]
pub struct Element {
    /// Its groups, increasing.
    pub groups: Vec<u32>,
    pub rows: usize,
    /// Centred residues, row-major over `groups.len() * width` columns
    /// (exact in f32: they are below `2^23`).
    pub data: Vec<f32>,
}

/// The elements a front absorbs, the groups it eliminates and those its
/// rows still touch.
pub struct Gathered {
    /// Groups eliminated here, the chosen one first.
    pub own: Vec<u32>,
    /// The other groups of the absorbed elements, increasing.
    pub pattern: Vec<u32>,
    pub elements: Vec<Element>,
    /// Whether this is the dense tail: everything that was left.
    pub tail: bool,
}

/// Live elements and the minimum-degree queue.
pub struct Quotient {
    elements: Vec<Option<Element>>,
    /// Elements touching each group; dead ones are dropped lazily.
    adjacent: Vec<Vec<u32>>,
    done: Vec<bool>,
    /// Groups not eliminated yet, and the rows and row-group blocks of the
    /// live elements: how dense what is left is.
    remaining: usize,
    live_rows: usize,
    live_blocks: usize,
    /// Whether a group's elements changed since it was queued.
    dirty: Vec<bool>,
    queue: BinaryHeap<Reverse<(usize, u32)>>,
    /// Scratch marks per group and per element.
    mark: Vec<u32>,
    element_mark: Vec<u32>,
    stamp: u32,
    rescored: usize,
    modulus: Modulus,
    /// The deferred group, if any, and the rows set aside over it alone
    /// (row-major over its `width` columns).
    deferred: Option<u32>,
    width: usize,
    aside: Vec<f32>,
}

impl Quotient {
    /// The elements of the original rows: rows over the same groups form
    /// one element, in the order they first appear. With `deferred`, the
    /// last group is deferred.
    pub fn new<F: Field>(
        rows: &[SparseRow<F>],
        groups: usize,
        width: usize,
        deferred: bool,
    ) -> Quotient {
        let modulus = Modulus::new(F::modulus());
        let deferred = (deferred && groups > 0).then(|| groups as u32 - 1);
        let mut q = Quotient {
            elements: Vec::new(),
            adjacent: vec![Vec::new(); groups],
            done: vec![false; groups],
            remaining: groups - usize::from(deferred.is_some()),
            live_rows: 0,
            live_blocks: 0,
            dirty: vec![false; groups],
            queue: BinaryHeap::new(),
            mark: vec![0; groups],
            element_mark: Vec::new(),
            stamp: 0,
            rescored: 0,
            modulus,
            deferred,
            width,
            aside: Vec::new(),
        };
        let mut index: FxHashMap<Vec<u32>, usize> = FxHashMap::default();
        let mut built: Vec<Element> = Vec::new();
        for r in rows {
            if r.is_empty() {
                continue;
            }
            let mut gs: Vec<u32> = r.iter().map(|&(c, _)| c / width as u32).collect();
            gs.sort_unstable();
            gs.dedup();
            let k = *index.entry(gs.clone()).or_insert_with(|| {
                built.push(Element {
                    groups: gs.clone(),
                    rows: 0,
                    data: Vec::new(),
                });
                built.len() - 1
            });
            let e = &mut built[k];
            e.rows += 1;
            let ncols = e.groups.len() * width;
            let start = e.data.len();
            e.data.resize(start + ncols, 0.0);
            for &(c, v) in r {
                let g = c / width as u32;
                let l = e.groups.binary_search(&g).expect("its own group");
                e.data[start + l * width + c as usize % width] = modulus.centre(v.residue()) as f32;
            }
        }
        for e in built {
            q.insert(e);
        }
        for g in 0..groups as u32 {
            if Some(g) != deferred {
                q.requeue(g);
            }
        }
        q
    }

    /// Groups of `e` that count in degrees and densities: all but the
    /// deferred one.
    fn counted(&self, e: &Element) -> usize {
        e.groups.len() - usize::from(self.deferred.is_some_and(|d| e.groups.contains(&d)))
    }

    /// The rows set aside over the deferred group alone, row-major over
    /// its columns (empty without a deferred group).
    pub fn take_aside(&mut self) -> Vec<f32> {
        std::mem::take(&mut self.aside)
    }

    /// Sets `rows` aside over the deferred group (after a reduction).
    pub fn put_aside(&mut self, rows: Vec<f32>) {
        self.aside.extend(rows);
    }

    /// Rows set aside so far.
    pub fn aside_rows(&self) -> usize {
        self.aside.len() / self.width
    }

    /// Takes out every element over one group only: rows that constrain a
    /// single part (a rod's spin, a class's wrap), eliminated before the
    /// order starts (see [`Quotient::clear_columns`]).
    pub fn take_single(&mut self) -> Vec<Element> {
        let mut out = Vec::new();
        for slot in &mut self.elements {
            if slot.as_ref().is_some_and(|e| e.groups.len() == 1) {
                let e = slot.take().expect("live");
                self.live_rows -= e.rows;
                self.live_blocks -= e.rows;
                out.push(e);
            }
        }
        out
    }

    /// Clears the columns `pivots` of group `g` from every live element by
    /// the matching rows of `pivot_rows` (over the group's `width` columns,
    /// each 1 at its pivot column and zero before it): a column operation
    /// inside one group, so no element gains a group. Afterwards those
    /// columns are zero everywhere and the fronts leave them out.
    pub fn clear_columns(&mut self, g: u32, width: usize, pivots: &[usize], pivot_rows: &[f64]) {
        let md = self.modulus;
        for &e in &self.adjacent[g as usize] {
            let Some(e) = self.elements[e as usize].as_mut() else {
                continue;
            };
            let ecols = e.groups.len() * width;
            let at = e.groups.binary_search(&g).expect("its own group") * width;
            for row in e.data.chunks_exact_mut(ecols) {
                let block = &mut row[at..at + width];
                for (t, &c) in pivots.iter().enumerate() {
                    let f = block[c] as f64;
                    if f != 0.0 {
                        let u = &pivot_rows[t * width..(t + 1) * width];
                        for (x, &v) in block.iter_mut().zip(u) {
                            *x = md.reduce(*x as f64 - f * v) as f32;
                        }
                    }
                }
            }
        }
    }

    fn next_stamp(&mut self) -> u32 {
        self.stamp += 1;
        if self.stamp == u32::MAX {
            self.mark.fill(0);
            self.element_mark.fill(0);
            self.stamp = 1;
        }
        self.stamp
    }

    /// Adds a live element; one over the deferred group alone is set aside.
    fn insert(&mut self, e: Element) {
        if e.groups.len() == 1 && Some(e.groups[0]) == self.deferred {
            debug_assert_eq!(e.data.len(), e.rows * self.width);
            self.aside.extend_from_slice(&e.data);
            return;
        }
        let id = self.elements.len() as u32;
        self.live_rows += e.rows;
        self.live_blocks += e.rows * self.counted(&e);
        for &g in &e.groups {
            if Some(g) != self.deferred {
                self.adjacent[g as usize].push(id);
            }
        }
        self.elements.push(Some(e));
        self.element_mark.push(0);
    }

    /// Adds what a front left; the groups its absorbed elements touched
    /// have their degrees recomputed when they come up.
    pub fn settle(&mut self, pattern: &[u32], left: Vec<Element>) {
        for e in left {
            self.insert(e);
        }
        for &g in pattern {
            self.dirty[g as usize] = true;
        }
    }

    /// Queues `g` with its current degree.
    fn requeue(&mut self, g: u32) {
        let d = self.exact_degree(g);
        self.queue.push(Reverse((d, g)));
    }

    /// Neighbouring groups of `g` through its live elements.
    fn exact_degree(&mut self, g: u32) -> usize {
        let elements = &self.elements;
        self.adjacent[g as usize].retain(|&e| elements[e as usize].is_some());
        let stamp = self.next_stamp();
        self.mark[g as usize] = stamp;
        if let Some(d) = self.deferred {
            self.mark[d as usize] = stamp;
        }
        let mut n = 0;
        for &e in &self.adjacent[g as usize] {
            for &h in &self.elements[e as usize].as_ref().expect("live").groups {
                if self.mark[h as usize] != stamp {
                    self.mark[h as usize] = stamp;
                    n += 1;
                }
            }
        }
        n
    }

    /// The next group to eliminate: least degree, ties by index. Degrees
    /// are recomputed lazily, as in the minimum-degree codes that keep
    /// exact degrees: a group whose elements changed is queued again when
    /// it comes up with a larger degree than it was queued with.
    pub fn next_group(&mut self) -> Option<u32> {
        while let Some(Reverse((d, g))) = self.queue.pop() {
            if self.done[g as usize] {
                continue;
            }
            if self.dirty[g as usize] {
                self.dirty[g as usize] = false;
                let now = self.exact_degree(g);
                if now > d {
                    self.rescored += 1;
                    self.queue.push(Reverse((now, g)));
                    continue;
                }
            }
            return Some(g);
        }
        None
    }

    /// Takes out every element touching `g`, with the groups the front
    /// eliminates: `g` and every group each of whose elements is among
    /// those or lies inside their groups (then taken out too), so that none
    /// of its rows is left elsewhere.
    pub fn gather(&mut self, g: u32) -> Gathered {
        let elements = &self.elements;
        self.adjacent[g as usize].retain(|&e| elements[e as usize].is_some());
        let ids = std::mem::take(&mut self.adjacent[g as usize]);
        let stamp = self.next_stamp();
        for &e in &ids {
            self.element_mark[e as usize] = stamp;
        }
        self.mark[g as usize] = stamp;
        let mut union = Vec::new();
        for &e in &ids {
            for &h in &self.elements[e as usize].as_ref().expect("live").groups {
                if self.mark[h as usize] != stamp {
                    self.mark[h as usize] = stamp;
                    union.push(h);
                }
            }
        }
        if self.remaining >= DENSE_TAIL && 2 * self.live_blocks >= self.live_rows * self.remaining {
            return self.gather_all();
        }
        union.sort_unstable();
        let mut own = vec![g];
        let mut pattern = Vec::with_capacity(union.len());
        let mut ids = ids;
        let mut extra = Vec::new();
        for h in union {
            if Some(h) == self.deferred {
                pattern.push(h);
                continue;
            }
            // h is eliminated here too when each of its rows is in the front
            // already or lies inside the front's groups: absorbing those
            // adds rows but no column, and spares a later front that would
            // gather the same big elements again (supernodal amalgamation).
            let elements = &self.elements;
            let (marks, groups) = (&self.element_mark, &self.mark);
            extra.clear();
            let inside = self.adjacent[h as usize]
                .iter()
                .filter(|&&e| elements[e as usize].is_some())
                .all(|&e| {
                    marks[e as usize] == stamp || {
                        let fits = elements[e as usize]
                            .as_ref()
                            .expect("live")
                            .groups
                            .iter()
                            .all(|&k| groups[k as usize] == stamp);
                        if fits {
                            extra.push(e);
                        }
                        fits
                    }
                });
            if inside {
                own.push(h);
                for &e in &extra {
                    self.element_mark[e as usize] = stamp;
                    ids.push(e);
                }
            } else {
                pattern.push(h);
            }
        }
        for &h in &own {
            self.done[h as usize] = true;
            self.adjacent[h as usize] = Vec::new();
        }
        self.remaining -= own.len();
        let elements = ids
            .iter()
            .map(|&e| self.elements[e as usize].take().expect("live"))
            .collect::<Vec<_>>();
        for e in &elements {
            self.live_rows -= e.rows;
            self.live_blocks -= e.rows * self.counted(e);
        }
        Gathered {
            own,
            pattern,
            elements,
            tail: false,
        }
    }

    /// Everything that is left, in one front: once the live rows touch on
    /// average half the groups not yet eliminated, what is left is a dense
    /// matrix, and eliminating it group by group would gather the same rows
    /// again for every group. One front does it in panels of matrix
    /// products instead.
    fn gather_all(&mut self) -> Gathered {
        let own: Vec<u32> = (0..self.done.len() as u32)
            .filter(|&h| !self.done[h as usize] && Some(h) != self.deferred)
            .collect();
        for &h in &own {
            self.done[h as usize] = true;
            self.adjacent[h as usize] = Vec::new();
        }
        self.remaining = 0;
        self.live_rows = 0;
        self.live_blocks = 0;
        Gathered {
            own,
            pattern: self.deferred.into_iter().collect(),
            elements: self.elements.iter_mut().filter_map(Option::take).collect(),
            tail: true,
        }
    }

    /// Row-group blocks of the live elements: their storage, in blocks of
    /// `width` values.
    pub fn live_blocks(&self) -> usize {
        self.live_blocks
    }

    /// Groups queued again because their degree had grown.
    pub fn rescored(&self) -> usize {
        self.rescored
    }
}
