//! Row echelon form of a dense matrix over a prime field F_q with q below
//! `2^24`, in exact f64 arithmetic: the kernel under every dense front of
//! the sparse elimination ([`super::sparse`]).
//!
//! Residues are kept centred, in `(-q/2, q/2)`, as f64 integers. A product
//! of two is below `2^46` and exact, and so is a sum of up to [`PANEL`] of
//! them (below `2^52`), so the bulk of the work can be done by faer's
//! floating-point matrix product and reduced once per entry afterwards:
//! the approach of FFLAS-FFPACK. Pivots are found a panel of [`PANEL`]
//! columns at a time; inside the panel the elimination is the textbook one,
//! on the panel's columns only, with the multipliers kept where the
//! eliminated entries were (as LAPACK keeps `L`). The rest of the matrix is
//! then updated once per panel: the panel's pivot rows by a small
//! triangular solve, every other row by one matrix product.

use super::field::inverse_mod;
use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

/// Columns per panel: a sum of this many products of centred residues
/// stays exact in f64.
pub const PANEL: usize = 64;

/// The largest prime this kernel takes: residues and their products must
/// stay exact in f64.
pub const MAX_MODULUS: u64 = 1 << 24;

const _: () = assert!(
    (PANEL as u64 + 1) * (MAX_MODULUS / 2) * (MAX_MODULUS / 2) < 1 << 53,
    "a panel's sums must stay exact"
);

/// Arithmetic modulo a prime `q < 2^24` on centred f64 residues.
#[derive(Clone, Copy, Debug)]
pub struct Modulus {
    q: f64,
    inv: f64,
}

/// Adding and subtracting `1.5 * 2^52` rounds an f64 below `2^51` to the
/// nearest integer with plain additions, which vectorize without SSE4.1.
const ROUND: f64 = 6_755_399_441_055_744.0;

impl Modulus {
    pub fn new(q: u64) -> Modulus {
        assert!(
            q > 2 && q < MAX_MODULUS,
            "the f64 kernel needs an odd prime below 2^24, not {q}"
        );
        Modulus {
            q: q as f64,
            inv: 1.0 / q as f64,
        }
    }

    /// The centred residue of an exact integer `x` with `|x| < 2^53`. The
    /// quotient is rounded from `x / q`, whose rounding error cannot move
    /// the result farther than one off `±q/2`.
    #[inline(always)]
    pub fn reduce(self, x: f64) -> f64 {
        let k = (x * self.inv + ROUND) - ROUND;
        x - k * self.q
    }

    /// `a * b` for centred residues.
    #[inline(always)]
    pub fn mul(self, a: f64, b: f64) -> f64 {
        self.reduce(a * b)
    }

    /// The inverse of a non-zero centred residue.
    pub fn inverse(self, a: f64) -> f64 {
        let q = self.q as u64;
        self.centre(inverse_mod(self.residue(a), q))
    }

    /// The centred residue of a residue in `0..q`.
    pub fn centre(self, v: u64) -> f64 {
        self.reduce(v as f64)
    }

    /// The residue in `0..q` of a centred one.
    pub fn residue(self, x: f64) -> u64 {
        let v = x as i64;
        v.rem_euclid(self.q as i64) as u64
    }
}

/// Rows and columns of the tiles the trailing update is done in: a tile of
/// f64 (2 MiB) stays in a core's L2 cache between its product and its
/// reduction.
const TILE_ROWS: usize = 128;
const TILE_COLS: usize = 1024;

/// One panel being factored, in buffers reused from panel to panel (and
/// from block to block by [`Block::echelon_in`]).
#[derive(Default)]
pub struct Panel {
    width: usize,
    /// The panel's rows, row-major over `width` columns.
    rows: Vec<f64>,
    /// Each row's multipliers of the pivot rows, `width` apart.
    multipliers: Vec<f64>,
    /// The pivot rows found so far, normalised, row-major.
    pivot_rows: Vec<f64>,
    /// `at_pivots[t * PANEL + s]`: pivot row `t` at the pivot column of
    /// pivot row `s` (for `s > t`), what solving for a row's multipliers
    /// reads.
    at_pivots: Vec<f64>,
    /// The panel column of each pivot row and its inverted pivot, in the
    /// order found.
    cols: Vec<usize>,
    inverses: Vec<f64>,
}

impl Panel {
    fn reset(&mut self, rows: usize, width: usize) {
        self.width = width;
        self.rows.clear();
        self.rows.resize(rows * width, 0.0);
        self.multipliers.clear();
        self.multipliers.resize(rows * width, 0.0);
        self.pivot_rows.clear();
        self.pivot_rows.resize(PANEL * width, 0.0);
        self.at_pivots.clear();
        self.at_pivots.resize(PANEL * PANEL, 0.0);
        self.cols.clear();
        self.inverses.clear();
    }
}

/// A dense row-major `rows x cols` matrix of centred residues, borrowed.
pub struct Block<'a> {
    pub data: &'a mut [f64],
    pub rows: usize,
    pub cols: usize,
    pub modulus: Modulus,
}

impl Block<'_> {
    #[inline(always)]
    fn swap_rows(&mut self, i: usize, j: usize) {
        if i != j {
            let (lo, hi) = (i.min(j), i.max(j));
            let (a, b) = self.data.split_at_mut(hi * self.cols);
            a[lo * self.cols..(lo + 1) * self.cols].swap_with_slice(&mut b[..self.cols]);
        }
    }

    /// Brings rows `top..` into row echelon form on the columns
    /// `from..to`, assuming they are zero on every column before `from`:
    /// afterwards rows `top..top + k` are pivot rows, each with a 1 at its
    /// pivot column (pushed to `pivots` in increasing order) and zeros
    /// before it, and the rows after them are zero on `from..to`. Every
    /// step is a row operation on the whole row, so the row space is
    /// unchanged. Returns the row after the last pivot row, `top + k`.
    pub fn echelon(
        &mut self,
        top: usize,
        from: usize,
        to: usize,
        pivots: &mut Vec<usize>,
    ) -> usize {
        self.echelon_in(top, from, to, pivots, &mut Panel::default())
    }

    /// [`Block::echelon`] in the buffers of `panel`, which a caller that
    /// eliminates many small blocks reuses.
    pub fn echelon_in(
        &mut self,
        top: usize,
        from: usize,
        to: usize,
        pivots: &mut Vec<usize>,
        panel: &mut Panel,
    ) -> usize {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has AVX-512F, checked just above.
                return unsafe { self.echelon_avx512(top, from, to, pivots, panel) };
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2, checked just above.
                return unsafe { self.echelon_avx2(top, from, to, pivots, panel) };
            }
        }
        self.echelon_portable(top, from, to, pivots, panel)
    }

    /// [`Block::echelon`] compiled for AVX-512: the loops that reduce and
    /// update rows are plain Rust, which the compiler vectorises only as
    /// wide as it is allowed to (faer's product dispatches by itself).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn echelon_avx512(
        &mut self,
        top: usize,
        from: usize,
        to: usize,
        pivots: &mut Vec<usize>,
        panel: &mut Panel,
    ) -> usize {
        self.echelon_portable(top, from, to, pivots, panel)
    }

    /// [`Block::echelon`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn echelon_avx2(
        &mut self,
        top: usize,
        from: usize,
        to: usize,
        pivots: &mut Vec<usize>,
        panel: &mut Panel,
    ) -> usize {
        self.echelon_portable(top, from, to, pivots, panel)
    }

    #[inline(always)]
    fn echelon_portable(
        &mut self,
        top: usize,
        from: usize,
        to: usize,
        pivots: &mut Vec<usize>,
        panel: &mut Panel,
    ) -> usize {
        debug_assert!(from <= to && to <= self.cols && top <= self.rows);
        let mut top = top;
        let mut j = from;
        while j < to && top < self.rows {
            let end = (j + PANEL).min(to);
            self.factor_panel(top, j, end, panel);
            let k = panel.cols.len();
            if k > 0 {
                if end < self.cols {
                    self.update_rest(top, panel, end);
                }
                self.write_panel(top, j, panel);
                self.sort_pivot_rows(top, &panel.cols);
                let mut sorted = panel.cols.clone();
                sorted.sort_unstable();
                pivots.extend(sorted.into_iter().map(|c| j + c));
            }
            top += k;
            j = end;
        }
        top
    }

    /// Eliminates the panel `from..end` of rows `top..`, a row at a time
    /// in a copy of the panel: each row is reduced by the panel's pivot
    /// rows so far (their multipliers solved first, then one exact sum
    /// reduced once per entry), and becomes the next pivot row if anything
    /// is left. Each row is read once, and the pivot rows stay in cache.
    /// Pivot rows are moved up to `top..` in the order they are found.
    #[inline(always)]
    fn factor_panel(&mut self, top: usize, from: usize, end: usize, panel: &mut Panel) {
        let md = self.modulus;
        let (cols, w) = (self.cols, end - from);
        let n = self.rows - top;
        panel.reset(n, w);
        for i in 0..n {
            let src = &self.data[(top + i) * cols + from..(top + i) * cols + end];
            panel.rows[i * w..(i + 1) * w].copy_from_slice(src);
        }
        let mut acc = vec![0.0; w];
        for i in 0..n {
            let k = panel.cols.len();
            let x = &panel.rows[i * w..(i + 1) * w];
            let m = &mut panel.multipliers[i * w..i * w + k];
            // m_t = x[c_t] - sum_{s<t} m_s u_s[c_t]: pivot row u_s is zero
            // at the columns of the pivots found before it, so reducing by
            // u_0, u_1, ... in turn clears c_0, c_1, ... for good. The sums
            // are exact, so they are accumulated in m and reduced in turn.
            for (m, &c) in m.iter_mut().zip(&panel.cols) {
                *m = x[c];
            }
            for t in 0..k {
                let f = md.reduce(m[t]);
                m[t] = f;
                if f != 0.0 {
                    let (_, later) = m.split_at_mut(t + 1);
                    let at = &panel.at_pivots[t * PANEL + t + 1..t * PANEL + k];
                    for (y, &u) in later.iter_mut().zip(at) {
                        *y -= f * u;
                    }
                }
            }
            acc.copy_from_slice(x);
            for (t, &f) in m.iter().enumerate() {
                if f != 0.0 {
                    for (a, &u) in acc.iter_mut().zip(&panel.pivot_rows[t * w..(t + 1) * w]) {
                        *a -= f * u;
                    }
                }
            }
            for a in &mut acc {
                *a = md.reduce(*a);
            }
            let Some(c) = acc.iter().position(|&a| a != 0.0) else {
                continue;
            };
            let inv = md.inverse(acc[c]);
            for a in &mut acc {
                *a = md.mul(*a, inv);
            }
            for (t, &ct) in panel.cols.iter().enumerate() {
                panel.at_pivots[t * PANEL + k] = panel.pivot_rows[t * w + c];
                debug_assert_eq!(acc[ct], 0.0);
            }
            panel.pivot_rows[k * w..(k + 1) * w].copy_from_slice(&acc);
            panel.cols.push(c);
            panel.inverses.push(inv);
            // The new pivot row moves to place k, above every row not
            // processed yet; the row it displaces has been processed.
            if i != k {
                self.swap_rows(top + i, top + k);
                let (a, b) = panel.multipliers.split_at_mut(i * w);
                a[k * w..(k + 1) * w].swap_with_slice(&mut b[..w]);
            }
        }
    }

    /// Applies a factored panel to the columns `rest..`: its pivot rows by
    /// forward substitution, in the order they were found, then every row
    /// below them by matrix products over tiles that are reduced while
    /// they are still in cache.
    #[inline(always)]
    fn update_rest(&mut self, top: usize, panel: &Panel, rest: usize) {
        let md = self.modulus;
        let cols = self.cols;
        let k = panel.cols.len();
        let width = cols - rest;
        let below = self.rows - top - k;
        let (upper, lower) = self.data.split_at_mut((top + k) * cols);
        let upper = &mut upper[top * cols..];
        // Pivot row t: (row_t - sum_{s<t} m_ts u_s) / pivot_t on the rest,
        // the sum exact in f64 and reduced once.
        let mut acc = vec![0.0; width];
        for t in 0..k {
            let (done, row) = upper.split_at_mut(t * cols);
            let row = &mut row[rest..cols];
            acc.fill(0.0);
            let w = panel.width;
            for (s, &m) in panel.multipliers[t * w..t * w + t].iter().enumerate() {
                if m != 0.0 {
                    let u = &done[s * cols + rest..(s + 1) * cols];
                    for (a, &v) in acc.iter_mut().zip(u) {
                        *a += m * v;
                    }
                }
            }
            let inv = panel.inverses[t];
            for (x, &a) in row.iter_mut().zip(&acc) {
                *x = md.mul(md.reduce(*x - a), inv);
            }
        }
        // Every other row: row -= sum_t m_it u_t, in transposed,
        // column-major views of the same memory (faer 0.24.4 crashes on a
        // row-major destination).
        let upper = &upper[..k * cols];
        for r0 in (0..below).step_by(TILE_ROWS) {
            let rn = TILE_ROWS.min(below - r0);
            let factors = MatRef::from_column_major_slice_with_stride(
                &panel.multipliers[(k + r0) * panel.width..],
                k,
                rn,
                panel.width,
            );
            for c0 in (0..width).step_by(TILE_COLS) {
                let cn = TILE_COLS.min(width - c0);
                let at = r0 * cols + rest + c0;
                let dst =
                    MatMut::from_column_major_slice_with_stride_mut(&mut lower[at..], cn, rn, cols);
                let pivot_rows =
                    MatRef::from_column_major_slice_with_stride(&upper[rest + c0..], cn, k, cols);
                matmul(dst, Accum::Add, pivot_rows, factors, -1.0, Par::Seq);
                for row in lower[at..].chunks_mut(cols).take(rn) {
                    for x in &mut row[..cn] {
                        *x = md.reduce(*x);
                    }
                }
            }
        }
    }

    /// Writes the panel back: pivot rows with their leading 1, every other
    /// row zero.
    #[inline(always)]
    fn write_panel(&mut self, top: usize, from: usize, panel: &Panel) {
        let cols = self.cols;
        let w = panel.width;
        let k = panel.cols.len();
        for i in 0..self.rows - top {
            let row = &mut self.data[(top + i) * cols + from..(top + i) * cols + from + w];
            if i < k {
                row.copy_from_slice(&panel.pivot_rows[i * w..(i + 1) * w]);
            } else {
                row.fill(0.0);
            }
        }
    }

    /// Orders the pivot rows `top..` by their pivot columns (`cols`, in the
    /// order found): each is zero before its own pivot column, so sorted
    /// they are in echelon form.
    #[inline(always)]
    fn sort_pivot_rows(&mut self, top: usize, cols: &[usize]) {
        let n = self.cols;
        let mut order: Vec<usize> = (0..cols.len()).collect();
        order.sort_unstable_by_key(|&t| cols[t]);
        if order.iter().enumerate().all(|(a, &b)| a == b) {
            return;
        }
        let rows = &mut self.data[top * n..(top + cols.len()) * n];
        let copy = rows.to_vec();
        for (to, &from) in order.iter().enumerate() {
            rows[to * n..(to + 1) * n].copy_from_slice(&copy[from * n..(from + 1) * n]);
        }
    }

    /// Whether row `i` is zero on the columns `from..`.
    pub fn is_zero_row(&self, i: usize, from: usize) -> bool {
        self.data[i * self.cols + from..(i + 1) * self.cols]
            .iter()
            .all(|&x| x == 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::field::{Field, Q1};
    use crate::math::{Matrix, Scalar, rank_exact};
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn modulus() -> Modulus {
        Modulus::new(Q1::modulus())
    }

    /// A random `rows x cols` matrix over Q1 of rank at most `r` (a product
    /// of random factors), with every seventh column zero when `gaps` is
    /// set, so that pivots skip them.
    fn low_rank(seed: u64, rows: usize, cols: usize, r: usize, gaps: bool) -> Vec<Q1> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let a: Vec<Q1> = (0..rows * r).map(|_| Q1::random(&mut rng)).collect();
        let b: Vec<Q1> = (0..r * cols)
            .map(|i| {
                if gaps && (i % cols) % 7 == 3 {
                    Q1::zero()
                } else {
                    Q1::random(&mut rng)
                }
            })
            .collect();
        let mut m = vec![Q1::zero(); rows * cols];
        for i in 0..rows {
            for k in 0..r {
                for j in 0..cols {
                    m[i * cols + j] = m[i * cols + j] + a[i * r + k] * b[k * cols + j];
                }
            }
        }
        m
    }

    fn reference(m: &[Q1], rows: usize, cols: usize) -> usize {
        rank_exact(&Matrix {
            rows,
            cols,
            data: m.to_vec(),
        })
    }

    fn centred(m: &[Q1]) -> Vec<f64> {
        m.iter().map(|x| modulus().centre(x.residue())).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(40))]
        /// Several panels deep: the rank is the reference's, the form is
        /// echelon with unit pivots, entries stay centred, and the row space
        /// is the original one (stacking both does not raise the rank).
        #[test]
        fn echelon_form_has_the_reference_rank_and_row_space(
            seed in 0u64..1_000_000, rows in 1usize..160, cols in 1usize..330, r in 0usize..160,
        ) {
            let m = low_rank(seed, rows, cols, r, true);
            let mut a = centred(&m);
            let mut pivots = Vec::new();
            let k = Block { data: &mut a, rows, cols, modulus: modulus() }.echelon(0, 0, cols, &mut pivots);
            prop_assert_eq!(k, reference(&m, rows, cols));
            prop_assert_eq!(pivots.len(), k);
            let half = (Q1::modulus() / 2) as f64;
            prop_assert!(a.iter().all(|x| x.abs() <= half && x.fract() == 0.0));
            for (t, &c) in pivots.iter().enumerate() {
                prop_assert!(t == 0 || pivots[t - 1] < c);
                prop_assert_eq!(a[t * cols + c], 1.0);
                prop_assert!(a[t * cols..t * cols + c].iter().all(|&x| x == 0.0));
            }
            prop_assert!(a[k * cols..].iter().all(|&x| x == 0.0));
            let mut both = m.clone();
            both.extend(a.iter().map(|&x| Q1::from_i64(x as i64)));
            prop_assert_eq!(reference(&both, 2 * rows, cols), k);
        }
    }

    #[test]
    fn full_rank_square_over_three_panels() {
        let n = 2 * PANEL + 5;
        let m = low_rank(5, n, n, n, false);
        let mut a = centred(&m);
        let mut block = Block {
            data: &mut a,
            rows: n,
            cols: n,
            modulus: modulus(),
        };
        assert_eq!(block.echelon(0, 0, n, &mut Vec::new()), n);
    }

    #[test]
    fn a_column_range_leaves_the_columns_after_it_unpivoted() {
        // Eliminating only the first 10 of 300 columns: 10 pivots, and the
        // rows below are zero there but not on the rest.
        let (rows, cols) = (60, 300);
        let m = low_rank(9, rows, cols, 40, false);
        let mut a = centred(&m);
        let mut pivots = Vec::new();
        let mut block = Block {
            data: &mut a,
            rows,
            cols,
            modulus: modulus(),
        };
        let top = block.echelon(0, 0, 10, &mut pivots);
        assert_eq!((top, pivots.len()), (10, 10));
        assert!((top..rows).all(|i| block.is_zero_row(i, 0) == block.is_zero_row(i, 10)));
        assert!((top..rows).any(|i| !block.is_zero_row(i, 10)));
        // Finishing on the rest gives the whole rank.
        let top = block.echelon(top, 10, cols, &mut pivots);
        assert_eq!(top, reference(&m, rows, cols));
    }

    #[test]
    fn reduction_is_exact_at_the_extremes() {
        let md = modulus();
        let q = Q1::modulus() as i64;
        let half = q / 2;
        // The largest product a panel sums, 64 of them, and a residue on top.
        let big = (PANEL as i64) * half * half + half;
        assert!(big < 1 << 53);
        for x in [big, -big, q, -q, half, -half, half + 1, 0, 1, -1] {
            let r = md.reduce(x as f64);
            assert_eq!((r as i64 - x).rem_euclid(q), 0, "{x}");
            assert!(r.abs() <= half as f64, "{x} -> {r}");
        }
        for a in [1.0, -1.0, 2.0, half as f64, -(half as f64), 12345.0] {
            assert_eq!(md.mul(md.inverse(a), a), 1.0, "{a}");
        }
    }
}
