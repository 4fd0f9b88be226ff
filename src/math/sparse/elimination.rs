//! The elimination: groups in minimum-degree order, each in a dense front,
//! the pivot rows kept where kernel vectors are asked for; its rank, its
//! counts, and the refusal of a front over the memory limit.

use std::cell::Cell;

use rand::Rng;

use super::front;
use super::quotient::{Quotient, SparseRow};
use crate::math::echelon::{MAX_MODULUS, Modulus};
use crate::math::field::{Field, Fp};
use crate::usage::{self, Guard, Refusal};

/// The outcome of an elimination.
#[derive(Clone, Debug)]
pub struct Elimination<F = Fp> {
    pub rank: usize,
    /// Columns of the matrix.
    pub cols: usize,
    /// Random vectors of the kernel (uniform over it, so a linear relation
    /// that holds on them holds on the whole kernel except with probability
    /// `1/p` each).
    pub kernel: Vec<Vec<F>>,
    /// The largest dense front, rows times columns: what the cost grew with.
    pub largest_front: (usize, usize),
    /// Fronts, and multiply–adds of their dense work (an upper bound).
    pub fronts: usize,
    pub work: f64,
    /// How often each path of the elimination ran.
    pub counts: Counts,
    /// With a deferred group ([`Layout::deferring`]): its Schur complement.
    /// `rank` then counts the pivots of the other groups only.
    pub deferred: Option<Deferred>,
}

/// How the columns are grouped: `groups * width` columns, column `c` in
/// group `c / width`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub groups: usize,
    pub width: usize,
    /// Whether the last group is deferred: eliminated after all the others
    /// ([`super::quotient`]).
    pub deferred: bool,
}

impl Layout {
    pub fn plain(groups: usize, width: usize) -> Layout {
        Layout {
            groups,
            width,
            deferred: false,
        }
    }

    /// The last of `groups` deferred.
    pub fn deferring(groups: usize, width: usize) -> Layout {
        Layout {
            deferred: true,
            ..Layout::plain(groups, width)
        }
    }

    /// Columns before the deferred group (all of them without one).
    fn leading(self) -> usize {
        (self.groups - usize::from(self.deferred && self.groups > 0)) * self.width
    }
}

/// The deferred group's columns once every other group is eliminated: the
/// rows left over them alone (their Schur complement, up to row
/// operations). With `R` the other columns and `B` the deferred ones,
/// `rank = rank([R | B]) - rank(R)`, and column `k` is nonzero exactly when
/// `B e_k` is not in the column space of `R`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Deferred {
    pub rank: usize,
    /// Per deferred column, whether it is nonzero.
    pub nonzero: Vec<bool>,
}

/// How often each path of the elimination ran: the tests make sure every
/// one is reached, and the benchmarks report them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Groups whose degree had grown when they came up, and were queued again.
    pub rescored: usize,
    /// Groups eliminated in another group's front (all their rows were there).
    pub mass: usize,
    /// Fronts whose leftover rows outnumbered their columns and were reduced.
    pub reduced: usize,
    /// Groups eliminated in the dense tail.
    pub tail: usize,
    /// Columns cleared before the order by rows over one group only.
    pub pinned: usize,
}

/// The rank of the matrix of `rows` over the columns of `layout`; no pivot
/// row is kept. With a `limit` in bytes, it stops before any front that
/// would pass it.
pub fn rank<F: Field>(
    rows: &[SparseRow<F>],
    layout: Layout,
    limit: Option<u64>,
) -> Result<Elimination<F>, Refused> {
    Ok(factorize(rows, layout, false, limit)?.0)
}

/// [`rank`], and `kernel_vectors` random kernel vectors drawn from `rng`:
/// with a deferred group, vectors of the kernel of the other columns alone
/// (the deferred columns held at zero, and left out). Every kernel vector
/// is checked against the original rows; a failure is a bug and panics.
pub fn eliminate<F: Field>(
    rows: &[SparseRow<F>],
    layout: Layout,
    kernel_vectors: usize,
    rng: &mut impl Rng,
    limit: Option<u64>,
) -> Result<Elimination<F>, Refused> {
    let (mut out, factors) = factorize(rows, layout, true, limit)?;
    let free = layout.leading();
    out.kernel = (0..kernel_vectors)
        .map(|_| {
            let mut x = front::kernel_vector::<F>(&factors, out.cols, free, rng);
            for (i, r) in rows.iter().enumerate() {
                let s = r
                    .iter()
                    .fold(F::zero(), |acc, &(c, v)| acc + v * x[c as usize]);
                assert!(s == F::zero(), "kernel vector violates row {i}");
            }
            x.truncate(free);
            x
        })
        .collect();
    Ok(out)
}

/// A step stopped before it would have taken the process past its memory
/// limit: an elimination's front, or (for its callers) what comes before.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Refused {
    /// What the step needed, what the process held, and the bound.
    #[serde(flatten)]
    pub refusal: Refusal,
    pub step: Step,
}

/// The step refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Step {
    /// Building the rows (the caller's realization and matrix).
    Rows,
    /// The elimination's copy of the rows as its first elements.
    Elements,
    /// A dense front, rows times columns.
    Front(usize, usize),
}

impl Step {
    /// The step in words, for a message.
    pub fn describe(self) -> String {
        match self {
            Step::Rows => "its realization and matrix".into(),
            Step::Elements => "its elimination's copy of the matrix".into(),
            Step::Front(r, c) => format!("the dense front of {r} x {c} of its elimination"),
        }
    }
}

thread_local! {
    /// Whether this thread's matrix products have reserved their scratch
    /// ([`usage::product_scratch`]).
    static PRODUCT_SCRATCH: Cell<bool> = const { Cell::new(false) };
}

/// Matrix products of fewer multiply-adds than this take faer's small
/// kernels, which reserve no scratch.
const SMALL_PRODUCT: usize = 16 * 16 * 16;

/// Admits the front of `rows` x `cols` against `guard`: what it adds to
/// the dense buffer, in f64, and the rows it leaves (an element, or pivot
/// rows kept) in f32. Before this thread's first front whose products may
/// take faer's large kernels, the address space they reserve is admitted
/// too and reserved at once, so that it never fails inside a product.
fn admit_front(
    guard: &mut Guard,
    scratch: &front::Scratch,
    (rows, cols): (usize, usize),
) -> Result<(), Refused> {
    let need = scratch.growth(rows, cols) + rows * cols * 4;
    let large = rows * cols * rows.min(cols) > SMALL_PRODUCT;
    let pending = large && !PRODUCT_SCRATCH.get();
    let reserved = if pending { usage::product_scratch() } else { 0 };
    guard
        .admit(need as u64, reserved)
        .map_err(|refusal| Refused {
            refusal,
            step: Step::Front(rows, cols),
        })?;
    if pending {
        reserve_product_scratch();
    }
    Ok(())
}

/// One matrix product just above faer's small kernels: it makes the
/// thread reserve its products' scratch now.
fn reserve_product_scratch() {
    use faer::{Accum, Mat, Par, linalg::matmul::matmul};
    let a = Mat::<f64>::zeros(17, 17);
    let mut c = Mat::<f64>::zeros(17, 17);
    matmul(
        c.as_mut(),
        Accum::Add,
        a.as_ref(),
        a.as_ref(),
        1.0,
        Par::Seq,
    );
    PRODUCT_SCRATCH.set(true);
}

/// The elimination, with the pivot rows of every front if `keep` is set.
/// Memory is checked before each front is assembled, on what the process
/// holds and what the front adds: a pattern alone cannot size the fronts
/// ahead (inside a rigid region the redundant rows vanish, which only their
/// values tell), so the guard counts the real sizes as they come, with the
/// process's size read now and then ([`Guard`]).
fn factorize<F: Field>(
    rows: &[SparseRow<F>],
    layout: Layout,
    keep: bool,
    limit: Option<u64>,
) -> Result<(Elimination<F>, Vec<front::Factor>), Refused> {
    let Layout { groups, width, .. } = layout;
    assert!(
        F::modulus() < MAX_MODULUS,
        "the dense kernel needs a prime below 2^24, not {}",
        F::modulus()
    );
    let cols = groups * width;
    assert!(
        rows.iter().flatten().all(|&(c, _)| (c as usize) < cols),
        "a row entry beyond the {cols} columns"
    );
    let mut guard = Guard::new(limit);
    // The live elements start as a copy of the rows, in f32 and dense over
    // their groups.
    let entries: usize = rows.iter().map(|r| r.len()).sum();
    guard
        .admit((entries * 8 + rows.len() * 48) as u64, 0)
        .map_err(|refusal| Refused {
            refusal,
            step: Step::Elements,
        })?;
    let mut quotient = Quotient::new(rows, groups, width, layout.deferred);
    let mut scratch = front::Scratch::new(Modulus::new(F::modulus()), groups, width);
    let mut factors = Vec::new();
    let mut out = Elimination {
        rank: 0,
        cols,
        kernel: Vec::new(),
        largest_front: (0, 0),
        fronts: 0,
        work: 0.0,
        counts: Counts::default(),
        deferred: None,
    };
    for e in quotient.take_single() {
        admit_front(&mut guard, &scratch, (e.rows, width))?;
        let pinned = front::pin(e, keep, &mut scratch);
        quotient.clear_columns(pinned.group, width, &pinned.pivots, &pinned.rows);
        out.rank += pinned.pivots.len();
        out.counts.pinned += pinned.pivots.len();
        factors.extend(pinned.factor);
    }
    while let Some(g) = quotient.next_group() {
        let gathered = quotient.gather(g);
        admit_front(&mut guard, &scratch, front::size(&gathered, &scratch))?;
        if gathered.tail {
            out.counts.tail += gathered.own.len();
        } else {
            out.counts.mass += gathered.own.len() - 1;
        }
        let pattern = gathered.pattern.clone();
        let done = front::eliminate(gathered, width, keep, &mut scratch);
        out.counts.reduced += usize::from(done.reduced);
        quotient.settle(&pattern, done.left);
        out.rank += done.pivots;
        out.fronts += 1;
        out.work += done.work;
        let (r, c) = done.size;
        if r * c > out.largest_front.0 * out.largest_front.1 {
            out.largest_front = done.size;
        }
        factors.extend(done.factor);
        if quotient.aside_rows() > ASIDE_ROWS {
            let aside = quotient.take_aside();
            quotient.put_aside(front::reduce(&aside, &mut scratch).0);
        }
    }
    out.counts.rescored = quotient.rescored();
    if layout.deferred {
        let (rows, rank) = front::reduce(&quotient.take_aside(), &mut scratch);
        let nonzero = (0..width)
            .map(|k| rows.chunks_exact(width).any(|r| r[k] != 0.0))
            .collect();
        out.deferred = Some(Deferred { rank, nonzero });
    }
    Ok((out, factors))
}

/// Rows set aside over the deferred group are brought back to at most
/// `width` rows once they pass this many (a rigid region leaves one per
/// redundant row).
const ASIDE_ROWS: usize = 256;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Matrix, Q1, Scalar, rank_exact};
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn dense(rows: &[SparseRow<Q1>], cols: usize) -> Matrix<Q1> {
        let mut m = Matrix::zeros(rows.len(), cols);
        for (i, r) in rows.iter().enumerate() {
            for &(c, v) in r {
                m.set(i, c as usize, v);
            }
        }
        m
    }

    /// The sum of two sparse rows, zeros dropped.
    fn sum(a: &SparseRow<Q1>, b: &SparseRow<Q1>) -> SparseRow<Q1> {
        let mut out: SparseRow<Q1> = a.clone();
        for &(c, v) in b {
            match out.binary_search_by_key(&c, |&(k, _)| k) {
                Ok(i) => out[i].1 = out[i].1 + v,
                Err(i) => out.insert(i, (c, v)),
            }
        }
        out.retain(|(_, v)| !v.is_zero());
        out
    }

    /// Random rows touching two or three groups, some of them copies or
    /// sums of others so that the rank falls short.
    fn random_rows(seed: u64, groups: usize, width: usize, n: usize) -> Vec<SparseRow<Q1>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut rows: Vec<SparseRow<Q1>> = Vec::new();
        for i in 0..n {
            if i > 2 && rng.random_range(0..4) == 0 {
                let (i, j) = (
                    rng.random_range(0..rows.len()),
                    rng.random_range(0..rows.len()),
                );
                rows.push(sum(&rows[i], &rows[j]));
                continue;
            }
            let mut gs: Vec<usize> = (0..rng.random_range(1..=3))
                .map(|_| rng.random_range(0..groups))
                .collect();
            gs.sort_unstable();
            gs.dedup();
            let mut r: SparseRow<Q1> = Vec::new();
            for g in gs {
                for k in 0..width {
                    if rng.random_range(0..3) > 0 {
                        r.push(((g * width + k) as u32, Q1::random_nonzero(&mut rng)));
                    }
                }
            }
            rows.push(r);
        }
        rows
    }

    /// The shape of a rigidity matrix: `groups` parts of six columns
    /// `(omega, t)`, `contacts` random pairs of parts, each three rows of
    /// equal velocity `t_a + omega_a x y = t_b + omega_b x y` at a random
    /// point `y`, spin rows `omega . d = 0` on some parts, and some rows
    /// repeated as sums (the dependent rows of over-constrained parts).
    /// Every translation of the whole is a motion of it.
    fn framework(seed: u64, groups: usize, contacts: usize) -> Vec<SparseRow<Q1>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut rows: Vec<SparseRow<Q1>> = Vec::new();
        for _ in 0..contacts {
            let a = rng.random_range(0..groups as u32);
            let b = (a + rng.random_range(1..groups as u32)) % groups as u32;
            rows.extend(contact(a.min(b), a.max(b), &mut rng));
        }
        for g in 0..groups as u32 {
            if rng.random_range(0..3) > 0 {
                rows.push(
                    (0..3)
                        .map(|k| (g * 6 + k, Q1::random_nonzero(&mut rng)))
                        .collect(),
                );
            }
        }
        for _ in 0..rows.len() / 10 {
            let (i, j) = (
                rng.random_range(0..rows.len()),
                rng.random_range(0..rows.len()),
            );
            rows.push(sum(&rows[i], &rows[j]));
        }
        rows
    }

    /// The three rows of equal velocity of parts `a < b` at a random point.
    fn contact(a: u32, b: u32, rng: &mut ChaCha8Rng) -> Vec<SparseRow<Q1>> {
        let y = [0; 3].map(|_| Q1::random(rng));
        let velocity = [
            [Q1::ZERO, y[2], -y[1], Q1::ONE, Q1::ZERO, Q1::ZERO],
            [-y[2], Q1::ZERO, y[0], Q1::ZERO, Q1::ONE, Q1::ZERO],
            [y[1], -y[0], Q1::ZERO, Q1::ZERO, Q1::ZERO, Q1::ONE],
        ];
        velocity
            .into_iter()
            .map(|v| {
                let mut row: SparseRow<Q1> = Vec::new();
                row.extend((0..6).map(|k| (a * 6 + k as u32, v[k])));
                row.extend((0..6).map(|k| (b * 6 + k as u32, -v[k])));
                row.retain(|(_, v)| !v.is_zero());
                row
            })
            .collect()
    }

    /// A translation of every part by `t`.
    fn translation(groups: usize, t: [Q1; 3]) -> Vec<Q1> {
        (0..groups)
            .flat_map(|_| [Q1::ZERO, Q1::ZERO, Q1::ZERO, t[0], t[1], t[2]])
            .collect()
    }

    /// Checks an elimination of `rows` against dense elimination: the rank,
    /// kernel vectors that span the kernel as far as their number allows,
    /// and the translations inside the span of enough of them.
    fn check_against_dense(rows: &[SparseRow<Q1>], groups: usize) -> Elimination<Q1> {
        let cols = groups * 6;
        let rank = rank_exact(&dense(rows, cols));
        let nullity = cols - rank;
        let k = nullity + 2;
        let e = eliminate(
            rows,
            Layout::plain(groups, 6),
            k,
            &mut ChaCha8Rng::seed_from_u64(5),
            None,
        )
        .unwrap();
        assert_eq!(e.rank, rank, "rank");
        let mut m = Matrix::zeros(0, cols);
        for x in &e.kernel {
            let r = m.push_row();
            for (c, &v) in x.iter().enumerate() {
                m.set(r, c, v);
            }
        }
        assert_eq!(
            rank_exact(&m),
            nullity.min(k),
            "the kernel vectors span the kernel"
        );
        for t in [[1, 0, 0], [0, 1, 0], [0, 0, 1]] {
            let r = m.push_row();
            for (c, v) in translation(groups, t.map(Q1::new)).into_iter().enumerate() {
                m.set(r, c, v);
            }
        }
        assert_eq!(rank_exact(&m), nullity, "translations lie in the span");
        e
    }

    #[test]
    fn frameworks_of_50_to_300_parts_match_dense_elimination() {
        let mut total = Counts::default();
        for (seed, groups, contacts) in [
            (1, 50, 60),
            (2, 80, 140),
            (3, 120, 150),
            (4, 300, 420),
            (5, 150, 700),
        ] {
            let rows = framework(seed, groups, contacts);
            let c = check_against_dense(&rows, groups).counts;
            total.rescored += c.rescored;
            total.mass += c.mass;
            total.reduced += c.reduced;
            total.pinned += c.pinned;
        }
        // Lazy rescoring, mass elimination (with amalgamation) and the
        // clearing of spin columns ran.
        assert!(total.pinned > 0, "{total:?}");
        assert!(total.rescored > 0, "{total:?}");
        assert!(total.mass > 0, "{total:?}");
    }

    #[test]
    fn leftover_rows_that_outnumber_their_columns_are_reduced() {
        // Part 0 touches parts 1 and 2 by ten contacts each, and 1 and 2 are
        // joined through a ring of 18 parts: part 0 goes first, and its
        // front leaves 54 rows over the 12 columns of parts 1 and 2.
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let mut rows = Vec::new();
        for _ in 0..10 {
            rows.extend(contact(0, 1, &mut rng));
            rows.extend(contact(0, 2, &mut rng));
        }
        let ring: Vec<u32> = std::iter::once(1).chain(3..21).chain([2]).collect();
        for w in ring.windows(2) {
            rows.extend(contact(w[0].min(w[1]), w[0].max(w[1]), &mut rng));
        }
        let e = check_against_dense(&rows, 21);
        assert!(e.counts.reduced > 0, "{:?}", e.counts);
    }

    #[test]
    fn a_dense_matrix_is_eliminated_in_one_tail_front() {
        // 50 groups, 240 random rows over all of them, 60 of them sums of
        // others: dense from the start, so the first front takes it all.
        let (groups, width) = (50, 6);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut rows: Vec<SparseRow<Q1>> = (0..180)
            .map(|_| {
                (0..(groups * width) as u32)
                    .map(|c| (c, Q1::random_nonzero(&mut rng)))
                    .collect()
            })
            .collect();
        for i in 0..60 {
            let (a, b) = (&rows[i], &rows[i + 1]);
            let sum = a
                .iter()
                .zip(b)
                .map(|(&(c, x), &(_, y))| (c, x + y))
                .collect();
            rows.push(sum);
        }
        let e = eliminate(&rows, Layout::plain(groups, width), 1, &mut rng, None).unwrap();
        assert_eq!(e.rank, 180);
        assert_eq!(e.rank, rank_exact(&dense(&rows, groups * width)));
        assert_eq!((e.counts.tail, e.fronts), (groups, 1), "{:?}", e.counts);
    }

    #[test]
    fn a_memory_limit_counts_what_the_process_holds() {
        // The dense matrix of the tail test is one front of 240 x 300. A
        // limit below what the process already holds stops before the
        // elimination copies the rows, naming what it holds; one far above
        // lets the same elimination finish with the same rank.
        let (groups, width) = (50, 6);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let rows: Vec<SparseRow<Q1>> = (0..240)
            .map(|_| {
                (0..(groups * width) as u32)
                    .map(|c| (c, Q1::random_nonzero(&mut rng)))
                    .collect()
            })
            .collect();
        let Some(held) = usage::held() else {
            return;
        };
        let refused =
            rank(&rows, Layout::plain(groups, width), Some(held.resident / 2)).unwrap_err();
        assert_eq!(refused.step, Step::Elements);
        assert_eq!(refused.refusal.bound, usage::Bound::Limit);
        assert_eq!(refused.refusal.need, 240 * 300 * 8 + 240 * 48);
        assert!(refused.refusal.held >= held.resident / 2, "{refused:?}");
        let e = rank(
            &rows,
            Layout::plain(groups, width),
            Some(held.resident + (1 << 30)),
        )
        .expect("within");
        assert_eq!(e.rank, 240);
    }

    #[test]
    fn a_front_needs_its_growth_in_f64_and_its_rows_in_f32() {
        // A first front of 240 x 300 grows the dense buffer by all of it;
        // the rows it leaves or keeps take half that again. The guard reads
        // the process's size for it (8 MiB of estimates pass unread).
        let scratch = front::Scratch::new(Modulus::new(Q1::modulus()), 50, 6);
        let mut guard = Guard::new(None);
        admit_front(&mut guard, &scratch, (240, 300)).unwrap();
        assert_eq!(scratch.growth(240, 300), 240 * 300 * 8);
        assert_eq!(guard.readings(), usize::from(usage::held().is_some()));
        admit_front(&mut guard, &scratch, (2, 3)).unwrap();
        assert_eq!(guard.readings(), usize::from(usage::held().is_some()));
    }

    #[test]
    fn a_chain_of_bars_never_reaches_the_dense_tail() {
        // Parts in a ring, each touching the next: every front is small, so
        // no front ever holds half of what is left until the very end.
        let groups = 200;
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let mut rows: Vec<SparseRow<Q1>> = Vec::new();
        for g in 0..groups as u32 {
            let h = (g + 1) % groups as u32;
            let (a, b) = (g.min(h), g.max(h));
            let row: SparseRow<Q1> = [a, b]
                .into_iter()
                .flat_map(|p| (0..6).map(move |k| p * 6 + k))
                .map(|c| (c, Q1::random_nonzero(&mut rng)))
                .collect();
            rows.push(row);
        }
        let e = eliminate(&rows, Layout::plain(groups, 6), 1, &mut rng, None).unwrap();
        assert_eq!(e.rank, groups, "one independent bar per link");
        assert_eq!(e.counts.tail, 0, "{:?}", e.counts);
        assert!(e.largest_front.1 <= 3 * 6, "{:?}", e.largest_front);
    }

    #[test]
    fn a_deferred_group_leaves_its_schur_complement() {
        // Frameworks of 40 to 150 parts with a seventh group of six columns
        // touched by a third of the rows (and two rows over it alone): the
        // rank of the other columns, rank([R | B]) - rank(R), and which
        // columns of B leave the column space of R, all as dense
        // elimination finds them; kernel vectors of R alone.
        let mut seen = [false; 2];
        for (seed, groups, contacts) in [(21, 40, 30), (22, 60, 90), (23, 150, 400)] {
            let mut rows = framework(seed, groups, contacts);
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let d = (groups * 6) as u32;
            // Column 5 is in no row: in R's span (zero).
            for r in rows.iter_mut() {
                if rng.random_range(0..3) == 0 {
                    for k in 0..5 {
                        r.push((d + k, Q1::random_nonzero(&mut rng)));
                    }
                }
            }
            rows.push(vec![(d + 1, Q1::ONE)]);
            rows.push(vec![(d + 1, Q1::new(3)), (d + 2, Q1::ONE)]);
            let cols = (groups + 1) * 6;
            let (r, rb) = (
                rank_exact(&dense(
                    &rows
                        .iter()
                        .map(|r| r.iter().copied().filter(|&(c, _)| c < d).collect())
                        .collect::<Vec<_>>(),
                    cols,
                )),
                rank_exact(&dense(&rows, cols)),
            );
            let layout = Layout::deferring(groups + 1, 6);
            let mut draws = ChaCha8Rng::seed_from_u64(3);
            let e = eliminate(&rows, layout, 2, &mut draws, None).unwrap();
            let deferred = e.deferred.clone().expect("a deferred group");
            assert_eq!((e.rank, deferred.rank), (r, rb - r), "seed {seed}");
            for k in 0..6 {
                let only: Vec<SparseRow<Q1>> = rows
                    .iter()
                    .map(|row| {
                        row.iter()
                            .copied()
                            .filter(|&(c, _)| c < d || c == d + k)
                            .collect()
                    })
                    .collect();
                let outside = rank_exact(&dense(&only, cols)) > r;
                assert_eq!(
                    deferred.nonzero[k as usize], outside,
                    "seed {seed}, column {k}"
                );
                seen[usize::from(outside)] = true;
            }
            assert!(e.kernel.iter().all(|x| x.len() == groups * 6));
            // The same rank without the deferred columns' rows ranked last.
            assert_eq!(
                rank(&rows, Layout::plain(groups + 1, 6), None)
                    .unwrap()
                    .rank,
                rb
            );
        }
        assert_eq!(seen, [true, true], "columns inside and outside R's span");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// The block elimination agrees with dense elimination, and its
        /// kernel vectors are kernel vectors (checked inside `eliminate`).
        #[test]
        fn rank_matches_dense(seed in 0u64..1_000_000, groups in 1usize..12, width in 1usize..4, n in 0usize..40) {
            let rows = random_rows(seed, groups, width, n);
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 7);
            let e = eliminate(&rows, Layout::plain(groups, width), 2, &mut rng, None).unwrap();
            prop_assert_eq!(e.rank, rank_exact(&dense(&rows, groups * width)));
            prop_assert_eq!(e.kernel.len(), 2);
        }
    }

    #[test]
    fn kernel_of_a_full_rank_square_is_zero() {
        // Four independent rows over two groups of width 2.
        let one = Q1::ONE;
        let rows = vec![
            vec![(0, one), (1, one)],
            vec![(1, one)],
            vec![(0, one), (2, one)],
            vec![(3, one)],
        ];
        let e = eliminate(
            &rows,
            Layout::plain(2, 2),
            1,
            &mut ChaCha8Rng::seed_from_u64(1),
            None,
        )
        .unwrap();
        assert_eq!(e.rank, 4);
        assert!(e.kernel[0].iter().all(|v| v.is_zero()));
    }
}
