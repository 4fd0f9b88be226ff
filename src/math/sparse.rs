//! Exact rank and a random kernel vector of a large sparse matrix over F_p,
//! by block elimination in minimum-degree order.
//!
//! The columns come in groups (the six motion coordinates of one rigid
//! part), and a row touches few groups (a contact touches two parts). Dense
//! elimination of a whole rod system is hopeless (thousands of columns,
//! cubic cost), and eliminating in a fixed order fills the band between
//! parts that touch across the periodic box. So the groups are eliminated
//! one at a time, always the one with the fewest neighbouring groups left
//! (the minimum-degree rule that keeps sparse factorizations sparse): its
//! rows are gathered into a small dense front, its columns are eliminated,
//! and what is left of the front is reduced to independent rows that stay
//! in the matrix. Every step is a row operation, so the number of pivots is
//! the rank; the pivot rows kept along the way solve for a kernel vector.

use rand::Rng;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::field::Fp;

/// A sparse row: `(column, value)` with increasing columns and no zeros;
/// over F_p unless said otherwise (the float fallback builds `f64` rows).
pub type SparseRow<S = Fp> = Vec<(u32, S)>;

/// The outcome of an elimination.
#[derive(Clone, Debug)]
pub struct Elimination {
    pub rank: usize,
    /// Columns of the matrix.
    pub cols: usize,
    /// Random vectors of the kernel (uniform over it, so a linear relation
    /// that holds on them holds on the whole kernel except with probability
    /// `1/p` each).
    pub kernel: Vec<Vec<Fp>>,
    /// The largest dense front, rows times columns: what the cost grew with.
    pub largest_front: (usize, usize),
}

/// A pivot row kept for back substitution.
struct Pivot {
    col: u32,
    row: SparseRow,
}

/// Eliminates the matrix of `rows` over `groups * width` columns, column
/// `c` belonging to group `c / width`, and draws `kernel_vectors` random
/// kernel vectors from `rng`. Every kernel vector is checked against the
/// original rows; a failure is a bug and panics.
pub fn eliminate(
    rows: &[SparseRow],
    groups: usize,
    width: usize,
    kernel_vectors: usize,
    rng: &mut impl Rng,
) -> Elimination {
    let cols = groups * width;
    let mut state = State::new(rows, groups, width);
    let mut heap: BinaryHeap<Reverse<(usize, u32)>> = (0..groups as u32)
        .map(|g| Reverse((state.degree(g), g)))
        .collect();
    while let Some(Reverse((score, g))) = heap.pop() {
        if state.done[g as usize] {
            continue;
        }
        if state.dirty[g as usize] {
            state.dirty[g as usize] = false;
            let d = state.degree(g);
            if d > score {
                heap.push(Reverse((d, g)));
                continue;
            }
        }
        state.eliminate_group(g);
    }
    let kernel = (0..kernel_vectors)
        .map(|_| {
            let x = state.kernel_vector(rng);
            for (i, r) in rows.iter().enumerate() {
                let s = r
                    .iter()
                    .fold(Fp::ZERO, |acc, &(c, v)| acc + v * x[c as usize]);
                assert!(s.is_zero(), "kernel vector violates row {i}");
            }
            x
        })
        .collect();
    Elimination {
        rank: state.pivots.len(),
        cols,
        kernel,
        largest_front: state.largest_front,
    }
}

struct State {
    width: usize,
    rows: Vec<Option<SparseRow>>,
    /// Rows that touch each group (some may have died since).
    group_rows: Vec<Vec<u32>>,
    done: Vec<bool>,
    dirty: Vec<bool>,
    pivots: Vec<Pivot>,
    /// Scratch: a mark per group.
    mark: Vec<u32>,
    stamp: u32,
    largest_front: (usize, usize),
}

impl State {
    fn new(rows: &[SparseRow], groups: usize, width: usize) -> Self {
        let mut s = State {
            width,
            rows: Vec::with_capacity(rows.len()),
            group_rows: vec![Vec::new(); groups],
            done: vec![false; groups],
            dirty: vec![false; groups],
            pivots: Vec::new(),
            mark: vec![0; groups],
            stamp: 0,
            largest_front: (0, 0),
        };
        for r in rows {
            let r: SparseRow = r.iter().copied().filter(|(_, v)| !v.is_zero()).collect();
            if !r.is_empty() {
                s.add_row(r);
            }
        }
        s
    }

    fn group(&self, col: u32) -> u32 {
        col / self.width as u32
    }

    fn next_stamp(&mut self) -> u32 {
        self.stamp += 1;
        if self.stamp == u32::MAX {
            self.mark.fill(0);
            self.stamp = 1;
        }
        self.stamp
    }

    fn add_row(&mut self, r: SparseRow) {
        let id = self.rows.len() as u32;
        let stamp = self.next_stamp();
        for &(c, _) in &r {
            let g = self.group(c) as usize;
            if self.mark[g] != stamp {
                self.mark[g] = stamp;
                self.group_rows[g].push(id);
                self.dirty[g] = true;
            }
        }
        self.rows.push(Some(r));
    }

    /// The live rows of group `g`, with dead entries dropped from its list.
    fn live_rows(&mut self, g: u32) -> Vec<u32> {
        let rows = &self.rows;
        let list = &mut self.group_rows[g as usize];
        list.retain(|&id| rows[id as usize].is_some());
        list.clone()
    }

    /// Neighbouring groups of `g` through its live rows.
    fn degree(&mut self, g: u32) -> usize {
        let ids = self.live_rows(g);
        let stamp = self.next_stamp();
        self.mark[g as usize] = stamp;
        let mut n = 0;
        for id in ids {
            for &(c, _) in self.rows[id as usize].as_ref().expect("live") {
                let h = (c / self.width as u32) as usize;
                if self.mark[h] != stamp {
                    self.mark[h] = stamp;
                    n += 1;
                }
            }
        }
        n
    }

    /// Eliminates the columns of group `g`: its rows go into a dense front,
    /// pivots on `g`'s columns are kept, and the rest of the front is
    /// reduced to independent rows that replace the gathered ones.
    fn eliminate_group(&mut self, g: u32) {
        self.done[g as usize] = true;
        let ids = self.live_rows(g);
        if ids.is_empty() {
            return;
        }
        // Local columns: g's own first, then every other column the rows touch.
        let base = g * self.width as u32;
        let mut local: Vec<u32> = (base..base + self.width as u32).collect();
        for &id in &ids {
            for &(c, _) in self.rows[id as usize].as_ref().expect("live") {
                if self.group(c) != g {
                    local.push(c);
                }
            }
        }
        local[self.width..].sort_unstable();
        local.dedup();
        let ncols = local.len();
        let index = |c: u32| -> usize {
            if c >= base && c < base + self.width as u32 {
                (c - base) as usize
            } else {
                self.width + local[self.width..].binary_search(&c).expect("local column")
            }
        };
        let mut front: Vec<Vec<Fp>> = ids
            .iter()
            .map(|&id| {
                let mut dense = vec![Fp::ZERO; ncols];
                for &(c, v) in self.rows[id as usize].as_ref().expect("live") {
                    dense[index(c)] = v;
                }
                dense
            })
            .collect();
        let (fr, fc) = self.largest_front;
        if ids.len() * ncols > fr * fc {
            self.largest_front = (ids.len(), ncols);
        }
        for &id in &ids {
            self.rows[id as usize] = None;
        }
        // Forward elimination on g's columns: the pivots are kept for back
        // substitution. What remains of the front stays in the matrix; when it
        // has more rows than columns some are dependent, and reducing it to
        // echelon form drops them (otherwise rows would pile up step by step).
        let top = forward(&mut front, 0, 0, self.width, |col, row| {
            self.pivots.push(Pivot {
                col: local[col],
                row: row.iter().map(|&(k, v)| (local[k], v)).collect(),
            });
        });
        let rest = front.split_off(top);
        let sparse = |dense: &[Fp]| -> SparseRow {
            dense
                .iter()
                .enumerate()
                .filter(|(_, v)| !v.is_zero())
                .map(|(k, &v)| (local[k], v))
                .collect()
        };
        if rest.len() > ncols - self.width {
            let mut rest = rest;
            let mut reduced = Vec::new();
            forward(&mut rest, 0, self.width, ncols, |_, row| {
                reduced.push(row.iter().map(|&(k, v)| (local[k], v)).collect())
            });
            for r in reduced {
                self.add_row(r);
            }
        } else {
            for dense in &rest {
                let r = sparse(dense);
                if !r.is_empty() {
                    self.add_row(r);
                }
            }
        }
    }

    /// A uniformly random kernel vector: random free columns, pivots solved
    /// in the reverse order of elimination.
    fn kernel_vector(&self, rng: &mut impl Rng) -> Vec<Fp> {
        let cols = self.done.len() * self.width;
        let mut pivot_col = vec![false; cols];
        for p in &self.pivots {
            pivot_col[p.col as usize] = true;
        }
        let mut x: Vec<Fp> = pivot_col
            .iter()
            .map(|&is_pivot| if is_pivot { Fp::ZERO } else { Fp::random(rng) })
            .collect();
        for p in self.pivots.iter().rev() {
            let mut lead = Fp::ZERO;
            let mut sum = Fp::ZERO;
            for &(c, v) in &p.row {
                if c == p.col {
                    lead = v;
                } else {
                    sum = sum + v * x[c as usize];
                }
            }
            x[p.col as usize] = -(sum * lead.inv().expect("non-zero pivot"));
        }
        x
    }
}

/// Forward Gaussian elimination of `front` from row `top` on, pivoting on
/// the columns `from..to` in order; hands each pivot row (its non-zeros from
/// the pivot column on) to `pivot` and returns the row after the last pivot.
fn forward(
    front: &mut [Vec<Fp>],
    mut top: usize,
    from: usize,
    to: usize,
    mut pivot: impl FnMut(usize, &[(usize, Fp)]),
) -> usize {
    let ncols = front.first().map_or(0, Vec::len);
    let mut row_nz: Vec<(usize, Fp)> = Vec::with_capacity(ncols);
    for col in from..to {
        if top == front.len() {
            break;
        }
        let Some(p) = (top..front.len()).find(|&r| !front[r][col].is_zero()) else {
            continue;
        };
        front.swap(top, p);
        let inv = front[top][col].inv().expect("non-zero pivot");
        row_nz.clear();
        row_nz.extend(
            (col..ncols)
                .filter(|&k| !front[top][k].is_zero())
                .map(|k| (k, front[top][k])),
        );
        for row in &mut front[top + 1..] {
            let f = row[col];
            if f.is_zero() {
                continue;
            }
            let f = f * inv;
            for &(k, v) in &row_nz {
                row[k] = row[k] - f * v;
            }
        }
        pivot(col, &row_nz);
        top += 1;
    }
    top
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Matrix, rank_fp};
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn dense(rows: &[SparseRow], cols: usize) -> Matrix<Fp> {
        let mut m = Matrix::zeros(rows.len(), cols);
        for (i, r) in rows.iter().enumerate() {
            for &(c, v) in r {
                m.set(i, c as usize, v);
            }
        }
        m
    }

    /// Random rows touching two or three groups, some of them copies or
    /// sums of others so that the rank falls short.
    fn random_rows(seed: u64, groups: usize, width: usize, n: usize) -> Vec<SparseRow> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut rows: Vec<SparseRow> = Vec::new();
        for i in 0..n {
            if i > 2 && rng.random_range(0..4) == 0 {
                let a = rows[rng.random_range(0..rows.len())].clone();
                let b = rows[rng.random_range(0..rows.len())].clone();
                let mut d = vec![Fp::ZERO; groups * width];
                for (c, v) in a.into_iter().chain(b) {
                    d[c as usize] = d[c as usize] + v;
                }
                rows.push(
                    d.into_iter()
                        .enumerate()
                        .filter(|(_, v)| !v.is_zero())
                        .map(|(c, v)| (c as u32, v))
                        .collect(),
                );
                continue;
            }
            let mut gs: Vec<usize> = (0..rng.random_range(1..=3))
                .map(|_| rng.random_range(0..groups))
                .collect();
            gs.sort_unstable();
            gs.dedup();
            let mut r: SparseRow = Vec::new();
            for g in gs {
                for k in 0..width {
                    if rng.random_range(0..3) > 0 {
                        r.push(((g * width + k) as u32, Fp::random_nonzero(&mut rng)));
                    }
                }
            }
            rows.push(r);
        }
        rows
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// The block elimination agrees with dense elimination, and its
        /// kernel vectors are kernel vectors (checked inside `eliminate`).
        #[test]
        fn rank_matches_dense(seed in 0u64..1_000_000, groups in 1usize..12, width in 1usize..4, n in 0usize..40) {
            let rows = random_rows(seed, groups, width, n);
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 7);
            let e = eliminate(&rows, groups, width, 2, &mut rng);
            prop_assert_eq!(e.rank, rank_fp(&dense(&rows, groups * width)));
            prop_assert_eq!(e.kernel.len(), 2);
        }
    }

    #[test]
    fn kernel_of_a_full_rank_square_is_zero() {
        // Four independent rows over two groups of width 2.
        let one = Fp::ONE;
        let rows = vec![
            vec![(0, one), (1, one)],
            vec![(1, one)],
            vec![(0, one), (2, one)],
            vec![(3, one)],
        ];
        let e = eliminate(&rows, 2, 2, 1, &mut ChaCha8Rng::seed_from_u64(1));
        assert_eq!(e.rank, 4);
        assert!(e.kernel[0].iter().all(|v| v.is_zero()));
    }
}
