//! The index of loaded rules and host nodes that lets the matcher skip what
//! cannot match.
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
//! Each check only rejects attempts, or partial matches, that could not
//! have been completed: the engine still tries the remaining attempts in the
//! same order with the same random draws, and the matcher still meets the
//! complete matches in the same order, so it finds exactly the motifs the
//! plain matcher finds.
//!
//! Three more skip what a search already showed: a rod whose task found
//! no rods-only match leaves the cores those rules search, since no later
//! task can find one containing it ([`Index::leave`]); a rod task's trie
//! search stops at the first attempt in the plain order with a complete
//! map (the earlier ones have none; a later one is searched only if that
//! attempt's own search fails); and a pair task's pattern contact with no node map
//! from the pair rules out every contact of a pattern that contains it
//! ([`Catalog::implies`]), since a node map of the larger pattern would
//! give one of the smaller.

use crate::body::BodyClass;
use crate::graph::ContactGraph;

use std::sync::Arc;

use super::ball::{Ball, Bits, MAX_BALL, MAX_CORE, MAX_DEGREE, Search};
use super::catalog::{Catalog, PairEntry};
use super::cores::FreeCores;
use super::demand::{Common, Profile, class_index};
use super::rule::{CompiledRule, Step};
use super::sieve::{MAX_RADIUS, THRESHOLDS};
use super::state::State;
use super::trie::{Trie, Walk};

/// Bodies with more neighbours than this are not profiled.
const LARGE: usize = 256;

/// A neighbouring node as the index caches it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Neighbour {
    pub node: u32,
    /// [`class_index`] of the node.
    pub class: u8,
    /// Contacts shared with it.
    pub mult: u32,
}

/// The rule set's [`Catalog`]; host nodes' neighbour lists and profiles,
/// computed when first needed and dropped when a merge changes a node's
/// neighbours; the free rods' cores; and the scratch of one task.
pub(super) struct Index {
    /// Whether skipped attempts are matched anyway, to prove them impossible.
    pub audit: bool,
    catalog: Arc<Catalog>,
    fresh: Vec<bool>,
    profile: Vec<Profile>,
    /// Each node's neighbours, in the matcher's candidate order: by node for
    /// a rod, in the body's map order for a body.
    adjacency: Vec<Vec<Neighbour>>,
    /// Per pair task: the rules some entry of which passes the conditions, as bits.
    candidates: Vec<u64>,
    /// Per pair task: what each distinct need says of `x`, of `y` and of
    /// their common neighbours (0 unknown, 1 no, 2 yes).
    said_x: Vec<u8>,
    said_y: Vec<u8>,
    said_common: Vec<u8>,
    /// The free rods' cores of the orders the rods-only rules need.
    cores: Option<FreeCores>,
    /// Per rod task: the rod; its neighbours in each core by their degree
    /// there; the keys and attempts the sieve admits; and the cyclomatic
    /// number (contacts − rods + 1) of the rods of the least core within
    /// each distance of it (0 to the sieve's radius): a match lies in that
    /// core, at most its pattern distances apart.
    rod: u32,
    counts: Vec<[u32; THRESHOLDS]>,
    keys: Vec<u64>,
    marked: Vec<u64>,
    cycles: [i64; MAX_RADIUS + 1],
    /// The state of a trie search.
    walk: Walk,
    /// Per rod task: the attempts that can match, in the plain order, when
    /// all are listed at once (an audit, or a ball too large), and the
    /// next one to try.
    found: Vec<u32>,
    next: usize,
    /// Per rod task, when its attempts are found one at a time: the plain
    /// order (where it starts, and the number of attempts), the radius
    /// searched, the slots found to have a complete map and not yet
    /// tried, and the scratch of one search.
    first: Option<(u32, u32)>,
    radius: usize,
    known: Vec<u32>,
    pending: Vec<u64>,
    asked: Vec<u64>,
    /// Per rod task: what it knows of each rod (where the rod's stamp is
    /// the task's), and the rods of the ball to peel.
    marks: Vec<Mark>,
    stamp: u32,
    peeled: Vec<u32>,
    /// A rod task's rod, then the rods of the least core around it in
    /// breadth-first order.
    around: Vec<u32>,
    /// The rods of `around` whose neighbours are in it.
    searched: usize,
    ball: Ball,
    search: Search,
    /// The common neighbours of a pair task.
    common: Vec<Common>,
    /// The profiles of a pair task's ends.
    pair: (Profile, Profile),
    /// A pair task's ends, and whether `common` lists their common neighbours.
    pair_nodes: (u32, u32),
    common_known: bool,
    /// Complete maps found by a survey.
    maps: Vec<Option<u32>>,
    /// Per pair task: the pattern contacts shown to have no node map from
    /// the pair (as bits by [`PairEntry::id`]), and the words set.
    dead: Vec<u64>,
    dead_words: Vec<u32>,
    /// Whether the last match of a pattern contact found no node map
    /// (set by the matcher).
    pub no_map: bool,
}

/// What a rod task knows of a rod, together so that a look-up touches one
/// cache line: valid when `stamp` is the task's.
#[derive(Clone, Copy, Debug, Default)]
struct Mark {
    stamp: u32,
    /// Its neighbours in the ball as the ball is peeled.
    inner: u32,
    /// Its distance from the task's rod.
    distance: u8,
    /// Its place in the task's [`Ball`], when built.
    slot: u8,
}

/// What became of a rod task's ball.
enum Built {
    Ball,
    /// Its rod is not in the least core of the rods around it: no match.
    Empty,
    /// Too many rods for one set of bits.
    TooLarge,
}

impl Index {
    pub fn new(state: &mut State, rules: &[CompiledRule], audit: bool) -> Self {
        let n_rods = state.g.n_nodes();
        let catalog = Catalog::of(rules);
        let sieve = &catalog.sieve;
        let cores = (!sieve.is_empty()).then(|| FreeCores::new(state, sieve.low, sieve.high));
        let orders = usize::from(sieve.high - sieve.low) + 1;
        Index {
            audit,
            fresh: vec![false; n_rods],
            profile: vec![Profile::default(); n_rods],
            adjacency: vec![Vec::new(); n_rods],
            candidates: vec![0; rules.len().div_ceil(64)],
            said_x: vec![0; catalog.needs.len()],
            said_y: vec![0; catalog.needs.len()],
            said_common: vec![0; catalog.commons.len()],
            rod: 0,
            counts: vec![[0; THRESHOLDS]; orders],
            keys: vec![0; sieve.key_words()],
            marked: vec![0; sieve.attempt_words()],
            cycles: [0; MAX_RADIUS + 1],
            walk: Walk::default(),
            found: Vec::new(),
            next: 0,
            first: None,
            radius: 0,
            known: Vec::new(),
            pending: Vec::new(),
            asked: Vec::new(),
            cores,
            catalog: Arc::clone(&catalog),
            marks: vec![Mark::default(); n_rods],
            stamp: 0,
            peeled: Vec::new(),
            around: Vec::new(),
            searched: 0,
            ball: Ball::default(),
            search: Search::default(),
            common: Vec::new(),
            pair: (Profile::default(), Profile::default()),
            pair_nodes: (0, 0),
            common_known: false,
            maps: Vec::new(),
            dead: vec![0; catalog.implies.len().div_ceil(64)],
            dead_words: Vec::new(),
            no_map: false,
        }
    }

    /// Forgets what is cached of node `x`: its neighbours or their classes changed.
    pub fn invalidate(&mut self, x: u32) {
        self.fresh[x as usize] = false;
    }

    /// Computes node `x`'s neighbour list and profile unless cached.
    fn refresh(&mut self, state: &mut State, x: u32) {
        if self.fresh[x as usize] {
            return;
        }
        let mut list = std::mem::take(&mut self.adjacency[x as usize]);
        list.clear();
        if state.class(x).is_some() {
            list.extend(
                state.nodes[x as usize]
                    .adj
                    .iter()
                    .map(|(&y, links)| Neighbour {
                        node: y,
                        class: class_index(state.class(y)),
                        mult: links.len() as u32,
                    }),
            );
        } else {
            let g = state.g;
            for &(nb, _) in g.neighbors(x) {
                let y = state.find(nb);
                match list.iter_mut().find(|n| n.node == y) {
                    Some(n) => n.mult += 1,
                    None => list.push(Neighbour {
                        node: y,
                        class: class_index(state.class(y)),
                        mult: 1,
                    }),
                }
            }
            list.sort_unstable_by_key(|n| n.node);
        }
        let mut p = Profile::default();
        for n in &list {
            p.add(n.class as usize, n.mult as usize);
        }
        self.profile[x as usize] = p;
        self.adjacency[x as usize] = list;
        self.fresh[x as usize] = true;
    }

    /// The profile of node `x` (a current node); for a body of more than
    /// [`LARGE`] neighbours one that admits everything, so its list, which
    /// changes with most merges, is built only when walked.
    pub fn profile(&mut self, state: &mut State, x: u32) -> Profile {
        if !self.fresh[x as usize] && state.class(x).is_some() && state.degree(x) > LARGE {
            return Profile::ANY;
        }
        self.refresh(state, x);
        self.profile[x as usize]
    }

    /// Scratch for complete maps, handed back with [`Index::give_maps`].
    pub fn take_maps(&mut self) -> Vec<Option<u32>> {
        std::mem::take(&mut self.maps)
    }

    pub fn give_maps(&mut self, maps: Vec<Option<u32>>) {
        self.maps = maps;
    }

    /// The number of neighbours of node `x`, caching its list.
    pub fn n_neighbours(&mut self, state: &mut State, x: u32) -> usize {
        self.refresh(state, x);
        self.adjacency[x as usize].len()
    }

    /// Neighbour `i` of node `x`, whose list [`Index::n_neighbours`] cached.
    pub fn neighbour(&self, x: u32, i: usize) -> Neighbour {
        self.adjacency[x as usize][i]
    }

    /// Rod `r` leaves the rods a rods-only match can use: it joined a body,
    /// or its task found no such match, and none will ever contain it, since
    /// such a match needs only free rods and their contacts and rods only
    /// ever leave the free rods (a rod left so stays free for the rules with
    /// bodies).
    pub fn leave(&mut self, state: &State, r: u32) {
        if let Some(cores) = self.cores.as_mut() {
            cores.remove(state, r);
        }
    }

    /// Starts rod task `r` (a free rod), whose rules start at rule
    /// `start`: which attempts of the rods-only rules can match there, in
    /// the plain matcher's order ([`Index::next_rod_attempt`]); false when
    /// none can. Unless `all` are wanted (an audit), the ball's attempts
    /// are searched lazily: one search finds the first attempt with a
    /// complete map and leaves the later ones unknown, since the first
    /// that matches ends the task.
    pub fn start_rod(&mut self, state: &State, r: u32, start: usize, all: bool) -> bool {
        self.found.clear();
        self.known.clear();
        self.next = 0;
        self.first = None;
        if !self.admit_rod(state, r) {
            return false;
        }
        // The ball as far as the admitted attempts reach; where it is too
        // large, every admitted attempt is searched on its own.
        let catalog = Arc::clone(&self.catalog);
        let radius = catalog.sieve.reach(&self.keys).min(catalog.sieve.radius);
        match self.build_ball(state.g, radius) {
            Built::Ball if !all => {
                self.radius = radius;
                self.first = Some(catalog.sieve.order_from(start));
                return true;
            }
            Built::Ball => {
                self.walk.want_first(None);
                catalog.trie.search(
                    &mut self.ball,
                    radius,
                    &mut self.marked,
                    &mut self.found,
                    &mut self.walk,
                )
            }
            Built::Empty => {}
            Built::TooLarge => self.found.extend(slots(&self.marked)),
        }
        for s in &mut self.found {
            *s = catalog.trie.attempt_of[*s as usize];
        }
        catalog.sieve.sort_from(start, &mut self.found);
        !self.found.is_empty()
    }

    /// The started rod task's next attempt (rule, pattern node) that can
    /// match, in the plain matcher's order.
    pub fn next_rod_attempt(&mut self) -> Option<(usize, usize)> {
        let catalog = Arc::clone(&self.catalog);
        let attempt = |a: u32| {
            let (k, v) = catalog.sieve.attempts[a as usize];
            (k as usize, v as usize)
        };
        let Some(order) = self.first else {
            let a = *self.found.get(self.next)?;
            self.next += 1;
            return Some(attempt(a));
        };
        let trie = &catalog.trie;
        let least = |known: &[u32]| known.iter().map(|&s| trie.rank(s, order)).min();
        // Only the attempts before the first known one are searched.
        let bound = least(&self.known).unwrap_or(u32::MAX);
        self.asked.clear();
        self.asked.extend_from_slice(&self.marked);
        keep_before(trie, order, bound, &mut self.asked);
        if self.asked.iter().any(|&w| w != 0) {
            self.pending.clear();
            self.pending.extend_from_slice(&self.asked);
            let before = self.known.len();
            self.walk.want_first(Some(order));
            trie.search(
                &mut self.ball,
                self.radius,
                &mut self.pending,
                &mut self.known,
                &mut self.walk,
            );
            // Those asked before the first found are settled; so is every
            // one found.
            let bound = least(&self.known).unwrap_or(u32::MAX);
            keep_before(trie, order, bound, &mut self.asked);
            for (m, a) in self.marked.iter_mut().zip(&self.asked) {
                *m &= !a;
            }
            for &s in &self.known[before..] {
                self.marked[s as usize / 64] &= !(1 << (s % 64));
            }
        }
        let (i, _) = self
            .known
            .iter()
            .enumerate()
            .min_by_key(|&(_, &s)| trie.rank(s, order))?;
        let s = self.known.swap_remove(i);
        Some(attempt(trie.attempt_of[s as usize]))
    }

    /// Which attempts of the rods-only rules rod `r`'s surroundings admit
    /// ([`Sieve`]), marked by slot; whether any.
    fn admit_rod(&mut self, state: &State, r: u32) -> bool {
        let Some(cores) = &self.cores else {
            return false;
        };
        self.rod = r;
        self.ball.built = false;
        let low = cores.low();
        let level = cores.level(r);
        if level < low {
            return false;
        }
        let sieve = &self.catalog.sieve;
        let top = level.min(sieve.high);
        let g = state.g;
        for (i, m) in (low..=top).enumerate() {
            let counts = &mut self.counts[i];
            *counts = [0; THRESHOLDS];
            for &(w, _) in g.neighbors(r) {
                if cores.level(w) >= m {
                    let d = (cores.degree(m, w) as usize).min(THRESHOLDS);
                    for c in &mut counts[..d] {
                        *c += 1;
                    }
                }
            }
        }
        let short = [3, 4].map(|l| cores.short_cycle_distance(l, r));
        if !sieve.admit(level, &self.counts, &mut self.keys)
            || !sieve.admit_short(short, &mut self.keys)
        {
            return false;
        }
        self.measure_cycles(state);
        let sieve = &self.catalog.sieve;
        if !sieve.admit_cycles(&self.cycles, &mut self.keys) {
            return false;
        }
        sieve.mark(&self.keys, &mut self.marked);
        true
    }

    /// Whether some rule has a body: only those are matched on pairs.
    pub fn has_pair_rules(&self) -> bool {
        self.catalog.has_pair_rules
    }

    /// The attempts (rule, pattern node) of a rod task started for `all`
    /// that can match, in the plain matcher's order.
    pub fn rod_attempts(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.found.iter().map(|&a| {
            let (k, v) = self.catalog.sieve.attempts[a as usize];
            (k as usize, v as usize)
        })
    }

    /// The cycles of the started rod task's surroundings by distance:
    /// breadth first through the rods of the least core, a contact
    /// counting at the larger distance of its rods, once. A rod's cycles
    /// only grow with the distance, so once they reach the most any rule
    /// needs the search stops ([`Index::grow_around`] goes on for the
    /// ball) and the larger distances get the same number, which admits
    /// the same keys.
    fn measure_cycles(&mut self, state: &State) {
        let cores = self.cores.as_ref().expect("rods-only rules");
        let (low, radius) = (cores.low(), self.catalog.sieve.radius);
        let most = i64::from(self.catalog.sieve.most_cycles);
        let g = state.g;
        let r = self.rod;
        self.stamp += 1;
        let stamp = self.stamp;
        self.marks[r as usize] = Mark {
            stamp,
            distance: 0,
            ..Mark::default()
        };
        let ball = &mut self.around;
        ball.clear();
        ball.push(r);
        let (mut rods, mut contacts) = (0i64, 0i64);
        let mut next = 0;
        let mut layer = 0;
        loop {
            let d = ball
                .get(next)
                .map_or(usize::MAX, |&u| self.marks[u as usize].distance as usize);
            if d != layer {
                // Every rod and contact within `layer` is counted.
                let cycles = contacts - rods + 1;
                self.cycles[layer] = cycles;
                if d == usize::MAX || cycles >= most {
                    for c in &mut self.cycles[layer + 1..] {
                        *c = cycles;
                    }
                    break;
                }
                layer = d;
            }
            let u = ball[next];
            next += 1;
            rods += 1;
            for &(w, _) in g.neighbors(u) {
                if cores.level(w) < low {
                    continue;
                }
                let w = w as usize;
                let mark = &mut self.marks[w];
                if mark.stamp != stamp {
                    if d < radius {
                        mark.stamp = stamp;
                        mark.distance = d as u8 + 1;
                        ball.push(w as u32);
                    }
                } else if (mark.distance as usize) < d
                    || (mark.distance as usize == d && (w as u32) < u)
                {
                    contacts += 1;
                }
            }
        }
        self.searched = next;
    }

    /// Goes on with the breadth-first search of [`Index::measure_cycles`]
    /// until it holds every rod of the least core within `radius`.
    fn grow_around(&mut self, g: &ContactGraph, radius: usize) {
        let cores = self.cores.as_ref().expect("rods-only rules");
        let low = cores.low();
        let stamp = self.stamp;
        while let Some(&u) = self.around.get(self.searched) {
            let d = self.marks[u as usize].distance as usize;
            if d >= radius {
                break;
            }
            self.searched += 1;
            for &(w, _) in g.neighbors(u) {
                let mark = &mut self.marks[w as usize];
                if cores.level(w) >= low && mark.stamp != stamp {
                    mark.stamp = stamp;
                    mark.distance = d as u8 + 1;
                    self.around.push(w);
                }
            }
        }
    }

    /// Builds the rod task's [`Ball`] of the rods within `radius` of its
    /// rod, peeled to the least core the rules need (a match lies there).
    fn build_ball(&mut self, g: &ContactGraph, radius: usize) -> Built {
        self.grow_around(g, radius);
        let stamp = self.stamp;
        // `around` is in breadth-first order.
        let size = self
            .around
            .partition_point(|&u| self.marks[u as usize].distance as usize <= radius);
        let low = u32::from(self.catalog.sieve.low);
        let inside = |m: &Mark| m.stamp == stamp && m.distance as usize <= radius;
        self.peeled.clear();
        for &u in &self.around[..size] {
            let d = g
                .neighbors(u)
                .iter()
                .filter(|&&(w, _)| inside(&self.marks[w as usize]))
                .count() as u32;
            self.marks[u as usize].inner = d;
            if d < low {
                self.peeled.push(u);
            }
        }
        while let Some(u) = self.peeled.pop() {
            if self.marks[u as usize].stamp != stamp {
                continue;
            }
            self.marks[u as usize].stamp = 0;
            for &(w, _) in g.neighbors(u) {
                let mark = &mut self.marks[w as usize];
                if inside(mark) {
                    mark.inner -= 1;
                    if mark.inner < low {
                        self.peeled.push(w);
                    }
                }
            }
        }
        if self.marks[self.rod as usize].stamp != stamp {
            return Built::Empty;
        }
        let ball = &mut self.ball;
        ball.rods.clear();
        ball.rods.extend(
            self.around[..size]
                .iter()
                .filter(|&&u| self.marks[u as usize].stamp == stamp),
        );
        if ball.rods.len() > MAX_BALL {
            return Built::TooLarge;
        }
        ball.radius = radius;
        ball.radius = radius;
        ball.rods.sort_unstable();
        ball.rows.clear();
        ball.near.clear();
        ball.near.resize(radius + 1, Bits::default());
        ball.wide = [Bits::default(); MAX_DEGREE + 1];
        // Ball rods by host rod, as `distance` (stamped by `seen`) is kept.
        for (i, &u) in ball.rods.iter().enumerate() {
            self.marks[u as usize].slot = i as u8;
        }
        for (i, &u) in ball.rods.iter().enumerate() {
            let mut row = Bits::default();
            for &(w, _) in g.neighbors(u) {
                let mark = &self.marks[w as usize];
                if mark.stamp == stamp && mark.distance as usize <= radius {
                    row.insert(mark.slot as usize);
                }
            }
            ball.rows.push(row);
            for d in self.marks[u as usize].distance as usize..=radius {
                ball.near[d].insert(i);
            }
            for k in 0..=(row.count() as usize).min(MAX_DEGREE) {
                ball.wide[k].insert(i);
            }
        }
        ball.core.clear();
        ball.core.resize(radius + 1, [None; MAX_CORE + 1]);
        ball.root = self.marks[self.around[0] as usize].slot as usize;
        ball.built = true;
        Built::Ball
    }

    /// Searches the rod task's ball as the plain matcher would search from
    /// pattern node `start` on the task's rod (`plan`), calling `complete`
    /// on each complete map until it returns true. `None` when the ball is
    /// too large to build or narrower than the pattern.
    pub fn search_ball(
        &mut self,
        start: usize,
        eccentricity: usize,
        min_degree: usize,
        plan: &[Step],
        n: usize,
        complete: &mut dyn FnMut(&[Option<u32>]) -> bool,
    ) -> Option<bool> {
        if !self.ball.built || eccentricity > self.ball.radius {
            return None;
        }
        self.search.within = self.ball.within(eccentricity, min_degree.min(MAX_CORE));
        Some(self.ball.search(start, plan, n, &mut self.search, complete))
    }

    /// Starts pair task `x`, `y`, with `m` contacts between them: their
    /// profiles, common neighbours and candidate rules.
    pub fn start_pair(&mut self, state: &mut State, x: u32, y: u32, m: usize) {
        let (px, py) = (self.profile(state, x), self.profile(state, y));
        self.pair = (px, py);
        self.pair_nodes = (x, y);
        self.common_known = false;
        self.said_x.fill(0);
        self.said_y.fill(0);
        self.said_common.fill(0);
        self.candidates.fill(0);
        for &w in &self.dead_words {
            self.dead[w as usize] = 0;
        }
        self.dead_words.clear();
        let c = 3 * class_index(state.class(x)) as usize + class_index(state.class(y)) as usize;
        let catalog = Arc::clone(&self.catalog);
        let shared = &catalog.shared[c];
        let (px, py) = self.pair;
        let mut i = 0;
        while let Some(s) = shared.get(i).filter(|s| s.entry.mult <= m) {
            let e = &s.entry;
            if !ask(&mut self.said_x, e.need_a, || {
                px.admits(&catalog.needs[e.need_a])
            }) {
                i = s.skip_a;
            } else if !ask(&mut self.said_y, e.need_b, || {
                py.admits(&catalog.needs[e.need_b])
            }) {
                i = s.skip_b;
            } else {
                if self.common_admits(state, e.common) {
                    for (w, bits) in self.candidates.iter_mut().zip(&s.rules) {
                        *w |= bits;
                    }
                }
                i += 1;
            }
        }
    }

    /// The rules some pattern contact of which passes the started pair's
    /// conditions, from rule `start` on, cyclically.
    pub fn candidates(&self, start: usize) -> impl Iterator<Item = usize> + '_ {
        let bits = |from: usize, to: usize| {
            (from / 64..to.div_ceil(64))
                .flat_map(move |w| {
                    let mut word = self.candidates[w];
                    std::iter::from_fn(move || {
                        (word != 0).then(|| {
                            let b = word.trailing_zeros() as usize;
                            word &= word - 1;
                            64 * w + b
                        })
                    })
                })
                .filter(move |&k| (from..to).contains(&k))
        };
        let n = self.catalog.entries.len();
        bits(start, n).chain(bits(0, start))
    }

    /// The pattern contacts of rule `k` whose ends fit the classes of the
    /// started pair, in the plain matcher's order.
    pub fn entries(&self, k: usize, cx: Option<BodyClass>, cy: Option<BodyClass>) -> &[PairEntry] {
        &self.catalog.entries[k][3 * class_index(cx) as usize + class_index(cy) as usize]
    }

    /// Whether the started pair was shown unable to carry `e`.
    pub fn dead(&self, e: &PairEntry) -> bool {
        self.dead[e.id as usize / 64] & (1 << (e.id % 64)) != 0
    }

    /// The started pair has no node map from `e`: nor from the pattern
    /// contacts that contain it.
    pub fn kill(&mut self, e: &PairEntry) {
        for &(w, bits) in &self.catalog.implies[e.id as usize] {
            let dead = &mut self.dead[w as usize];
            if *dead == 0 {
                self.dead_words.push(w);
            }
            *dead |= bits;
        }
    }

    /// Whether the started pair can carry `e` (given enough contacts between them).
    pub fn pair_could_match(&mut self, state: &mut State, e: &PairEntry) -> bool {
        let (px, py) = self.pair;
        let needs = &self.catalog.needs;
        ask(&mut self.said_x, e.need_a, || px.admits(&needs[e.need_a]))
            && ask(&mut self.said_y, e.need_b, || py.admits(&needs[e.need_b]))
            && self.common_admits(state, e.common)
    }

    /// Whether the started pair's common neighbours admit [`CommonNeeds`]
    /// `k`; they are listed when first needed (most pairs fail on their ends).
    fn common_admits(&mut self, state: &mut State, k: usize) -> bool {
        if self.said_common[k] == 0 && !self.common_known {
            let (x, y) = self.pair_nodes;
            let (small, large, flip) = if state.degree(x) <= state.degree(y) {
                (x, y, false)
            } else {
                (y, x, true)
            };
            self.refresh(state, small);
            self.common.clear();
            for n in &self.adjacency[small as usize] {
                if n.node == large {
                    continue;
                }
                let m_large = state.multiplicity(large, n.node) as u32;
                if m_large > 0 {
                    self.common.push(if flip {
                        (n.class, m_large, n.mult)
                    } else {
                        (n.class, n.mult, m_large)
                    });
                }
            }
            self.common_known = true;
        }
        ask(&mut self.said_common, k, || {
            self.catalog.commons[k].admitted_by(&self.common)
        })
    }
}

/// The slots set in `bits`, in order.
fn slots(bits: &[u64]) -> impl Iterator<Item = u32> + '_ {
    bits.iter().enumerate().flat_map(|(w, &word)| {
        let mut word = word;
        std::iter::from_fn(move || {
            (word != 0).then(|| {
                let b = word.trailing_zeros();
                word &= word - 1;
                64 * w as u32 + b
            })
        })
    })
}

/// Clears the slots of `bits` at or after `bound` in the plain order `order`.
fn keep_before(trie: &Trie, order: (u32, u32), bound: u32, bits: &mut [u64]) {
    if bound == u32::MAX {
        return;
    }
    for (w, word) in bits.iter_mut().enumerate() {
        let mut rest = *word;
        while rest != 0 {
            let b = rest.trailing_zeros();
            rest &= rest - 1;
            if trie.rank(64 * w as u32 + b, order) >= bound {
                *word &= !(1 << b);
            }
        }
    }
}

/// Condition `k`'s answer for the current task, asking `answer` once
/// (`said`: 0 not asked, 1 no, 2 yes).
fn ask(said: &mut [u8], k: usize, answer: impl FnOnce() -> bool) -> bool {
    if said[k] == 0 {
        said[k] = 1 + u8::from(answer());
    }
    said[k] == 2
}
