//! Levenberg–Marquardt, written once for every projection onto a family
//! of realizations (a motif's grouping, a whole system's incidences).
//!
//! The equations say what they are through [`Residual`]: their residuals
//! and a sparse Jacobian by rows at a point, and the residual accepted
//! there. [`solve`] owns the rest: the damped normal equations
//! `(JᵀJ + λ·top·I) δ = −Jᵀr` by faer's sparse Cholesky on one thread
//! ([`super::cholesky`]), with the pattern analysed once per start, and
//! the damping schedule: `λ` from 1e-3, divided by 4 after a step that
//! lowers the cost and multiplied by 4 after one that does not, given up
//! past 1e8. A start whose cost stalls ([`STALL`], unless the equations ask
//! for more patience) while its residual is still refused is given up too,
//! and so is one the equations call trapped: the cost then sits on a trap
//! (on the unit sphere a plane's normal shrunk to zero costs exactly 1)
//! that the damping took a hundred factorizations to confess. A large system also
//! takes chord steps (the last factor again with the new gradient) while
//! they quarter the cost, and polishes by them alone.

use faer::MatMut;
use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};

use super::cholesky::Llt;

/// Damped steps per start.
const MAX_STEPS: usize = 300;

/// Steps taken after the residual is accepted, while they still reduce it:
/// a float rank needs the incidences as exact as rounding allows.
const POLISH_STEPS: usize = 3;

/// Systems of at least this many unknowns take chord steps: the last
/// factor again with the new gradient, kept while each step lowers the cost
/// to [`CHORD_GAIN`] of what it was. A factorization there costs hundreds
/// of triangular solves (1.2 s against 0.03 s at 68,000 unknowns); smaller
/// systems, the motifs' among them, take a fresh one every step.
const CHORD_UNKNOWNS: usize = 20_000;
const CHORD_GAIN: f64 = 0.25;

/// A start is given up when its cost fell by less than this share (1%)
/// over the last this many steps (10) taken with its residual still
/// refused, unless its equations ask for more patience.
pub const STALL: (f64, usize) = (0.01, 10);

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

    /// Whether `u` lies in a trap that no step leaves, so that the start is
    /// given up at once rather than by the stall rule (none by default).
    fn trapped(&self, _u: &[f64]) -> bool {
        false
    }

    /// The stall rule: the share the cost must fall by over how many
    /// steps for the start to go on.
    fn stall(&self) -> (f64, usize) {
        STALL
    }
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

/// [`Normal`]'s pattern, value order and products, before a factor.
type Pattern = (
    SymbolicSparseColMat<usize>,
    faer::sparse::Argsort<usize>,
    Vec<(usize, usize)>,
);

impl Normal {
    fn new(at: &Residuals, n: usize) -> Option<Self> {
        let (symbolic, argsort, from) = Self::pattern(at, n)?;
        let llt = Llt::analyse(symbolic.as_ref())?;
        Some(Normal {
            symbolic,
            argsort,
            llt,
            from,
        })
    }

    /// The pattern of `JᵀJ` (lower triangle and diagonal), the order its
    /// values come in, and the two Jacobian entries of each product.
    fn pattern(at: &Residuals, n: usize) -> Option<Pattern> {
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
        Some((symbolic, argsort, from))
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
        Some(self.again(grad))
    }

    /// The step `δ = −M⁻¹ grad` with the matrix `M` last factored (a chord
    /// step: the Jacobian of an earlier point).
    fn again(&mut self, grad: &[f64]) -> Vec<f64> {
        let n = grad.len();
        let mut x: Vec<f64> = grad.iter().map(|g| -g).collect();
        self.llt
            .solve(MatMut::from_column_major_slice_mut(&mut x, n, 1));
        x
    }
}

/// The gradient `Jᵀr` at `at`.
fn gradient(at: &Residuals, n: usize) -> Vec<f64> {
    let mut grad = vec![0.0; n];
    for (i, r) in at.r.iter().enumerate() {
        for x in at.entries(i) {
            grad[at.cols[x]] += at.vals[x] * r;
        }
    }
    grad
}

/// Chord steps from `u` (the last factor again, with the gradient at each
/// new point) while each lowers the cost to [`CHORD_GAIN`] of what it was;
/// every step taken is recorded in `costs`.
fn chord(
    eq: &impl Residual,
    normal: &mut Normal,
    u: &mut Vec<f64>,
    at: &mut Residuals,
    cost: &mut f64,
    costs: &mut Vec<f64>,
) {
    let n = u.len();
    loop {
        let step = normal.again(&gradient(at, n));
        let trial: Vec<f64> = u.iter().zip(&step).map(|(a, b)| a + b).collect();
        let cost_t = eq.eval(&trial, false).cost();
        // A NaN cost is no gain either.
        if cost_t.is_nan() || cost_t >= CHORD_GAIN * *cost {
            return;
        }
        *u = trial;
        *at = eq.eval(u, true);
        *cost = cost_t;
        costs.push(cost_t);
    }
}

/// Bytes [`solve`] holds at once from `u`, beyond `u` itself: the
/// Jacobian (twice, with the trial point's residuals), the normal
/// equations' pattern, products and values, and the Cholesky factor with
/// its workspace, sized by faer's symbolic step; `None` when faer cannot
/// order the pattern. Counting it builds the pattern once.
pub fn memory(eq: &impl Residual, u: &[f64]) -> Option<u64> {
    let n = eq.unknowns();
    let at = eq.eval(u, true);
    let (symbolic, _, from) = Normal::pattern(&at, n)?;
    let factor = Llt::need(symbolic.as_ref())?;
    let jacobian = 2 * (at.cols.len() * 16 + at.r.len() * 16);
    // Per product: its source pair, its value (twice: JᵀJ and the shifted
    // copy), its place in the pattern (index and argsort).
    let products = from.len() * (16 + 16 + 16);
    // Per unknown: the point, the trial, the step, the gradient, the
    // diagonal and the shifted values' tail, with room to spare.
    let unknowns = 8 * n * 8;
    Some((jacobian + products + unknowns) as u64 + factor)
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
    // The costs after the steps taken, for the stall rule.
    let mut costs: Vec<f64> = vec![cost];
    let (drop, steps) = eq.stall();
    for _ in 0..MAX_STEPS {
        if at.largest() <= eq.tolerance(&u) {
            // A large system polishes by chord steps alone.
            if n >= CHORD_UNKNOWNS && normal.llt.is_factored() {
                chord(eq, &mut normal, &mut u, &mut at, &mut cost, &mut costs);
                return Some(u);
            }
            polish += 1;
            if polish > POLISH_STEPS {
                return Some(u);
            }
        } else if eq.trapped(&u)
            || costs
                .iter()
                .rev()
                .nth(steps)
                .is_some_and(|&before| cost > (1.0 - drop) * before)
        {
            return None;
        }
        let jtj: Vec<f64> = normal
            .from
            .iter()
            .map(|&(x, y)| at.vals[x] * at.vals[y])
            .collect();
        let grad = gradient(&at, n);
        let mut diag = vec![0.0; n];
        for x in 0..at.vals.len() {
            diag[at.cols[x]] += at.vals[x] * at.vals[x];
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
                    if n >= CHORD_UNKNOWNS && polish == 0 {
                        chord(eq, &mut normal, &mut u, &mut at, &mut cost, &mut costs);
                    }
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

    /// Copies of [`CircleAndLine`] side by side, enough unknowns for chord
    /// steps, each circle a little larger than the last.
    struct Circles(usize);

    impl Residual for Circles {
        fn unknowns(&self) -> usize {
            2 * self.0
        }
        fn eval(&self, u: &[f64], jacobian: bool) -> Residuals {
            let mut r = Residuals::new(jacobian);
            for k in 0..self.0 {
                let (x, y) = (2 * k, 2 * k + 1);
                let radius = 1.0 + k as f64 / self.0 as f64;
                r.row(
                    u[x] * u[x] + u[y] * u[y] - radius * radius,
                    [(x, 2.0 * u[x]), (y, 2.0 * u[y])],
                );
                r.row(u[x] - u[y], [(x, 1.0), (y, -1.0)]);
            }
            r
        }
        fn tolerance(&self, _: &[f64]) -> f64 {
            1e-13
        }
    }

    #[test]
    fn a_large_system_converges_with_chord_steps() {
        let circles = Circles(CHORD_UNKNOWNS / 2 + 1);
        let start: Vec<f64> = (0..circles.unknowns())
            .map(|i| if i % 2 == 0 { 2.0 } else { 0.5 })
            .collect();
        let u = solve(&circles, start).unwrap();
        let h = 0.5_f64.sqrt();
        for k in 0..circles.0 {
            let radius = 1.0 + k as f64 / circles.0 as f64;
            for x in [u[2 * k], u[2 * k + 1]] {
                assert!((x - h * radius).abs() < 1e-13, "circle {k}: {x}");
            }
        }
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
