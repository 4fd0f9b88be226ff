//! The k-cores of the free rods, kept up to date as rods join bodies.
//!
//! A match of a rods-only rule maps every pattern node to a free rod, and
//! a pattern node of `k` neighbours to a rod with at least `k` of the
//! match's rods as neighbours: so a match whose least pattern degree is `k`
//! lies in the `k`-core of the free rods, and each of its rods has at
//! least its pattern degree of neighbours there. Rods only ever leave the
//! free rods, so each core only shrinks: a rod that leaves lowers its
//! neighbours' counts, and those that fall below `k` leave in turn.

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
}

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
            stack.extend((0..n as u32).filter(|&r| alive[r as usize] && left[r as usize] < u32::from(k)));
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
        FreeCores {
            low,
            high,
            level,
            degree,
            stack,
        }
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
