//! Levenberg–Marquardt, written once for every projection onto a family
//! of realizations (a motif's grouping, a whole system's incidences).
//!
//! The equations say what they are through [`Residual`]: their residuals
//! and a sparse Jacobian by rows at a point, and the residual accepted
//! there. [`solve`] owns the rest: the damped normal equations
//! `(JᵀJ + λ·top·I) δ = −Jᵀr` by faer's sparse Cholesky on one thread
//! ([`super::cholesky`]), with the pattern analysed once per start, and the damping schedule: `λ` from 1e-3,
//! divided by 4 after a step that lowers the cost and multiplied by 4
//! after one that does not, given up past 1e8. A start whose cost stalls, less
//! than 1% lower over 10 steps while its residual
//! is still refused, is given up too: the cost then sits on a trap (on the
//! unit sphere a plane's normal shrunk to zero costs exactly 1) that the
//! damping took a hundred factorizations to confess.

use faer::MatMut;
use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};

use super::cholesky::Llt;

/// Damped steps per start.
const MAX_STEPS: usize = 300;

/// Steps taken after the residual is accepted, while they still reduce it:
/// a float rank needs the incidences as exact as rounding allows.
const POLISH_STEPS: usize = 3;

/// A start is given up when its cost fell by less than this share over
/// the last [`STALL_STEPS`] steps taken with its residual still refused.
const STALL_DROP: f64 = 0.01;
const STALL_STEPS: usize = 10;

/// The residuals of a set of equations at a point and, when asked, their
/// Jacobian by rows: row `i` has the entries `starts[i]..starts[i + 1]` of
/// `cols` and `vals`, always in the same order, so the pattern of the
/// normal equations is the same at every point. Entries of one row may
/// repeat a column; they add up.
pub struct Residuals {
    r: Vec<f64>,
    starts: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    jacobian: bool,
}

impl Residuals {
    /// No equations yet; rows keep their Jacobian entries when `jacobian`.
    pub fn new(jacobian: bool) -> Self {
        Residuals {
            r: Vec::new(),
            starts: vec![0],
            cols: Vec::new(),
            vals: Vec::new(),
            jacobian,
        }
    }

    /// One equation: its residual and the partial derivatives `(column,
    /// value)` of the residual.
    pub fn row(&mut self, r: f64, entries: impl IntoIterator<Item = (usize, f64)>) {
        self.r.push(r);
        if self.jacobian {
            for (c, v) in entries {
                self.cols.push(c);
                self.vals.push(v);
            }
            self.starts.push(self.cols.len());
        }
    }

    /// The sum of squared residuals, which the steps lower.
    pub fn cost(&self) -> f64 {
        self.r.iter().map(|x| x * x).sum()
    }

    /// The largest residual in absolute value.
    pub fn largest(&self) -> f64 {
        self.r.iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    fn entries(&self, i: usize) -> std::ops::Range<usize> {
        self.starts[i]..self.starts[i + 1]
    }
}

/// Equations to be solved for a point `u` of `unknowns()` coordinates.
pub trait Residual {
    fn unknowns(&self) -> usize;

    /// The residuals at `u`, with their Jacobian when `jacobian`.
    fn eval(&self, u: &[f64], jacobian: bool) -> Residuals;

    /// The largest residual at `u` that counts as solved (relative to the
    /// size of the solution, which the equations know).
    fn tolerance(&self, u: &[f64]) -> f64;
}

/// The normal equations' pattern (lower triangle and diagonal), analysed
/// once, with where each of its entries comes from.
struct Normal {
    symbolic: SymbolicSparseColMat<usize>,
    argsort: faer::sparse::Argsort<usize>,
    llt: Llt,
    /// Per off-diagonal-or-diagonal product: the two Jacobian entries.
    from: Vec<(usize, usize)>,
}

impl Normal {
    fn new(at: &Residuals, n: usize) -> Option<Self> {
        let mut pairs: Vec<Pair<usize, usize>> = Vec::new();
        let mut from: Vec<(usize, usize)> = Vec::new();
        for i in 0..at.r.len() {
            for x in at.entries(i) {
                for y in at.entries(i) {
                    if at.cols[x] >= at.cols[y] {
                        pairs.push(Pair {
                            row: at.cols[x],
                            col: at.cols[y],
                        });
                        from.push((x, y));
                    }
                }
            }
        }
        pairs.extend((0..n).map(|c| Pair { row: c, col: c }));
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs).ok()?;
        let llt = Llt::analyse(symbolic.as_ref())?;
        Some(Normal {
            symbolic,
            argsort,
            llt,
            from,
        })
    }

    /// The step `δ` of `(jtj + shift·I) δ = −grad`, or `None` when the
    /// Cholesky factorization fails.
    fn step(&mut self, jtj: &[f64], grad: &[f64], shift: f64) -> Option<Vec<f64>> {
        let n = grad.len();
        let mut vals = jtj.to_vec();
        vals.extend(std::iter::repeat_n(shift, n));
        let a = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &vals).ok()?;
        if !self.llt.factor(a.as_ref()) {
            return None;
        }
        let mut x: Vec<f64> = grad.iter().map(|g| -g).collect();
        self.llt
            .solve(MatMut::from_column_major_slice_mut(&mut x, n, 1));
        Some(x)
    }
}

/// Levenberg–Marquardt from `u`: a point whose residuals are within the
/// equations' tolerance (polished by a few more steps), or
/// `None` when the damping runs away or the steps run out first.
pub fn solve(eq: &impl Residual, mut u: Vec<f64>) -> Option<Vec<f64>> {
    let n = eq.unknowns();
    let mut at = eq.eval(&u, true);
    let mut normal = Normal::new(&at, n)?;
    let mut cost = at.cost();
    let mut lambda = 1e-3;
    let mut polish = 0;
    // The costs after the steps taken while the residual was refused.
    let mut costs: Vec<f64> = vec![cost];
    for _ in 0..MAX_STEPS {
        if at.largest() <= eq.tolerance(&u) {
            polish += 1;
            if polish > POLISH_STEPS {
                return Some(u);
            }
        } else if let Some(&before) = costs.iter().rev().nth(STALL_STEPS)
            && cost > (1.0 - STALL_DROP) * before
        {
            return None;
        }
        let jtj: Vec<f64> = normal
            .from
            .iter()
            .map(|&(x, y)| at.vals[x] * at.vals[y])
            .collect();
        let mut grad = vec![0.0; n];
        let mut diag = vec![0.0; n];
        for (i, r) in at.r.iter().enumerate() {
            for x in at.entries(i) {
                grad[at.cols[x]] += at.vals[x] * r;
                diag[at.cols[x]] += at.vals[x] * at.vals[x];
            }
        }
        let top = diag.iter().fold(1.0_f64, |m, &x| m.max(x));
        loop {
            if let Some(step) = normal.step(&jtj, &grad, lambda * top) {
                let trial: Vec<f64> = u.iter().zip(&step).map(|(a, b)| a + b).collect();
                let cost_t = eq.eval(&trial, false).cost();
                if cost_t.is_finite() && cost_t < cost {
                    u = trial;
                    at = eq.eval(&u, true);
                    cost = cost_t;
                    if polish == 0 {
                        costs.push(cost);
                    }
                    lambda = (lambda / 4.0).max(1e-14);
                    break;
                }
            }
            lambda *= 4.0;
            if lambda > 1e8 {
                return (polish > 0).then_some(u);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit circle met by the line `x = y`, from a start off both.
    struct CircleAndLine;

    impl Residual for CircleAndLine {
        fn unknowns(&self) -> usize {
            2
        }
        fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
            let mut r = Residuals::new(jacobian);
            r.row(
                u[0] * u[0] + u[1] * u[1] - 1.0,
                [(0, 2.0 * u[0]), (1, 2.0 * u[1])],
            );
            r.row(u[0] - u[1], [(0, 1.0), (1, -1.0)]);
            r
        }
        fn tolerance(&self, _: &[f64]) -> f64 {
            1e-14
        }
    }

    #[test]
    fn solves_a_circle_met_by_a_line() {
        let u = solve(&CircleAndLine, vec![2.0, 0.5]).unwrap();
        let h = 0.5_f64.sqrt();
        assert!(
            (u[0] - h).abs() < 1e-14 && (u[1] - h).abs() < 1e-14,
            "{u:?}"
        );
    }

    /// `x² + 1 = 0` has no real solution: the damping runs away.
    struct NoRoot;

    impl Residual for NoRoot {
        fn unknowns(&self) -> usize {
            1
        }
        fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
            let mut r = Residuals::new(jacobian);
            r.row(u[0] * u[0] + 1.0, [(0, 2.0 * u[0])]);
            r
        }
        fn tolerance(&self, _: &[f64]) -> f64 {
            1e-12
        }
    }

    #[test]
    fn gives_up_without_a_solution() {
        assert_eq!(solve(&NoRoot, vec![0.7]), None);
    }

    /// A residual of 1 that nothing moves (a plane's normal collapsed on
    /// the unit sphere costs exactly that) beside `m³ = 0`, which each step
    /// brings a third nearer: the cost sinks to 1 by ever smaller steps,
    /// all taken. Evaluations counted.
    struct Trap(std::cell::Cell<usize>);

    impl Residual for Trap {
        fn unknowns(&self) -> usize {
            1
        }
        fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
            self.0.set(self.0.get() + 1);
            let mut r = Residuals::new(jacobian);
            r.row(1.0, []);
            r.row(u[0].powi(3), [(0, 3.0 * u[0] * u[0])]);
            r
        }
        fn tolerance(&self, _: &[f64]) -> f64 {
            1e-12
        }
    }

    #[test]
    fn a_stalled_cost_is_given_up_soon() {
        let trap = Trap(std::cell::Cell::new(0));
        assert_eq!(solve(&trap, vec![1.0]), None);
        // Two evaluations a step: two steps to the plateau (1% of the cost
        // left above 1) and ten on it; without the stall rule the steps go
        // on until `m⁶` is below rounding of 1, and the damping then runs
        // away to 1e8 (about 60 evaluations).
        let evals = trap.0.get();
        assert!(evals <= 30, "{evals} evaluations");
    }

    /// One equation `3u = 3` written as `u + 2u`: two entries of a column.
    struct Split;

    impl Residual for Split {
        fn unknowns(&self) -> usize {
            1
        }
        fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
            let mut r = Residuals::new(jacobian);
            r.row(u[0] + 2.0 * u[0] - 3.0, [(0, 1.0), (0, 2.0)]);
            r
        }
        fn tolerance(&self, _: &[f64]) -> f64 {
            1e-13
        }
    }

    #[test]
    fn repeated_columns_in_a_row_add_up() {
        assert_eq!(Split.eval(&[5.0], false).cost(), 144.0);
        let u = solve(&Split, vec![5.0]).unwrap();
        assert!((u[0] - 1.0).abs() < 1e-13, "{u:?}");
    }
}
