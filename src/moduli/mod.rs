//! The elastic moduli of a rod system (MODEL §10, elastic moduli): every
//! contact a spring of stiffness `k` in each direction (the ball joint made
//! elastic), the rods rigid, the periodic box strained affinely. The rods
//! relax non-affinely, `E(eps) = (k/2) min_u |R u + B eps|^2`, so the 6 x 6
//! tensor (Voigt) per unit volume is `C = (k/V) Bᵀ (I - R R⁺) B`:
//!
//! * [`relax`] — the least squares of every strain column at once, by
//!   faer's sparse QR of `R` over `√λ I`, refined, or where that does not
//!   fit in memory by LSMR preconditioned by the normal equations' factor;
//! * [`voigt`] — the tensor in Voigt's notation, its spectrum, its
//!   isotropic (Voigt) averages;
//! * [`elastic`] — the matrix in floats from truth's own rows, the tensor
//!   kept at the exact strain rank, and a whole rod system's moduli.

pub mod elastic;
pub mod relax;
pub mod voigt;

pub use elastic::{
    Conditioning, Elastic, Exact, Floats, ModuliOptions, Moved, Springs, exact, floats, of_exact,
    of_floats, of_realization, of_system, springs,
};
pub use relax::{FIRST_LSMR_ITERATIONS, LSMR_ITERATIONS, MAX_LSMR_ITERATIONS, Relaxation, Solver};
pub use voigt::Voigt;
