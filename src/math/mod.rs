//! The arithmetic under everything else: the prime field F_p and the
//! [`Scalar`] trait, dense matrices and their exact rank, float rank by SVD
//! or QR, sparse exact elimination for whole systems, three-vectors,
//! statistics, one sparse Cholesky and one sparse QR on one thread, LSMR
//! preconditioned by the first where the second does not fit, and one
//! Levenberg–Marquardt.

pub mod cholesky;
pub mod echelon;
pub mod field;
pub mod float;
pub mod lsmr;
pub mod marquardt;
pub mod matrix;
pub mod prime;
pub mod qr;
pub mod sparse;
pub mod stats;
pub mod vec3;

pub use field::{Field, Fp, Fq, P, Q1, Q2, Scalar};
pub use matrix::{Matrix, rank_exact, rank_fp, reduce_fp};
pub use prime::{Fr, with_prime};
