//! Finite-size scaling (MODEL §8, the paper's numerics protocol): from the
//! observations of each box size to the threshold, `nu` and their intervals.
//!
//! Per box size `L` a cumulative logistic `F(rho; mu, s)` is fitted by
//! maximum likelihood, `Delta rho = s pi / sqrt(3)` gives `nu` through
//! `Delta rho ~ L^(-1/nu)`, and the inverse predictions `rho_x(L)` are
//! extrapolated against `L^(-1/nu)` with one intercept shared by every `x`:
//! the threshold. Intervals come from a case bootstrap over sequences. The
//! tables a study writes from the result are `threshold::report`'s.
//!
//! The files, each using only those listed before it:
//! * `boxes` — what each sequence contributes to a box size, and one box
//!   size's empirical spanning probability and logistic fit on its own
//!   ([`BoxData`], [`pi_curve`], [`fit_each_box`]);
//! * `estimate` — a value with its bootstrap interval ([`Estimate`]);
//! * `scaling` — `nu` and the common-intercept extrapolation by least
//!   squares ([`fit_nu`], [`extrapolate`]);
//! * `contacts` — contact numbers at the threshold ([`ContactNumbers`]);
//! * `bootstrap` — one pass of the analysis, on the data or a resample,
//!   and the resamples;
//! * `analysis` — the whole analysis and its warnings ([`analyse`]), and
//!   the checks before a study's work ([`check_design`]).

mod analysis;
mod bootstrap;
mod boxes;
mod contacts;
mod estimate;
mod scaling;

pub use analysis::{
    BoxFit, Fss, FssOptions, MIN_BOOTSTRAP, MIN_BOXES, analyse, check_bootstrap, check_design,
};
pub use boxes::{BoxAlone, BoxData, ContactPoint, Observation, Protocol, fit_each_box, pi_curve};
pub use contacts::{ContactFits, ContactNumbers, LinearFit};
pub use estimate::Estimate;
pub use scaling::{Extrapolation, NuFit, extrapolate, fit_nu};
