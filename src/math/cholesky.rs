//! faer's sparse Cholesky, on one thread: the pattern analysed once, then
//! factored and solved as often as the values change. One thread because
//! rgc's parallelism is over systems and sequences (rayon), and a factor
//! must not depend on the thread count; on this project's systems faer's
//! own threads also cost more than they save (the moduli of a few thousand
//! rods took twice as long with them).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::{temp_mat_scratch, temp_mat_zeroed};
use faer::mat::AsMatMut;
use faer::matrix_free::{BiLinOp, BiPrecond, LinOp, Precond};
use faer::perm::{PermRef, permute_rows};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    LltRef, SymbolicCholesky, SymbolicCholeskyRaw, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_lower_triangular_transpose_in_place,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, MatRef, Par, Side};

/// A symmetric positive definite pattern's Cholesky factor `L Lᵀ`, read
/// from the lower triangle.
pub struct Llt {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    mem: MemBuffer,
    /// Whether `values` hold the factor of the last matrix given.
    factored: bool,
}

impl Llt {
    /// Analyses the pattern of the matrices to come (its ordering and
    /// supernodes), or `None` when faer cannot.
    pub fn analyse(pattern: SymbolicSparseColMatRef<'_, usize>) -> Option<Self> {
        let (symbolic, scratch) = symbolic(pattern)?;
        Some(Llt {
            values: vec![0.0; symbolic.len_val()],
            symbolic,
            mem: MemBuffer::new(scratch),
            factored: false,
        })
    }

    /// Bytes the factor of `pattern` and its workspace would take (sized
    /// by faer's symbolic step, before they exist), or `None` when faer
    /// cannot order it.
    pub fn need(pattern: SymbolicSparseColMatRef<'_, usize>) -> Option<u64> {
        let (symbolic, scratch) = symbolic(pattern)?;
        Some((symbolic.len_val() * 8 + scratch.size_bytes()) as u64)
    }

    /// Factors `a` (of the analysed pattern); `false` when it is not
    /// positive definite.
    pub fn factor(&mut self, a: SparseColMatRef<'_, usize, f64>) -> bool {
        self.factored = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.values,
                a,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .is_ok();
        self.factored
    }

    /// Whether a matrix was factored (the last given was positive definite).
    pub fn is_factored(&self) -> bool {
        self.factored
    }

    /// Overwrites `x` (at most 6 columns) with `A⁻¹ x` for the matrix last
    /// factored.
    pub fn solve(&mut self, x: MatMut<'_, f64>) {
        assert!(self.factored, "solve after a successful factor");
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            x,
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }

    /// The factor of `A = Qᵀ L Lᵀ Q` (`Q` faer's fill-reducing order) as
    /// the right preconditioner `M = Qᵀ L⁻ᵀ`, for which `Mᵀ A M = I`; none
    /// before a successful factor.
    pub fn root(&self) -> Option<Root<'_>> {
        let factor = match self.symbolic.raw() {
            _ if !self.factored => return None,
            SymbolicCholeskyRaw::Simplicial(s) => {
                Factor::Simplicial(SparseColMatRef::new(s.factor(), &self.values))
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                Factor::Supernodal(SupernodalLltRef::new(s, &self.values))
            }
        };
        Some(Root {
            factor,
            order: self.symbolic.perm(),
        })
    }
}

/// `L`, as faer's simplicial or supernodal factor stores it.
#[derive(Clone, Copy)]
enum Factor<'a> {
    Simplicial(SparseColMatRef<'a, usize, f64>),
    Supernodal(SupernodalLltRef<'a, usize, f64>),
}

/// A Cholesky factor applied as `M = Qᵀ L⁻ᵀ` and `Mᵀ = L⁻¹ Q` (faer's
/// operator traits, for its Krylov solvers).
#[derive(Clone, Copy)]
pub struct Root<'a> {
    factor: Factor<'a>,
    /// `Q`, where faer reordered.
    order: Option<PermRef<'a, usize>>,
}

impl std::fmt::Debug for Root<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Root")
            .field("n", &self.n())
            .finish_non_exhaustive()
    }
}

impl Root<'_> {
    fn n(&self) -> usize {
        match self.factor {
            Factor::Simplicial(l) => l.nrows(),
            Factor::Supernodal(l) => l.symbolic().nrows(),
        }
    }

    /// `out = Qᵀ L⁻ᵀ rhs`.
    fn inverse_transpose(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, stack: &mut MemStack) {
        // In the workspace, not the heap: LSMR applies it every iteration.
        let (mut z, stack) = temp_mat_zeroed::<f64, _, _>(rhs.nrows(), rhs.ncols(), stack);
        let mut z = z.as_mat_mut();
        z.copy_from(rhs);
        match self.factor {
            Factor::Simplicial(l) => {
                solve_lower_triangular_transpose_in_place(l, Conj::No, z.as_mut(), Par::Seq)
            }
            Factor::Supernodal(l) => {
                l.l_transpose_solve_with_conj(Conj::No, z.as_mut(), Par::Seq, stack)
            }
        }
        match self.order {
            Some(q) => permute_rows(out, z.as_ref(), q.inverse()),
            None => { out }.copy_from(&z),
        }
    }

    /// `out = L⁻¹ Q rhs`.
    fn inverse(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, stack: &mut MemStack) {
        let mut out = out;
        match self.order {
            Some(q) => permute_rows(out.as_mut(), rhs, q),
            None => out.copy_from(rhs),
        }
        match self.factor {
            Factor::Simplicial(l) => solve_lower_triangular_in_place(l, Conj::No, out, Par::Seq),
            Factor::Supernodal(l) => l.l_solve_with_conj(Conj::No, out, Par::Seq, stack),
        }
    }

    /// A copy of the right-hand sides, and the supernodal solves' own.
    fn scratch(&self, k: usize) -> StackReq {
        let solve = match self.factor {
            Factor::Simplicial(_) => StackReq::EMPTY,
            Factor::Supernodal(l) => l.symbolic().solve_in_place_scratch::<f64>(k, Par::Seq),
        };
        temp_mat_scratch::<f64>(self.n(), k).and(solve)
    }
}

impl LinOp<f64> for Root<'_> {
    fn apply_scratch(&self, k: usize, _par: Par) -> StackReq {
        self.scratch(k)
    }
    fn nrows(&self) -> usize {
        self.n()
    }
    fn ncols(&self) -> usize {
        self.n()
    }
    fn apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, stack: &mut MemStack) {
        self.inverse_transpose(out, rhs, stack);
    }
    /// Real: the conjugate is the operator.
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack);
    }
}

impl BiLinOp<f64> for Root<'_> {
    fn transpose_apply_scratch(&self, k: usize, _par: Par) -> StackReq {
        self.scratch(k)
    }
    fn transpose_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        _par: Par,
        stack: &mut MemStack,
    ) {
        self.inverse(out, rhs, stack);
    }
    /// Real: the adjoint is the transpose.
    fn adjoint_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.transpose_apply(out, rhs, par, stack);
    }
}

impl Precond<f64> for Root<'_> {}
impl BiPrecond<f64> for Root<'_> {}

/// faer's symbolic factor of `pattern` and the workspace its factor and
/// solves (up to 6 columns) take.
fn symbolic(
    pattern: SymbolicSparseColMatRef<'_, usize>,
) -> Option<(SymbolicCholesky<usize>, StackReq)> {
    let symbolic =
        factorize_symbolic_cholesky(pattern, Side::Lower, Default::default(), Default::default())
            .ok()?;
    let scratch = symbolic
        .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
        .or(symbolic.solve_in_place_scratch::<f64>(6, Par::Seq));
    Some((symbolic, scratch))
}
