//! The k-cores of the free rods, kept up to date as rods join bodies.
//!
//! A match of a rods-only rule maps every pattern node to a free rod, and
//! a pattern node of `k` neighbours to a rod with at least `k` of the
//! match's rods as neighbours: so a match whose least pattern degree is `k`
//! lies in the `k`-core of the free rods, and each of its rods has at
//! least its pattern degree of neighbours there. Rods only ever leave the
//! free rods (and a rod whose task found no match leaves the rods kept
//! here, as no later match can contain it), so each core only shrinks: a rod that leaves lowers its
//! neighbours' counts, and those that fall below `k` leave in turn.
//!
//! A match also maps a pattern's triangles and 4-cycles onto triangles and
//! cycles of at most 4 rods of free rods: so how far each rod is from such
//! short cycles, measured once among the rods free at the start (a cycle
//! now was one then), bounds how close to the pattern's short cycles it can
//! lie.

use super::state::State;

/// The free rods' `k`-cores for `k` from `low` to `high`.
pub(super) struct FreeCores {
    low: u8,
    high: u8,
    /// Each rod's highest order from `low` to `high` whose core holds it,
    /// or `low - 1` (a rod that is no longer free, or in no core kept).
    level: Vec<u8>,
    /// By order `k - low`: each rod's neighbours in the `k`-core, while it
    /// is in that core itself.
    degree: Vec<Vec<u32>>,
    stack: Vec<u32>,
    /// By cycle length (3, then at most 4): each rod's distance, among the
    /// rods of the `low`-core at the start, from the nearest rod on such a
    /// cycle, up to [`FAR`].
    short: [Vec<u8>; 2],
}

/// Distances from short cycles are counted up to this.
pub(super) const FAR: u8 = 7;

impl FreeCores {
    /// The cores of the rods free in `state`, of orders `low..=high` (`low` at least 1).
    pub fn new(state: &State, low: u8, high: u8) -> Self {
        debug_assert!(1 <= low && low <= high);
        let g = state.g;
        let n = g.n_nodes();
        let free: Vec<bool> = (0..n as u32).map(|r| state.is_free_rod(r)).collect();
        // Core numbers capped at `high`, by peeling order by order.
        let mut level = vec![0u8; n];
        let mut alive = free.clone();
        let mut left: Vec<u32> = (0..n as u32)
            .map(|r| {
                g.neighbors(r)
                    .iter()
                    .filter(|&&(w, _)| free[w as usize])
                    .count() as u32
            })
            .collect();
        let mut stack = Vec::new();
        for k in 1..=high {
            stack.extend(
                (0..n as u32).filter(|&r| alive[r as usize] && left[r as usize] < u32::from(k)),
            );
            while let Some(r) = stack.pop() {
                if !alive[r as usize] {
                    continue;
                }
                alive[r as usize] = false;
                level[r as usize] = k - 1;
                for &(w, _) in g.neighbors(r) {
                    if alive[w as usize] {
                        left[w as usize] -= 1;
                        if left[w as usize] < u32::from(k) {
                            stack.push(w);
                        }
                    }
                }
            }
        }
        for (l, a) in level.iter_mut().zip(&alive) {
            if *a {
                *l = high;
            }
        }
        for l in &mut level {
            *l = (*l).max(low - 1);
        }
        let degree = (low..=high)
            .map(|k| {
                (0..n as u32)
                    .map(|r| {
                        if level[r as usize] < k {
                            return 0;
                        }
                        g.neighbors(r)
                            .iter()
                            .filter(|&&(w, _)| level[w as usize] >= k)
                            .count() as u32
                    })
                    .collect()
            })
            .collect();
        let short = short_cycles(state, &level, low);
        FreeCores {
            low,
            high,
            level,
            degree,
            stack,
            short,
        }
    }

    /// Rod `r`'s distance (up to [`FAR`]) from the nearest triangle
    /// (`length` 3) or cycle of at most 4 rods (`length` 4) of the rods
    /// free at the start, through them.
    pub fn short_cycle_distance(&self, length: usize, r: u32) -> u8 {
        self.short[length - 3][r as usize]
    }

    /// The least order kept.
    pub fn low(&self) -> u8 {
        self.low
    }

    /// The highest order from `low` to `high` whose core holds rod `r`
    /// (below `low` when none does).
    pub fn level(&self, r: u32) -> u8 {
        self.level[r as usize]
    }

    /// Rod `r`'s neighbours in the `k`-core (`k` at most its level).
    pub fn degree(&self, k: u8, r: u32) -> u32 {
        self.degree[(k - self.low) as usize][r as usize]
    }

    /// Rod `r` (free until now) joins a body: it leaves every core, and so
    /// may rods around it.
    pub fn remove(&mut self, state: &State, r: u32) {
        let g = state.g;
        // Higher cores first: once the `k + 1`-core is that of the rods
        // left, the `k`-core's cascade cannot reach it.
        for k in (self.low..=self.high).rev() {
            if self.level[r as usize] < k {
                continue;
            }
            let degree = &mut self.degree[(k - self.low) as usize];
            self.stack.push(r);
            while let Some(u) = self.stack.pop() {
                if self.level[u as usize] < k {
                    continue;
                }
                self.level[u as usize] = k - 1;
                for &(w, _) in g.neighbors(u) {
                    if self.level[w as usize] >= k {
                        degree[w as usize] -= 1;
                        if degree[w as usize] < u32::from(k) {
                            self.stack.push(w);
                        }
                    }
                }
            }
        }
        self.level[r as usize] = self.low - 1;
    }
}

/// Each rod's distance from the nearest rod on a triangle, and on a cycle
/// of at most 4 rods, among the rods whose `level` is at least `low`.
fn short_cycles(state: &State, level: &[u8], low: u8) -> [Vec<u8>; 2] {
    let g = state.g;
    let n = g.n_nodes();
    let core = |r: u32| level[r as usize] >= low;
    let (mut on3, mut on4) = (vec![false; n], vec![false; n]);
    // 2-paths from `u` to each rod, with the first middle rod seen; the
    // neighbours of `u` marked with `u + 1`.
    let (mut paths, mut middle, mut seen) = (vec![0u32; n], vec![0u32; n], Vec::new());
    let mut beside = vec![0u32; n];
    for u in (0..n as u32).filter(|&u| core(u)) {
        for &(a, _) in g.neighbors(u) {
            beside[a as usize] = u + 1;
        }
        for &(a, _) in g.neighbors(u) {
            if !core(a) {
                continue;
            }
            // Each pair of ends once, from its lower end (lists are sorted).
            let nb = g.neighbors(a);
            for &(x, _) in &nb[nb.partition_point(|&(x, _)| x <= u)..] {
                if !core(x) {
                    continue;
                }
                if beside[x as usize] == u + 1 {
                    for t in [u, a, x] {
                        on3[t as usize] = true;
                        on4[t as usize] = true;
                    }
                }
                let p = &mut paths[x as usize];
                *p += 1;
                if *p == 1 {
                    middle[x as usize] = a;
                    seen.push(x);
                } else {
                    for t in [u, a, x, middle[x as usize]] {
                        on4[t as usize] = true;
                    }
                }
            }
        }
        for x in seen.drain(..) {
            paths[x as usize] = 0;
        }
    }
    [on3, on4].map(|on| {
        let mut distance = vec![FAR; n];
        let mut queue: std::collections::VecDeque<u32> = (0..n as u32)
            .filter(|&r| on[r as usize])
            .inspect(|&r| distance[r as usize] = 0)
            .collect();
        while let Some(u) = queue.pop_front() {
            let d = distance[u as usize];
            if d + 1 >= FAR {
                continue;
            }
            for &(w, _) in g.neighbors(u) {
                if core(w) && distance[w as usize] > d + 1 {
                    distance[w as usize] = d + 1;
                    queue.push_back(w);
                }
            }
        }
        distance
    })
}
