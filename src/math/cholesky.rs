//! faer's sparse Cholesky, on one thread: the pattern analysed once, then
//! factored and solved as often as the values change. One thread because
//! rgc's parallelism is over systems and sequences (rayon), and a factor
//! must not depend on the thread count; on this project's systems faer's
//! own threads also cost more than they save (the moduli of a few thousand
//! rods took twice as long with them).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

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
}

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
